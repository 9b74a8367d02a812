#!/usr/bin/env python
# Start the belt's spawner and wait for the first part in Gazebo's model and link states
# (what the course's scripts watch), then stop it. Run with ros-run.
import json
import sys

import rospy
from gazebo_msgs.msg import LinkStates, ModelStates
from std_msgs.msg import Header
from std_srvs.srv import Empty

seen = {"models": None, "links": None, "spawned": None}


def models_cb(msg):
    if seen["models"] is None and any("object" in name for name in msg.name):
        seen["models"] = list(msg.name)


def links_cb(msg):
    if seen["links"] is None and any(name.startswith("object") for name in msg.name):
        seen["links"] = list(msg.name)


def spawned_cb(msg):
    seen["spawned"] = {"stamp": msg.stamp.to_sec(), "frame_id": msg.frame_id}


if __name__ == "__main__":
    rospy.init_node("spawner_watcher")
    rospy.Subscriber("/gazebo/model_states", ModelStates, models_cb)
    rospy.Subscriber("/gazebo/link_states", LinkStates, links_cb)
    rospy.Subscriber("/spawned_part", Header, spawned_cb)
    before = rospy.wait_for_message("/gazebo/model_states", ModelStates)
    rospy.wait_for_service("/start_spawn")
    seen["before"] = list(before.name)
    seen["called"] = rospy.get_time()
    rospy.ServiceProxy("/start_spawn", Empty)()
    while not rospy.is_shutdown() and not (seen["models"] and seen["links"] and seen["spawned"]):
        rospy.sleep(0.1)
    rospy.ServiceProxy("/stop_spawn", Empty)()
    with open(sys.argv[1], "w") as f:
        json.dump(seen, f)
