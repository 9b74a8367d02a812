#!/usr/bin/env python
# Lecture 6 assignment 3 habit: spawn a part next to robot 2 and read it as the last model
# camera 2 lists.
import json
import sys

import rospy
from omtp_gazebo.msg import LogicalCameraImage
from std_srvs.srv import Empty


def logical_camera2_callback(data):
    if data.models[-1].type == "object":
        found.append(data.models[-1].pose.position.x)


found = []
rospy.init_node("lecture6_assignment3", anonymous=True)
rospy.wait_for_service("/spawn_object_at_robot2")
rospy.ServiceProxy("/spawn_object_at_robot2", Empty)()
rospy.sleep(2.0)
rospy.Subscriber("omtp/logical_camera_2", LogicalCameraImage, logical_camera2_callback)
rospy.sleep(1.0)
image = rospy.wait_for_message("/omtp/logical_camera_2", LogicalCameraImage)
json.dump(
    {"types": [m.type for m in image.models], "found": len(found), "x": found[-1]}, open(sys.argv[1], "w")
)
