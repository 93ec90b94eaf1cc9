#!/usr/bin/python3
"""Stereo visual odometry benchmark: runs `slam run` (configs/kitti_stereo.yaml,
only run.sequence changed) on every shared stereo sequence at full and at half
resolution, and prints one table (markdown and CSV): end-point error (% of
the path), estimated / true path length, APE rmse (no alignment), RPE rmse
over one frame (as `slam eval` computes them against the sequence's
poses.txt; empty without ground truth), keyframes, the median and p95
milliseconds per frame of the whole pipeline and the median of each stage
(features, stereo matching, tracking, local BA), and the wall time of the
whole run (start to exit, vocabulary and global BA included) per frame and
its ratio to the run's median per frame (the issue's bound: at most 2).

Sequences (under --datasets): stereo_kitti06_full (the KITTI 06 excerpt at
its original resolution; odometry layout) and
kitti_raw_2011_09_26_drive_0001_first20 (KITTI raw layout, no ground truth).
The half-resolution version of each is made on the fly by the exact 2x2 mean
(round half up) of the full-resolution images, as the shared
stereo_kitti06_half was made (its images are identical to the ones made
here), with the calibration scaled to match (fx / 2, (cx - 0.5) / 2).
Timings: median over --runs runs.

Usage: scripts/benchmark_stereo.py [--datasets DIR] [--runs 3]
       [--slam build/apps/slam] [--config configs/kitti_stereo.yaml]
Runs with Debian's python3 (python3-numpy, python3-opencv)."""

import argparse
import json
import math
import os
import shutil
import statistics
import subprocess
import sys
import tempfile
import time

import cv2
import numpy as np

import run_benchmarks

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))

COLUMNS = [
    ("sequence", "sequence"), ("resolution", "resolution"),
    ("frames", "frames"), ("keyframes", "keyframes"),
    ("end", "end-point error [% of path]"),
    ("length", "est. / true path length"),
    ("ape", "APE rmse [m], no alignment"), ("rpe", "RPE rmse [m], 1 frame"),
    ("median_ms", "median ms/frame"), ("p95_ms", "p95 ms/frame"),
    ("features_ms", "features"), ("matching_ms", "stereo matching"),
    ("tracking_ms", "tracking"), ("local_ba_ms", "local BA"),
    ("wall_ms", "whole run ms/frame"),
    ("wall_ratio", "whole run / median"),
]

SEQUENCES = [("KITTI 06 excerpt", "stereo_kitti06_full"),
             ("KITTI raw 0001 first 20", "kitti_raw_2011_09_26_drive_0001_first20")]


def run(cmd):
    proc = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                          text=True)
    if proc.returncode != 0:
        sys.exit(" ".join(cmd) + " failed:\n" + proc.stdout[-1500:] +
                 proc.stderr[-1500:])
    return proc.stdout


def half_image(path_in, path_out):
    full = cv2.imread(path_in, cv2.IMREAD_GRAYSCALE)
    if full is None:
        sys.exit(path_in + ": cannot read")
    h, w = full.shape[0] // 2 * 2, full.shape[1] // 2 * 2
    f = full[:h, :w].astype(np.uint32)
    half = (f[0::2, 0::2] + f[1::2, 0::2] + f[0::2, 1::2] + f[1::2, 1::2] +
            2) >> 2
    cv2.imwrite(path_out, half.astype(np.uint8))


def scaled_projection(numbers):
    """A 3x4 projection matrix (12 numbers) for the 2x2-mean image."""
    p = [float(x) for x in numbers]
    p[0] /= 2.0  # fx
    p[5] /= 2.0  # fy
    p[2] = (p[2] - 0.5) / 2.0  # cx: half pixel (i) covers 2i, 2i + 1.
    p[6] = (p[6] - 0.5) / 2.0
    p[3] /= 2.0  # -fx b
    return " ".join("%.12e" % x for x in p)


def make_half(src, dst):
    """The half-resolution copy of a sequence folder (either layout)."""
    raw = os.path.isdir(os.path.join(src, "image_00", "data"))
    sides = ([("image_00/data", "image_00/data"),
              ("image_01/data", "image_01/data")] if raw else
             [("image_0", "image_0"), ("image_1", "image_1")])
    for s, d in sides:
        os.makedirs(os.path.join(dst, d))
        for name in sorted(os.listdir(os.path.join(src, s))):
            half_image(os.path.join(src, s, name), os.path.join(dst, d, name))
    if raw:
        shutil.copy(os.path.join(src, "image_00", "timestamps.txt"),
                    os.path.join(dst, "image_00", "timestamps.txt"))
        lines = []
        with open(os.path.join(src, "calib_cam_to_cam.txt")) as f:
            for line in f:
                tokens = line.split()
                if tokens and tokens[0] in ("P_rect_00:", "P_rect_01:"):
                    lines.append(tokens[0] + " " +
                                 scaled_projection(tokens[1:13]))
        with open(os.path.join(dst, "calib_cam_to_cam.txt"), "w") as f:
            f.write("\n".join(lines) + "\n")
    else:
        with open(os.path.join(src, "calib.txt")) as f:
            rows = [line.split() for line in f if line.split()]
        out = []
        for k, tokens in enumerate(rows[:2]):
            numbers = tokens[1:13] if tokens[0].endswith(":") else tokens[:12]
            out.append("P%d: %s" % (k, scaled_projection(numbers)))
        with open(os.path.join(dst, "calib.txt"), "w") as f:
            f.write("\n".join(out) + "\n")
        for extra in ("poses.txt", "times.txt"):
            if os.path.exists(os.path.join(src, extra)):
                shutil.copy(os.path.join(src, extra), os.path.join(dst, extra))


def read_kitti_positions(path):
    positions = []
    with open(path) as f:
        for line in f:
            v = [float(x) for x in line.split()]
            if len(v) == 12:
                positions.append((v[3], v[7], v[11]))
    return positions


def path_length(positions):
    return sum(math.dist(a, b) for a, b in zip(positions, positions[1:]))


def benchmark(slam, config, sequence_dir, runs, tmp):
    """One row: the accuracy of the first run, timings' medians over runs."""
    text = open(config).read()
    cfg = os.path.join(tmp, "run.yaml")
    lines = []
    for line in text.splitlines():
        if line.strip().startswith("sequence:"):
            line = line[:len(line) - len(line.lstrip())] + "sequence: " + \
                sequence_dir
        lines.append(line)
    with open(cfg, "w") as f:
        f.write("\n".join(lines) + "\n")
    stats = {k: [] for k in ("median_ms", "p95_ms", "features_ms",
                             "matching_ms", "tracking_ms", "local_ba_ms",
                             "wall_ms", "wall_ratio")}
    row = {}
    for i in range(runs):
        out = os.path.join(tmp, "out%d" % i)
        start = time.monotonic()
        run([slam, "run", "--config", cfg, "--output_dir", out,
             "--report", os.path.join(out, "report.json")])
        wall = time.monotonic() - start
        with open(os.path.join(out, "report.json")) as f:
            report = json.load(f)
        t = report["timing"]
        frames = report["frames"]
        stats["median_ms"].append(t["median_ms"])
        stats["p95_ms"].append(t["p95_ms"])
        stats["features_ms"].append(t["features"]["median_ms"])
        stats["matching_ms"].append(t["stereo_matching"]["median_ms"])
        stats["tracking_ms"].append(t["tracking"]["median_ms"])
        stats["local_ba_ms"].append(t["local_ba"]["median_ms"])
        stats["wall_ms"].append(1000.0 * wall / frames)
        # Per run, then the median: the run's own median per frame is the
        # yardstick (the issue asks for at most 2), so the ratio holds on a
        # machine whose speed drifts between runs.
        stats["wall_ratio"].append(stats["wall_ms"][-1] / t["median_ms"])
        print("  run %d/%d: %.1f ms median per frame, %.1f ms wall per frame"
              % (i + 1, runs, t["median_ms"], stats["wall_ms"][-1]),
              file=sys.stderr)
        if i == 0:
            row["frames"] = frames
            row["keyframes"] = report["keyframes"]
            gt = os.path.join(sequence_dir, "poses.txt")
            if os.path.exists(gt):
                est = os.path.join(out, "trajectory_kitti.txt")
                ev_path = os.path.join(tmp, "eval.json")
                run([slam, "eval", "--ref", gt, "--est", est, "--format",
                     "kitti", "--align", "none", "--report", ev_path])
                with open(ev_path) as f:
                    ev = json.load(f)
                ev = ev.get("results", ev)
                row["ape"] = ev["ape_translation"]["rmse"]
                row["rpe"] = ev["rpe_translation"]["rmse"]
                row["end"] = report["evaluation"]["end_point_error_percent"]
                ref = read_kitti_positions(gt)
                row["length"] = (path_length(read_kitti_positions(est)) /
                                 path_length(ref))
    for k, values in stats.items():
        row[k] = statistics.median(values)
    return row


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--datasets", default=os.environ.get(
        "SLAM_DATASETS", os.path.join(ROOT, "..", "shared", "datasets")))
    parser.add_argument("--runs", type=int, default=3)
    parser.add_argument("--slam", default="")
    parser.add_argument("--config",
                        default=os.path.join(ROOT, "configs",
                                             "kitti_stereo.yaml"))
    args = parser.parse_args()
    slam = run_benchmarks.find_slam(args.slam)
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for label, name in SEQUENCES:
            full = os.path.join(os.path.abspath(args.datasets), name)
            if not os.path.isdir(full):
                print("%s: not found, skipped" % full, file=sys.stderr)
                continue
            half = os.path.join(tmp, name + "_half")
            make_half(full, half)
            for resolution, folder in (("full", full), ("half", half)):
                print("%s, %s resolution" % (label, resolution),
                      file=sys.stderr)
                work = os.path.join(tmp, "%s_%s_work" % (name, resolution))
                os.makedirs(work)
                row = benchmark(slam, args.config, folder, args.runs, work)
                row["sequence"] = label
                row["resolution"] = "%s" % resolution
                rows.append(row)
    markdown, csv_text = run_benchmarks.tables(rows, COLUMNS)
    print(markdown)
    print(csv_text)


if __name__ == "__main__":
    main()
