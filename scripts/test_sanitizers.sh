#!/usr/bin/env bash
# Runs the test suite (ctest) under AddressSanitizer +
# UndefinedBehaviorSanitizer, in the sanitizer build (build_asan/, built
# first by scripts/sanitizer_build.sh: clang, -O1, libFuzzer coverage too),
# except the few long tests listed in tests/sanitizer_excluded.txt (each
# repeats, for its statistics, code that a shorter test runs here; the
# Release stage runs them all). SLAM_ASAN_ALL=1 runs those too.
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
# intercept_tls_get_addr=0: the __tls_get_addr interceptor of clang 14's
# runtime (fixed after LLVM 16) takes a dynamic TLS block whose address is
# 16 mod 4096 for a glibc 2.19 header and hands LeakSanitizer a garbage
# range (seen: "DTLS 11 at 0x5736-0x800006838"), so its tracer dies with
# signal 11 at exit, at random by heap layout (reproduced with the Victoria
# Park command of landmark_data_test). Leak checking stays on; only the
# dynamic TLS of dlopen'ed modules is not scanned as roots.
export ASAN_OPTIONS="detect_leaks=1:intercept_tls_get_addr=0:strict_string_checks=1:log_path=$reports/report${ASAN_OPTIONS:+:$ASAN_OPTIONS}"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1:log_path=$reports/report${UBSAN_OPTIONS:+:$UBSAN_OPTIONS}"
start=$SECONDS
status=0
exclude=()
if [ "${SLAM_ASAN_ALL:-0}" != "1" ]; then
  names="$(sed -e 's/#.*//' -e 's/[[:space:]]//g' tests/sanitizer_excluded.txt |
    grep -v '^$' | paste -sd'|')"
  listed="$(cd "$build" && ctest -N)"
  for name in ${names//|/ }; do
    if ! grep -q "Test *#[0-9]*: $name\$" <<< "$listed"; then
      echo "sanitizers: tests/sanitizer_excluded.txt names $name, which is no ctest test" >&2
      exit 1
    fi
  done
  [ -n "$names" ] && exclude=(-E "^($names)\$")
  echo "sanitizers: not running the $(tr '|' '\n' <<< "$names" | wc -l) long tests of tests/sanitizer_excluded.txt (the Release stage ran them)"
fi
(cd "$build" && ctest --output-on-failure -j "${SLAM_JOBS:-2}" "${exclude[@]}" "$@") || status=$?
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
