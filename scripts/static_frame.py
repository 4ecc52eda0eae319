#!/usr/bin/env python3
"""Publishes the bag's cloud frame on /tf_static, an identity transform from `map`, and stays up.

scripts/demo runs it: rviz's global status reads "Fixed Frame [velodyne] does not exist" (a
warning) while no transform names the fixed frame, even though every display is in that frame.
Next to a real driver the robot's own tf tree does this; a replayed bag has none.

Usage: static_frame.py FRAME [PARENT]   (PARENT defaults to map)
"""
import sys

import rospy
from geometry_msgs.msg import TransformStamped
from tf2_msgs.msg import TFMessage


def main():
    argv = rospy.myargv()[1:]
    if not 1 <= len(argv) <= 2:
        sys.exit(__doc__)
    frame, parent = argv[0], argv[1] if len(argv) > 1 else "map"
    rospy.init_node("demo_static_frame", anonymous=True)
    t = TransformStamped()
    t.header.stamp = rospy.Time.now()
    t.header.frame_id = parent
    t.child_frame_id = frame
    t.transform.rotation.w = 1.0
    # latched, as tf2's static broadcaster: rviz gets it whenever it subscribes
    pub = rospy.Publisher("/tf_static", TFMessage, queue_size=1, latch=True)
    pub.publish(TFMessage(transforms=[t]))
    rospy.spin()


if __name__ == "__main__":
    main()
