#!/usr/bin/env python
"""A student's MoveIt script, as the course's class writes them (Melodic's
moveit_commander): robot 1 to its named state R1Home, its joints printed. Half of
``bench_grade.py``'s class: MoveIt loads the arms' description after the script starts,
the runs whose rows once held the model cache's folders as refusals (issue 45)."""

import sys

import moveit_commander
import rospy

moveit_commander.roscpp_initialize(sys.argv)
rospy.init_node("move_home", anonymous=True)
group = moveit_commander.MoveGroupCommander("robot1")
group.set_named_target("R1Home")
group.go(wait=True)
group.stop()
print("joints", group.get_current_joint_values())
moveit_commander.roscpp_shutdown()
