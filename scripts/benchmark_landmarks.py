#!/usr/bin/python3
"""Landmark benchmark: runs `slam optimize` on every entry of
configs/benchmarks/landmarks.yaml (Victoria Park, KITTI stereo bundle
adjustment, ...), three times each, and prints one table as markdown and
CSV: dataset, nodes, landmarks, factors, linear solver, initial and final
chi2, iterations, reprojection RMS before/after (camera factors), median
wall time and the time target.

Usage: scripts/benchmark_landmarks.py [--datasets DIR] [--runs 3]
       [--slam build/apps/slam] [--csv out.csv] [--md out.md] [--only NAME...]
Runs with Debian's python3 (python3-yaml). Table output and the lookup of
the slam binary are shared with scripts/run_benchmarks.py."""

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time

import yaml

import run_benchmarks

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))

COLUMNS = [
    ("dataset", "dataset"), ("nodes", "nodes"), ("landmarks", "landmarks"),
    ("factors", "factors"), ("linear_solver", "linear solver"),
    ("initial_chi2", "initial chi2"), ("final_chi2", "final chi2"),
    ("iterations", "iterations"), ("rms_before", "reproj. RMS before px"),
    ("rms_after", "reproj. RMS after px"), ("median_s", "median s"),
    ("target_s", "target s"), ("ok", "ok"),
]


def command(slam, entry, datasets, out_dir):
    """The slam optimize command line of an entry."""
    cmd = [slam, "optimize", "-i", os.path.join(datasets, entry["input"]),
           "-o", os.path.join(out_dir, "out.g2o"),
           "--report", os.path.join(out_dir, "report.json"), "--quiet"]
    stereo = entry.get("stereo")
    if stereo:
        cmd += ["--stereo_calibration",
                os.path.join(datasets, stereo["calibration"]),
                "--stereo_poses", os.path.join(datasets, stereo["poses"])]
    if entry.get("optimize"):
        config = os.path.join(out_dir, "config.yaml")
        with open(config, "w") as f:
            yaml.safe_dump({"optimize": entry["optimize"]}, f)
        cmd += ["--config", config]
    return cmd


def run_once(cmd, out_dir):
    start = time.perf_counter()
    proc = subprocess.run(cmd, capture_output=True, text=True)
    wall = time.perf_counter() - start
    if proc.returncode != 0:
        raise RuntimeError("%s failed (%d):\n%s%s" % (" ".join(cmd),
                           proc.returncode, proc.stdout, proc.stderr))
    with open(os.path.join(out_dir, "report.json")) as f:
        return wall, json.load(f)


def inputs(entry):
    files = [entry["input"]]
    if entry.get("stereo"):
        files += [entry["stereo"]["calibration"], entry["stereo"]["poses"]]
    return files


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--datasets", default=os.environ.get(
        "SLAM_DATASETS", os.path.join(ROOT, "..", "shared", "datasets")))
    parser.add_argument("--config", default=os.path.join(
        ROOT, "configs", "benchmarks", "landmarks.yaml"))
    parser.add_argument("--slam", default=None,
                        help="the slam binary (default: build/apps/slam)")
    parser.add_argument("--runs", type=int, default=3)
    parser.add_argument("--csv", help="also write the CSV table here")
    parser.add_argument("--md", help="also write the markdown table here")
    parser.add_argument("--only", nargs="*", help="substrings of entry names")
    args = parser.parse_args()
    args.slam = run_benchmarks.find_slam(args.slam)

    with open(args.config) as f:
        entries = yaml.safe_load(f)["datasets"]
    rows = []
    failures = 0
    with tempfile.TemporaryDirectory() as tmp:
        for entry in entries:
            name = entry["name"]
            if args.only and not any(s in name for s in args.only):
                continue
            missing = [p for p in inputs(entry)
                       if not os.path.exists(os.path.join(args.datasets, p))]
            if missing:
                print("skip %s: %s not found under %s" %
                      (name, ", ".join(missing), args.datasets),
                      file=sys.stderr)
                continue
            cmd = command(args.slam, entry, args.datasets, tmp)
            walls, report = [], None
            try:
                for _ in range(args.runs):
                    wall, report = run_once(cmd, tmp)
                    walls.append(wall)
            except RuntimeError as e:
                print(e, file=sys.stderr)
                failures += 1
                continue
            target = entry.get("target_seconds")
            bound = entry.get("max_final_chi2")
            median = statistics.median(walls)
            ok_time = target is None or median <= target
            ok_chi2 = report["converged"] and (
                bound is None or report["final_chi2"] <= bound)
            before = report.get("reprojection_rms_before")
            after = report.get("reprojection_rms_after")
            rows.append({
                "dataset": name,
                "nodes": report["nodes"],
                "landmarks": report.get("landmarks", 0),
                "factors": report["factors"],
                "linear_solver": report["linear_solver"],
                "initial_chi2": "%.10g" % report["initial_chi2"],
                "final_chi2": "%.10g" % report["final_chi2"],
                "iterations": report["iterations"],
                "rms_before": "%.4f" % before if before is not None else "",
                "rms_after": "%.4f" % after if after is not None else "",
                "median_s": "%.3f" % median,
                "target_s": "%.2f" % target if target else "",
                "ok": "yes" if ok_chi2 and ok_time else
                      ("CHI2" if not ok_chi2 else "TIME"),
            })
            print("%-36s done (%.3f s)" % (name, median), file=sys.stderr)

    if not rows:
        print("no dataset found", file=sys.stderr)
        return 1
    md_text, csv_text = run_benchmarks.tables(rows, COLUMNS)
    print(md_text)
    print(csv_text)
    if args.md:
        with open(args.md, "w") as f:
            f.write(md_text)
    if args.csv:
        with open(args.csv, "w") as f:
            f.write(csv_text)
    print("summary: %d datasets, %d ok, %d failed" %
          (len(rows), sum(r["ok"] == "yes" for r in rows), failures),
          file=sys.stderr)
    return 1 if failures or any(r["ok"] != "yes" for r in rows) else 0


if __name__ == "__main__":
    sys.exit(main())
