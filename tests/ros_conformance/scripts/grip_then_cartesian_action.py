#!/usr/bin/env python3
# Assignment 4 with straight-line moves: down onto the part, suction on, straight up, into bin 1.
import copy
import sys

import actionlib
import moveit_commander
import moveit_msgs.msg
import rospy
import tf2_ros
from geometry_msgs.msg import PoseStamped
from omtp_gazebo.msg import LogicalCameraImage
from omtp_gazebo.srv import VacuumGripperControl
from std_srvs.srv import Empty


def execute(plan):
    goal = moveit_msgs.msg.ExecuteTrajectoryGoal()
    goal.trajectory = plan
    client.send_goal(goal)
    client.wait_for_result()


moveit_commander.roscpp_initialize(sys.argv)
rospy.init_node("assignment4_cartesian")
group = moveit_commander.MoveGroupCommander("robot2")
client = actionlib.SimpleActionClient("execute_trajectory", moveit_msgs.msg.ExecuteTrajectoryAction)
client.wait_for_server()
tf_buffer = tf2_ros.Buffer()
tf2_ros.TransformListener(tf_buffer)
gripper = rospy.ServiceProxy("/gripper2/control", VacuumGripperControl)
rospy.ServiceProxy("/spawn_object_at_robot2", Empty)()

group.set_named_target("R2Home")
group.go(wait=True)
rospy.sleep(1.5)
image = rospy.wait_for_message("/omtp/logical_camera_2", LogicalCameraImage)
seen = PoseStamped()
seen.header.frame_id = "logical_camera_2_frame"
seen.pose = [m for m in image.models if m.type == "object"][0].pose
part = tf_buffer.transform(seen, "world", rospy.Duration(1.0)).pose.position

above = group.get_current_pose().pose
above.position.x, above.position.y, above.position.z = part.x, part.y, part.z + 0.35
group.set_pose_target(above)
group.go(wait=True)

down = copy.deepcopy(above)
down.position.z = part.z + 0.16
(plan, fraction) = group.compute_cartesian_path([down], 0.01, 0.0)
execute(plan)

gripper(True)
(plan, fraction) = group.compute_cartesian_path([above], 0.01, 0.0)
execute(plan)

group.set_named_target("R2Place")
group.go(wait=True)
gripper(False)
rospy.sleep(1.0)
