#!/usr/bin/env bash
# Builds the project with AddressSanitizer + UndefinedBehaviorSanitizer
# (-DSLAM_SANITIZE=ON, in build_asan/) and runs test programs under them.
#
#   bash scripts/test_sanitizers.sh [TEST_PROGRAM ...]
#
# Without names every test program runs (the whole suite); CI names the
# reader / writer / command tests (scripts/test.sh) to stay within its time
# budget. Each program runs whole (one process); any sanitizer report fails
# it.
set -euo pipefail
cd "$(dirname "$0")/.."
build=build_asan
jobs="${SLAM_JOBS:-2}"
launcher=()
if command -v ccache > /dev/null; then
  launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
fi
cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=Release -DSLAM_SANITIZE=ON \
  "${launcher[@]}" > /dev/null
programs=("$@")
if [ ${#programs[@]} -eq 0 ]; then
  for source in tests/*_test.cc; do programs+=("$(basename "$source" .cc)"); done
fi
cmake --build "$build" -j "$jobs" --target slam slam_plot "${programs[@]}"

export ASAN_OPTIONS="${ASAN_OPTIONS:-detect_leaks=1:strict_string_checks=1}"
export UBSAN_OPTIONS="${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}"
logs="$build/sanitizer_logs"
mkdir -p "$logs"
run_one() {
  if "$1/tests/$2" > "$1/sanitizer_logs/$2.log" 2>&1; then
    echo "  ok      $2"
  else
    echo "  FAILED  $2 (log: $1/sanitizer_logs/$2.log)"
    tail -n 30 "$1/sanitizer_logs/$2.log"
    return 1
  fi
}
export -f run_one
echo "sanitizers: running ${#programs[@]} test programs under ASan + UBSan"
printf '%s\n' "${programs[@]}" |
  xargs -P "$jobs" -I{} bash -c 'run_one "$0" "$1"' "$build" {}
