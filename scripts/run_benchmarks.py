#!/usr/bin/python3
"""Benchmark runner: runs a list of entries from a YAML file, evaluates each
result against its ground truth with `slam eval`, and writes one table
(markdown and CSV) of ATE, RPE and run time.

Usage: scripts/run_benchmarks.py [CONFIG.yaml] [--slam build/slam]
       [--datasets DIR] [--out DIR] [--md FILE] [--csv FILE] [--only NAME...]
       [--plots]
Runs with Debian's /usr/bin/python3 (python3-yaml), no other package.

The YAML file (see configs/benchmarks/evaluation.yaml):

  defaults:                 # optional, merged into every entry
    eval_args: [--align, se3]
  entries:
    - name: kitti00_orb     # one row of the table
      gt: "{datasets}/trajectories_evo/KITTI_00_gt.txt"
      format: kitti         # of the ground truth and the estimate (or
                            # gt_format / est_format); default auto
      # The estimate comes from exactly one of:
      estimate: "{datasets}/trajectories_evo/KITTI_00_ORB.txt"  # a file, or
      # input: graph.g2o    # `slam optimize -i INPUT -o {output}`
      # config: cfg.yaml    #   (+ --config CONFIG when given), or
      # command: "..."      # any shell command that writes {output}
      # output: out.txt     # name of {output} in the entry's work folder
      eval_args: [--rpe_delta, 10, --rpe_unit, m, --kitti]

Placeholders in paths and commands: {datasets} (--datasets, default
$SLAM_DATASETS or ../shared/datasets), {root} (the checkout), {slam} (the
binary), {output} (the estimate to write), {workdir} (the entry's folder).
Relative paths are taken from the checkout. The run time is the wall time of
the input/command step (empty for a given estimate file); the evaluation time
is that of `slam eval`. Exit code 1 when an entry failed (its row says why).
"""

import argparse
import csv
import io
import json
import os
import shlex
import subprocess
import sys
import time

import yaml

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))

COLUMNS = [
    ("name", "entry"),
    ("matched", "pairs"),
    ("ate_rmse", "ATE rmse [m]"),
    ("ate_mean", "ATE mean [m]"),
    ("ate_max", "ATE max [m]"),
    ("are_rmse", "APE rot rmse [deg]"),
    ("rpe_t_rmse", "RPE trans rmse [m]"),
    ("rpe_r_rmse", "RPE rot rmse [deg]"),
    ("rpe_delta", "RPE delta"),
    ("kitti_t", "KITTI t_rel [%]"),
    ("kitti_r", "KITTI r_rel [deg/100m]"),
    ("align", "align"),
    ("run_s", "run time [s]"),
    ("eval_s", "eval time [s]"),
    ("status", "status"),
]


def find_slam(explicit):
    if explicit:
        return os.path.abspath(explicit)
    for candidate in ("build/slam", "build/apps/slam", "build-release/apps/slam",
                      "build-eval/apps/slam"):
        path = os.path.join(ROOT, candidate)
        if os.path.isfile(path) and os.access(path, os.X_OK):
            return path
    return "slam"  # From PATH.


def expand(text, values):
    """Fills {placeholders}; relative paths are taken from the checkout."""
    out = str(text)
    for key, value in values.items():
        out = out.replace("{" + key + "}", value)
    return out


def as_path(text, values):
    path = expand(text, values)
    return path if os.path.isabs(path) else os.path.join(ROOT, path)


def fmt(value, digits=6):
    if value is None:
        return ""
    if isinstance(value, float):
        return "%.*f" % (digits, value)
    return str(value)


def run_entry(entry, args, slam):
    row = {key: None for key, _ in COLUMNS}
    row["name"] = entry["name"]
    workdir = os.path.join(args.out, entry["name"])
    os.makedirs(workdir, exist_ok=True)
    values = {"datasets": args.datasets, "root": ROOT, "slam": slam,
              "workdir": workdir}
    output = os.path.join(workdir, entry.get("output", "estimate.txt"))
    values["output"] = output

    sources = [k for k in ("estimate", "input", "command") if k in entry]
    if len(sources) != 1:
        raise RuntimeError("give exactly one of estimate, input, command "
                           "(found %s)" % (", ".join(sources) or "none"))
    if "estimate" in entry:
        estimate = as_path(entry["estimate"], values)
    else:
        if "input" in entry:
            if "output" not in entry:
                ext = os.path.splitext(str(entry["input"]))[1] or ".g2o"
                output = os.path.join(workdir, "optimized" + ext)
                values["output"] = output
            cmd = [slam, "optimize", "-i", as_path(entry["input"], values),
                   "-o", output, "--quiet"]
            if entry.get("config"):
                cmd += ["--config", as_path(entry["config"], values)]
            cmd += [expand(a, values) for a in entry.get("run_args", [])]
            shell = False
        else:
            cmd = expand(entry["command"], values)
            shell = True
        start = time.perf_counter()
        proc = subprocess.run(cmd, shell=shell, capture_output=True, text=True,
                              cwd=ROOT)
        row["run_s"] = time.perf_counter() - start
        with open(os.path.join(workdir, "run.log"), "w") as f:
            f.write(proc.stdout + proc.stderr)
        if proc.returncode != 0:
            raise RuntimeError("run failed (exit %d): %s" % (
                proc.returncode, (proc.stderr or proc.stdout).strip()[-300:]))
        estimate = output
        if not os.path.exists(estimate):
            raise RuntimeError("the run wrote no %s" % estimate)

    report = os.path.join(workdir, "eval.json")
    cmd = [slam, "eval", "--ref", as_path(entry["gt"], values),
           "--est", estimate, "--report", report]
    fmt_all = entry.get("format")
    if fmt_all:
        cmd += ["--format", str(fmt_all)]
    for key in ("gt_format", "est_format"):
        if entry.get(key):
            cmd += ["--" + ("ref_format" if key == "gt_format" else key),
                    str(entry[key])]
    if entry.get("gt_times"):
        cmd += ["--ref_times", as_path(entry["gt_times"], values)]
    if args.plots:
        cmd += ["--plot", os.path.join(workdir, "plots")]
    cmd += [expand(a, values) for a in entry.get("eval_args", [])]
    start = time.perf_counter()
    proc = subprocess.run(cmd, capture_output=True, text=True)
    row["eval_s"] = time.perf_counter() - start
    with open(os.path.join(workdir, "eval.log"), "w") as f:
        f.write(" ".join(shlex.quote(c) for c in cmd) + "\n" + proc.stdout +
                proc.stderr)
    if proc.returncode != 0:
        raise RuntimeError("slam eval failed (exit %d): %s" % (
            proc.returncode, (proc.stderr or proc.stdout).strip()[-300:]))
    with open(report) as f:
        res = json.load(f)
    row["matched"] = res["matched_pairs"]
    row["ate_rmse"] = res["ape_translation"]["rmse"]
    row["ate_mean"] = res["ape_translation"]["mean"]
    row["ate_max"] = res["ape_translation"]["max"]
    row["are_rmse"] = res["ape_rotation"]["rmse"]
    row["rpe_t_rmse"] = res["rpe_translation"]["rmse"]
    row["rpe_r_rmse"] = res["rpe_rotation"]["rmse"]
    rpe = res["rpe_translation"]
    row["rpe_delta"] = "%g %s%s" % (rpe["delta"], rpe["delta_unit"],
                                    " all" if rpe["all_pairs"] else "")
    row["align"] = res["settings"]["align"]
    if "kitti" in res and res["kitti"].get("t_rel_percent") is not None:
        row["kitti_t"] = res["kitti"]["t_rel_percent"]
        row["kitti_r"] = res["kitti"]["r_rel_deg_per_100m"]
    row["status"] = "ok"
    return row


def tables(rows, columns=None):
    """Markdown and CSV text of `rows` (dicts) for (key, title) `columns`."""
    columns = COLUMNS if columns is None else columns
    header = [title for _, title in columns]
    lines = ["| " + " | ".join(header) + " |",
             "|" + "|".join("---" for _ in header) + "|"]
    buf = io.StringIO()
    writer = csv.writer(buf, lineterminator="\n")
    writer.writerow([key for key, _ in columns])
    for row in rows:
        cells = []
        for key, _ in columns:
            value = row.get(key)
            digits = 3 if key in ("run_s", "eval_s") else (
                4 if key in ("kitti_t", "kitti_r") else 6)
            cells.append(fmt(value, digits))
        lines.append("| " + " | ".join(c.replace("|", "/") for c in cells) + " |")
        writer.writerow([("%.9g" % row[k]) if isinstance(row.get(k), float)
                         else ("" if row.get(k) is None else row[k])
                         for k, _ in columns])
    return "\n".join(lines) + "\n", buf.getvalue()


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("config", nargs="?", default=os.path.join(
        ROOT, "configs", "benchmarks", "evaluation.yaml"))
    parser.add_argument("--slam", help="the slam binary (default: build dir)")
    parser.add_argument("--datasets", default=os.environ.get(
        "SLAM_DATASETS", os.path.join(ROOT, "..", "shared", "datasets")))
    parser.add_argument("--out", default=os.path.join(ROOT, "build",
                                                      "benchmark_results"),
                        help="work folder (estimates, logs, reports)")
    parser.add_argument("--md", help="markdown table file (default OUT/results.md)")
    parser.add_argument("--csv", help="CSV table file (default OUT/results.csv)")
    parser.add_argument("--only", nargs="*", help="substrings of entry names")
    parser.add_argument("--plots", action="store_true",
                        help="also write the plots of every entry")
    args = parser.parse_args()
    args.datasets = os.path.abspath(args.datasets)
    args.out = os.path.abspath(args.out)
    slam = find_slam(args.slam)

    with open(args.config) as f:
        spec = yaml.safe_load(f) or {}
    unknown = set(spec) - {"defaults", "entries"}
    if unknown:
        sys.exit("%s: unknown top-level keys %s (known: defaults, entries)" %
                 (args.config, sorted(unknown)))
    defaults = spec.get("defaults") or {}
    known = {"name", "gt", "gt_times", "format", "gt_format", "est_format",
             "estimate", "input", "config", "command", "output", "run_args",
             "eval_args"}
    rows = []
    failed = 0
    for i, raw in enumerate(spec.get("entries") or []):
        entry = dict(defaults)
        entry.update(raw)
        if "eval_args" in defaults and "eval_args" in raw:
            entry["eval_args"] = list(defaults["eval_args"]) + list(raw["eval_args"])
        bad = set(entry) - known
        name = entry.get("name", "entry%d" % i)
        if args.only and not any(s in name for s in args.only):
            continue
        print("== %s" % name, file=sys.stderr, flush=True)
        try:
            if bad:
                raise RuntimeError("unknown keys %s (known: %s)" % (
                    sorted(bad), ", ".join(sorted(known))))
            if "gt" not in entry:
                raise RuntimeError("no gt (ground truth) given")
            entry["name"] = name
            rows.append(run_entry(entry, args, slam))
        except (RuntimeError, OSError, KeyError, ValueError) as e:
            failed += 1
            rows.append({"name": name, "status": "FAILED: %s" % e})
            print("   failed: %s" % e, file=sys.stderr)
    md, csv_text = tables(rows)
    os.makedirs(args.out, exist_ok=True)
    md_path = args.md or os.path.join(args.out, "results.md")
    csv_path = args.csv or os.path.join(args.out, "results.csv")
    with open(md_path, "w") as f:
        f.write(md)
    with open(csv_path, "w") as f:
        f.write(csv_text)
    sys.stdout.write(md)
    print("tables: %s, %s" % (md_path, csv_path), file=sys.stderr)
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
