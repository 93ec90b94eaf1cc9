#!/usr/bin/env bash
# Configures and builds the sanitizer build (README "Reliability"): clang,
# ASan + UBSan, libFuzzer coverage (-DSLAM_SANITIZE=ON -DSLAM_FUZZ=ON) in
# $SLAM_ASAN_BUILD (default build_asan/). One build serves both the test
# suite under the sanitizers (scripts/test_sanitizers.sh) and the fuzz
# targets (scripts/fuzz.sh).
#
#   bash scripts/sanitizer_build.sh [TARGET ...]   # default: everything
set -euo pipefail
cd "$(dirname "$0")/.."
build="${SLAM_ASAN_BUILD:-build_asan}"
launcher=()
if command -v ccache > /dev/null; then
  launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
fi
cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=Release \
  -DCMAKE_CXX_COMPILER=clang++ -DSLAM_SANITIZE=ON -DSLAM_FUZZ=ON \
  -DSLAM_BUILD_TESTS=ON "${launcher[@]}" > /dev/null
targets=()
for target in "$@"; do targets+=(--target "$target"); done
cmake --build "$build" -j "${SLAM_JOBS:-2}" "${targets[@]}"
