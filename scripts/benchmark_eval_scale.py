#!/usr/bin/python3
"""Scale benchmark of `slam eval`: writes a synthetic reference and estimate
of N poses (TUM and KITTI text, 100 Hz, stamps with 6 decimals as TUM files
have them), runs `slam eval` on them (median of --repeat runs) and prints one
table: poses, format, wall time reading the two files and evaluating (APE,
RPE 1 frame, SE(3) Umeyama), from the JSON report's timing, and the CPU time
(user + system) of the whole process, which depends less on the load of a
shared machine.

Usage: scripts/benchmark_eval_scale.py [--poses 1000000] [--repeat 3]
       [--slam build/apps/slam] [--baseline OTHER_SLAM_BINARY]
--baseline runs a second binary on the same files (e.g. a build of an older
commit) and adds its times, for a before/after comparison.
Runs with Debian's /usr/bin/python3 (no other package)."""

import argparse
import json
import math
import os
import resource
import statistics
import subprocess
import sys
import tempfile

import run_benchmarks


def write_files(directory, n):
    """ref/est in TUM and KITTI form: a smooth 3D path, the estimate with a
    small drift and rotation noise."""
    paths = {k: os.path.join(directory, k) for k in
             ("ref.tum", "est.tum", "ref.kitti", "est.kitti")}
    files = {k: open(p, "w") for k, p in paths.items()}
    for i in range(n):
        s = 1e-3 * i
        t = 1600000000.0 + 0.01 * i
        for name, drift in (("ref", 0.0), ("est", 1e-6 * i)):
            x = 50.0 * math.cos(s) + drift
            y = 30.0 * math.sin(1.3 * s)
            z = 2.0 * math.sin(0.7 * s)
            yaw = s + (1e-3 * math.sin(0.1 * i) if drift else 0.0)
            c, sn = math.cos(yaw), math.sin(yaw)
            files[name + ".tum"].write(
                "%.6f %.6f %.6f %.6f 0 0 %.9f %.9f\n" %
                (t, x, y, z, math.sin(yaw / 2), math.cos(yaw / 2)))
            files[name + ".kitti"].write(
                "%.6e %.6e 0 %.6e %.6e %.6e 0 %.6e 0 0 1 %.6e\n" %
                (c, -sn, x, sn, c, y, z))
    for f in files.values():
        f.close()
    return paths


def run(slam, ref, est, fmt, workdir, repeat):
    report = os.path.join(workdir, "report.json")
    reads, evals, cpus = [], [], []
    for _ in range(repeat):
        before = resource.getrusage(resource.RUSAGE_CHILDREN)
        cmd = [slam, "eval", "--ref", ref, "--est", est, "--format", fmt,
               "--report", report]
        result = subprocess.run(cmd, stdout=subprocess.PIPE,
                                stderr=subprocess.STDOUT, text=True)
        after = resource.getrusage(resource.RUSAGE_CHILDREN)
        cpus.append(after.ru_utime - before.ru_utime + after.ru_stime -
                    before.ru_stime)
        if result.returncode != 0:
            raise RuntimeError("%s failed: %s" % (" ".join(cmd),
                                                  result.stdout[-500:]))
        with open(report) as f:
            timing = json.load(f)["timing"]
        reads.append(timing["read_ms"] / 1e3)
        evals.append(timing["evaluate_ms"] / 1e3)
    return (statistics.median(reads), statistics.median(evals),
            statistics.median(cpus))


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--poses", type=int, default=1000000)
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--slam", default="")
    parser.add_argument("--baseline", default="")
    args = parser.parse_args()
    slam = run_benchmarks.find_slam(args.slam)
    with tempfile.TemporaryDirectory() as workdir:
        sys.stderr.write("writing 2 x %d poses (TUM, KITTI)...\n" % args.poses)
        paths = write_files(workdir, args.poses)
        rows = []
        for fmt in ("tum", "kitti"):
            ref, est = paths["ref." + fmt], paths["est." + fmt]
            sys.stderr.write("slam eval, %s...\n" % fmt)
            read_s, eval_s, cpu_s = run(slam, ref, est, fmt, workdir,
                                        args.repeat)
            row = {"poses": args.poses, "format": fmt, "read_s": read_s,
                   "eval_s": eval_s, "cpu_s": cpu_s}
            if args.baseline:
                b_read, b_eval, b_cpu = run(args.baseline, ref, est, fmt,
                                            workdir, args.repeat)
                row.update(base_read_s=b_read, base_eval_s=b_eval,
                           base_cpu_s=b_cpu, speedup=b_read / read_s)
            rows.append(row)
    columns = [("poses", "poses"), ("format", "format"),
               ("read_s", "read [s]"), ("eval_s", "evaluate [s]"),
               ("cpu_s", "process CPU [s]")]
    if args.baseline:
        columns += [("base_read_s", "baseline read [s]"),
                    ("base_eval_s", "baseline evaluate [s]"),
                    ("base_cpu_s", "baseline CPU [s]"),
                    ("speedup", "read speed-up")]
    for row in rows:  # Seconds to the millisecond, the ratio to 0.1.
        for key in list(row):
            if isinstance(row[key], float):
                row[key] = ("%.1f" if key == "speedup" else "%.3f") % row[key]
    md, _ = run_benchmarks.tables(rows, columns)
    print(md, end="")


if __name__ == "__main__":
    main()
