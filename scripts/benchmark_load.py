#!/usr/bin/python3
"""Load benchmark: time and peak memory of large problems, one table.

Pose graphs: `slam simulate` writes simulated 2D grid worlds (default
1,000,000 poses on a 1000 x 1000 and on a 200 x 200 lattice, 402k and 767k
loop closures) and a 3D sphere world (default 200,000 poses), then
`slam optimize` with default settings optimizes each; the table gives the
simulation time, the optimizer's load / initialization / solve / total
times (from its JSON report), its final chi2 and the peak resident memory of
each command (getrusage of the child, ru_maxrss).

Laser: `slam run` on the ACES CARMEN log (configs/aces.yaml), once as it is
and once on the log played three times in a row (written into a temporary
directory: the second and third copies have their stamps shifted past the
previous copy's end; their odometry is left as logged, so the robot is
carried back to the start, as the odometry says), comparing CPU time (user +
system) with the expected linear growth (3x).

Usage: scripts/benchmark_load.py [--slam build/apps/slam] [--datasets DIR]
       [--poses_2d 1000000] [--grid_size_2d 1000,200] [--poses_3d 200000]
       [--poses_per_ring 50] [--radius_3d 20] [--skip_posegraph]
       [--skip_laser] [--work_dir DIR]
Runs with Debian's python3; the table output and the lookup of the slam
binary are shared with scripts/run_benchmarks.py."""

import argparse
import bz2
import json
import os
import re
import subprocess
import sys
import tempfile
import time

import run_benchmarks

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))

COLUMNS = [
    ("problem", "problem"), ("size", "size"),
    ("sim_s", "simulate s"), ("load_s", "load s"), ("init_s", "init s"),
    ("solve_s", "solve s"), ("total_s", "total s"), ("cpu_s", "CPU s"),
    ("peak_gb", "peak RSS [GB]"), ("result", "result"),
]


def run(cmd, log_path):
    """Runs cmd with its output in log_path; returns (exit code, wall s,
    CPU s, peak RSS in GB) of that child alone."""
    print("$ " + " ".join(cmd), file=sys.stderr, flush=True)
    start = time.monotonic()
    with open(log_path, "w") as log:
        proc = subprocess.Popen(cmd, stdout=log, stderr=subprocess.STDOUT)
        _, status, usage = os.wait4(proc.pid, 0)
    wall = time.monotonic() - start
    code = os.waitstatus_to_exitcode(status)
    return (code, wall, usage.ru_utime + usage.ru_stime,
            usage.ru_maxrss / 1024.0 / 1024.0)


def tail(path, lines=5):
    with open(path) as f:
        return "".join(f.readlines()[-lines:]).strip()


LASER_SUMMARY = re.compile(
    r"(\d+) scans, (\d+) keyframes.*loop closures: (\d+) proposed, "
    r"(\d+) accepted")
# The loop search's wall time (s) in the run's time split.
LASER_LOOPS = re.compile(r"run: time .* loops ([\d.]+),")


def simulated_graph(slam, name, world_yaml, num_poses, work):
    """Simulates one world and optimizes it with the defaults."""
    out_dir = os.path.join(work, name)
    config = os.path.join(work, name + ".yaml")
    with open(config, "w") as f:
        f.write(world_yaml)
    row = {"problem": name}
    code, wall, _, sim_gb = run(
        [slam, "simulate", "--config", config, "--num_poses", str(num_poses),
         "-o", out_dir], os.path.join(work, name + "_simulate.log"))
    if code != 0:
        row["result"] = "simulate failed: " + tail(
            os.path.join(work, name + "_simulate.log"), 1)
        return row
    row["sim_s"] = wall
    graph = os.path.join(out_dir, "graph.g2o")
    with open(graph) as f:
        edges = sum(1 for line in f if line.startswith("EDGE"))
    row["size"] = "%d poses, %d loop closures" % (num_poses,
                                                  edges - (num_poses - 1))
    report = os.path.join(out_dir, "report.json")
    log = os.path.join(work, name + "_optimize.log")
    code, wall, cpu, peak_gb = run(
        [slam, "optimize", "-i", graph, "-o",
         os.path.join(out_dir, "optimized.g2o"), "--quiet", "--report",
         report], log)
    row["cpu_s"] = cpu
    row["peak_gb"] = max(peak_gb, 0.0)
    if code != 0:
        row["total_s"] = wall
        row["result"] = "exit %d: %s" % (code, tail(log, 1))
        return row
    with open(report) as f:
        data = json.load(f)
    timing = data.get("timing", data)
    for key, column in (("load_seconds", "load_s"), ("init_seconds", "init_s"),
                        ("solve_seconds", "solve_s"),
                        ("total_seconds", "total_s")):
        value = find_key(timing, key)
        if value is not None:
            row[column] = float(value)
    row["result"] = tail(log, 1).split("; total")[0]
    # Only the pose graph's own files are large: remove them right away.
    for file_name in os.listdir(out_dir):
        os.remove(os.path.join(out_dir, file_name))
    return row


def find_key(data, key):
    """The value of `key` anywhere in the JSON report."""
    if isinstance(data, dict):
        if key in data:
            return data[key]
        for value in data.values():
            found = find_key(value, key)
            if found is not None:
                return found
    elif isinstance(data, list):
        for value in data:
            found = find_key(value, key)
            if found is not None:
                return found
    return None


def repeat_log(source, copies, target):
    """Writes the CARMEN log `source` played `copies` times: every later copy
    repeats the sensor lines with their two stamps (the last and third-last
    fields) shifted by the span of the log plus one second."""
    with bz2.open(source, "rt") as f:
        lines = f.read().splitlines()
    stamps = []
    for line in lines:
        fields = line.split()
        if fields and fields[0] in ("ODOM", "FLASER", "ROBOTLASER1",
                                    "RAWLASER1"):
            stamps.append(float(fields[-3]))
    if not stamps:
        sys.exit("%s: no sensor lines" % source)
    shift = max(stamps) - min(stamps) + 1.0
    with bz2.open(target, "wt") as out:
        for copy in range(copies):
            for line in lines:
                fields = line.split()
                if not fields:
                    continue
                if fields[0] not in ("ODOM", "FLASER", "ROBOTLASER1",
                                     "RAWLASER1"):
                    if copy == 0:
                        out.write(line + "\n")
                    continue
                if copy > 0:
                    fields[-3] = "%.6f" % (float(fields[-3]) + copy * shift)
                    fields[-1] = "%.6f" % (float(fields[-1]) + copy * shift)
                out.write(" ".join(fields) + "\n")


def laser_rows(slam, datasets, work):
    datasets = datasets or os.environ.get(
        "SLAM_DATASETS", os.path.join(os.path.dirname(ROOT), "shared",
                                      "datasets"))
    source = os.path.join(datasets, "laser_logs_carmen", "aces.clf.bz2")
    if not os.path.isfile(source):
        return [{"problem": "aces", "result": "skipped: no " + source}]
    # A datasets directory of its own holding the repeated log.
    local = os.path.join(work, "datasets")
    os.makedirs(os.path.join(local, "laser_logs_carmen"))
    repeated = os.path.join(local, "laser_logs_carmen", "aces_x3.clf.bz2")
    repeat_log(source, 3, repeated)
    os.symlink(source, os.path.join(local, "laser_logs_carmen",
                                    "aces.clf.bz2"))
    os.symlink(os.path.join(datasets, "laser_logs_carmen", "aces.relations"),
               os.path.join(local, "laser_logs_carmen", "aces.relations"))
    with open(os.path.join(ROOT, "configs", "aces.yaml")) as f:
        aces = f.read()
    config_x3 = os.path.join(work, "aces_x3.yaml")
    with open(config_x3, "w") as f:
        # The relations belong to one pass: not evaluated on three.
        f.write("\n".join(
            line.replace("aces.clf.bz2", "aces_x3.clf.bz2")
            for line in aces.splitlines()
            if not line.strip().startswith("relations:")) + "\n")
    rows = []
    for name, config in (("aces", os.path.join(ROOT, "configs", "aces.yaml")),
                         ("aces x3", config_x3)):
        log = os.path.join(work, name.replace(" ", "_") + "_run.log")
        code, wall, cpu, peak_gb = run(
            [slam, "run", "--config", config, "--datasets", local,
             "--output_dir", os.path.join(work, name.replace(" ", "_"))], log)
        row = {"problem": name, "size": "%d pass%s of the log" %
               ((3, "es") if "x3" in name else (1, "")), "total_s": wall,
               "cpu_s": cpu,
               "peak_gb": peak_gb}
        with open(log) as f:
            text = f.read()
        summary = LASER_SUMMARY.search(text)
        loops = LASER_LOOPS.search(text)
        if code != 0:
            row["result"] = "exit %d: %s" % (code, tail(log, 1))
        elif summary:
            row["result"] = ("%s scans, %s keyframes, loop closures %s "
                             "proposed, %s accepted" % summary.groups())
            if loops:
                row["result"] += ", loop search %s s (%.2f ms per scan)" % (
                    loops.group(1),
                    1000.0 * float(loops.group(1)) / int(summary.group(1)))
        rows.append(row)
    if len(rows) == 2 and rows[0].get("cpu_s") and rows[1].get("cpu_s"):
        rows[1]["result"] = "CPU %.2fx one pass (linear: 3x); %s" % (
            rows[1]["cpu_s"] / rows[0]["cpu_s"], rows[1]["result"])
    return rows


GRID_2D = """simulate:
  seed: 1
  world:
    type: grid2d
    grid_size: {grid_size}
"""

SPHERE_3D = """simulate:
  seed: 1
  world:
    type: sphere3d
    poses_per_ring: {poses_per_ring}
    radius: {radius}
"""


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--slam", default="")
    parser.add_argument("--datasets", default="")
    parser.add_argument("--poses_2d", type=int, default=1000000)
    parser.add_argument("--grid_size_2d", default="1000,200",
                        help="lattice points per side of each 2D world, "
                        "comma-separated (200: the 767k loop closures whose "
                        "factor does not fit, solved by conjugate gradients)")
    parser.add_argument("--poses_3d", type=int, default=200000)
    parser.add_argument("--poses_per_ring", type=int, default=50,
                        help="sphere: poses per revolution (the simulator's "
                        "default)")
    parser.add_argument("--radius_3d", type=float, default=20.0,
                        help="sphere radius [m] (the simulator's default)")
    parser.add_argument("--skip_posegraph", action="store_true")
    parser.add_argument("--skip_laser", action="store_true")
    parser.add_argument("--work_dir", default="",
                        help="keep the logs here (default: a temp dir)")
    args = parser.parse_args()
    slam = run_benchmarks.find_slam(args.slam)
    rows = []
    with tempfile.TemporaryDirectory() as temp:
        work = args.work_dir or temp
        os.makedirs(work, exist_ok=True)
        if not args.skip_posegraph:
            for grid_size in args.grid_size_2d.split(","):
                rows.append(simulated_graph(
                    slam, "grid2d_%s" % grid_size.strip(),
                    GRID_2D.format(grid_size=int(grid_size)), args.poses_2d,
                    work))
            rows.append(simulated_graph(
                slam, "sphere3d",
                SPHERE_3D.format(poses_per_ring=args.poses_per_ring,
                                 radius=args.radius_3d), args.poses_3d, work))
        if not args.skip_laser:
            rows += laser_rows(slam, args.datasets, work)
    for row in rows:
        for key in ("sim_s", "load_s", "init_s", "solve_s", "total_s",
                    "cpu_s", "peak_gb"):
            if isinstance(row.get(key), float):
                row[key] = "%.2f" % row[key]
    markdown, csv_text = run_benchmarks.tables(rows, COLUMNS)
    print(markdown)
    print(csv_text)


if __name__ == "__main__":
    main()
