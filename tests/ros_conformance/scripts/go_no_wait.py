#!/usr/bin/env python3
# Start the move, do other things meanwhile.
import json
import sys

import moveit_commander
import rospy

rospy.init_node("async_go")
group = moveit_commander.MoveGroupCommander("robot2")
start = group.get_current_joint_values()
group.set_named_target("R2Place")
t0 = rospy.get_time()
group.go(wait=False)
returned = rospy.get_time() - t0
moved = []
for _ in range(6):
    rospy.sleep(0.05)
    now = group.get_current_joint_values()
    moved.append(max(abs(a - b) for a, b in zip(now, start)))
json.dump({"returned": returned, "moved": moved}, open(sys.argv[1], "w"))
