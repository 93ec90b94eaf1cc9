#!/usr/bin/python3
"""Laser SLAM benchmark: runs `slam run` on every CARMEN log of the laser
folder that has a matching .relations file, all with the one default
configuration (only the log, the relations and the output differ), and
prints one table (markdown, then CSV): the relation error of Kuemmerle et
al. 2009 (mean +- std of the absolute errors), wall and CPU time and the
peak memory of the slam process, beside Cartographer's published figures
(Hess et al. 2016, Table II) where known, and whether each figure beats
Cartographer's (mean and std of each error, wall time).

Usage: scripts/benchmark_laser.py [--datasets DIR] [--only NAME[,NAME]]
       [--runs N] [--slam build/apps/slam]

The logs are DIR/laser_logs_carmen/NAME.relations with NAME.clf.bz2 (or
NAME.clf, NAME.log.bz2, NAME.log); logs dropped in later (e.g. fr079) are
picked up as they are. DIR defaults to $SLAM_DATASETS, else
../shared/datasets beside the checkout. With --runs N the times and memory
are medians over N runs. Runs with Debian's python3."""

import argparse
import glob
import os
import re
import statistics
import subprocess
import sys
import tempfile
import time

import run_benchmarks

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))

# Hess et al. 2016, "Real-Time Loop Closure in 2D LIDAR SLAM", Table II:
# (translation mean, std [m], rotation mean, std [deg], wall time [s]).
CARTOGRAPHER = {
    "aces": (0.0375, 0.0426, 0.373, 0.469, 41.0),
    "intel": (0.0229, 0.0239, 0.453, 1.335, 179.0),
    "mit-csail": (0.0319, 0.0363, 0.369, 0.365, 35.0),
}

# Log file names beside NAME.relations, in order of preference.
LOG_SUFFIXES = (".clf.bz2", ".clf", ".log.bz2", ".log")

COLUMNS = [
    ("log", "log"), ("relations", "relations used"),
    ("trans", "trans. error [m]"), ("rot", "rot. error [deg]"),
    ("wall", "wall [s]"), ("cpu", "CPU [s]"), ("mem", "peak mem [MB]"),
    ("loops", "loop search [s] (share of slam)"),
    ("carto_trans", "Cartographer trans. [m]"),
    ("carto_rot", "Cartographer rot. [deg]"),
    ("carto_wall", "Cartographer wall [s]"),
    ("beats", "beats Cartographer (trans. mean/std, rot. mean/std, wall)"),
]

RELATION = re.compile(
    r"relation error \((\d+) of (\d+) relations\): translation ([\d.]+) "
    r"\+- ([\d.]+) m .*rotation ([\d.]+) \+- ([\d.]+) deg")

# The run's time split (wall clock, seconds): slam total and loop search.
TIMES = re.compile(r"run: time [\d.]+ s \(read [\d.]+ s, slam ([\d.]+) s: "
                   r"matching [\d.]+, loops ([\d.]+),")


def find_logs(folder):
    """(name, log path, relations path) of every log with relations."""
    logs = []
    for relations in sorted(glob.glob(os.path.join(folder, "*.relations"))):
        name = os.path.basename(relations)[:-len(".relations")]
        for suffix in LOG_SUFFIXES:
            log = os.path.join(folder, name + suffix)
            if os.path.isfile(log):
                logs.append((name, log, relations))
                break
        else:
            print("benchmark_laser: %s has no log (%s); skipped" %
                  (relations, ", ".join(name + s for s in LOG_SUFFIXES)),
                  file=sys.stderr)
    return logs


def write_config(path, log, relations, output_dir):
    """The default configuration: only the log, relations and output."""
    with open(path, "w") as f:
        f.write("run:\n  log: %s\n  relations: %s\n  output_dir: %s\n" %
                (log, relations, output_dir))


def run_once(slam, config):
    """stdout, wall s, CPU s (user + system) and peak RSS in MB of one run
    of the slam process itself (os.wait4: its own rusage)."""
    with tempfile.TemporaryFile("w+") as out, \
            tempfile.TemporaryFile("w+") as err:
        start = time.monotonic()
        proc = subprocess.Popen([slam, "run", "--config", config],
                                stdout=out, stderr=err)
        _, status, usage = os.wait4(proc.pid, 0)
        wall = time.monotonic() - start
        proc.returncode = os.waitstatus_to_exitcode(status)
        out.seek(0)
        err.seek(0)
        stdout, stderr = out.read(), err.read()
    if proc.returncode != 0:
        print("slam run --config %s failed (exit %d):\n%s" %
              (config, proc.returncode, stderr[-2000:]), file=sys.stderr)
        return None
    # ru_maxrss is in kilobytes on Linux.
    return (stdout, wall, usage.ru_utime + usage.ru_stime,
            usage.ru_maxrss / 1024.0)


def beats(ours, theirs):
    return "yes" if ours < theirs else "no"


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--datasets", default=os.environ.get(
        "SLAM_DATASETS", os.path.join(ROOT, "..", "shared", "datasets")))
    parser.add_argument("--only", default="",
                        help="comma-separated log names (e.g. aces,intel)")
    parser.add_argument("--runs", type=int, default=1)
    parser.add_argument("--slam", default="")
    args = parser.parse_args()
    if args.runs < 1:
        sys.exit("benchmark_laser: --runs must be >= 1")
    folder = os.path.join(os.path.abspath(args.datasets), "laser_logs_carmen")
    logs = find_logs(folder)
    if args.only:
        wanted = set(n for n in args.only.split(",") if n)
        unknown = wanted - set(name for name, _, _ in logs)
        if unknown:
            sys.exit("benchmark_laser: no log with relations named %s in %s" %
                     (", ".join(sorted(unknown)), folder))
        logs = [entry for entry in logs if entry[0] in wanted]
    if not logs:
        sys.exit("benchmark_laser: no log with a .relations file in " + folder)
    slam = run_benchmarks.find_slam(args.slam)
    rows, failed = [], []
    with tempfile.TemporaryDirectory() as tmp:
        for name, log, relations in logs:
            config = os.path.join(tmp, name + ".yaml")
            write_config(config, log, relations, os.path.join(tmp, name))
            walls, cpus, mems, errors, match = [], [], [], set(), None
            loops = []
            for i in range(args.runs):
                result = run_once(slam, config)
                if result is None:
                    break
                text, wall, cpu, mem = result
                walls.append(wall)
                cpus.append(cpu)
                mems.append(mem)
                match = RELATION.search(text)
                if not match:
                    print("benchmark_laser: no relation error in the output "
                          "of %s:\n%s" % (name, text[-2000:]), file=sys.stderr)
                    break
                errors.add(match.groups())
                times = TIMES.search(text)
                share = ""
                if times:
                    slam_s, loop_s = (float(v) for v in times.groups())
                    loops.append((loop_s, loop_s / max(slam_s, 1e-9)))
                    share = ", loop search %.1f s (%.1f %% of slam)" % (
                        loop_s, 100 * loops[-1][1])
                print("%s run %d/%d: %.1f s wall, %.1f s CPU, %.0f MB%s" %
                      (name, i + 1, args.runs, wall, cpu, mem, share),
                      file=sys.stderr)
            if len(walls) < args.runs or not match:
                # A log that fails still gets its row (and the exit status).
                failed.append(name)
                rows.append({"log": os.path.basename(log),
                             "trans": "failed", "rot": "failed"})
                continue
            if len(errors) > 1:
                print("benchmark_laser: %s: the runs differ in their relation "
                      "error; the table shows the last" % name,
                      file=sys.stderr)
            used, total, t_mean, t_std, r_mean, r_std = match.groups()
            row = {
                "log": os.path.basename(log),
                "relations": "%s of %s" % (used, total),
                "trans": "%s +- %s" % (t_mean, t_std),
                "rot": "%s +- %s" % (r_mean, r_std),
                "wall": "%.1f" % statistics.median(walls),
                "cpu": "%.1f" % statistics.median(cpus),
                "mem": "%.0f" % statistics.median(mems),
                "loops": ("%.1f (%.0f %%)" % (
                    statistics.median(l for l, _ in loops),
                    100 * statistics.median(f for _, f in loops))
                          if loops else "n/a"),
                "carto_trans": "n/a", "carto_rot": "n/a",
                "carto_wall": "n/a", "beats": "n/a",
            }
            carto = CARTOGRAPHER.get(name)
            if carto:
                ours = (float(t_mean), float(t_std), float(r_mean),
                        float(r_std), statistics.median(walls))
                row["carto_trans"] = "%.4f +- %.4f" % carto[0:2]
                row["carto_rot"] = "%.3f +- %.3f" % carto[2:4]
                row["carto_wall"] = "%.0f" % carto[4]
                marks = [beats(o, c) for o, c in zip(ours, carto)]
                row["beats"] = "%s/%s, %s/%s, %s" % tuple(marks)
            rows.append(row)
    markdown, csv_text = run_benchmarks.tables(rows, COLUMNS)
    print(markdown)
    print(csv_text)
    print("benchmark_laser: %d logs, %d run(s) each (times and memory: "
          "medians), Cartographer: Hess et al. 2016, Table II" %
          (len(rows), args.runs))
    if failed:
        sys.exit("benchmark_laser: failed: " + ", ".join(failed))


if __name__ == "__main__":
    main()
