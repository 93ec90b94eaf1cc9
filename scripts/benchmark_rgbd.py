#!/usr/bin/python3
"""RGB-D visual SLAM benchmark: runs `slam run` (configs/tum_rgbd.yaml) on the
TUM fr1/rpy excerpt (110 colour frames at 30 Hz, fast roll, pitch and yaw
in place) a few times, evaluates the trajectory with `slam eval` as the TUM
benchmark does (association of stamps within 0.02 s, SE(3) alignment: ATE
rmse; RPE over one frame, translation and rotation rmse), and prints one
table (markdown and CSV) beside the issue's anchors and targets: ATE, RPE
per frame, median and p95 milliseconds per frame of the whole pipeline
(features, depth lookup, tracking, local BA; median over the runs), the
path ratio (estimated / true path length of the matched poses, after the
alignment), and on the fast steps (true rotation above 3 deg between
consecutive frames) the rmse of the per-frame rotation error and the share
of the rotation the estimate keeps (its rotation angle over the true one).

Usage: scripts/benchmark_rgbd.py [--datasets DIR] [--runs 3]
       [--slam build/apps/slam] [--config configs/tum_rgbd.yaml]
       [--sequence rgbd_tum_fr1_rpy_0-109]
Runs with Debian's python3 (no numpy)."""

import argparse
import bisect
import json
import math
import os
import statistics
import sys
import tempfile

import run_benchmarks
from benchmark_stereo import run  # A command, exiting with its output on failure.

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))

COLUMNS = [
    ("method", "method"), ("ate", "ATE rmse [m], SE(3)"),
    ("rpe_t", "RPE/frame transl. [m]"), ("rpe_r", "RPE/frame rot. [deg]"),
    ("median_ms", "median ms/frame"), ("p95_ms", "p95 ms/frame"),
    ("path_ratio", "path ratio"), ("fast_r", "fast steps: rot. err [deg]"),
    ("fast_kept", "fast steps: rot. kept"),
]

PEERS = [
    {"method": "camera that never moves (reference)", "ate": 0.040,
     "rpe_t": 0.0030, "rpe_r": 2.26},
    {"method": "Open3D 0.16 RGB-D odometry, hybrid", "ate": 0.139,
     "rpe_t": 0.0147, "rpe_r": 1.09, "median_ms": 657, "fast_kept": "0.67"},
    {"method": "Open3D, colour term", "ate": 0.057, "rpe_t": 0.0092,
     "rpe_r": 0.51, "median_ms": 551},
    {"method": "OpenCV ORB + depth + solvePnPRansac", "ate": 0.041,
     "rpe_t": 0.0084, "rpe_r": 0.50, "median_ms": 44},
]
TARGET = {"method": "target", "ate": 0.020, "rpe_r": 0.40, "median_ms": 30}


def read_tum(path):
    """[(t, (tx, ty, tz), (qx, qy, qz, qw))] of a TUM trajectory file."""
    poses = []
    with open(path) as f:
        for line in f:
            fields = line.split()
            if not fields or fields[0].startswith("#"):
                continue
            v = [float(x) for x in fields[:8]]
            poses.append((v[0], tuple(v[1:4]), tuple(v[4:8])))
    return poses


def q_mul(a, b):
    ax, ay, az, aw = a
    bx, by, bz, bw = b
    return (aw * bx + ax * bw + ay * bz - az * by,
            aw * by - ax * bz + ay * bw + az * bx,
            aw * bz + ax * by - ay * bx + az * bw,
            aw * bw - ax * bx - ay * by - az * bz)


def q_conj(q):
    return (-q[0], -q[1], -q[2], q[3])


def q_angle_deg(q):
    n = math.sqrt(sum(c * c for c in q))
    w = min(1.0, abs(q[3]) / n)
    return math.degrees(2.0 * math.acos(w))


def fast_step_rotation(gt, est, max_diff=0.02, fast_deg=3.0):
    """Per consecutive estimated frames whose true rotation exceeds fast_deg:
    rmse of the relative rotation error (deg) and the median share of the
    rotation the estimate keeps."""
    stamps = [p[0] for p in gt]
    matched = []
    for t, _, q in est:
        i = bisect.bisect_left(stamps, t)
        best = None
        for j in (i - 1, i):
            if 0 <= j < len(stamps) and abs(stamps[j] - t) < max_diff:
                if best is None or abs(stamps[j] - t) < abs(stamps[best] - t):
                    best = j
        matched.append(None if best is None else (q, gt[best][2]))
    errors, kept = [], []
    for a, b in zip(matched, matched[1:]):
        if a is None or b is None:
            continue
        rel_est = q_mul(q_conj(a[0]), b[0])
        rel_gt = q_mul(q_conj(a[1]), b[1])
        gt_angle = q_angle_deg(rel_gt)
        if gt_angle <= fast_deg:
            continue
        errors.append(q_angle_deg(q_mul(q_conj(rel_gt), rel_est)))
        kept.append(q_angle_deg(rel_est) / gt_angle)
    if not errors:
        return float("nan"), float("nan"), 0
    rmse = math.sqrt(sum(e * e for e in errors) / len(errors))
    return rmse, statistics.median(kept), len(errors)


def q_rotate(q, v):
    x, y, z, _ = q_mul(q_mul(q, (v[0], v[1], v[2], 0.0)), q_conj(q))
    return (x, y, z)


def keyframe_steps(gt, est, timings_csv, max_diff=0.02):
    """RPE over one frame (translation m, rotation deg; rmse and count) of
    the steps into a keyframe and of the other steps (timings.csv flags the
    keyframes): a frame between keyframes keeps its pose relative to its
    keyframe, so errors of the keyframes' poses show on the steps into
    them."""
    keyframes = set()
    with open(timings_csv) as f:
        for line in f:
            fields = line.strip().split(",")
            if fields and fields[0].isdigit() and fields[7].strip() == "1":
                keyframes.add(int(fields[0]))
    stamps = [p[0] for p in gt]
    matched = []
    for t, tr, q in est:
        i = bisect.bisect_left(stamps, t)
        cands = [j for j in (i - 1, i) if 0 <= j < len(stamps)
                 and abs(stamps[j] - t) < max_diff]
        best = min(cands, key=lambda j: abs(stamps[j] - t)) if cands else None
        matched.append(None if best is None else ((tr, q), gt[best][1:]))
    groups = {True: ([], []), False: ([], [])}
    for k in range(1, len(matched)):
        a, b = matched[k - 1], matched[k]
        if a is None or b is None:
            continue
        rel = []
        for (ta, qa), (tb, qb) in ((a[0], b[0]), (a[1], b[1])):
            d = tuple(x - y for x, y in zip(tb, ta))
            rel.append((q_rotate(q_conj(qa), d), q_mul(q_conj(qa), qb)))
        (te, qe), (tg, qg) = rel
        dq = q_mul(q_conj(qg), qe)
        dt = tuple(x - y for x, y in zip(q_rotate(q_conj(qg), te),
                                         q_rotate(q_conj(qg), tg)))
        group = groups[k in keyframes]
        group[0].append(math.sqrt(sum(x * x for x in dt)))
        group[1].append(q_angle_deg(dq))
    out = {}
    for key, (ts, rs) in groups.items():
        if ts:
            out[key] = (math.sqrt(sum(x * x for x in ts) / len(ts)),
                        math.sqrt(sum(x * x for x in rs) / len(rs)), len(ts))
    return out


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--datasets", default=os.environ.get(
        "SLAM_DATASETS", os.path.join(ROOT, "..", "shared", "datasets")))
    parser.add_argument("--runs", type=int, default=3)
    parser.add_argument("--slam", default="")
    parser.add_argument("--config",
                        default=os.path.join(ROOT, "configs", "tum_rgbd.yaml"))
    parser.add_argument("--sequence", default="rgbd_tum_fr1_rpy_0-109")
    args = parser.parse_args()
    slam = run_benchmarks.find_slam(args.slam)
    folder = os.path.join(args.datasets, args.sequence)
    gt = os.path.join(folder, "groundtruth.txt")
    medians, p95s = [], []
    row = {"method": "this backend (slam run)"}
    with tempfile.TemporaryDirectory() as tmp:
        config = os.path.join(tmp, "run.yaml")
        with open(args.config) as f:
            text = f.read()
        lines = []
        for line in text.splitlines():
            if line.strip().startswith("sequence:"):
                line = line[:line.index("sequence:")] + "sequence: " + folder
            lines.append(line)
        with open(config, "w") as f:
            f.write("\n".join(lines) + "\n")
        for i in range(args.runs):
            out = os.path.join(tmp, "out")
            run([slam, "run", "--config", config, "--output_dir", out,
                 "--report", os.path.join(tmp, "report.json")])
            with open(os.path.join(tmp, "report.json")) as f:
                report = json.load(f)
            medians.append(report["timing"]["median_ms"])
            p95s.append(report["timing"]["p95_ms"])
            print("run %d/%d: %.1f ms median per frame" %
                  (i + 1, args.runs, medians[-1]), file=sys.stderr)
        est = os.path.join(tmp, "out", "trajectory.tum")
        # The trajectory evaluated by slam eval itself, as TUM does.
        run([slam, "eval", "--ref", gt, "--est", est, "--format", "tum",
             "--associate", "time", "--t_max_diff", "0.02", "--align",
             "se3", "--report", os.path.join(tmp, "eval.json")])
        with open(os.path.join(tmp, "eval.json")) as f:
            ev = json.load(f)
        ev = ev.get("results", ev)
        row["ate"] = ev["ape_translation"]["rmse"]
        row["rpe_t"] = ev["rpe_translation"]["rmse"]
        row["rpe_r"] = ev["rpe_rotation"]["rmse"]
        row["path_ratio"] = (ev["path_length"]["estimate"] /
                             ev["path_length"]["reference"])
        row["median_ms"] = statistics.median(medians)
        row["p95_ms"] = statistics.median(p95s)
        fast_r, fast_kept, fast_n = fast_step_rotation(read_tum(gt),
                                                       read_tum(est))
        row["fast_r"] = fast_r
        row["fast_kept"] = "%.2f" % fast_kept
        print("%d fast steps (> 3 deg per frame)" % fast_n, file=sys.stderr)
        steps = keyframe_steps(read_tum(gt), read_tum(est),
                               os.path.join(tmp, "out", "timings.csv"))
    markdown, csv_text = run_benchmarks.tables(PEERS + [row, TARGET], COLUMNS)
    print(markdown)
    print(csv_text)
    for key, name in ((True, "into a keyframe"), (False, "other frames")):
        if key in steps:
            print("RPE per frame, steps %s: %.4f m / %.3f deg (%d steps)" %
                  ((name,) + steps[key]))


if __name__ == "__main__":
    main()
