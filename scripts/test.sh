#!/usr/bin/env bash
# The README's second command (and CI's, .ci/run): install what is missing,
# build, run all tests, then the reliability stage.
# Tests that read real data use $SLAM_DATASETS (default ../shared/datasets).
#
# Stages (README "Reliability"):
#   1. Release build (build/) and the whole test suite (ctest).
#   2. One clang build with ASan + UBSan + libFuzzer coverage (build_asan/)
#      and the whole test suite again under the sanitizers.
#   3. Every reader's libFuzzer target (from the same build) for
#      $SLAM_FUZZ_SECONDS each (default 30), two at a time.
# Any test failure, sanitizer report or fuzz finding fails the run.
# SLAM_RELIABILITY=0 skips stages 2 and 3 (local runs); CI runs them.
# Cold cache (no ccache, fresh build folders), quiet 2-core wall estimated
# from CPU time (README "Reliability"): 1. build 4.7 min + tests ~5 min;
# 2. build 16.1 min CPU (~8 min) + tests 14.2 min CPU (~7 min); 3. ~2.7 min.
# About 28 minutes in all (CI's hard limit: 90).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install_deps.sh
start=$SECONDS
bash scripts/build.sh
(cd build && ctest --output-on-failure -j "${SLAM_JOBS:-2}")
echo "test: Release build + tests took $((SECONDS - start)) s"

if [ "${SLAM_RELIABILITY:-1}" != "0" ]; then
  bash scripts/test_sanitizers.sh
  bash scripts/fuzz.sh "${SLAM_FUZZ_SECONDS:-30}"
fi
