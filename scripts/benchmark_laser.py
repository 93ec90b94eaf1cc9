#!/usr/bin/python3
"""Laser SLAM benchmark: runs `slam run` on the ACES CARMEN log
(configs/aces.yaml) a few times and prints one table (markdown and CSV):
keyframes, loop closures, the relation error of Kuemmerle et al. 2009
against the published Cartographer figures, and the median wall and user
time against the 20 s target.

Usage: scripts/benchmark_laser.py [--datasets DIR] [--runs 3]
       [--slam build/apps/slam] [--config configs/aces.yaml]
Runs with Debian's python3; table output and the lookup of the slam binary
are shared with scripts/run_benchmarks.py."""

import argparse
import os
import re
import resource
import statistics
import subprocess
import sys
import tempfile
import time

import run_benchmarks

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))

COLUMNS = [
    ("config", "config"), ("keyframes", "keyframes"),
    ("closures", "closures prop/acc/rej"),
    ("trans", "trans. error [m]"), ("rot", "rot. error [deg]"),
    ("cartographer", "Cartographer"), ("median_s", "median wall s"),
    ("user_s", "median user s"), ("target_s", "target s"), ("ok", "ok"),
]

SUMMARY = re.compile(
    r"(\d+) keyframes.*loop closures: (\d+) proposed, (\d+) accepted, "
    r"(\d+) rejected")
RELATION = re.compile(
    r"translation ([\d.]+) \+- ([\d.]+) m .*rotation ([\d.]+) \+- ([\d.]+) deg")


def run_once(slam, config, datasets, out_dir):
    cmd = [slam, "run", "--config", config, "--output_dir", out_dir]
    if datasets:
        cmd += ["--datasets", datasets]
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    start = time.monotonic()
    proc = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                          text=True)
    wall = time.monotonic() - start
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    if proc.returncode != 0:
        sys.exit("slam run failed:\n" + proc.stderr[-2000:])
    return proc.stdout, wall, after.ru_utime - before.ru_utime


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--datasets", default="")
    parser.add_argument("--runs", type=int, default=3)
    parser.add_argument("--slam", default="")
    parser.add_argument("--config",
                        default=os.path.join(ROOT, "configs", "aces.yaml"))
    args = parser.parse_args()
    slam = run_benchmarks.find_slam(args.slam)
    walls, users, text = [], [], ""
    with tempfile.TemporaryDirectory() as out_dir:
        for i in range(args.runs):
            text, wall, user = run_once(slam, args.config, args.datasets,
                                        out_dir)
            walls.append(wall)
            users.append(user)
            print("run %d/%d: %.2f s wall, %.2f s user" %
                  (i + 1, args.runs, wall, user), file=sys.stderr)
    summary = SUMMARY.search(text)
    relation = RELATION.search(text)
    row = {"config": os.path.relpath(args.config, ROOT),
           "cartographer": "0.0375+-0.0426 m, 0.373+-0.469 deg",
           "median_s": statistics.median(walls),
           "user_s": statistics.median(users), "target_s": 20.0}
    if summary:
        row["keyframes"] = summary.group(1)
        row["closures"] = "/".join(summary.group(i) for i in (2, 3, 4))
    if relation:
        row["trans"] = "%s +- %s" % (relation.group(1), relation.group(2))
        row["rot"] = "%s +- %s" % (relation.group(3), relation.group(4))
    row["ok"] = "yes" if row["median_s"] <= 20.0 else "no"
    markdown, csv_text = run_benchmarks.tables([row], COLUMNS)
    print(markdown)
    print(csv_text)
    print("benchmark_laser: %d runs, median %.2f s wall" %
          (args.runs, row["median_s"]))


if __name__ == "__main__":
    main()
