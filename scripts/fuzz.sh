#!/usr/bin/env bash
# Runs every libFuzzer target of fuzz/ for a while, from a seed corpus made of
# the tiny fixtures in tests/data and the shipped configs.
#
#   bash scripts/fuzz.sh [SECONDS_PER_TARGET (30)]
#
# The targets live in the sanitizer build (build_asan/, built first by
# scripts/sanitizer_build.sh: clang, ASan + UBSan + libFuzzer coverage).
# $SLAM_FUZZ_TARGETS picks some of them (default: all); $SLAM_JOBS of them
# (default 2) run at once, one core each.
# The corpus grows in a temporary folder (never in the repository); a crash
# leaves its input as build_asan/fuzz_artifacts/crash-* and fails the script.
set -euo pipefail
cd "$(dirname "$0")/.."
seconds="${1:-30}"
build="${SLAM_ASAN_BUILD:-build_asan}"
jobs="${SLAM_JOBS:-2}"
data=tests/data
read -r -a targets <<< "${SLAM_FUZZ_TARGETS:-g2o toro isam trajectory relations carmen imu stereo_vo config visual}"

bash scripts/sanitizer_build.sh "${targets[@]/#/fuzz_}"

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
# Visual readers (fuzz/fuzz_visual.cc): calib.txt, times.txt, KITTI poses,
# then vocabularies (binary, DBoW2 YAML, gzipped YAML; made here).
printf 'P0: 300 0 160 0 0 300 60 0 0 0 1 0\nP1: 300 0 160 -150 0 300 60 0 0 0 1 0\n' \
  > "$work/calib.txt"
seed visual "$work/calib.txt" 0
seed visual "$work/times.txt" 1
seed visual "$data/kitti_small.txt" 2
{
  printf 'SLAMBOW1'
  printf '\x02\x00\x00\x00\x01\x00\x00\x00\x20\x00\x00\x00\x03\x00\x00\x00'
  for node in 1 2; do
    printf '\x00\x00\x00\x00'                  # Parent: the root.
    printf '\x00\x00\x00\x00\x00\x00\xf0\x3f'  # Weight 1.0.
    head -c 32 /dev/zero | tr '\0' "\\$((node + 1))"
  done
} > "$work/voc.bin"
seed visual "$work/voc.bin" 3
descriptor="$(printf '7 %.0s' $(seq 32))"
cat > "$work/voc.yml" <<YAML
%YAML:1.0
---
vocabulary:
   k: 2
   L: 1
   scoringType: 0
   weightingType: 0
   nodes:
      - { nodeId:1, parentId:0, weight:1., descriptor:"${descriptor% }" }
      - { nodeId:2, parentId:0, weight:0.5, descriptor:"${descriptor% }" }
   words:
      - { wordId:0, nodeId:1 }
      - { wordId:1, nodeId:2 }
YAML
seed visual "$work/voc.yml" 4
gzip -c "$work/voc.yml" > "$work/voc.yml.gz"
seed visual "$work/voc.yml.gz" 5
for f in configs/*.yaml configs/benchmarks/*.yaml; do
  for selector in 0 1 2 3 4; do seed config "$f" "$selector"; done
done

# The targets write each input to a scratch file: in memory when possible.
fuzz_tmp="${TMPDIR:-/tmp}"
if [ -d /dev/shm ] && [ -w /dev/shm ]; then fuzz_tmp=/dev/shm; fi

# fuzz_one TARGET: runs fuzz_TARGET for $seconds; prints its summary line.
fuzz_one() {
  local target="$1" log="$work/$1.log" units
  mkdir -p "$work/$target/corpus"
  if TMPDIR="$fuzz_tmp" "$build/fuzz/fuzz_$target" -max_total_time="$seconds" \
      -timeout=10 -rss_limit_mb=2048 -max_len=16384 -print_final_stats=1 \
      -artifact_prefix="$artifacts/" "$work/$target/corpus" \
      "$work/$target/seeds" > "$log" 2>&1; then
    units="$(grep -E '^stat::number_of_executed_units' "$log" | awk '{print $2}')"
    echo "  ok      fuzz_$target (${units:-?} inputs in ${seconds} s)"
  else
    touch "$work/$target.failed"
    echo "  FAILED  fuzz_$target"
    tail -n 40 "$log"
    return 1
  fi
}
export -f fuzz_one
export work build seconds artifacts fuzz_tmp

echo "fuzz: ${#targets[@]} targets, ${seconds} s each, ${jobs} at a time"
start=$SECONDS
printf '%s\n' "${targets[@]}" | xargs -P "$jobs" -I{} bash -c 'fuzz_one {}' ||
  true
echo "fuzz: took $((SECONDS - start)) s"
failed=()
for target in "${targets[@]}"; do
  if [ -e "$work/$target.failed" ]; then failed+=("$target"); fi
done
if [ ${#failed[@]} -gt 0 ]; then
  echo "fuzz: FAILED: ${failed[*]} (inputs in $artifacts)"
  exit 1
fi
echo "fuzz: all targets ran ${seconds} s without a finding"
