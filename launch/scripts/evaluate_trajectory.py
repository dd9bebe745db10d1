#!/usr/bin/env python3
"""Score an estimated trajectory against ground truth with the suite's one accuracy metric and
plot them like the thesis's Fig. 4.15.

usage: evaluate_trajectory.py --gt groundtruth.txt --est trajectory.txt [--plot out.png]
                              [--title TEXT] [--json out.json] [--max-age S]

Both files: TUM lines `t tx ty tz qx qy qz qw` (T_world_camera; '#' comments allowed).
Every figure comes from dvs_calibration's `evaluate_trajectory` tool (trajectory_accuracy.h):
at every ground-truth sample from the first estimate on, the estimate in force is the latest
one at or before that time; a sample is tracked when that estimate is at most --max-age old
(default the tool's, 0.05 s) and within 10 cm and 10 deg. This script only converts the units
(cm, percent), adds the time of the first estimate after the first ground-truth sample, and
draws the plot. Prints one JSON line; exit 1 with a one-line message on a missing or malformed
file or when the tool is not built."""
import argparse
import json
import math
import os
import subprocess
import sys

TOOL_ENV = "DVS_EVALUATE_TRAJECTORY"  # path of the tool, overrides the search below


class EvaluationError(Exception):
    pass


def find_tool():
    """dvs_calibration's evaluate_trajectory: $DVS_EVALUATE_TRAJECTORY, else catkin_find (the
    devel or install space of the sourced workspace), else this source tree's devel space."""
    path = os.environ.get(TOOL_ENV)
    if path:
        if not os.access(path, os.X_OK):
            raise EvaluationError("%s=%s is not an executable" % (TOOL_ENV, path))
        return path
    try:
        out = subprocess.run(["catkin_find", "--first-only", "dvs_calibration", "evaluate_trajectory"],
                             capture_output=True, text=True, timeout=30).stdout.strip()
        if out and os.access(out.splitlines()[0], os.X_OK):
            return out.splitlines()[0]
    except (OSError, subprocess.SubprocessError):
        pass
    here = os.path.dirname(os.path.realpath(__file__))
    devel = os.path.join(here, "..", "..", "devel", "lib", "dvs_calibration", "evaluate_trajectory")
    if os.access(devel, os.X_OK):
        return os.path.realpath(devel)
    raise EvaluationError("dvs_calibration's evaluate_trajectory tool not found (build the workspace and "
                          "source devel/setup.bash, or set %s)" % TOOL_ENV)


def run_tool(gt_path, est_path, max_age=None, from_s=None, to_s=None):
    """The tool's JSON object for the two files (raises EvaluationError with its message).
    Other scripts (launch/test/check_pipeline.py) import this to score through the tool too."""
    for what, path in (("ground truth", gt_path), ("estimate", est_path)):
        if not os.path.isfile(path):
            raise EvaluationError("%s file %s does not exist" % (what, path))
    cmd = [find_tool(), "--groundtruth", gt_path, "--estimate", est_path]
    for option, value in (("--max-age", max_age), ("--from", from_s), ("--to", to_s)):
        if value is not None:
            cmd += [option, repr(float(value))]
    res = subprocess.run(cmd, capture_output=True, text=True)
    if res.returncode != 0:
        lines = res.stderr.strip().splitlines()
        raise EvaluationError(lines[0] if lines else "%s exited with %d" % (cmd[0], res.returncode))
    try:
        return json.loads(res.stdout.strip().splitlines()[-1])
    except (ValueError, IndexError):
        raise EvaluationError("%s printed no JSON object: %r" % (cmd[0], res.stdout[:200]))


def summary_of(metric):
    """The figures in the units the demo reports (cm, deg, percent); keys as before the tool."""
    if metric["samples"] == 0:
        raise EvaluationError("no ground-truth sample after the first estimate (first estimate %.6f s, "
                              "ground truth starts %.6f s)" % (metric["first_estimate_s"],
                                                               metric["groundtruth_start_s"]))
    return {
        "gt_samples_evaluated": int(metric["samples"]),
        "gt_samples_fresh": int(metric["samples_fresh"]),
        "gt_samples_total": int(metric["groundtruth_poses"]),
        "first_estimate_after_s": round(metric["first_estimate_s"] - metric["groundtruth_start_s"], 6),
        "position_rms_cm": round(100 * metric["rms_position_m"], 3),
        "position_max_cm": round(100 * metric["max_position_m"], 3),
        "orientation_rms_deg": round(metric["rms_orientation_deg"], 3),
        "orientation_max_deg": round(metric["max_orientation_deg"], 3),
        "tracked_percent": round(100.0 * metric["tracked_fraction"], 2),
        "estimates": int(metric["estimate_poses"]),
    }


# ---- plotting only: reads the (already validated) files and draws what the tool scored ----

def load_tum(path):
    import numpy as np
    rows = []
    with open(path) as f:
        for line in f:
            s = line.strip()
            if s and not s.startswith("#"):
                try:
                    rows.append([float(p) for p in s.replace(",", " ").split()])
                except ValueError:
                    continue  # a CSV header line (the tool has accepted the file)
    return np.array(rows)


def quat_to_rot(q):
    import numpy as np
    x, y, z, w = q / np.linalg.norm(q)
    return np.array([
        [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
        [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
        [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]])


def rot_to_rpy_deg(R):
    """roll (x), pitch (y), yaw (z) of R = Rz(yaw) Ry(pitch) Rx(roll), degrees."""
    import numpy as np
    pitch = math.asin(max(-1.0, min(1.0, -R[2, 0])))
    roll = math.atan2(R[2, 1], R[2, 2])
    yaw = math.atan2(R[1, 0], R[0, 0])
    return np.degrees([roll, pitch, yaw])


def plot(gt_path, est_path, summary, path, title):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import numpy as np
    gt, est = load_tum(gt_path), load_tum(est_path)
    # The estimate in force at each ground-truth sample (drawn as the metric pairs them).
    idx = np.searchsorted(est[:, 0], gt[:, 0], side="right") - 1
    g, e = gt[idx >= 0], est[idx[idx >= 0]]
    t = g[:, 0] - g[0, 0]
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
    fig.suptitle("%s\nposition RMS %.2f cm, max %.2f cm; orientation RMS %.2f deg, max %.2f deg; tracked %.1f %%" % (
        title, summary["position_rms_cm"], summary["position_max_cm"], summary["orientation_rms_deg"],
        summary["orientation_max_deg"], summary["tracked_percent"]))
    fig.tight_layout()
    fig.savefig(path, dpi=90)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--gt", required=True)
    ap.add_argument("--est", required=True)
    ap.add_argument("--plot")
    ap.add_argument("--json")
    ap.add_argument("--max-age", type=float, help="s; an older estimate counts as none (the tool's default)")
    ap.add_argument("--title", default="estimate vs ground truth")
    args = ap.parse_args()
    try:
        summary = summary_of(run_tool(args.gt, args.est, args.max_age))
        if args.plot:
            plot(args.gt, args.est, summary, args.plot, args.title)
            summary["plot"] = args.plot
        line = json.dumps(summary)
        if args.json:
            with open(args.json, "w") as f:
                f.write(line + "\n")
    except (EvaluationError, OSError) as e:
        sys.stderr.write("evaluate_trajectory.py: %s\n" % e)
        return 1
    print(line)
    return 0


if __name__ == "__main__":
    sys.exit(main())
