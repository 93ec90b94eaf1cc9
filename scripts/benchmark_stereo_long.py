#!/usr/bin/python3
"""Long-run benchmark of the stereo pipeline: plays the KITTI 06 half
excerpt (51 frames) back and forth (0..50..0..50..) up to --frames frames
(default 2000) through `slam run` (configs/kitti_stereo.yaml, loop closure
off) and prints one table (markdown and CSV): per block of 200 frames the
median milliseconds per frame of the whole pipeline, local BA, features and
tracking (timings.csv), then the peak resident memory of the run. The
per-frame cost must stay flat: the script fails (exit 1) when the last
block's median is more than --max_growth (default 1.5) times the first's.

The played sequence is a temporary folder of symbolic links to the
excerpt's images (never a copy), with its calib.txt.

Usage: scripts/benchmark_stereo_long.py [--datasets DIR] [--frames 2000]
       [--block 200] [--slam build/slam] [--max_growth 1.5]
Runs with Debian's python3."""

import argparse
import csv
import os
import statistics
import subprocess
import sys
import tempfile
import time

import run_benchmarks

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))

COLUMNS = [("frames", "frames"), ("total", "median ms/frame"),
           ("local_ba", "local BA ms"), ("features", "features + matching ms"),
           ("tracking", "tracking ms"), ("keyframes", "keyframes")]


def ping_pong(n, frames):
    """Frame indices 0..n-1..0..n-1.. up to `frames` of them."""
    order, k, step = [], 0, 1
    while len(order) < frames:
        order.append(k)
        if not 0 <= k + step < n:
            step = -step
        k += step
    return order


def make_sequence(source, dest, frames):
    names = sorted(os.listdir(os.path.join(source, "image_0")))
    for side in ("image_0", "image_1"):
        os.makedirs(os.path.join(dest, side))
    ext = os.path.splitext(names[0])[1]
    for i, k in enumerate(ping_pong(len(names), frames)):
        for side in ("image_0", "image_1"):
            os.symlink(os.path.join(source, side, names[k]),
                       os.path.join(dest, side, "%06d%s" % (i, ext)))
    os.symlink(os.path.join(source, "calib.txt"),
               os.path.join(dest, "calib.txt"))


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--datasets", default=os.environ.get(
        "SLAM_DATASETS", os.path.join(ROOT, "..", "shared", "datasets")))
    parser.add_argument("--frames", type=int, default=2000)
    parser.add_argument("--block", type=int, default=200)
    parser.add_argument("--max_growth", type=float, default=1.5)
    parser.add_argument("--slam", default="")
    parser.add_argument("--config",
                        default=os.path.join(ROOT, "configs",
                                             "kitti_stereo.yaml"))
    args = parser.parse_args()
    slam = run_benchmarks.find_slam(args.slam)
    source = os.path.join(os.path.abspath(args.datasets), "stereo_kitti06_half")
    if not os.path.isdir(source):
        sys.exit(source + ": not found (--datasets or $SLAM_DATASETS)")
    with tempfile.TemporaryDirectory() as tmp:
        sequence = os.path.join(tmp, "seq")
        make_sequence(source, sequence, args.frames)
        with open(args.config) as f:
            text = f.read()
        config = os.path.join(tmp, "long.yaml")
        with open(config, "w") as f:
            f.write(text.replace(
                "run:\n", "run:\n  loop_closure:\n    enabled: false\n", 1)
                .replace("sequence: stereo_kitti06_half",
                         "sequence: " + sequence))
        out = os.path.join(tmp, "out")
        start = time.monotonic()
        log_path = os.path.join(tmp, "log.txt")
        with open(log_path, "w") as log:
            # wait4: the peak memory of this process alone.
            proc = subprocess.Popen([slam, "run", "--config", config,
                                     "--output_dir", out],
                                    stdout=log, stderr=subprocess.STDOUT)
            _, status, usage = os.wait4(proc.pid, 0)
            proc.returncode = 0  # Reaped here.
        seconds = time.monotonic() - start
        if status != 0:
            with open(log_path) as f:
                sys.exit("slam run failed:\n" + f.read()[-3000:])
        with open(os.path.join(out, "timings.csv")) as f:
            rows = [r for r in csv.reader(f) if r and not r[0].startswith("#")]
    # frame, read, features, matching, tracking, local_ba, total, keyframe.
    table = []
    for b in range(0, len(rows), args.block):
        block = rows[b:b + args.block]
        col = lambda i: round(statistics.median(float(r[i]) for r in block), 1)
        table.append({
            "frames": "%d-%d" % (b, b + len(block) - 1),
            "total": col(6), "local_ba": col(5),
            "features": round(col(2) + col(3), 1), "tracking": col(4),
            "keyframes": sum(int(r[7]) for r in block)})
    markdown, csv_text = run_benchmarks.tables(table, COLUMNS)
    print(markdown)
    print(csv_text)
    growth = table[-1]["total"] / table[0]["total"]
    print("%d frames in %.1f s; peak resident memory %.0f MB; last block's "
          "median / first block's: %.2f" %
          (len(rows), seconds, usage.ru_maxrss / 1024.0, growth))
    if growth > args.max_growth:
        print("FAILED: the per-frame median grew by more than %.2fx" %
              args.max_growth)
        sys.exit(1)


if __name__ == "__main__":
    main()
