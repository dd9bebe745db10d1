#!/usr/bin/env python3
"""rostest checker of replay.launch file:=...: the recording's events arrive on /dvs/events as
dvs_msgs/EventArray, exactly the known answers (count, ON count, first and last events with the
file's own times: run the launch with file_time:=original), the sensor size on /dvs/camera_info,
no packet lost (consecutive header.seq), and the driver's end-of-file log line names the file, the
detected format, the sensor size and the event count.

Parameters:
  ~file          the recording (as given to the launch file)
  ~count, ~on    events, ON events
  ~first, ~last  "x y t_us p"
  ~width, ~height  sensor size
  ~format        detected format as the driver names it (e.g. "Prophesee RAW EVT 3.0")
  ~timeout       s to wait for everything (default 90)
"""
import threading
import time
import unittest

import rospy
import rostest
from dvs_msgs.msg import EventArray
from rosgraph_msgs.msg import Log
from sensor_msgs.msg import CameraInfo

PKG = "dvs_launch"


def event_tuple(e):
    return (e.x, e.y, e.ts.secs * 1000000000 + e.ts.nsecs, 1 if e.polarity else 0)


def expected_tuple(text):
    x, y, t_us, p = (int(v) for v in text.split())
    return (x, y, t_us * 1000, p)


class ReplayEventsTest(unittest.TestCase):
    def setUp(self):
        self.lock = threading.Lock()
        self.count = self.on = self.packets = 0
        self.first = self.last = None
        self.seq_gaps = 0
        self.last_seq = None
        self.info = None
        self.logs = []

    def on_log(self, msg):
        with self.lock:
            self.logs.append(msg.msg)

    def on_info(self, msg):
        self.info = msg

    def on_events(self, msg):
        with self.lock:
            if self.last_seq is not None and msg.header.seq != self.last_seq + 1:
                self.seq_gaps += 1
            self.last_seq = msg.header.seq
            self.packets += 1
            if not msg.events:
                return
            if self.first is None:
                self.first = event_tuple(msg.events[0])
            self.last = event_tuple(msg.events[-1])
            self.count += len(msg.events)
            self.on += sum(1 for e in msg.events if e.polarity)

    def end_line(self, path):
        with self.lock:
            for line in self.logs:
                if line.startswith("dvs_driver: end of " + path):
                    return line
        return None

    def test_replay_gives_the_known_answers(self):
        path = rospy.get_param("~file")
        count = int(rospy.get_param("~count"))
        timeout = float(rospy.get_param("~timeout", 90.0))
        # The log first: the driver starts replaying once /dvs/events has a subscriber, and its
        # end-of-file line must not be missed.
        rospy.Subscriber("/rosout", Log, self.on_log, queue_size=1000)
        rospy.Subscriber("/dvs/camera_info", CameraInfo, self.on_info, queue_size=10)
        rospy.sleep(0.5)
        rospy.Subscriber("/dvs/events", EventArray, self.on_events, queue_size=100000)
        deadline = time.monotonic() + timeout
        while time.monotonic() < deadline and not rospy.is_shutdown():
            with self.lock:
                done = self.count >= count
            if done and self.end_line(path) is not None and self.info is not None:
                break
            time.sleep(0.1)
        rospy.sleep(0.5)  # anything arriving after the expected count would be an error
        with self.lock:
            self.assertEqual(self.count, count, "events received on /dvs/events in %d packets" % self.packets)
            self.assertEqual(self.on, int(rospy.get_param("~on")), "ON events")
            self.assertEqual(self.first, expected_tuple(rospy.get_param("~first")), "first event (x, y, t_ns, p)")
            self.assertEqual(self.last, expected_tuple(rospy.get_param("~last")), "last event (x, y, t_ns, p)")
            self.assertEqual(self.seq_gaps, 0, "packets lost (header.seq gaps)")
        self.assertIsNotNone(self.info, "no /dvs/camera_info")
        size = (int(rospy.get_param("~width")), int(rospy.get_param("~height")))
        self.assertEqual((self.info.width, self.info.height), size, "camera_info size")
        line = self.end_line(path)
        self.assertIsNotNone(line, "the driver's end-of-file log line (logs seen: %s)" % self.logs[-5:])
        for part in (rospy.get_param("~format"), "%dx%d" % size, "%d events" % count):
            self.assertIn(part, line)
        rospy.loginfo("check_replay_events: %d events in %d packets; %s", self.count, self.packets, line)


if __name__ == "__main__":
    rospy.init_node("check_replay_events")
    rostest.rosrun(PKG, "check_replay_events", ReplayEventsTest)
