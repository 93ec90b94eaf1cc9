#!/usr/bin/env bash
# Runs the whole test suite (ctest) under AddressSanitizer +
# UndefinedBehaviorSanitizer, in the sanitizer build (build_asan/, built
# first by scripts/sanitizer_build.sh: clang, -O1, libFuzzer coverage too).
#
#   bash scripts/test_sanitizers.sh [CTEST_ARGUMENT ...]   # e.g. -R G2o
#
# Every sanitizer report fails the run, also one of a `slam` process that a
# test starts and expects to fail (bad input): the reports go to files
# (log_path) that are checked after ctest. UBSan does not recover
# (-fno-sanitize-recover), ASan stops at the first error, LeakSanitizer
# reports leaks at exit.
set -euo pipefail
cd "$(dirname "$0")/.."
build="${SLAM_ASAN_BUILD:-build_asan}"
start=$SECONDS
bash scripts/sanitizer_build.sh
echo "sanitizers: build took $((SECONDS - start)) s"

reports="$PWD/$build/sanitizer_reports"
rm -rf "$reports"
mkdir -p "$reports"
# Debian's libraries (libceres, glog, OpenCV, ...) are not instrumented;
# Eigen allocations crossing that boundary are handled in CMakeLists.txt
# (EIGEN_MALLOC_ALREADY_ALIGNED). The slam processes of the tests inherit
# these options.
export ASAN_OPTIONS="detect_leaks=1:strict_string_checks=1:log_path=$reports/report${ASAN_OPTIONS:+:$ASAN_OPTIONS}"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1:log_path=$reports/report${UBSAN_OPTIONS:+:$UBSAN_OPTIONS}"
start=$SECONDS
status=0
(cd "$build" && ctest --output-on-failure -j "${SLAM_JOBS:-2}" "$@") || status=$?
echo "sanitizers: tests took $((SECONDS - start)) s"
shopt -s nullglob
found=("$reports"/*)
if [ ${#found[@]} -gt 0 ]; then
  echo "sanitizers: ${#found[@]} report(s) in $reports:"
  for f in "${found[@]}"; do
    echo "== $f"
    head -n 60 "$f"
  done
  exit 1
fi
exit "$status"
