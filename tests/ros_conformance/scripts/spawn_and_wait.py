#!/usr/bin/env python
# Ask for parts next to robot 2 (twice, as students do when nothing shows up) and wait.
import rospy
from std_srvs.srv import Empty

rospy.init_node("spawn_and_wait")
spawn = rospy.ServiceProxy("/spawn_object_at_robot2", Empty)
spawn()
rospy.sleep(1.5)
spawn()
rospy.sleep(2.0)
