#!/usr/bin/env python
# Plan robot2 to a joint goal with its gripper against its own pedestal.
import json
import sys

import moveit_commander
import rospy

moveit_commander.roscpp_initialize(sys.argv)
rospy.init_node("plan_into_pedestal", anonymous=True)
group = moveit_commander.MoveGroupCommander("robot2")
group.set_joint_value_target([1.5708, 0.3, 1.5, -1.5708, -1.5708, 0.0])
success, plan, planning_time, error_code = group.plan()
with open(sys.argv[1], "w") as f:
    json.dump({"success": success, "code": error_code.val}, f)
