#!/usr/bin/env python
"""The same student's move as tutorial_node.py, written for ROS 1 (rospy, run by
``omtp-drake ros-run --robot``): one trajectory on /set_joint_trajectory stamped START,
every /joint_states message recorded until END.

    ros-run ros1_tutorial_script.py --robot ROBOT -- OUT.json START END
"""
import json
import os
import sys

import rospy
from sensor_msgs.msg import JointState
from trajectory_msgs.msg import JointTrajectory, JointTrajectoryPoint

out, start, end = sys.argv[1], float(sys.argv[2]), float(sys.argv[3])
spec = json.load(open(os.path.join(os.path.dirname(os.path.abspath(__file__)), "trajectory.json")))
rospy.init_node("tutorial_student")
states = []
rospy.Subscriber("/joint_states", JointState, states.append, queue_size=200)
pub = rospy.Publisher("/set_joint_trajectory", JointTrajectory, queue_size=1)
rospy.sleep(0.5)

msg = JointTrajectory()
msg.header.frame_id = spec["frame_id"]
msg.header.stamp = rospy.Time.from_sec(start)
msg.joint_names = spec["joint_names"]
for positions, after in spec["points"]:
    msg.points.append(JointTrajectoryPoint(positions=positions, time_from_start=rospy.Duration(after)))
sent_at = rospy.get_time()
pub.publish(msg)
while not rospy.is_shutdown() and rospy.get_time() < end:
    rospy.sleep(0.1)

with open(out, "w") as f:
    json.dump(
        {
            "sent_at": sent_at,
            "states": [[m.header.stamp.to_sec(), list(m.name), list(m.position)] for m in states],
        },
        f,
    )
