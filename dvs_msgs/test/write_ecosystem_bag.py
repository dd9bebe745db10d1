#!/usr/bin/env python3
"""Write a bag the way another tool would: the rosbag Python API with raw, hand-serialised
dvs_msgs/EventArray messages carrying the ecosystem's type name, MD5 sum and definition text.
Nothing of our own package is imported, so the bag does not depend on our generated code.

usage: write_ecosystem_bag.py OUT.bag
The content is a fixed pattern that test_bag_compat.cpp checks field by field."""
import struct
import sys

import rosbag
import rospy

TYPE = "dvs_msgs/EventArray"
MD5 = "5e8beee5a6c107e504c2e78903c224b8"
FULL_TEXT = """# This message contains an array of events
# (0, 0) is at top-left corner of image
#

Header header

uint32 height         # image height, that is, number of rows
uint32 width          # image width, that is, number of columns

# an array of events
Event[] events

================================================================================
MSG: std_msgs/Header
# Standard metadata for higher-level stamped data types.
# This is generally used to communicate timestamped data
# in a particular coordinate frame.
#
# sequence ID: consecutively increasing ID
uint32 seq
#Two-integer timestamp that is expressed as:
# * stamp.sec: seconds (stamp_secs) since epoch (in Python the variable is called 'secs')
# * stamp.nsec: nanoseconds since stamp_secs (in Python the variable is called 'nsecs')
# time-handling sugar is provided by the client library
time stamp
#Frame this data is associated with
string frame_id

================================================================================
MSG: dvs_msgs/Event
# A DVS event
uint16 x
uint16 y
time ts
bool polarity
"""

PACKETS = 3
EVENTS_PER_PACKET = 1000


class EcosystemEventArray(object):
    """The type information rosbag needs for a raw write (what a genpy class would carry)."""
    _type = TYPE
    _md5sum = MD5
    _full_text = FULL_TEXT


def event_fields(packet, i):
    """Known pattern: exercises every field, including odd nanoseconds and both polarities."""
    n = packet * EVENTS_PER_PACKET + i
    x = (n * 7) % 128
    y = (n * 13) % 128
    secs = 1400000000 + packet
    nsecs = (n * 999983) % 1000000000  # not a multiple of 1000: nanoseconds must survive
    polarity = (n % 3) == 0
    return x, y, secs, nsecs, polarity


def serialise(packet):
    frame_id = ("dvs%d" % packet).encode()
    out = [struct.pack("<I", 17 + packet),                      # header.seq
           struct.pack("<II", 1400000000 + packet, 123456789),  # header.stamp
           struct.pack("<I", len(frame_id)), frame_id,          # header.frame_id
           struct.pack("<II", 128, 128),                        # height, width
           struct.pack("<I", EVENTS_PER_PACKET)]                # events[] length
    for i in range(EVENTS_PER_PACKET):
        x, y, secs, nsecs, polarity = event_fields(packet, i)
        out.append(struct.pack("<HHIIB", x, y, secs, nsecs, 1 if polarity else 0))
    return b"".join(out)


def main():
    if len(sys.argv) != 2:
        sys.stderr.write(__doc__)
        return 2
    with rosbag.Bag(sys.argv[1], "w") as bag:
        for p in range(PACKETS):
            data = serialise(p)
            bag.write("/dvs/events", (TYPE, data, MD5, None, EcosystemEventArray),
                      rospy.Time(1400000000 + p, 0), raw=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
