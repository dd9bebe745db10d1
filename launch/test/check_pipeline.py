#!/usr/bin/env python3
"""rostest checker for a running launch file: events flow in, and the tracker's per-event
poses, TF (world -> dvs) and markers come out; the poses agree with ground truth.

Parameters:
  ~events_topic        /dvs/events
  ~pose_topic          /dvs_line_tracker/pose          (geometry_msgs/PoseStamped, per event)
  ~markers_topic       /dvs_line_tracker/markers       (visualization_msgs/MarkerArray)
  ~world_frame, ~camera_frame   world, dvs
  ~groundtruth_file    TUM file (time base = the pose stamps), or
  ~groundtruth_topic   geometry_msgs/PoseStamped topic (default /dvs/ground_truth/pose); at least
                       one message must arrive
  ~groundtruth_tolerance  s, largest stamp difference of a pose and its ground-truth sample (default 0.002)
  ~compare_first_seconds  s; > 0: compare only the poses stamped within this long after the first
                       ground-truth sample (and wait until the ground truth got there); 0 (default):
                       every pose received so far
  ~min_poses           per-event poses to receive (default 200)
  ~max_position_error  m, mean position error over the compared ground-truth samples, by the
                       suite's one metric (dvs_calibration's evaluate_trajectory) (default 0.05)
  ~max_angle_error     deg, mean orientation error, likewise (default 5)
  ~timeout             s to wait for everything (default 60)
  ~dump_dir            if set (or the environment's CHECK_PIPELINE_DUMP): write the compared
                       estimate and ground truth there as TUM files (estimate.tum,
                       groundtruth.tum), to look at a run, e.g.
                       CHECK_PIPELINE_DUMP=/tmp/run rostest dvs_launch screen_sim.test data_dir:=...

The event, marker and TF subscriptions are dropped once they have shown what they check: the
checker shares the machine with the pipeline it measures, and should load it as little as it can.
"""
import bisect
import os
import struct
import sys
import tempfile
import threading
import time
import unittest

import rospy
import rostest
import tf2_ros
from diagnostic_msgs.msg import DiagnosticArray
from geometry_msgs.msg import PoseStamped
from visualization_msgs.msg import MarkerArray

PKG = "dvs_launch"
sys.path.insert(0, os.path.join(os.path.dirname(os.path.realpath(__file__)), "..", "scripts"))
import evaluate_trajectory  # noqa: E402  (the suite's one accuracy metric, through its tool)


def write_tum(path, rows):
    with open(path, "w") as f:
        for r in rows:
            f.write("%.9f %.9f %.9f %.9f %.9f %.9f %.9f %.9f\n" % tuple(r))


def tool_report(poses, gt_rows, until, dump_dir=""):
    """dvs_calibration's evaluate_trajectory on the received poses and the ground truth up to
    `until` (s): its JSON object. With dump_dir, the two TUM files are also written there."""
    with tempfile.TemporaryDirectory(prefix="check_pipeline_") as d:
        folder = dump_dir or d
        os.makedirs(folder, exist_ok=True)
        est, gt = os.path.join(folder, "estimate.tum"), os.path.join(folder, "groundtruth.tum")
        write_tum(est, [r for r in poses if r[0] <= until])
        write_tum(gt, [r for r in gt_rows if r[0] <= until])
        return evaluate_trajectory.run_tool(gt, est)


def load_tum(path):
    rows = []
    with open(path) as f:
        for line in f:
            s = line.strip()
            if s and not s.startswith("#"):
                rows.append([float(v) for v in s.split()])
    return rows


class GroundTruth:
    """Poses by time; nearest sample lookup (ground truth comes at 1 kHz)."""

    def __init__(self):
        self.t, self.rows = [], []
        self.lock = threading.Lock()

    def add(self, row):
        with self.lock:
            if self.t and row[0] <= self.t[-1]:
                return
            self.t.append(row[0])
            self.rows.append(row)

    def rows_copy(self):
        with self.lock:
            return list(self.rows)

    def first_time(self):
        with self.lock:
            return self.t[0]

    def last_time(self):
        with self.lock:
            return self.t[-1]

    def __len__(self):
        with self.lock:
            return len(self.t)

    def at(self, t, tolerance=0.002):
        with self.lock:
            i = bisect.bisect_left(self.t, t)
            best = None
            for j in (i - 1, i):
                if 0 <= j < len(self.t) and abs(self.t[j] - t) <= tolerance:
                    if best is None or abs(self.t[j] - t) < abs(best[0] - t):
                        best = self.rows[j]
            return best


def row_of(msg):
    p, q = msg.pose.position, msg.pose.orientation
    return [msg.header.stamp.to_sec(), p.x, p.y, p.z, q.x, q.y, q.z, q.w]


class PipelineTest(unittest.TestCase):
    def setUp(self):
        self.timeout = float(rospy.get_param("~timeout", 60.0))
        self.min_poses = int(rospy.get_param("~min_poses", 200))
        self.world = rospy.get_param("~world_frame", "world")
        self.camera = rospy.get_param("~camera_frame", "dvs")
        self.events = 0
        self.poses = []
        self.pose_stamps_monotonic = True
        self.markers = []
        self.gt = GroundTruth()
        self.gt_tolerance = float(rospy.get_param("~groundtruth_tolerance", 0.002))
        gt_file = rospy.get_param("~groundtruth_file", "")
        self.gt_from_topic = not gt_file
        self.compare_first = float(rospy.get_param("~compare_first_seconds", 0.0))
        if gt_file:
            for row in load_tum(gt_file):
                self.gt.add(row)
        else:
            rospy.Subscriber(rospy.get_param("~groundtruth_topic", "/dvs/ground_truth/pose"), PoseStamped,
                             lambda m: self.gt.add(row_of(m)), queue_size=5000)
        self.tf_buffer = tf2_ros.Buffer(cache_time=rospy.Duration(30.0))
        self.tf_listener = tf2_ros.TransformListener(self.tf_buffer)
        self.dump_dir = rospy.get_param("~dump_dir", os.environ.get("CHECK_PIPELINE_DUMP", ""))
        self.events_sub = rospy.Subscriber(rospy.get_param("~events_topic", "/dvs/events"), rospy.AnyMsg,
                                           self.on_events, queue_size=1000)
        rospy.Subscriber(rospy.get_param("~pose_topic", "/dvs_line_tracker/pose"), PoseStamped, self.on_pose,
                         queue_size=2000)
        self.markers_sub = rospy.Subscriber(rospy.get_param("~markers_topic", "/dvs_line_tracker/markers"),
                                            MarkerArray, self.on_markers, queue_size=10)
        # The tracker's latest diagnostics (state, initialiser counters), quoted when a check fails.
        self.tracker_diagnostics = "none received"
        rospy.Subscriber("/diagnostics", DiagnosticArray, self.on_diagnostics, queue_size=10)

    def on_events(self, raw):
        buf = raw._buff
        (frame_len,) = struct.unpack_from("<I", buf, 12)
        (n,) = struct.unpack_from("<I", buf, 16 + frame_len + 8)
        self.events += n

    def on_pose(self, msg):
        row = row_of(msg)
        if self.poses and row[0] < self.poses[-1][0]:
            self.pose_stamps_monotonic = False
        self.poses.append(row)

    def on_diagnostics(self, msg):
        for s in msg.status:
            if "tracker" in s.name:
                self.tracker_diagnostics = "%s: %s [%s]" % (
                    s.name, s.message, ", ".join("%s=%s" % (kv.key, kv.value) for kv in s.values))

    def situation(self):
        """What a failure message needs to tell a slow start from a wrong one."""
        first = ("first pose %.2f s after the first ground-truth sample" % (self.poses[0][0] - self.gt.first_time())
                 if self.poses and len(self.gt) else "no pose or no ground truth yet")
        return "%s; tracker diagnostics: %s" % (first, self.tracker_diagnostics)

    def on_markers(self, msg):
        if msg.markers:
            self.markers.append(msg)

    def wait_for(self, what, condition):
        deadline = time.monotonic() + self.timeout
        while not rospy.is_shutdown() and time.monotonic() < deadline:
            if condition():
                return
            time.sleep(0.05)
        self.fail("timed out after %.0f s waiting for %s (events %d, ground-truth poses %d, poses %d, "
                  "marker arrays %d; %s)" % (self.timeout, what, self.events, len(self.gt), len(self.poses),
                                             len(self.markers), self.situation()))

    def test_pipeline(self):
        self.wait_for("events on the event topic", lambda: self.events > 0)
        self.events_sub.unregister()
        if self.gt_from_topic:
            self.wait_for("ground truth on its topic", lambda: len(self.gt) > 0)
        self.wait_for("markers", lambda: len(self.markers) > 0)
        self.markers_sub.unregister()
        self.wait_for("TF %s -> %s" % (self.world, self.camera),
                      lambda: self.tf_buffer.can_transform(self.world, self.camera, rospy.Time(0)))
        # The TF agrees with the poses' frame convention: world -> dvs is the camera pose.
        tf = self.tf_buffer.lookup_transform(self.world, self.camera, rospy.Time(0))
        self.assertEqual(tf.header.frame_id.lstrip("/"), self.world)
        self.tf_listener.unregister()
        self.wait_for("%d per-event poses" % self.min_poses, lambda: len(self.poses) >= self.min_poses)
        self.assertTrue(self.pose_stamps_monotonic, "per-event pose stamps went backwards")

        # Accuracy: every received pose that has a ground-truth sample within the tolerance (2 ms).
        compare_until = float("inf")
        if self.compare_first > 0:
            compare_until = self.gt.first_time() + self.compare_first
            self.wait_for("ground truth %.1f s after its first sample" % self.compare_first,
                          lambda: self.gt.last_time() >= compare_until)
        else:
            self.wait_for("ground truth around the poses",
                          lambda: self.gt.at(self.poses[-1][0], self.gt_tolerance) is not None)
        # Coverage: enough poses have a ground-truth sample within the tolerance (time bases agree).
        poses = [r for r in list(self.poses) if r[0] <= compare_until]
        compared = sum(1 for r in poses if self.gt.at(r[0], self.gt_tolerance) is not None)
        self.assertGreaterEqual(compared, self.min_poses // 2,
                                "only %d of %d poses have ground truth within %.1f ms%s" % (
                                    compared, len(self.poses), 1e3 * self.gt_tolerance,
                                    "" if self.compare_first <= 0 else
                                    " in the first %.1f s of ground truth" % self.compare_first) +
                                "; " + self.situation())
        # Accuracy through the suite's one metric (dvs_calibration's evaluate_trajectory): every
        # ground-truth sample from the first pose to the last compared one.
        report = tool_report(poses, self.gt.rows_copy(), min(compare_until, poses[-1][0]), self.dump_dir)
        rospy.loginfo("check_pipeline: %d events, %d ground-truth poses, %d poses (%d with ground truth; the first "
                      "pose %.2f s after the first ground truth); evaluate_trajectory: %s", self.events, len(self.gt),
                      len(self.poses), compared, self.poses[0][0] - self.gt.first_time(), report)
        self.assertGreater(report["samples_fresh"], 0, "no ground-truth sample with a fresh estimate: %s" % report)
        self.assertLess(report["mean_position_m"], float(rospy.get_param("~max_position_error", 0.05)),
                        "mean position error %.3f m (%s)" % (report["mean_position_m"], report))
        self.assertLess(report["mean_orientation_deg"], float(rospy.get_param("~max_angle_error", 5.0)),
                        "mean orientation error %.2f deg (%s)" % (report["mean_orientation_deg"], report))


if __name__ == "__main__":
    rospy.init_node("check_pipeline")
    rostest.rosrun(PKG, "check_pipeline", PipelineTest, sys.argv)
