#!/usr/bin/env python
# Lecture 7's feeder (FlexBE's control_feeder_state calls /start_spawn and /stop_spawn).
import json
import sys

import rospy
from std_msgs.msg import Header
from std_srvs.srv import Empty

seen = []


def spawned_cb(msg):
    seen.append([msg.seq, round(msg.stamp.to_sec(), 3), msg.frame_id])


rospy.init_node("feeder")
try:
    rospy.wait_for_service("/spawn_object_once", timeout=1.0)
    remapped = True
except rospy.ROSException:
    remapped = False
rospy.Subscriber("/spawned_part", Header, spawned_cb)
rospy.ServiceProxy("/start_spawn", Empty)()
rospy.sleep(6.5)
rospy.ServiceProxy("/stop_spawn", Empty)()
rospy.sleep(3.0)
with open(sys.argv[1], "w") as f:
    json.dump({"remapped": remapped, "seen": seen}, f)
