#!/usr/bin/env python
# Lecture 5: move robot2 through the named poses of our own omtp_moveit_config.
import json
import sys

import moveit_commander
import rospy

moveit_commander.roscpp_initialize(sys.argv)
rospy.init_node("srdf_named_states", anonymous=True)

robot = moveit_commander.RobotCommander()
group = moveit_commander.MoveGroupCommander("robot2")

result = {
    "groups": robot.get_group_names(),
    "named": group.get_named_targets(),
    "high_values": group.get_named_target_values("high"),
    "eef": group.get_end_effector_link(),
    "semantic": rospy.get_param("/robot_description_semantic"),
    "has_description": rospy.has_param("/robot_description"),
}

start = rospy.get_time()
group.set_named_target("high")
result["high_ok"] = group.go(wait=True)
group.stop()
result["high_time"] = rospy.get_time() - start
result["high_q"] = group.get_current_joint_values()

group.set_named_target("R2Home")
result["home_ok"] = group.go(wait=True)
group.stop()
result["home_q"] = group.get_current_joint_values()

try:
    group.set_named_target("R2Up")
except moveit_commander.MoveItCommanderException as e:
    result["missing"] = str(e)

with open(sys.argv[1], "w") as f:
    json.dump(result, f)
