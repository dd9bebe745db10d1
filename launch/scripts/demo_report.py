#!/usr/bin/env python3
"""Print the demo's results from its output directory (scripts/demo.sh calls this).

usage: demo_report.py OUT_DIR

Reads OUT_DIR/run.json (record_trajectories.py) and OUT_DIR/accuracy.json
(evaluate_trajectory.py), prints accuracy, throughput and where the outputs are, and writes
OUT_DIR/summary.json with the same figures."""
import json
import os
import sys


def number(value):
    try:
        return float(value)
    except (TypeError, ValueError):
        return None


def main(argv):
    if len(argv) != 2:
        sys.stderr.write(__doc__)
        return 2
    out = argv[1]
    try:
        with open(os.path.join(out, "run.json")) as f:
            run = json.load(f)
        with open(os.path.join(out, "accuracy.json")) as f:
            acc = json.loads(f.read().strip().splitlines()[-1])
    except (OSError, ValueError, IndexError) as e:
        sys.stderr.write("demo_report.py: cannot read the demo's results in %s: %s\n" % (out, e))
        return 1
    diag = run.get("tracker_diagnostics", {})
    summary = {
        "position_rms_cm": acc["position_rms_cm"],
        "position_max_cm": acc["position_max_cm"],
        "orientation_rms_deg": acc["orientation_rms_deg"],
        "orientation_max_deg": acc["orientation_max_deg"],
        "tracked_percent": acc["tracked_percent"],
        "first_estimate_after_s": acc["first_estimate_after_s"],
        "events": run["events"],
        "pose_updates": run["estimate_poses_received"],
        "event_rate_mean_per_s": run["event_rate_mean_per_s"],
        "event_rate_peak_10ms_per_s": run["event_rate_peak_10ms_per_s"],
        "estimate_latency_median_ms": run["estimate_latency_median_ms"],
        "estimate_latency_p99_ms": run["estimate_latency_p99_ms"],
        "estimate_latency_max_ms": run["estimate_latency_max_ms"],
        "tracker_state": diag.get("state", diag.get("message", "")),
        "tracker_losses": diag.get("losses"),
        "tracker_latency_split": {k[len("latency: "):]: v for k, v in diag.items() if k.startswith("latency: ")},
    }
    with open(os.path.join(out, "summary.json"), "w") as f:
        json.dump(summary, f, indent=1)
        f.write("\n")

    print("")
    print("=== demo: 1200 deg/s flip, software DVS -> tracker nodelet (live) ===")
    print("accuracy vs ground truth (%d ground-truth samples at 1 kHz, from the first estimate on):"
          % acc["gt_samples_evaluated"])
    print("  position    RMS %6.2f cm   max %6.2f cm" % (acc["position_rms_cm"], acc["position_max_cm"]))
    print("  orientation RMS %6.2f deg  max %6.2f deg" % (acc["orientation_rms_deg"], acc["orientation_max_deg"]))
    print("  tracked (estimate at most 50 ms old, error within 10 cm and 10 deg): %.1f %% of the samples; "
          "first estimate %.3f s after the start"
          % (acc["tracked_percent"], acc["first_estimate_after_s"]))
    print("throughput (live, real time, both in one nodelet manager on this machine):")
    print("  the tracker received %d events in %.2f s: %.0f events/s on average, %.0f events/s peak (10 ms),"
          % (run["events"], run["event_wall_span_s"], run["event_rate_mean_per_s"], run["event_rate_peak_10ms_per_s"]))
    print("  and published %d per-event pose updates; pose latency (event time -> pose received):"
          " median %.2f ms, p99 %.2f ms, max %.2f ms"
          % (run["estimate_poses_received"], run["estimate_latency_median_ms"], run["estimate_latency_p99_ms"],
             run["estimate_latency_max_ms"]))
    if diag:
        print("  tracker state at its last diagnostics: %s, losses %s, re-initialisations %s"
              % (diag.get("state", diag.get("message", "?")), diag.get("losses", "?"), diag.get("re-initializations", "?")))
        split = [(k[len("latency: "):], v) for k, v in diag.items() if k.startswith("latency: ")]
        if split:
            print("  the tracker's own latency split (per event, from its diagnostics; the recorder's figure above adds"
                  " the Python recorder's receipt):")
            for k, v in split:
                print("    %-58s %s" % (k, v))
    print("outputs in %s:" % out)
    for name, what in (("flip.png", "estimate vs ground truth per axis and angle, with errors (Fig. 4.15-like)"),
                       ("estimate.tum", "tracker poses, TUM"), ("groundtruth.tum", "ground truth, TUM"),
                       ("summary.json", "the figures above"), ("launch.log", "the ROS launch output")):
        print("  %-16s %s" % (name, what))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
