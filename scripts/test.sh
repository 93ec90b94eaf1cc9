#!/usr/bin/env bash
# The README's second command (and CI's, .ci/run): install what is missing,
# build, run all tests, then the reliability stage.
# Tests that read real data use $SLAM_DATASETS (default ../shared/datasets).
#
# Stages (README "Reliability"):
#   1. Release build (build/) and the whole test suite (ctest).
#   2. One clang build with ASan + UBSan + libFuzzer coverage (build_asan/)
#      and the test suite again under the sanitizers, without the long tests
#      of tests/sanitizer_excluded.txt (stage 1 ran them).
#   3. Every reader's libFuzzer target (from the same build) for
#      $SLAM_FUZZ_SECONDS each (default 30), two at a time.
# Any test failure, sanitizer report or fuzz finding fails the run.
# SLAM_RELIABILITY=0 skips stages 2 and 3 (local runs); CI runs them.
# Each stage prints its time; the README ("Reliability") has the figures of
# the last fresh-clone run. CI's hard limit is 90 minutes, the project's 45.
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
