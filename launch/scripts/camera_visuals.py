#!/usr/bin/env python3
"""Camera frusta and recent-trajectory paths for rviz, from TF (any source, any rate).

For every frame in ~frames (default: dvs = the tracker's estimate, dvs_gt = the simulator's
ground truth) this node publishes
  ~markers          visualization_msgs/MarkerArray: a frustum (LINE_LIST, frame-locked to the
                    camera frame, sized from /dvs/camera_info or the DVS128 preset) and a label
  ~path/<frame>     nav_msgs/Path: the camera centre over the last ~path_length seconds
by looking up TF world -> <frame> at ~rate Hz, and draws the tracker's state (std_msgs/String on
~state_topic) as a text marker in the world frame at ~state_position (in ~markers, ns "state"). Frames that do not exist (yet) are skipped
silently, so the same node serves flight, replay and simulation.

Parameters (all validated at start-up):
  ~frames          list of string   [dvs, dvs_gt]     camera frames to draw
  ~colors          list of [r,g,b]  [[1,0.5,0],[0,0.8,1]]  one colour per frame
  ~world_frame     string           world
  ~rate            double  Hz       30                 TF sampling rate
  ~path_length     double  s        3                  trajectory kept in the path
  ~frustum_depth   double  m        0.25               distance of the frustum's far rectangle
  ~state_topic     string           /dvs_line_tracker/state   the tracker's state (empty: none)
  ~state_position  [x,y,z] m        [0, -0.75, 0]      where the state text is drawn
"""
import math
import sys

import rospy
import tf2_ros
from geometry_msgs.msg import Point, PoseStamped
from nav_msgs.msg import Path
from sensor_msgs.msg import CameraInfo
from std_msgs.msg import ColorRGBA, String
from visualization_msgs.msg import Marker, MarkerArray

# DVS128 preset (dvs_calibration): used until a camera_info arrives.
DEFAULT_INTRINSICS = (128, 128, 115.0, 115.0, 63.5, 63.5)


def frustum_points(intrinsics, depth):
    """The 16 LINE_LIST points of a pinhole frustum (apex at the origin, far rectangle at z = depth)."""
    w, h, fx, fy, cx, cy = intrinsics
    corners = []
    for u, v in ((0.0, 0.0), (w, 0.0), (w, h), (0.0, h)):
        corners.append(Point(x=(u - cx) / fx * depth, y=(v - cy) / fy * depth, z=depth))
    apex = Point(0.0, 0.0, 0.0)
    pts = []
    for i in range(4):
        pts += [apex, corners[i], corners[i], corners[(i + 1) % 4]]
    return pts


class CameraVisuals:
    def __init__(self):
        self.frames = rospy.get_param("~frames", ["dvs", "dvs_gt"])
        self.colors = rospy.get_param("~colors", [[1.0, 0.5, 0.0], [0.0, 0.8, 1.0]])
        self.world = rospy.get_param("~world_frame", "world")
        self.rate = float(rospy.get_param("~rate", 30.0))
        self.path_length = float(rospy.get_param("~path_length", 3.0))
        self.depth = float(rospy.get_param("~frustum_depth", 0.25))
        if not isinstance(self.frames, list) or not self.frames or not all(isinstance(f, str) and f for f in self.frames):
            raise ValueError("parameter ~frames must be a non-empty list of frame names")
        if not isinstance(self.colors, list) or len(self.colors) < len(self.frames) or \
                not all(isinstance(c, list) and len(c) == 3 for c in self.colors):
            raise ValueError("parameter ~colors must hold one [r, g, b] per frame of ~frames")
        if not self.world:
            raise ValueError("parameter ~world_frame must not be empty")
        if not self.rate > 0:
            raise ValueError("parameter ~rate must be > 0 (Hz)")
        if not self.path_length > 0:
            raise ValueError("parameter ~path_length must be > 0 (s)")
        if not self.depth > 0:
            raise ValueError("parameter ~frustum_depth must be > 0 (m)")
        self.state_topic = rospy.get_param("~state_topic", "/dvs_line_tracker/state")
        self.state_position = rospy.get_param("~state_position", [0.0, -0.75, 0.0])
        if not isinstance(self.state_position, list) or len(self.state_position) != 3:
            raise ValueError("parameter ~state_position must be [x, y, z] (m)")
        self.state = None
        self.intrinsics = DEFAULT_INTRINSICS
        self.paths = {f: [] for f in self.frames}
        self.buffer = tf2_ros.Buffer(cache_time=rospy.Duration(10.0))
        self.listener = tf2_ros.TransformListener(self.buffer)
        self.marker_pub = rospy.Publisher("~markers", MarkerArray, queue_size=1, latch=True)
        self.path_pubs = {f: rospy.Publisher("~path/" + f, Path, queue_size=1) for f in self.frames}
        rospy.Subscriber("dvs/camera_info", CameraInfo, self.on_info, queue_size=1)
        if self.state_topic:
            rospy.Subscriber(self.state_topic, String, self.on_state, queue_size=10)
        self.publish_markers()
        self.timer = rospy.Timer(rospy.Duration(1.0 / self.rate), self.on_timer)

    def on_info(self, msg):
        if msg.width > 0 and msg.height > 0 and msg.K[0] > 0 and msg.K[4] > 0:
            intr = (msg.width, msg.height, msg.K[0], msg.K[4], msg.K[2], msg.K[5])
            if intr != self.intrinsics:
                self.intrinsics = intr
                self.publish_markers()

    def on_state(self, msg):
        self.state = msg.data
        self.publish_markers()

    def publish_markers(self):
        arr = MarkerArray()
        if self.state is not None:
            t = Marker()
            t.header.frame_id = self.world
            t.ns = "state"
            t.type = Marker.TEXT_VIEW_FACING
            t.action = Marker.ADD
            t.pose.position.x, t.pose.position.y, t.pose.position.z = (float(v) for v in self.state_position)
            t.pose.orientation.w = 1.0
            t.scale.z = 0.12
            t.color = ColorRGBA(1.0, 1.0, 1.0, 1.0)
            t.text = "tracker: " + self.state
            arr.markers.append(t)
        for i, frame in enumerate(self.frames):
            r, g, b = self.colors[i]
            m = Marker()
            m.header.frame_id = frame
            m.ns = "frustum"
            m.id = i
            m.type = Marker.LINE_LIST
            m.action = Marker.ADD
            m.frame_locked = True
            m.pose.orientation.w = 1.0
            m.scale.x = 0.012
            m.color = ColorRGBA(r, g, b, 1.0)
            m.points = frustum_points(self.intrinsics, self.depth)
            arr.markers.append(m)
            t = Marker()
            t.header.frame_id = frame
            t.ns = "label"
            t.id = i
            t.type = Marker.TEXT_VIEW_FACING
            t.action = Marker.ADD
            t.frame_locked = True
            t.pose.position.y = -0.12
            t.pose.orientation.w = 1.0
            t.scale.z = 0.08
            t.color = ColorRGBA(r, g, b, 1.0)
            t.text = frame
            arr.markers.append(t)
        self.marker_pub.publish(arr)

    def on_timer(self, _event):
        now = rospy.Time.now()
        for frame in self.frames:
            try:
                tf = self.buffer.lookup_transform(self.world, frame, rospy.Time(0))
            except (tf2_ros.LookupException, tf2_ros.ConnectivityException, tf2_ros.ExtrapolationException):
                continue
            path = self.paths[frame]
            stamp = tf.header.stamp
            if path and stamp <= path[-1].header.stamp:
                continue  # no new pose
            p = PoseStamped()
            p.header.frame_id = self.world
            p.header.stamp = stamp
            p.pose.position.x = tf.transform.translation.x
            p.pose.position.y = tf.transform.translation.y
            p.pose.position.z = tf.transform.translation.z
            p.pose.orientation = tf.transform.rotation
            path.append(p)
            # Keep the last path_length seconds (of the poses' own time).
            cutoff = stamp - rospy.Duration(self.path_length)
            while path and path[0].header.stamp < cutoff:
                path.pop(0)
            msg = Path()
            msg.header.frame_id = self.world
            msg.header.stamp = now
            msg.poses = path
            self.path_pubs[frame].publish(msg)


def main():
    rospy.init_node("camera_visuals")
    try:
        CameraVisuals()
    except ValueError as e:
        rospy.logfatal("camera_visuals: %s", e)
        return 1
    rospy.spin()
    return 0


if __name__ == "__main__":
    sys.exit(main())
