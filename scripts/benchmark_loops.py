#!/usr/bin/python3
"""Visual loop detection benchmark: runs `slam loops` on the rtabmap samples
(84 images with a ground-truth loop matrix) with each vocabulary choice and
prints one table (markdown and CSV): precision and recall at the default
threshold, recall at 100 % precision, PR AUC, the median time per query
(whole detection, and bag of words + database query alone) and the time to
get the vocabulary. A last row times the database with thousands of
entries: the 84 images repeated (symbolic links) to --repeat x 84 images,
without ground truth.

Vocabularies: `self` (the default: trained on the sequence itself), `dbow2`
(the shipped DBoW2 small_voc.yml.gz, 692 words), `kitti` (trained with
`slam vocabulary` on stereo_kitti06_half/image_0: another kind of scene).

Usage: scripts/benchmark_loops.py [--datasets DIR] [--slam build/apps/slam]
       [--repeat 30]
Runs with Debian's python3; table output and the lookup of the slam binary
are shared with scripts/run_benchmarks.py."""

import argparse
import json
import os
import subprocess
import sys
import tempfile
import time

import run_benchmarks

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))

COLUMNS = [
    ("vocabulary", "vocabulary"), ("images", "images"), ("words", "words"),
    ("precision", "precision"), ("recall", "recall"),
    ("recall100", "recall at 100 % precision"), ("auc", "PR AUC"),
    ("query_ms", "median ms / query"), ("db_ms", "median ms BoW + db query"),
    ("voc_s", "vocabulary s"), ("target", "target met"),
]


def run_loops(slam, images, extra, out_dir, name):
    report = os.path.join(out_dir, name + ".json")
    cmd = [slam, "loops", "--images", images, "--report", report] + extra
    start = time.monotonic()
    proc = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                          text=True)
    if proc.returncode != 0:
        sys.exit("slam loops failed:\n" + proc.stderr[-2000:])
    print("%s: %.1f s" % (name, time.monotonic() - start), file=sys.stderr)
    with open(report) as f:
        return json.load(f)


def row_of(name, r, voc_seconds=None):
    row = {"vocabulary": name, "images": r["images"],
           "words": r["vocabulary_words"],
           "query_ms": "%.3f" % r["query_ms_median"],
           "db_ms": "%.3f" % r["database_ms_median"],
           "voc_s": "%.2f" % (r["vocabulary_seconds"] if voc_seconds is None
                              else voc_seconds)}
    if "precision" in r:
        row.update({"precision": "%.3f" % r["precision"],
                    "recall": "%.3f" % r["recall"],
                    "recall100": "%.3f" % r["recall_at_100_precision"],
                    "auc": "%.3f" % r["auc"]})
        ok = r["precision"] >= 1.0 and r["recall"] >= 0.8
        row["target"] = "yes" if ok else "no"
    return row


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--datasets", default=os.environ.get(
        "SLAM_DATASETS", os.path.join(os.path.dirname(ROOT), "shared",
                                      "datasets")))
    parser.add_argument("--slam", default="")
    parser.add_argument("--repeat", type=int, default=30)
    args = parser.parse_args()
    slam = run_benchmarks.find_slam(args.slam)
    data = os.path.join(args.datasets, "bow_rtabmap_samples")
    images = os.path.join(data, "samples")
    gt = ["--gt", os.path.join(data, "samples_GT.bmp")]
    kitti = os.path.join(args.datasets, "stereo_kitti06_half", "image_0")
    rows = []
    with tempfile.TemporaryDirectory() as out:
        rows.append(row_of("self (default)",
                           run_loops(slam, images, gt, out, "self")))
        rows.append(row_of("dbow2 small_voc", run_loops(
            slam, images, gt + ["--voc", os.path.join(data,
                                                      "small_voc.yml.gz")],
            out, "dbow2")))
        if os.path.isdir(kitti):
            voc = os.path.join(out, "kitti.voc")
            start = time.monotonic()
            subprocess.run([slam, "vocabulary", "--images", kitti, "-o", voc,
                            "--k", "10", "--levels", "3"], check=True,
                           stdout=subprocess.DEVNULL)
            seconds = time.monotonic() - start
            rows.append(row_of("kitti06 k10 L3", run_loops(
                slam, images, gt + ["--voc", voc], out, "kitti"), seconds))
        big = os.path.join(out, "repeated")
        os.makedirs(big)
        names = sorted((f for f in os.listdir(images) if f.endswith(".jpg")),
                       key=lambda f: int(f.split(".")[0]))
        n = 0
        for _ in range(args.repeat):
            for f in names:
                n += 1
                os.symlink(os.path.join(images, f),
                           os.path.join(big, "%d.jpg" % n))
        rows.append(row_of("self, %dx repeated" % args.repeat,
                           run_loops(slam, big, [], out, "repeated")))
    markdown, csv_text = run_benchmarks.tables(rows, COLUMNS)
    print(markdown)
    print(csv_text)


if __name__ == "__main__":
    main()
