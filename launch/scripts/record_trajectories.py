#!/usr/bin/env python3
"""Record the tracker's estimate and the ground truth of a live run as TUM files, count the
events that flowed, and stop by itself when the run is over.

Writes into ~output_dir:
  estimate.tum      `t tx ty tz qx qy qz qw` (T_world_camera), every pose of ~estimate_topic
  groundtruth.tum   the same for ~groundtruth_topic
  run.json          counts, time spans, event rates (mean, peak over 10 ms), the latency of the
                    estimate (receipt time - stamp = the time of the event that produced it;
                    meaningful with wall-clock stamps, as the live simulator's), and the
                    tracker's last diagnostics (key: value)

~estimate_topic and ~groundtruth_topic may carry geometry_msgs/PoseStamped, nav_msgs/Path
(every pose with its own stamp: the tracker's per-packet batch of per-event poses, read straight
from the message bytes), geometry_msgs/PoseArray (one stamp for all: its last pose is recorded at
that stamp, and all its poses are counted) or geometry_msgs/TransformStamped; the type is read
from the connection. Events on ~events_topic are counted from the raw message bytes (no per-event
deserialisation in Python).

The node ends (exit code 0) once ground truth has arrived and then nothing new came on either
pose topic for ~idle_timeout seconds, or after ~timeout seconds in any case (exit code 1 when
nothing at all was recorded). Run it with required="true" in a launch file to end the launch.

Parameters:
  ~output_dir          string   (required)  created if missing
  ~estimate_topic      string   /dvs_line_tracker/poses
  ~groundtruth_topic   string   /dvs/ground_truth/pose
  ~events_topic        string   /dvs/events
  ~diagnostics_match   string   tracker     substring of the diagnostic status name to keep
  ~idle_timeout        double s 3.0
  ~timeout             double s 300
"""
import json
import os
import struct
import sys
import threading
import time

import roslib.message
import rospy
from diagnostic_msgs.msg import DiagnosticArray


def pose_count(msg):
    """Number of poses a message carries."""
    return len(msg.poses) if hasattr(msg, "poses") else 1


def poses_of(msg):
    """[(t, x, y, z, qx, qy, qz, qw)] of a pose-carrying message."""
    kind = msg._type
    out = []
    if kind == "geometry_msgs/PoseStamped":
        out.append((msg.header.stamp, msg.pose))
    elif kind == "nav_msgs/Path":
        out += [(p.header.stamp, p.pose) for p in msg.poses]
    elif kind == "geometry_msgs/PoseArray":
        # One stamp for the whole array (the tracker's per-packet batch: stamp = the packet's last
        # event): the pose in force at that time is the array's last one.
        if msg.poses:
            out.append((msg.header.stamp, msg.poses[-1]))
    elif kind == "geometry_msgs/TransformStamped":
        tr = msg.transform
        return [(msg.header.stamp.to_sec(), tr.translation.x, tr.translation.y, tr.translation.z,
                 tr.rotation.x, tr.rotation.y, tr.rotation.z, tr.rotation.w)]
    else:
        raise TypeError("unsupported pose message type %s" % kind)
    return [(s.to_sec(), p.position.x, p.position.y, p.position.z,
             p.orientation.x, p.orientation.y, p.orientation.z, p.orientation.w) for s, p in out]


def event_packet_info(raw):
    """(header stamp in s, number of events) of a serialised dvs_msgs/EventArray."""
    # Header: seq uint32, stamp 2 x uint32, frame_id (uint32 length + bytes); height, width, events[].
    secs, nsecs, frame_len = struct.unpack_from("<III", raw, 4)
    (n,) = struct.unpack_from("<I", raw, 16 + frame_len + 8)
    return secs + 1e-9 * nsecs, n


def stamped_array_header(raw):
    """(header stamp in s, element count, offset of the first element) of a serialised message
    made of a std_msgs/Header and one array (geometry_msgs/PoseArray, nav_msgs/Path)."""
    secs, nsecs, frame_len = struct.unpack_from("<III", raw, 4)
    (n,) = struct.unpack_from("<I", raw, 16 + frame_len)
    return secs + 1e-9 * nsecs, n, 20 + frame_len


def posearray_last_pose(raw):
    """(stamp in s, number of poses, last pose (x y z qx qy qz qw) or None) of a serialised
    geometry_msgs/PoseArray (header, uint32 count, count x 7 float64)."""
    stamp, n, first = stamped_array_header(raw)
    last = struct.unpack_from("<7d", raw, first + 56 * (n - 1)) if n > 0 else None
    return stamp, n, last


def path_poses(raw):
    """[(t, x, y, z, qx, qy, qz, qw)] of a serialised nav_msgs/Path (header, uint32 count, count x
    PoseStamped = header (seq, stamp, frame_id) + 7 float64), without deserialising messages."""
    _, n, off = stamped_array_header(raw)
    rows = []
    unpack_stamp, unpack_pose = struct.Struct("<III").unpack_from, struct.Struct("<7d").unpack_from
    for _ in range(n):
        _, secs, nsecs = unpack_stamp(raw, off)
        (frame_len,) = struct.unpack_from("<I", raw, off + 12)
        off += 16 + frame_len
        rows.append((secs + 1e-9 * nsecs,) + unpack_pose(raw, off))
        off += 56
    return rows


def peak_rate(packets, window):
    """Largest events/s over any `window` seconds of packet stamps [(t, n)]."""
    packets = sorted(packets)
    best, j, inside = 0.0, 0, 0
    for i, (t, n) in enumerate(packets):
        inside += n
        while packets[j][0] < t - window:
            inside -= packets[j][1]
            j += 1
        best = max(best, inside / window)
    return best


def percentile(values, q):
    v = sorted(values)
    return v[min(len(v) - 1, int(q / 100.0 * len(v)))] if v else 0.0


class Recorder:
    def __init__(self):
        self.output_dir = rospy.get_param("~output_dir", "")
        if not self.output_dir:
            raise ValueError("parameter ~output_dir must be set (directory for the TUM files)")
        self.idle_timeout = float(rospy.get_param("~idle_timeout", 3.0))
        self.timeout = float(rospy.get_param("~timeout", 300.0))
        if not self.idle_timeout > 0:
            raise ValueError("parameter ~idle_timeout must be > 0 (s)")
        if not self.timeout > 0:
            raise ValueError("parameter ~timeout must be > 0 (s)")
        self.diag_match = rospy.get_param("~diagnostics_match", "tracker")
        os.makedirs(self.output_dir, exist_ok=True)
        self.lock = threading.Lock()
        self.est, self.gt = [], []
        self.pose_counts = {id(self.est): 0, id(self.gt): 0}
        self.raw_paths = {}  # id(sink) -> serialised nav_msgs/Path messages, read in write()
        self.events = 0
        self.packets = 0
        self.event_packets = []
        self.latencies = []
        self.first_event_wall = None
        self.last_event_wall = None
        self.diagnostics = {}
        self.last_new = time.monotonic()
        self.errors = set()
        topics = {
            "estimate": rospy.get_param("~estimate_topic", "/dvs_line_tracker/poses"),
            "groundtruth": rospy.get_param("~groundtruth_topic", "/dvs/ground_truth/pose"),
        }
        self.topics = topics
        rospy.Subscriber(topics["estimate"], rospy.AnyMsg, self.on_pose, callback_args=self.est, queue_size=100000)
        rospy.Subscriber(topics["groundtruth"], rospy.AnyMsg, self.on_pose, callback_args=self.gt, queue_size=100000)
        rospy.Subscriber(rospy.get_param("~events_topic", "/dvs/events"), rospy.AnyMsg, self.on_events,
                         queue_size=100000)
        rospy.Subscriber("/diagnostics", DiagnosticArray, self.on_diagnostics, queue_size=100)

    def on_pose(self, raw, sink):
        kind = raw._connection_header["type"]
        if kind == "nav_msgs/Path":
            # The tracker's batches carry up to thousands of per-event poses: keep the bytes and
            # read the poses when writing (the callback stays short, so the latency measured here
            # is not that of this script's own backlog). The header stamp is the last pose's.
            received = rospy.get_rostime().to_sec()
            stamp, n, _ = stamped_array_header(raw._buff)
            with self.lock:
                self.raw_paths.setdefault(id(sink), []).append(raw._buff)
                if sink is self.est and n:
                    self.latencies.append(received - stamp)
                self.pose_counts[id(sink)] += n
                self.last_new = time.monotonic()
            return
        if kind == "geometry_msgs/PoseArray":
            # The tracker's batches are large (up to thousands of poses): read the stamp, the count
            # and the last pose straight from the bytes instead of deserialising every pose.
            received = rospy.get_rostime().to_sec()
            stamp, n, last = posearray_last_pose(raw._buff)
            with self.lock:
                if last is not None:
                    sink.append((stamp,) + last)
                    if sink is self.est:
                        self.latencies.append(received - stamp)
                self.pose_counts[id(sink)] += n
                self.last_new = time.monotonic()
            return
        cls = roslib.message.get_message_class(kind)
        try:
            if cls is None:
                raise TypeError("unknown message type %s" % kind)
            msg = cls()
            msg.deserialize(raw._buff)
            received = rospy.get_rostime().to_sec()
            rows = poses_of(msg)
            n = pose_count(msg)
        except TypeError as e:
            if str(e) not in self.errors:
                self.errors.add(str(e))
                rospy.logerr("record_trajectories: %s", e)
            return
        with self.lock:
            sink.extend(rows)
            self.pose_counts[id(sink)] += n
            if sink is self.est and rows:
                self.latencies.append(received - rows[-1][0])
            self.last_new = time.monotonic()

    def on_events(self, raw):
        stamp, n = event_packet_info(raw._buff)
        now = time.monotonic()
        with self.lock:
            self.event_packets.append((stamp, n))
            self.events += n
            self.packets += 1
            if self.first_event_wall is None:
                self.first_event_wall = now
            self.last_event_wall = now

    def on_diagnostics(self, msg):
        for status in msg.status:
            if self.diag_match in status.name:
                with self.lock:
                    self.diagnostics = {"name": status.name, "message": status.message}
                    self.diagnostics.update({kv.key: kv.value for kv in status.values})

    def finished(self):
        with self.lock:
            return (bool(self.gt) or bool(self.raw_paths.get(id(self.gt)))) and \
                time.monotonic() - self.last_new > self.idle_timeout

    def write(self, reason):
        with self.lock:
            for sink in (self.est, self.gt):
                for raw in self.raw_paths.pop(id(sink), []):
                    sink.extend(path_poses(raw))
            # Stable sort by time only: poses with equal stamps keep their order.
            est = sorted(self.est, key=lambda r: r[0])
            gt = sorted(self.gt, key=lambda r: r[0])
            for name, rows in (("estimate.tum", est), ("groundtruth.tum", gt)):
                with open(os.path.join(self.output_dir, name), "w") as f:
                    f.write("# t tx ty tz qx qy qz qw (T_world_camera)\n")
                    for r in rows:
                        f.write("%.9f %.6f %.6f %.6f %.7f %.7f %.7f %.7f\n" % r)
            span = (self.last_event_wall - self.first_event_wall) if self.events else 0.0
            run = {
                "end": reason,
                "estimate_topic": self.topics["estimate"],
                "groundtruth_topic": self.topics["groundtruth"],
                "estimates": len(est),
                "estimate_poses_received": self.pose_counts[id(self.est)],
                "groundtruth_poses": len(gt),
                "events": self.events,
                "event_packets": self.packets,
                "event_wall_span_s": round(span, 3),
                "estimate_span_s": round(est[-1][0] - est[0][0], 6) if est else 0.0,
                "groundtruth_span_s": round(gt[-1][0] - gt[0][0], 6) if gt else 0.0,
                "event_rate_mean_per_s": round(self.events / span) if span > 0 else 0,
                "event_rate_peak_10ms_per_s": round(peak_rate(self.event_packets, 0.01)),
                "estimate_latency_median_ms": round(1e3 * percentile(self.latencies, 50), 2),
                "estimate_latency_p99_ms": round(1e3 * percentile(self.latencies, 99), 2),
                "estimate_latency_max_ms": round(1e3 * max(self.latencies), 2) if self.latencies else 0.0,
                "tracker_diagnostics": self.diagnostics,
            }
        # Written last and atomically (a complete file appears under its name at once): a
        # reader that finds run.json finds it whole, and the TUM files above already closed.
        tmp = os.path.join(self.output_dir, ".run.json.tmp")
        with open(tmp, "w") as f:
            json.dump(run, f, indent=1)
            f.write("\n")
        os.replace(tmp, os.path.join(self.output_dir, "run.json"))
        rospy.loginfo("record_trajectories: %s: %d estimates, %d ground-truth poses, %d events -> %s",
                      reason, run["estimates"], run["groundtruth_poses"], run["events"], self.output_dir)
        return run


def main():
    rospy.init_node("record_trajectories")
    try:
        rec = Recorder()
    except ValueError as e:
        rospy.logfatal("record_trajectories: %s", e)
        return 2
    start = time.monotonic()
    reason = "shutdown"
    while not rospy.is_shutdown():
        if rec.finished():
            reason = "run over (nothing new for %.1f s)" % rec.idle_timeout
            break
        if time.monotonic() - start > rec.timeout:
            reason = "timeout (%.0f s)" % rec.timeout
            break
        time.sleep(0.1)
    run = rec.write(reason)
    return 0 if run["estimates"] and run["groundtruth_poses"] else 1


if __name__ == "__main__":
    sys.exit(main())
