#!/usr/bin/env python
# Listen to Gazebo's model and link states for a second; ask for two links.
import json
import sys

import rospy
from gazebo_msgs.msg import LinkStates, ModelStates
from gazebo_msgs.srv import GetLinkState

stamps = {"model": [], "link": []}
last = {}


def on_models(msg):
    stamps["model"].append(rospy.get_time())
    last["models"] = list(msg.name)


def on_links(msg):
    stamps["link"].append(rospy.get_time())
    last["links"] = list(msg.name)


rospy.init_node("listener")
rospy.Subscriber("/gazebo/model_states", ModelStates, on_models)
rospy.Subscriber("/gazebo/link_states", LinkStates, on_links)
rospy.sleep(1.0)
counts = {k: len(v) for k, v in stamps.items()}
link = rospy.ServiceProxy("/gazebo/get_link_state", GetLinkState)
cup = link("robot2::vacuum_gripper2_suction_cup", "world").link_state.pose.position
part = link("object_1::box_base_link", "").link_state.pose.position
with open(sys.argv[1], "w") as f:
    json.dump(
        {
            "n": counts,
            "last": last,
            "cup": [cup.x, cup.y, cup.z],
            "part": [part.x, part.y, part.z],
        },
        f,
    )
