#!/usr/bin/env bash
# Runs every libFuzzer target of fuzz/ for a while, from a seed corpus made of
# the tiny fixtures in tests/data and the shipped configs.
#
#   bash scripts/fuzz.sh [SECONDS_PER_TARGET (30)] [BUILD_DIR (build_fuzz)]
#
# Builds the targets first (clang, -DSLAM_FUZZ=ON: ASan + UBSan + libFuzzer).
# $SLAM_FUZZ_TARGETS picks some of them (default: all).
# The corpus grows in a temporary folder (never in the repository); a crash
# leaves its input as BUILD_DIR/fuzz_artifacts/crash-* and fails the script.
set -euo pipefail
cd "$(dirname "$0")/.."
seconds="${1:-30}"
build="${2:-build_fuzz}"
jobs="${SLAM_JOBS:-2}"
data=tests/data
read -r -a targets <<< "${SLAM_FUZZ_TARGETS:-g2o toro isam trajectory relations carmen imu stereo_vo config}"

launcher=()
if command -v ccache > /dev/null; then
  launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
fi
cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=Release -DCMAKE_CXX_COMPILER=clang++ \
  -DSLAM_FUZZ=ON -DSLAM_BUILD_TESTS=OFF "${launcher[@]}" > /dev/null
cmake --build "$build" -j "$jobs" --target "${targets[@]/#/fuzz_}"

work="$(mktemp -d "${TMPDIR:-/tmp}/slam_fuzz_corpus.XXXXXX")"
trap 'rm -rf "$work"' EXIT
artifacts="$build/fuzz_artifacts"
mkdir -p "$artifacts"

# seed TARGET FILE [PREFIX_BYTE]: adds FILE (after the selector byte the
# target reads first, when given) to the seeds of TARGET.
seed() {
  local dir="$work/$1/seeds" name
  mkdir -p "$dir"
  name="$(basename "$2")${3:+.$3}"
  if [ -n "${3:-}" ]; then
    { printf "\\x$(printf %02x "$3")"; cat "$2"; } > "$dir/$name"
  else
    cp "$2" "$dir/$name"
  fi
}

for f in "$data"/g2o_*.g2o "$data"/trajectory_vertices.g2o; do
  seed g2o "$f"
done
for f in "$data"/toro_*.graph; do seed toro "$f"; done
seed isam "$data/isam_small.txt"
seed relations "$data/small.relations"
seed carmen "$data/carmen_small.clf"
bzip2 -c "$data/carmen_small.clf" > "$work/carmen_small.clf.bz2"
seed carmen "$work/carmen_small.clf.bz2"
# Trajectory: the first byte picks the reader (fuzz/fuzz_trajectory.cc).
seed trajectory "$data/tum_small.tum" 0
seed trajectory "$data/tum_small.tum" 1
seed trajectory "$data/kitti_small.txt" 2
seed trajectory "$data/euroc_groundtruth_sample.csv" 3
seed trajectory "$data/trajectory_vertices.g2o" 4
printf '1.0\n2.0\n' > "$work/times.txt"
seed trajectory "$work/times.txt" 5
seed imu "$data/gtsam_imu_small.csv" 0
seed imu "$data/euroc_imu_small.csv" 1
seed imu "$data/euroc_groundtruth_sample.csv" 2
seed imu "$data/leica_small.csv" 3
seed stereo_vo "$data/stereo_vo_factors.txt" 0
seed stereo_vo "$data/stereo_vo_calibration.txt" 1
seed stereo_vo "$data/stereo_vo_poses.txt" 2
for f in configs/*.yaml configs/benchmarks/*.yaml; do
  for selector in 0 1 2 3 4; do seed config "$f" "$selector"; done
done

# The targets write each input to a scratch file: in memory when possible.
fuzz_tmp="${TMPDIR:-/tmp}"
if [ -d /dev/shm ] && [ -w /dev/shm ]; then fuzz_tmp=/dev/shm; fi

failed=()
for target in "${targets[@]}"; do
  mkdir -p "$work/$target/corpus"
  echo "fuzz_$target: ${seconds} s"
  if ! TMPDIR="$fuzz_tmp" "$build/fuzz/fuzz_$target" -max_total_time="$seconds" -timeout=10 \
      -rss_limit_mb=2048 -max_len=16384 -print_final_stats=1 \
      -artifact_prefix="$artifacts/" "$work/$target/corpus" \
      "$work/$target/seeds" > "$work/$target.log" 2>&1; then
    failed+=("$target")
    tail -n 40 "$work/$target.log"
  fi
  grep -E "^stat::number_of_executed_units|^stat::peak_rss_mb" \
    "$work/$target.log" | tr '\n' ' ' || true
  echo
done
if [ ${#failed[@]} -gt 0 ]; then
  echo "fuzz: FAILED: ${failed[*]} (inputs in $artifacts)"
  exit 1
fi
echo "fuzz: all targets ran ${seconds} s without a finding"
