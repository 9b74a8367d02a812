#!/usr/bin/env python
# Where is the part on the belt now?
import json
import sys

import rospy
from gazebo_msgs.srv import GetModelState

rospy.init_node("belt_check")
state = rospy.ServiceProxy("/gazebo/get_model_state", GetModelState)("object_1", "world")
with open(sys.argv[1], "w") as f:
    json.dump({"t": rospy.get_time(), "y": state.pose.position.y}, f)
