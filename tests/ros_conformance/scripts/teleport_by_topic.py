#!/usr/bin/env python
# Put the part over bin 1 by publishing its state to Gazebo.
import rospy
from gazebo_msgs.msg import ModelState

rospy.init_node("teleport")
pub = rospy.Publisher("/gazebo/set_model_state", ModelState, queue_size=10)
rospy.sleep(1.0)  # let the connection come up
state = ModelState()
state.model_name = "object_1"
state.pose.position.x = -8.0
state.pose.position.y = -2.2
state.pose.position.z = 1.0
state.pose.orientation.w = 1.0
state.reference_frame = "world"
pub.publish(state)
rospy.sleep(2.0)
