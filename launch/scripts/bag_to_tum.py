#!/usr/bin/env python3
"""Write the poses of one bag topic as a TUM file `t tx ty tz qx qy qz qw`.

usage: bag_to_tum.py BAG TOPIC OUT.tum

TOPIC may carry geometry_msgs/PoseStamped, nav_msgs/Path (every pose with its own stamp: the
tracker's per-packet batches), geometry_msgs/PoseArray (its last pose at its stamp) or geometry_msgs/TransformStamped. Prints one
JSON line {"poses": N, "out": OUT}. Exit code 1 (message naming the problem) when the bag cannot
be read or the topic is missing or of another type."""
import json
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.realpath(__file__)))
from record_trajectories import poses_of  # noqa: E402


def main(argv):
    if len(argv) != 4:
        sys.stderr.write(__doc__)
        return 2
    bag_path, topic, out = argv[1:]
    import rosbag
    try:
        bag = rosbag.Bag(bag_path)
    except Exception as e:  # rosbag raises several types for missing/corrupt files
        sys.stderr.write("bag_to_tum: cannot read %s: %s\n" % (bag_path, e))
        return 1
    topics = bag.get_type_and_topic_info().topics
    if topic not in topics:
        sys.stderr.write("bag_to_tum: %s has no topic %s (it has: %s)\n" % (bag_path, topic, ", ".join(sorted(topics))))
        return 1
    rows = []
    try:
        for _, msg, _ in bag.read_messages(topics=[topic]):
            rows += poses_of(msg)
    except TypeError as e:
        sys.stderr.write("bag_to_tum: %s: %s\n" % (topic, e))
        return 1
    rows.sort(key=lambda r: r[0])  # stable: equal stamps keep their order
    with open(out, "w") as f:
        f.write("# t tx ty tz qx qy qz qw (T_world_camera) from %s %s\n" % (os.path.basename(bag_path), topic))
        for r in rows:
            f.write("%.9f %.6f %.6f %.6f %.7f %.7f %.7f %.7f\n" % r)
    print(json.dumps({"poses": len(rows), "out": out}))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
