#!/usr/bin/env python3
# How long do the planning calls take? (simulated time, as rospy sees it; nothing moves)
import json
import sys

import moveit_commander
import rospy
from omtp_gazebo.srv import VacuumGripperControl

rospy.init_node("planning_call_times")
group = moveit_commander.MoveGroupCommander("robot2")
gripper = rospy.ServiceProxy("/gripper2/control", VacuumGripperControl)
took = {}

start = rospy.get_time()
gripper(False)
took["service"] = rospy.get_time() - start

group.set_named_target("R2Place")
start = rospy.get_time()
plan = group.plan()
took["plan"] = rospy.get_time() - start

pose = group.get_current_pose().pose
pose.position.z -= 0.05
start = rospy.get_time()
(path, fraction) = group.compute_cartesian_path([pose], 0.01, 0.0)
took["cartesian"] = rospy.get_time() - start
took["fraction"] = fraction

with open(sys.argv[1], "w") as f:
    json.dump(took, f)
