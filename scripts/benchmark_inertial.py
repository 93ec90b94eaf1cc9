#!/usr/bin/python3
"""Inertial benchmark: runs `slam inertial` (sliding window and batch) on the
entries of configs/benchmarks/inertial.yaml and prints one table as markdown
and CSV: ATE (position RMSE, no alignment) of the window's fixed-lag
estimate, of its real-time (filter) estimate and of the batch, their ratio,
the rotation APE (RMSE, deg, no alignment) of the real-time estimate, when
the yaw became known (s after the start; empty when never),
median and 99th-percentile per-update time of the window against the target,
the batch time, and with ground truth that has biases (`gt: input` entries,
simulated runs) the mean NEES of the window's real-time estimate after the
first 10 s (position 3, pose 6, bias 6 dof expected, the bias also as gyro
and accelerometer biases, 3 each, and over the keyframes after the yaw became
known alone; pose also after the yaw-only alignment of the reference, see
apps/inertial_consistency_report.h).
An entry's `config:` (a file of configs/) gives its base `inertial:`
settings, the entry's own `inertial:` keys go over them.

Usage: scripts/benchmark_inertial.py [--datasets DIR] [--slam build/apps/slam]
       [--csv out.csv] [--md out.md] [--only SUBSTRING...]
Runs with Debian's python3 (python3-yaml); table output and the lookup of the
slam binary are shared with scripts/run_benchmarks.py."""

import argparse
import json
import os
import subprocess
import sys
import tempfile

import yaml

import run_benchmarks

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))

COLUMNS = [
    ("name", "run"), ("keyframes", "keyframes"), ("window_size", "window"),
    ("ate_window", "ATE window m"), ("ate_filter", "ATE filter m"),
    ("ate_batch", "ATE batch m"), ("ratio", "window/batch"),
    ("rot_filter", "rotation filter deg"),
    ("rot_after_yaw", "rotation filter after yaw and 10 s deg"),
    ("yaw_known_s", "yaw known s"),
    ("nees_position", "NEES pos"), ("nees_pose", "NEES pose"),
    ("nees_pose_yaw", "NEES pose yaw-aligned"), ("nees_bias", "NEES bias"),
    ("nees_gyro_bias", "NEES gyro bias"), ("nees_accel_bias", "NEES accel bias"),
    ("nees_bias_after_yaw", "NEES bias after yaw"),
    ("median_ms", "update median ms"), ("p99_ms", "update p99 ms"),
    ("target_ms", "target ms"), ("batch_s", "batch s"), ("ok", "ok"),
]


def run(cmd):
    proc = subprocess.run(cmd, capture_output=True, text=True)
    if proc.returncode != 0:
        raise RuntimeError("%s failed (%d):\n%s%s" % (
            " ".join(cmd), proc.returncode, proc.stdout, proc.stderr))
    return proc.stdout


def run_entry(entry, args, tmp, index):
    work = os.path.join(tmp, str(index))
    os.makedirs(work)
    inertial = {}
    if "config" in entry:
        with open(os.path.join(ROOT, entry["config"])) as f:
            inertial = dict((yaml.safe_load(f) or {}).get("inertial", {}))
    inertial.update(entry.get("inertial", {}))
    config = {"inertial": inertial, "eval": {"align": "none"}}
    if "simulate" in entry:
        sim = dict(entry["simulate"])
        config["simulate"] = {"world": {"type": "inertial"}}
        if "seed" in sim:
            config["simulate"]["seed"] = sim.pop("seed")
        config["simulate"]["inertial"] = sim
    config_path = os.path.join(work, "config.yaml")
    with open(config_path, "w") as f:
        yaml.safe_dump(config, f)
    if "simulate" in entry:
        data = os.path.join(work, "sim")
        run([args.slam, "simulate", "--config", config_path, "-o", data])
        gt = ["--gt", "input"]
    else:
        data = os.path.join(args.datasets, entry["input"])
        if not os.path.exists(data):
            print("skip %s: %s not found" % (entry["name"], data),
                  file=sys.stderr)
            return None
        gt = ["--gt", entry["gt"]] if "gt" in entry else []
    report_path = os.path.join(work, "report.json")
    out = run([args.slam, "inertial", "-i", data, "-o",
               os.path.join(work, "out"), "--config", config_path,
               "--report", report_path] + gt)
    with open(report_path) as f:
        report = json.load(f)
    window = report.get("window", {})
    row = {"name": entry["name"],
           "keyframes": report.get("batch", {}).get("keyframes"),
           "window_size": window.get("window_size"),
           "median_ms": window.get("median_ms"),
           "p99_ms": window.get("p99_ms"),
           "target_ms": args.target_ms,
           "batch_s": report.get("batch", {}).get("total_s")}
    evaluation = report.get("evaluation", {})
    for key, name in (("ate_window", "window"), ("ate_filter", "window_filter"),
                      ("ate_batch", "batch")):
        if name in evaluation:
            row[key] = evaluation[name]["ape_translation"]["rmse"]
    if "window_filter" in evaluation:
        row["rot_filter"] = \
            evaluation["window_filter"]["ape_rotation"]["rmse"]
    init = report.get("initialization", {})
    if init.get("yaw_observable"):
        row["yaw_known_s"] = init.get("yaw_observable_after_s")
    nees = evaluation.get("window_filter", {}).get("nees")
    if nees:
        row["nees_position"] = nees["position"]["mean"]
        row["nees_pose"] = nees["pose"]["mean"]
        row["nees_pose_yaw"] = nees["yaw_aligned"]["pose"]["mean"]
        row["nees_bias"] = nees["bias"]["mean"]
        # Older builds (--slam) report the bias as one block only.
        for key in ("gyro_bias", "accel_bias"):
            if key in nees:
                row["nees_" + key] = nees[key]["mean"]
        if "after_yaw" in nees:
            row["nees_bias_after_yaw"] = nees["after_yaw"]["bias"]["mean"]
            row["rot_after_yaw"] = nees["after_yaw"]["rotation_rmse_deg"]
    if row.get("ate_window") is not None and row.get("ate_batch"):
        row["ratio"] = row["ate_window"] / row["ate_batch"]
    ok = row["median_ms"] is not None and row["p99_ms"] is not None and \
        row["median_ms"] < args.target_ms and row["p99_ms"] < args.target_ms
    row["ok"] = "yes" if ok else "no"
    print("%s: %s" % (entry["name"], out.strip().splitlines()[-1]),
          file=sys.stderr)
    return row


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--datasets", default=os.environ.get(
        "SLAM_DATASETS", os.path.join(ROOT, "..", "shared", "datasets")))
    parser.add_argument("--config", default=os.path.join(
        ROOT, "configs", "benchmarks", "inertial.yaml"))
    parser.add_argument("--slam", default=None,
                        help="the slam binary (default: build/apps/slam)")
    parser.add_argument("--csv", help="also write the CSV table here")
    parser.add_argument("--md", help="also write the markdown table here")
    parser.add_argument("--only", nargs="*", help="substrings of run names")
    args = parser.parse_args()
    args.slam = run_benchmarks.find_slam(args.slam)
    with open(args.config) as f:
        config = yaml.safe_load(f)
    args.target_ms = float(config.get("target_update_ms", 5.0))
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for index, entry in enumerate(config["runs"]):
            if args.only and not any(s in entry["name"] for s in args.only):
                continue
            print("running %s ..." % entry["name"], file=sys.stderr)
            row = run_entry(entry, args, tmp, index)
            if row is not None:
                rows.append(row)
    md, csv_text = run_benchmarks.tables(rows, COLUMNS)
    print(md)
    print(csv_text)
    if args.csv:
        with open(args.csv, "w") as f:
            f.write(csv_text)
    if args.md:
        with open(args.md, "w") as f:
            f.write(md)
    print("inertial benchmark: %d runs, %d within the %.1f ms update target"
          % (len(rows), sum(r["ok"] == "yes" for r in rows), args.target_ms))
    return 0


if __name__ == "__main__":
    sys.exit(main())
