#!/usr/bin/env python
# Pause Gazebo, look at the falling part, unpause.
import json
import sys
import time

import rospy
from gazebo_msgs.srv import GetModelState
from std_srvs.srv import Empty

rospy.init_node("pause_check")
pause = rospy.ServiceProxy("/gazebo/pause_physics", Empty)
unpause = rospy.ServiceProxy("/gazebo/unpause_physics", Empty)
get_state = rospy.ServiceProxy("/gazebo/get_model_state", GetModelState)

out = {}
rospy.sleep(0.2)
pause()
out["paused"] = [rospy.get_time(), get_state("object_1", "world").pose.position.z]
time.sleep(0.2)  # wall time passes; Gazebo's clock does not
out["later"] = [rospy.get_time(), get_state("object_1", "world").pose.position.z]
if len(sys.argv) > 2:
    with open(sys.argv[1], "w") as f:
        json.dump(out, f)
    rospy.sleep(1.0)  # waits on a clock that stands still
unpause()
rospy.sleep(1.0)
out["running"] = [rospy.get_time(), get_state("object_1", "world").pose.position.z]
with open(sys.argv[1], "w") as f:
    json.dump(out, f)
