#!/usr/bin/env python3
# How long do the calls take? (simulated time, as rospy sees it)
import json
import sys

import moveit_commander
import rospy
from omtp_gazebo.srv import VacuumGripperControl

rospy.init_node("call_times")
group = moveit_commander.MoveGroupCommander("robot2")
gripper = rospy.ServiceProxy("/gripper2/control", VacuumGripperControl)
took = {}

start = rospy.get_time()
gripper(False)
took["service"] = rospy.get_time() - start

group.set_named_target("R2Place")
start = rospy.get_time()
success, plan, planning_time, error_code = group.plan()
took["plan"] = rospy.get_time() - start
took["planning_time"] = planning_time

start = rospy.get_time()
group.execute(plan, wait=True)
took["execute"] = rospy.get_time() - start
took["duration"] = plan.joint_trajectory.points[-1].time_from_start.to_sec()

pose = group.get_current_pose().pose
pose.position.z -= 0.05
start = rospy.get_time()
(path, fraction) = group.compute_cartesian_path([pose], 0.01, 0.0)
took["cartesian"] = rospy.get_time() - start

group.set_named_target("R2Home")
start = rospy.get_time()
group.go(wait=True)
took["go"] = rospy.get_time() - start
took["at"] = rospy.get_time()

with open(sys.argv[1], "w") as f:
    json.dump(took, f)
