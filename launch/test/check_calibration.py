#!/usr/bin/env python3
"""rostest checker of calibration.launch: events replayed by the driver reach the calibration
nodelet in the same manager, which publishes a focus score per window and a preview image of
the accumulated window (sensor size x preview_upscale).

Parameters: ~timeout (s, default 60), ~min_scores (default 5), ~width, ~height (sensor, 128),
~upscale (4)."""
import sys
import time
import unittest

import rospy
import rostest
from sensor_msgs.msg import Image
from std_msgs.msg import Float64, UInt32

PKG = "dvs_launch"


class CalibrationLaunchTest(unittest.TestCase):
    def test_windows_flow(self):
        scores, previews, views = [], [], []
        rospy.Subscriber("/dvs_calibration/focus_score", Float64, lambda m: scores.append(m.data), queue_size=100)
        rospy.Subscriber("/dvs_calibration/preview", Image, lambda m: previews.append(m), queue_size=2)
        rospy.Subscriber("/dvs_calibration/views", UInt32, lambda m: views.append(m.data), queue_size=2)
        need = int(rospy.get_param("~min_scores", 5))
        deadline = time.monotonic() + float(rospy.get_param("~timeout", 60.0))
        while time.monotonic() < deadline and not rospy.is_shutdown():
            if len(scores) >= need and previews and views:
                break
            time.sleep(0.05)
        self.assertGreaterEqual(len(scores), need, "focus scores received: %d" % len(scores))
        self.assertTrue(previews, "no preview image")
        self.assertTrue(views, "no (latched) view count")
        # A moving square's edges give events in every window: positive, finite scores.
        self.assertTrue(all(s > 0 and s < 1e9 for s in scores), scores[:10])
        up = int(rospy.get_param("~upscale", 4))
        p = previews[-1]
        self.assertEqual((p.width, p.height), (int(rospy.get_param("~width", 128)) * up,
                                               int(rospy.get_param("~height", 128)) * up))
        self.assertEqual(views[0], 0, "no grid in this scene: no view may be kept")


if __name__ == "__main__":
    rospy.init_node("check_calibration")
    rostest.rosrun(PKG, "check_calibration", CalibrationLaunchTest, sys.argv)
