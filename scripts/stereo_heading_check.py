#!/usr/bin/python3
"""Heading check of a KITTI-style sequence's ground truth against the images
alone: for each pair of consecutive left images, the relative rotation from
a depth-free estimate (Shi-Tomasi corners tracked by pyramidal Lucas-Kanade
with a forward-backward check, essential matrix by OpenCV's USAC_ACCURATE at
0.3 px, cv::recoverPose), beside the ground truth's relative rotation
(poses.txt) and, optionally, an estimated trajectory's (KITTI format, e.g.
slam run's trajectory_kitti.txt). Prints per frame the yaw increments
(rotation about the camera's y axis, degrees) and the cumulative yaw of each
minus the ground truth's, so that a heading difference that the images and
the estimator agree on, and the ground truth does not, shows as such.

Usage: scripts/stereo_heading_check.py [--sequence DIR] [--frames N]
       [--estimate trajectory_kitti.txt]
Runs with Debian's python3, python3-numpy and python3-opencv (installed by
scripts/install_deps.sh)."""

import argparse
import math
import os
import sys

import cv2
import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def read_calibration(path):
    """fx, fy, cx, cy of P0 (labelled or unlabelled calib.txt)."""
    with open(path) as f:
        first = f.readline().split()
    values = [float(v) for v in (first[1:] if first[0].endswith(":")
                                 else first)]
    if len(values) != 12:
        sys.exit("%s: line 1: expected 12 numbers" % path)
    return values[0], values[5], values[2], values[6]


def read_kitti_poses(path):
    poses = np.loadtxt(path, ndmin=2)
    if poses.shape[1] != 12:
        sys.exit("%s: expected 12 numbers per line" % path)
    return poses.reshape(-1, 3, 4)


def yaw_deg(r):
    """Rotation about the camera's y axis (KITTI: down), degrees."""
    return math.degrees(math.atan2(r[0, 2], r[2, 2]))


def image_path(folder, index):
    names = sorted(os.listdir(folder),
                   key=lambda n: int(os.path.splitext(n)[0]))
    return os.path.join(folder, names[index])


def image_rotation(a, b, k):
    """T_a_b's rotation from two images, or None."""
    corners = cv2.goodFeaturesToTrack(a, 3000, 0.005, 5)
    if corners is None:
        return None
    lk = dict(winSize=(15, 15), maxLevel=3)
    forward, ok1, _ = cv2.calcOpticalFlowPyrLK(a, b, corners, None, **lk)
    back, ok2, _ = cv2.calcOpticalFlowPyrLK(b, a, forward, None, **lk)
    good = ((ok1.ravel() == 1) & (ok2.ravel() == 1) &
            (np.linalg.norm(back - corners, axis=2).ravel() < 0.3))
    pa = corners[good].reshape(-1, 2).astype(np.float64)
    pb = forward[good].reshape(-1, 2).astype(np.float64)
    if len(pa) < 8:
        return None
    e, mask = cv2.findEssentialMat(pa, pb, k, cv2.USAC_ACCURATE, 0.9999, 0.3)
    if e is None or e.shape != (3, 3):
        return None
    inliers, r, _, _ = cv2.recoverPose(e, pa, pb, k, mask=mask)
    return r.T, inliers  # recoverPose gives x_b = R x_a + t.


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--sequence", default=os.path.join(
        os.environ.get("SLAM_DATASETS",
                       os.path.join(ROOT, "..", "shared", "datasets")),
        "stereo_kitti06_half"))
    parser.add_argument("--frames", type=int, default=20)
    parser.add_argument("--estimate", default="")
    args = parser.parse_args()
    fx, fy, cx, cy = read_calibration(os.path.join(args.sequence,
                                                   "calib.txt"))
    k = np.array([[fx, 0, cx], [0, fy, cy], [0, 0, 1]])
    gt = read_kitti_poses(os.path.join(args.sequence, "poses.txt"))
    est = read_kitti_poses(args.estimate) if args.estimate else None
    folder = os.path.join(args.sequence, "image_0")
    frames = min(args.frames, len(gt) - 1)
    print("| frames | inliers | yaw GT [deg] | yaw images [deg] | "
          "cum. images - GT [deg] | cum. estimate - GT [deg] |")
    print("|---|---|---|---|---|---|")
    cumulative = 0.0
    previous = cv2.imread(image_path(folder, 0), cv2.IMREAD_GRAYSCALE)
    for i in range(frames):
        current = cv2.imread(image_path(folder, i + 1), cv2.IMREAD_GRAYSCALE)
        if previous is None or current is None:
            sys.exit("%s: cannot read frame %d or %d" % (folder, i, i + 1))
        yaw_gt = yaw_deg(gt[i][:, :3].T @ gt[i + 1][:, :3])
        result = image_rotation(previous, current, k)
        if result is None:
            sys.exit("frames %d-%d: no essential matrix" % (i, i + 1))
        r, inliers = result
        cumulative += yaw_deg(r) - yaw_gt
        est_text = ""
        if est is not None and i + 1 < len(est):
            est_text = "%+.3f" % yaw_deg(gt[i + 1][:, :3].T @ est[i + 1][:, :3])
        print("| %d-%d | %d | %+.3f | %+.3f | %+.3f | %s |" %
              (i, i + 1, inliers, yaw_gt, yaw_deg(r), cumulative, est_text))
        previous = current


if __name__ == "__main__":
    main()
