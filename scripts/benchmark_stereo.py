#!/usr/bin/python3
"""Stereo visual odometry benchmark: runs `slam run` on the KITTI 06 excerpt
(configs/kitti_stereo.yaml, 51 half-resolution frames, 59.86 m) a few times,
evaluates each trajectory with `slam eval` against the excerpt's poses.txt
(no alignment, RPE over one frame), and prints one table (markdown and CSV)
beside the peers measured on the same frames and the issue's targets:
end-point error (% of the path), APE rmse, RPE rmse, and the median and p95
milliseconds per frame of the whole pipeline (features, stereo matching,
tracking, local BA; median over the runs). A second table plays the
excerpt forward and back (frames 0..50..0) with and without loop closure.

Usage: scripts/benchmark_stereo.py [--datasets DIR] [--runs 3]
       [--slam build/apps/slam] [--config configs/kitti_stereo.yaml]
Runs with Debian's python3."""

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile

import run_benchmarks

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))

COLUMNS = [
    ("method", "method"), ("end", "end-point error [% of path]"),
    ("ape", "APE rmse [m], no alignment"), ("rpe", "RPE rmse [m], 1 frame"),
    ("median_ms", "median ms/frame"), ("p95_ms", "p95 ms/frame"),
]

PEERS = [
    {"method": "libviso2 (stereo, defaults)", "end": 0.81, "ape": 0.357,
     "rpe": 0.032, "median_ms": 9.8},
    {"method": "OpenCV stereo VO, no BA", "end": 1.08, "ape": 0.388,
     "rpe": 0.021, "median_ms": 40.7},
    {"method": "target", "end": 0.5, "ape": 0.25, "rpe": 0.02,
     "median_ms": 25.0},
]

LOOP_COLUMNS = [("playback", "playback 0..50..0"), ("loops", "loops acc/rej"),
                ("end_m", "end-point error [m]"), ("ape", "APE rmse [m]")]


def run(cmd):
    proc = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                          text=True)
    if proc.returncode != 0:
        sys.exit(" ".join(cmd) + " failed:\n" + proc.stdout[-1500:] +
                 proc.stderr[-1500:])
    return proc.stdout


def slam_run(slam, config, datasets, out_dir, extra=()):
    cmd = [slam, "run", "--config", config, "--output_dir", out_dir,
           "--report", os.path.join(out_dir, "report.json")] + list(extra)
    if datasets:
        cmd += ["--datasets", datasets]
    run(cmd)
    with open(os.path.join(out_dir, "report.json")) as f:
        return json.load(f)


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
    gt = os.path.join(args.datasets, "stereo_kitti06_half", "poses.txt")
    medians, p95s, row = [], [], {"method": "this backend (slam run)"}
    with tempfile.TemporaryDirectory() as tmp:
        for i in range(args.runs):
            report = slam_run(slam, args.config, args.datasets, tmp)
            medians.append(report["timing"]["median_ms"])
            p95s.append(report["timing"]["p95_ms"])
            print("run %d/%d: %.1f ms median per frame" %
                  (i + 1, args.runs, medians[-1]), file=sys.stderr)
        # The trajectory evaluated by slam eval itself.
        run([slam, "eval", "--ref", gt, "--est",
             os.path.join(tmp, "trajectory_kitti.txt"), "--format", "kitti",
             "--align", "none", "--report", os.path.join(tmp, "eval.json")])
        with open(os.path.join(tmp, "eval.json")) as f:
            ev = json.load(f)
        ev = ev.get("results", ev)
        row["ape"] = ev["ape_translation"]["rmse"]
        row["rpe"] = ev["rpe_translation"]["rmse"]
        row["end"] = report["evaluation"]["end_point_error_percent"]
        row["median_ms"] = statistics.median(medians)
        row["p95_ms"] = statistics.median(p95s)
        loop_rows = []
        for enabled in (False, True):
            extra_config = os.path.join(tmp, "fb.yaml")
            with open(args.config) as f:
                text = f.read()
            text = text.replace(
                "run:\n", "run:\n  playback: forward_backward\n"
                "  loop_closure:\n    enabled: %s\n" %
                ("true" if enabled else "false"), 1)
            with open(extra_config, "w") as f:
                f.write(text)
            r = slam_run(slam, extra_config, args.datasets,
                         os.path.join(tmp, "fb%d" % enabled))
            loop_rows.append({
                "playback": "loop closure " + ("on" if enabled else "off"),
                "loops": "%d/%d" % (r["loop_closure"]["accepted"],
                                    r["loop_closure"]["rejected"]),
                "end_m": r["evaluation"]["end_point_error_m"],
                "ape": r["evaluation"]["ape_translation"]["rmse"]})
    markdown, csv_text = run_benchmarks.tables(PEERS[:2] + [row, PEERS[2]],
                                               COLUMNS)
    print(markdown)
    print(csv_text)
    markdown, csv_text = run_benchmarks.tables(loop_rows, LOOP_COLUMNS)
    print(markdown)
    print(csv_text)


if __name__ == "__main__":
    main()
