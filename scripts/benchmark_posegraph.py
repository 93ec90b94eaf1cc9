#!/usr/bin/python3
"""Pose-graph benchmark: runs `slam optimize` (default settings) on every
pose graph listed in configs/benchmarks/posegraph.yaml, three times each, and
prints one table as markdown and CSV: dataset, nodes, edges, init, initial
chi2, final chi2, gap to the known optimum, iterations (against an upper
bound where the entry sets max_iterations: the slow-tail cases), median wall
time and the time target.

An entry with rotation_noise: SIGMA (and seed) runs on a copy of its g2o
file, written to a temporary folder, whose EDGE_SE2 angle measurements get
Gaussian noise of SIGMA rad (as Carlone's M3500a/b/c variants): graphs where
LM alone crawls after rejecting its first steps.

With --certify, one more run per graph with `slam optimize --certify`
gives the certification time (and whether it certified) beside the solve
time of the default runs, and its ratio to that run's own solve time (graphs
whose solve takes over 0.01 s). When a `g2o` binary is on the PATH it is timed
on the same file (20 iterations, CHOLMOD, OpenMP off).

Usage: scripts/benchmark_posegraph.py [--datasets DIR] [--runs 3]
       [--slam build/slam] [--csv out.csv] [--md out.md] [--only NAME...]
       [--certify]
Runs with Debian's python3 (python3-yaml). Table output and the lookup of
the slam binary are shared with scripts/run_benchmarks.py."""

import argparse
import json
import os
import random
import shutil
import statistics
import subprocess
import sys
import tempfile
import time

import yaml

import run_benchmarks

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))

COLUMNS = [
    ("dataset", "dataset"), ("nodes", "nodes"), ("edges", "edges"),
    ("init", "init"), ("initial_chi2", "initial chi2"),
    ("final_chi2", "final chi2"), ("optimum", "optimum"),
    ("rel_gap", "rel. gap"), ("iterations", "iterations"),
    ("max_iterations", "max it."),
    ("median_s", "median s"), ("target_s", "target s"),
    ("solve_s", "solve s"), ("jacobian_s", "of which Jacobians s"),
    ("linear_s", "linear solver s"), ("library", "sparse library"),
    ("certify_s", "certify s"), ("certify_ratio", "certify / solve"),
    ("certified", "certified"), ("g2o_s", "g2o s"), ("ok", "ok"),
]


def rotation_noise_variant(path, sigma, seed, out_dir):
    """Copy of a 2D g2o file with N(0, sigma^2) added to every EDGE_SE2
    angle measurement (deterministic for a seed)."""
    rng = random.Random(seed)
    out = os.path.join(out_dir, "noisy_%g_%d_%s" % (sigma, seed,
                                                    os.path.basename(path)))
    with open(path) as f, open(out, "w") as g:
        for line in f:
            t = line.split()
            if t and t[0] == "EDGE_SE2":
                t[5] = repr(float(t[5]) + rng.gauss(0.0, sigma))
            g.write(" ".join(t) + "\n")
    return out


# g2o's command-line tool, when one is on the PATH (Debian 12 ships no g2o
# package, neither the library nor the CLI): 20 Gauss-Newton iterations, CHOLMOD,
# OpenMP off (faster on 2 cores), whole process timed.
G2O = shutil.which("g2o")


def run_g2o(path, out_dir):
    out = os.path.join(out_dir, "g2o_out.g2o")
    env = dict(os.environ, OMP_NUM_THREADS="1", OMP_MAX_ACTIVE_LEVELS="0")
    start = time.perf_counter()
    proc = subprocess.run([G2O, "-i", "20", "-solver", "gn_var_cholmod",
                           "-o", out, path], capture_output=True, env=env)
    wall = time.perf_counter() - start
    return wall if proc.returncode == 0 else None


def run_once(slam, path, out_dir, extra):
    out = os.path.join(out_dir, "out" + os.path.splitext(path)[1])
    report = os.path.join(out_dir, "report.json")
    cmd = [slam, "optimize", "-i", path, "-o", out, "--report", report,
           "--quiet"] + extra
    start = time.perf_counter()
    proc = subprocess.run(cmd, capture_output=True, text=True)
    wall = time.perf_counter() - start
    if proc.returncode != 0:
        raise RuntimeError("%s failed (%d):\n%s%s" % (" ".join(cmd),
                           proc.returncode, proc.stdout, proc.stderr))
    with open(report) as f:
        return wall, json.load(f)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--datasets", default=os.environ.get(
        "SLAM_DATASETS", os.path.join(ROOT, "..", "shared", "datasets")))
    parser.add_argument("--config", default=os.path.join(
        ROOT, "configs", "benchmarks", "posegraph.yaml"))
    parser.add_argument("--slam", default=None,
                        help="the slam binary (default: build/apps/slam)")
    parser.add_argument("--runs", type=int, default=3)
    parser.add_argument("--csv", help="also write the CSV table here")
    parser.add_argument("--md", help="also write the markdown table here")
    parser.add_argument("--only", nargs="*", help="substrings of file names")
    parser.add_argument("--certify", action="store_true",
                        help="one more run with --certify per graph: "
                        "certification time beside the solve time")
    parser.add_argument("--extra", default="",
                        help="extra flags for slam optimize, e.g. '--init chordal'")
    args = parser.parse_args()
    args.slam = run_benchmarks.find_slam(args.slam)

    with open(args.config) as f:
        entries = yaml.safe_load(f)["datasets"]
    rows = []
    failures = 0
    with tempfile.TemporaryDirectory() as tmp:
        for entry in entries:
            name = entry["file"]
            if args.only and not any(s in name for s in args.only):
                continue
            path = os.path.join(args.datasets, name)
            if not os.path.exists(path):
                print("skip %s: not found under %s" % (name, args.datasets),
                      file=sys.stderr)
                continue
            label = os.path.basename(name)
            if entry.get("rotation_noise"):
                sigma = entry["rotation_noise"]
                path = rotation_noise_variant(path, sigma,
                                              entry.get("seed", 1), tmp)
                label += " + %g rad rotation noise" % sigma
            walls, report = [], None
            try:
                for _ in range(args.runs):
                    wall, report = run_once(args.slam, path, tmp,
                                            args.extra.split())
                    walls.append(wall)
            except RuntimeError as e:
                print(e, file=sys.stderr)
                failures += 1
                continue
            certificate = None
            if args.certify:
                try:
                    _, cert_report = run_once(
                        args.slam, path, tmp,
                        args.extra.split() + ["--certify"])
                    certificate = cert_report.get("certificate")
                except RuntimeError as e:
                    print(e, file=sys.stderr)
            g2o_s = run_g2o(path, tmp) if G2O else None
            optimum = entry.get("optimum")
            final = report["final_chi2"]
            gap = (final - optimum) / optimum if optimum else None
            target = entry.get("target_seconds")
            median = statistics.median(walls)
            ok_chi2 = gap is None or gap <= 1e-6
            ok_time = target is None or median <= target
            max_it = entry.get("max_iterations")
            ok_it = max_it is None or report["iterations"] <= max_it
            rows.append({
                "dataset": label,
                "nodes": report["nodes"],
                "edges": report["factors"],
                "init": report["init"],
                "initial_chi2": "%.10g" % report["initial_chi2"],
                "final_chi2": "%.10g" % final,
                "optimum": "%.10g" % optimum if optimum else "",
                "rel_gap": "%.1e" % gap if gap is not None else "",
                "iterations": report["iterations"],
                "max_iterations": max_it if max_it is not None else "",
                "median_s": "%.3f" % median,
                "target_s": "%.2f" % target if target else "",
                "solve_s": "%.3f" % report["solve_seconds"],
                "jacobian_s": "%.3f" % report["solve_breakdown"][
                    "jacobian_seconds"] if "solve_breakdown" in report
                    else "",
                "linear_s": "%.3f" % report["solve_breakdown"][
                    "linear_solver_seconds"] if "solve_breakdown" in report
                    else "",
                "library": report.get("sparse_library", ""),
                "certify_s": "%.3f" % certificate["seconds"]
                             if certificate and "seconds" in certificate
                             else "",
                # Both from the one --certify run: the ratio is meaningful on
                # a loaded machine, the absolute times less so.
                "certify_ratio": "%.2f" % (certificate["seconds"] /
                                           cert_report["solve_seconds"])
                                 if certificate and "seconds" in certificate
                                 and cert_report["solve_seconds"] > 0.01
                                 else "",
                "certified": ("yes" if certificate["certified"] else
                              "n/a" if "not_available" in certificate else
                              "NO") if certificate else "",
                "g2o_s": "%.3f" % g2o_s if g2o_s is not None else "",
                "ok": "yes" if ok_chi2 and ok_time and ok_it else
                      ("CHI2" if not ok_chi2 else
                       "ITERATIONS" if not ok_it else "TIME"),
            })
            print("%-32s done (%.3f s)" % (name, median), file=sys.stderr)

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
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
