#!/usr/bin/env python
# The groups and the end-effector link of our MoveIt config.
import json
import sys

import moveit_commander
import rospy

moveit_commander.roscpp_initialize(sys.argv)
rospy.init_node("end_effector", anonymous=True)
robot = moveit_commander.RobotCommander()
group = moveit_commander.MoveGroupCommander("robot2")
with open(sys.argv[1], "w") as f:
    json.dump({"eef": group.get_end_effector_link(), "groups": robot.get_group_names()}, f)
