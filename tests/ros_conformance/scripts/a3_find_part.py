#!/usr/bin/env python
# Lecture 6 assignment 3: (after `rosservice call /spawn_object_at_robot2`) the part's
# pose seen by logical camera 2, in the vacuum_gripper2_suction_cup frame.
import json
import sys

import rospy
import tf2_geometry_msgs  # noqa: F401
import tf2_ros
from gazebo_msgs.srv import SpawnModel  # noqa: F401  (left from trying things out)
from geometry_msgs.msg import PoseStamped
from omtp_gazebo.msg import LogicalCameraImage

rospy.init_node("lecture6_assignment3")
tf_buffer = tf2_ros.Buffer()
listener = tf2_ros.TransformListener(tf_buffer)
start = rospy.get_time()
image = rospy.wait_for_message("/omtp/logical_camera_2", LogicalCameraImage)
for model in image.models:
    if model.type == "object":
        object_pose = PoseStamped()
        object_pose.header.stamp = rospy.Time.now()
        object_pose.header.frame_id = "logical_camera_2_frame"
        object_pose.pose = model.pose
        in_world = tf_buffer.transform(object_pose, "world", rospy.Duration(1.0))
        in_cup = tf_buffer.transform(object_pose, "vacuum_gripper2_suction_cup", rospy.Duration(1.0))
        p, q = in_world.pose.position, in_cup.pose.position
        with open(sys.argv[1], "w") as f:
            json.dump({"start": start, "world": [p.x, p.y, p.z], "cup": [q.x, q.y, q.z]}, f)
        break
