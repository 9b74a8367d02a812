#!/usr/bin/env python
# Lecture 6 style: where is the part? Ask Gazebo, move it over the bin, delete it.
import json
import sys

import rospy
from gazebo_msgs.msg import ModelState
from gazebo_msgs.srv import DeleteModel, GetModelState, SetModelState, SpawnModel  # noqa: F401
from geometry_msgs.msg import Pose

out = {}

rospy.init_node("model_state_check")
rospy.wait_for_service("/gazebo/get_model_state")
get_state = rospy.ServiceProxy("/gazebo/get_model_state", GetModelState)
set_state = rospy.ServiceProxy("/gazebo/set_model_state", SetModelState)
delete = rospy.ServiceProxy("/gazebo/delete_model", DeleteModel)

rospy.sleep(1.5)  # the part falls to the floor
resp = get_state("object_1", "world")
p = resp.pose.position
out["rest"] = [p.x, p.y, p.z, resp.pose.orientation.w, resp.success]
in_robot2 = get_state("object_1", "robot2")
out["in_robot2"] = [in_robot2.pose.position.x, in_robot2.pose.position.y, in_robot2.pose.position.z]
out["missing"] = [get_state("object_9", "").success, get_state("object_9", "").status_message]

mode = sys.argv[2] if len(sys.argv) > 2 else "move"
if mode == "move":
    state = ModelState()
    state.model_name = "object_1"
    state.pose = Pose()
    state.pose.position.x = -8.0
    state.pose.position.y = -2.2
    state.pose.position.z = 1.0
    state.pose.orientation.w = 1.0
    state.reference_frame = "world"
    result = set_state(state)
    out["set"] = [result.success, result.status_message]
    rospy.sleep(2.0)  # it drops into bin 1
elif mode == "delete":
    result = delete("object_1")
    out["delete"] = [result.success, result.status_message]
    out["again"] = [get_state("object_1", "world").success, delete("object_1").success]
with open(sys.argv[1], "w") as f:
    json.dump(out, f)
