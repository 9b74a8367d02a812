#!/usr/bin/env python
# Which velocity limit did our joint_limits.yaml give the elbow?
import json
import sys

import rospy

rospy.init_node("joint_limits_param")
elbow = rospy.get_param("/robot_description_planning/joint_limits/robot2_elbow_joint/max_velocity")
with open(sys.argv[1], "w") as f:
    json.dump({"elbow": elbow}, f)
