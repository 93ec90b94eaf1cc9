#!/usr/bin/env bash
# The README's second command: install what is missing, build, run all tests.
# Tests that read real data use $SLAM_DATASETS (default ../shared/datasets).
#
# SLAM_RELIABILITY=1 adds the reliability stage (README "Reliability"): the
# reader, writer and command tests under ASan + UBSan (build_asan/) and a
# short libFuzzer run of every reader (build_fuzz/, SLAM_FUZZ_SECONDS per
# target, default 30). Off by default: its two extra builds of the libraries
# took 32 + 38 minutes on the shared 2-core CI machine (README "Reliability";
# CI's budget is about 30 minutes).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install_deps.sh
bash scripts/build.sh
(cd build && ctest --output-on-failure -j "${SLAM_JOBS:-2}")

if [ "${SLAM_RELIABILITY:-0}" = "1" ]; then
  bash scripts/test_sanitizers.sh reliability_test atomic_file_test \
    g2o_io_test toro_io_test carmen_io_test trajectory_io_test relations_test \
    inertial_io_test landmark_io_test info_command_test optimize_command_test \
    occupancy_grid_test scan_matcher_test
  bash scripts/fuzz.sh "${SLAM_FUZZ_SECONDS:-30}"
fi
