#!/usr/bin/env python3
"""rostest checker of the demo's recording path: simulation.launch with record_dir must end the
recording by itself (run.json written), leave estimate.tum and groundtruth.tum covering the
flip, and evaluate_trajectory.py must score the estimate against ground truth and draw the plot.

Parameters: ~out_dir (the launch's record_dir), ~timeout (s, default 90),
~max_position_rms_cm (default 8), ~max_orientation_rms_deg (default 4), ~min_tracked_percent (90).
"""
import json
import os
import subprocess
import sys
import time
import unittest

import rospy
import rostest

PKG = "dvs_launch"
HERE = os.path.dirname(os.path.realpath(__file__))


class RecordTest(unittest.TestCase):
    def test_record_and_evaluate(self):
        out = rospy.get_param("~out_dir")
        timeout = float(rospy.get_param("~timeout", 90.0))
        run_json = os.path.join(out, "run.json")
        start = time.time()
        deadline = time.monotonic() + timeout
        run = None
        # The recorder writes run.json last and atomically (after the TUM files): wait until a
        # fresh one parses; polling a condition, not a fixed delay.
        while run is None and time.monotonic() < deadline and not rospy.is_shutdown():
            try:
                if os.path.getmtime(run_json) >= start - 1:
                    with open(run_json) as f:
                        run = json.load(f)
            except (OSError, ValueError):
                pass
            if run is None:
                time.sleep(0.2)
        if run is None:
            self.fail("the recorder did not end the run within %.0f s (no fresh, complete %s)" % (timeout, run_json))
        self.assertTrue(run["end"].startswith("run over"), run["end"])
        self.assertGreater(run["events"], 10000, "events counted on /dvs/events")
        self.assertGreater(run["estimates"], 1000, "tracker pose batches recorded")
        self.assertGreater(run["estimate_poses_received"], 50000, "per-event pose updates in the batches")
        # The flip lasts 1.5 s; ground truth at 1 kHz.
        self.assertGreater(run["groundtruth_poses"], 1400)
        self.assertGreater(run["groundtruth_span_s"], 1.4)
        plot = os.path.join(out, "test_plot.png")
        if os.path.exists(plot):
            os.remove(plot)
        res = subprocess.run([sys.executable, os.path.join(HERE, "..", "scripts", "evaluate_trajectory.py"),
                              "--gt", os.path.join(out, "groundtruth.tum"), "--est", os.path.join(out, "estimate.tum"),
                              "--plot", plot], capture_output=True, text=True, timeout=120)
        self.assertEqual(res.returncode, 0, res.stderr)
        summary = json.loads(res.stdout.strip().splitlines()[-1])
        rospy.loginfo("check_record: %s", summary)
        self.assertTrue(os.path.getsize(plot) > 10000, "plot written")
        self.assertLess(summary["position_rms_cm"], float(rospy.get_param("~max_position_rms_cm", 8.0)))
        self.assertLess(summary["orientation_rms_deg"], float(rospy.get_param("~max_orientation_rms_deg", 4.0)))
        self.assertGreater(summary["tracked_percent"], float(rospy.get_param("~min_tracked_percent", 90.0)))


if __name__ == "__main__":
    rospy.init_node("check_record")
    rostest.rosrun(PKG, "check_record", RecordTest, sys.argv)
