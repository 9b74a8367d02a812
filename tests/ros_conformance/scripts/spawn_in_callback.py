#!/usr/bin/env python
# Ask for a new part whenever camera 2 sees none in reach... or sees one: the course's
# habit of calling the spawn service from a callback.
import json
import sys

import rospy
from omtp_gazebo.msg import LogicalCameraImage
from std_msgs.msg import Header
from std_srvs.srv import Empty

calls = []
spawned = []


def camera_cb(msg):
    if len(calls) < 1:
        spawn_object()
        calls.append(rospy.get_time())


def spawned_cb(msg):
    spawned.append([msg.seq, msg.stamp.to_sec(), msg.frame_id])


if __name__ == "__main__":
    rospy.init_node("spawn_from_callback")
    spawn_object = rospy.ServiceProxy("/spawn_object_at_robot2", Empty)
    rospy.Subscriber("/omtp/logical_camera_2", LogicalCameraImage, camera_cb)
    rospy.sleep(2.0)
    rospy.Subscriber("/spawned_part", Header, spawned_cb)
    rospy.sleep(0.5)
    with open(sys.argv[1], "w") as f:
        json.dump({"calls": calls, "spawned": spawned}, f)
