#!/usr/bin/env bash
# The README's second command: install what is missing, build, run all tests.
# Tests that read real data use $SLAM_DATASETS (default ../shared/datasets).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install_deps.sh
bash scripts/build.sh
cd build
ctest --output-on-failure -j "${SLAM_JOBS:-2}"
