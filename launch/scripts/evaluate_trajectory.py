#!/usr/bin/env python3
"""Compare an estimated trajectory with ground truth and plot them like the thesis's Fig. 4.15.

usage: evaluate_trajectory.py --gt groundtruth.txt --est trajectory.txt [--plot out.png]
                              [--title TEXT] [--json out.json]

Both files: TUM lines `t tx ty tz qx qy qz qw` (T_world_camera; '#' comments allowed).
At every ground-truth sample from the first estimate on, the estimate in force is the latest
one at or before that time (what a controller would have had). Errors: position = norm of the
translation difference; orientation = angle of R_est^T R_gt. A sample counts as tracked when
its errors are under 10 cm and 10 deg. Prints one JSON line."""
import argparse
import json
import math
import sys

import numpy as np


def load_tum(path):
    rows = []
    with open(path) as f:
        for n, line in enumerate(f, 1):
            s = line.strip()
            if not s or s.startswith("#"):
                continue
            parts = s.split()
            if len(parts) != 8:
                sys.exit("%s:%d: expected 8 fields `t tx ty tz qx qy qz qw`, got %d" % (path, n, len(parts)))
            try:
                rows.append([float(p) for p in parts])
            except ValueError:
                sys.exit("%s:%d: not a number" % (path, n))
    if not rows:
        sys.exit("%s: no poses" % path)
    a = np.array(rows)
    if np.any(np.diff(a[:, 0]) < 0):
        sys.exit("%s: time stamps go backwards" % path)
    return a


def quat_to_rot(q):
    x, y, z, w = q / np.linalg.norm(q)
    return np.array([
        [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
        [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
        [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]])


def rot_to_rpy_deg(R):
    """roll (x), pitch (y), yaw (z) of R = Rz(yaw) Ry(pitch) Rx(roll), degrees."""
    pitch = math.asin(max(-1.0, min(1.0, -R[2, 0])))
    roll = math.atan2(R[2, 1], R[2, 2])
    yaw = math.atan2(R[1, 0], R[0, 0])
    return np.degrees([roll, pitch, yaw])


def evaluate(gt, est):
    idx = np.searchsorted(est[:, 0], gt[:, 0], side="right") - 1
    valid = idx >= 0
    g = gt[valid]
    e = est[idx[valid]]
    pos_err = np.linalg.norm(g[:, 1:4] - e[:, 1:4], axis=1)
    ang_err = np.empty(len(g))
    for i in range(len(g)):
        R = quat_to_rot(e[i, 4:8]).T @ quat_to_rot(g[i, 4:8])
        ang_err[i] = math.degrees(math.acos(max(-1.0, min(1.0, (np.trace(R) - 1) / 2))))
    return g, e, pos_err, ang_err


def plot(g, e, pos_err, ang_err, path, title):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    t0 = g[0, 0]
    t = g[:, 0] - t0
    # unwrapped so that full rolls (flips) draw as ramps, not saw teeth
    g_rpy = np.degrees(np.unwrap(np.radians([rot_to_rpy_deg(quat_to_rot(q)) for q in g[:, 4:8]]), axis=0))
    e_rpy_raw = np.array([rot_to_rpy_deg(quat_to_rot(q)) for q in e[:, 4:8]])
    # The estimate's angles drawn on the ground truth's branch (+-180 deg are the same angle).
    e_rpy = g_rpy + ((e_rpy_raw - g_rpy + 180.0) % 360.0 - 180.0)
    fig, axes = plt.subplots(3, 2, figsize=(12, 9), sharex=True)
    names = ["x [m]", "y [m]", "z [m]", "roll (about world x) [deg]", "pitch (about world y) [deg]",
             "yaw (about world z) [deg]"]
    for k in range(6):
        ax = axes[k % 3, k // 3]
        if k < 3:
            gt_v, est_v = g[:, 1 + k], e[:, 1 + k]
            err, err_label = 100.0 * (est_v - gt_v), "error [cm]"
        else:
            gt_v, est_v = g_rpy[:, k - 3], e_rpy[:, k - 3]
            err, err_label = (est_v - gt_v + 180.0) % 360.0 - 180.0, "error [deg]"
        ax.plot(t, gt_v, color="tab:blue", label="ground truth")
        ax.plot(t, est_v, color="tab:red", linestyle="--", label="estimate")
        ax.set_ylabel(names[k])
        ax.grid(True, alpha=0.3)
        # The error on its own scale (right axis), as in the thesis's Fig. 4.15.
        ax_err = ax.twinx()
        ax_err.plot(t, err, color="black", linewidth=0.7, label="error (right axis)")
        ax_err.set_ylabel(err_label)
        if k == 0:
            lines = ax.get_lines() + ax_err.get_lines()
            ax.legend(lines, [ln.get_label() for ln in lines], loc="best", fontsize=8)
    axes[2, 0].set_xlabel("t [s]")
    axes[2, 1].set_xlabel("t [s]")
    fig.suptitle("%s\nposition RMS %.2f cm, max %.2f cm; orientation RMS %.2f deg, max %.2f deg" % (
        title, 100 * math.sqrt(np.mean(pos_err ** 2)), 100 * pos_err.max(),
        math.sqrt(np.mean(ang_err ** 2)), ang_err.max()))
    fig.tight_layout()
    fig.savefig(path, dpi=90)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--gt", required=True)
    ap.add_argument("--est", required=True)
    ap.add_argument("--plot")
    ap.add_argument("--json")
    ap.add_argument("--title", default="estimate vs ground truth")
    args = ap.parse_args()
    gt = load_tum(args.gt)
    est = load_tum(args.est)
    g, e, pos_err, ang_err = evaluate(gt, est)
    if len(g) == 0:
        sys.exit("no ground-truth sample after the first estimate (t_est0 = %.6f, gt ends %.6f)" % (est[0, 0], gt[-1, 0]))
    tracked = np.logical_and(pos_err < 0.10, ang_err < 10.0)
    summary = {
        "gt_samples_evaluated": int(len(g)),
        "gt_samples_total": int(len(gt)),
        "first_estimate_after_s": float(est[0, 0] - gt[0, 0]),
        "position_rms_cm": round(100 * math.sqrt(float(np.mean(pos_err ** 2))), 3),
        "position_max_cm": round(100 * float(pos_err.max()), 3),
        "orientation_rms_deg": round(math.sqrt(float(np.mean(ang_err ** 2))), 3),
        "orientation_max_deg": round(float(ang_err.max()), 3),
        "tracked_percent": round(100.0 * float(np.mean(tracked)), 2),
        "estimates": int(len(est)),
    }
    if args.plot:
        plot(g, e, pos_err, ang_err, args.plot, args.title)
        summary["plot"] = args.plot
    line = json.dumps(summary)
    print(line)
    if args.json:
        with open(args.json, "w") as f:
            f.write(line + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
