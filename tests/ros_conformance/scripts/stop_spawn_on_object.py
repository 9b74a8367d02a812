#!/usr/bin/env python
# Start the spawner next to robot 2 and stop it as soon as a part is in the world
# (what omtp_utilities' spawn_object_once.py does).
import json
import sys

import rospy
from gazebo_msgs.msg import ModelStates
from std_srvs.srv import Empty


def model_states_cb(data):
    if any("object" in idx for idx in data.name):
        stop_spawn = rospy.ServiceProxy("stop_spawn", Empty)
        stop_spawn()


if __name__ == "__main__":
    rospy.init_node("stop_spawning_object", anonymous=False)
    rospy.Subscriber("gazebo/model_states", ModelStates, model_states_cb)
    rospy.wait_for_service("/spawn_object_at_robot2")
    spawn = rospy.ServiceProxy("/spawn_object_at_robot2", Empty)
    spawn()
    rospy.sleep(3.5)
    states = rospy.wait_for_message("/gazebo/model_states", ModelStates)
    with open(sys.argv[1], "w") as f:
        json.dump({"models": list(states.name)}, f)
