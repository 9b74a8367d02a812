#!/usr/bin/env python
# Assignment 4 (MoveIt Melodic): plan first, look at the plan, then execute it.
import sys

import moveit_commander
import rospy
import tf2_ros
from geometry_msgs.msg import PoseStamped
from omtp_gazebo.msg import LogicalCameraImage
from omtp_gazebo.srv import VacuumGripperControl
from std_srvs.srv import Empty


def move(group, target):
    if type(target) is str:
        group.set_named_target(target)
    else:
        group.set_pose_target(target)
    plan = group.plan()
    group.execute(plan, wait=True)
    group.stop()
    group.clear_pose_targets()


moveit_commander.roscpp_initialize(sys.argv)
rospy.init_node("assignment4_melodic", anonymous=True)
robot2 = moveit_commander.MoveGroupCommander("robot2")
tf_buffer = tf2_ros.Buffer(rospy.Duration(10.0))
tf2_ros.TransformListener(tf_buffer)
gripper_control = rospy.ServiceProxy("/gripper2/control", VacuumGripperControl)
spawn_object = rospy.ServiceProxy("/spawn_object_at_robot2", Empty)

move(robot2, "R2Home")
spawn_object()
rospy.sleep(1.5)
image = rospy.wait_for_message("/omtp/logical_camera_2", LogicalCameraImage, timeout=5.0)
seen = PoseStamped()
seen.header.frame_id = "logical_camera_2_frame"
seen.header.stamp = rospy.Time.now()
for model in image.models:
    if model.type == "object":
        seen.pose = model.pose
part = tf_buffer.transform(seen, "world", rospy.Duration(1.0)).pose

pose = robot2.get_current_pose().pose
pose.position.x = part.position.x
pose.position.y = part.position.y
pose.position.z = part.position.z + 0.35
move(robot2, pose)
pose.position.z = part.position.z + 0.16
move(robot2, pose)
gripper_control(True)
move(robot2, "R2Home")
move(robot2, "R2Place")
gripper_control(False)
rospy.sleep(1.0)
