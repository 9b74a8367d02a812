#!/usr/bin/env python
# Our MoveIt config calls robot2's group "manipulator".
import json
import sys

import moveit_commander
import rospy

moveit_commander.roscpp_initialize(sys.argv)
rospy.init_node("own_group_name", anonymous=True)
robot = moveit_commander.RobotCommander()
arm = moveit_commander.MoveGroupCommander("manipulator")
arm.set_named_target("high")
result = {"ok": arm.go(wait=True), "q": arm.get_current_joint_values(), "groups": robot.get_group_names()}
try:
    moveit_commander.MoveGroupCommander("robot2")
except Exception as e:
    result["robot2"] = str(e)
with open(sys.argv[1], "w") as f:
    json.dump(result, f)
