#!/usr/bin/env python3
# Assignment 4 with a watcher: a thread asks Gazebo where the part is every 0.25 s
# while the main thread picks it (next to robot 2) and drops it into bin 1.
import json
import sys
import threading

import moveit_commander
import rospy
import tf2_ros
from geometry_msgs.msg import PoseStamped
from omtp_gazebo.msg import LogicalCameraImage
from omtp_gazebo.srv import VacuumGripperControl
from gazebo_msgs.srv import GetModelState
from std_srvs.srv import Empty

calls = []


def watch_part():
    get_state = rospy.ServiceProxy("/gazebo/get_model_state", GetModelState)
    while not rospy.is_shutdown():
        rospy.sleep(0.25)
        state = get_state("object_1", "world")
        calls.append([rospy.get_time(), state.success, state.pose.position.z])


moveit_commander.roscpp_initialize(sys.argv)
rospy.init_node("assignment4_watch")
arm = moveit_commander.MoveGroupCommander("robot2")
tfBuffer = tf2_ros.Buffer()
listener = tf2_ros.TransformListener(tfBuffer)
rospy.wait_for_service("/gripper2/control")
gripper = rospy.ServiceProxy("/gripper2/control", VacuumGripperControl)
spawn = rospy.ServiceProxy("/spawn_object_at_robot2", Empty)

watcher = threading.Thread(target=watch_part, daemon=True)
watcher.start()

arm.set_named_target("R2Home")
arm.go(wait=True)
spawn()
rospy.sleep(2)

msg = rospy.wait_for_message("/omtp/logical_camera_2", LogicalCameraImage)
for model in msg.models:
    if model.type == "object":
        p = PoseStamped()
        p.header.frame_id = "logical_camera_2_frame"
        p.pose = model.pose
        part = tfBuffer.transform(p, "world", rospy.Duration(1))

target = arm.get_current_pose().pose
target.position.x = part.pose.position.x
target.position.y = part.pose.position.y
target.position.z = part.pose.position.z + 0.3
arm.set_pose_target(target)
arm.go(wait=True)
target.position.z = part.pose.position.z + 0.16
arm.set_pose_target(target)
arm.go(wait=True)
gripper(True)
arm.set_named_target("R2Home")
arm.go(wait=True)
arm.set_named_target("R2Place")
arm.go(wait=True)
gripper(False)
rospy.sleep(1)

with open(sys.argv[1], "w") as f:
    json.dump({"calls": calls, "end": rospy.get_time()}, f)
