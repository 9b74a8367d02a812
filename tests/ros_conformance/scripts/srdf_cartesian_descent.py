#!/usr/bin/env python
# Plan a straight 20 cm descent of robot2's suction cup from R2Home.
import copy
import json
import sys

import moveit_commander
import rospy

moveit_commander.roscpp_initialize(sys.argv)
rospy.init_node("cartesian_descent", anonymous=True)
group = moveit_commander.MoveGroupCommander("robot2")
group.set_named_target("R2Home")
group.go(wait=True)

waypoint = copy.deepcopy(group.get_current_pose().pose)
waypoint.position.z -= 0.2
plan, fraction = group.compute_cartesian_path([waypoint], 0.01, 0.0)
points = plan.joint_trajectory.points
with open(sys.argv[1], "w") as f:
    json.dump(
        {
            "fraction": fraction,
            "duration": points[-1].time_from_start.to_sec(),
            "first": list(points[0].positions),
            "last": list(points[-1].positions),
        },
        f,
    )
