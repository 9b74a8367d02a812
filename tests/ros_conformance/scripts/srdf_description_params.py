#!/usr/bin/env python
# What the parameter server holds of the robot: the URDF and the SRDF.
import json
import sys

import rospy

rospy.init_node("description_params")
with open(sys.argv[1], "w") as f:
    json.dump(
        {
            "srdf": rospy.get_param("/robot_description_semantic"),
            "urdf": rospy.get_param("robot_description"),
        },
        f,
    )
