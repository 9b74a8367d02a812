#!/usr/bin/env python
# Lecture 6 assignment 4 (robot 1) habit: a relative topic name with a trailing slash.
import json
import sys

import rospy
from omtp_gazebo.msg import LogicalCameraImage

images = []


def logical_camera1_callback(data):
    images.append(data.pose.position.x)


if __name__ == "__main__":
    rospy.init_node("lecture6_assignment4", anonymous=True)
    sub = rospy.Subscriber(
        "omtp/logical_camera_1/", LogicalCameraImage, logical_camera1_callback, queue_size=1
    )
    rospy.sleep(1.0)
    with open(sys.argv[1], "w") as f:
        json.dump({"images": images, "topic": sub.name}, f)
