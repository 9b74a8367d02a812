#!/usr/bin/env python
# A node configured from its command line: a private parameter (~rate, set with
# _rate:=...), a remapped camera topic (omtp/logical_camera:=...), rospy.myargv for the
# script's own arguments.
import json

import rospy
from omtp_gazebo.msg import LogicalCameraImage

if __name__ == "__main__":
    rospy.init_node("camera_reader")
    args = rospy.myargv()
    rate = rospy.get_param("~rate", 10)
    rospy.set_param("~seen", True)
    image = rospy.wait_for_message("omtp/logical_camera", LogicalCameraImage, timeout=2.0)
    with open(args[1], "w") as f:
        json.dump(
            {
                "args": args[2:],
                "rate": rate,
                "seen_param": rospy.get_param(rospy.get_name() + "/seen"),
                "name": rospy.get_name(),
                "namespace": rospy.get_namespace(),
                "camera_x": image.pose.position.x,
                "resolved": rospy.resolve_name("omtp/logical_camera"),
            },
            f,
        )
