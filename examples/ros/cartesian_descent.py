#!/usr/bin/env python3
"""Lecture 6, assignment 4 with a Cartesian descent: robot 2 moves above the part, plans a
straight-line descent with compute_cartesian_path (the cup pressed onto the part), runs it
through MoveIt's execute_trajectory action, lifts the part straight up and drops it into
bin 1.

    omtp-drake ros-run examples/ros/cartesian_descent.py --scenario lecture6_assignment4
"""

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

CUP_ABOVE_CENTRE = 0.145  # the course's deepest press: the cup face 22.5 mm into the top face


def execute(client, plan):
    goal = moveit_msgs.msg.ExecuteTrajectoryGoal()
    goal.trajectory = plan
    client.send_goal(goal)
    client.wait_for_result()
    return client.get_result().error_code.val == moveit_msgs.msg.MoveItErrorCodes.SUCCESS


def main():
    moveit_commander.roscpp_initialize(sys.argv)
    rospy.init_node("cartesian_descent")
    group = moveit_commander.MoveGroupCommander("robot2")
    client = actionlib.SimpleActionClient("execute_trajectory", moveit_msgs.msg.ExecuteTrajectoryAction)
    client.wait_for_server()
    tf_buffer = tf2_ros.Buffer()
    tf2_ros.TransformListener(tf_buffer)
    gripper = rospy.ServiceProxy("/gripper2/control", VacuumGripperControl)
    rospy.ServiceProxy("/spawn_object_at_robot2", Empty)()

    group.set_named_target("R2Home")
    group.go(wait=True)
    rospy.sleep(1.0)
    image = rospy.wait_for_message("omtp/logical_camera_2", LogicalCameraImage)
    seen = PoseStamped()
    seen.header.frame_id = "logical_camera_2_frame"
    seen.header.stamp = rospy.Time.now()
    seen.pose = [m for m in image.models if m.type == "object"][0].pose
    part = tf_buffer.transform(seen, "world", rospy.Duration(1.0)).pose.position

    above = group.get_current_pose().pose  # R2Home: the cup points straight down
    above.position.x, above.position.y, above.position.z = part.x, part.y, part.z + 0.4
    group.set_pose_target(above)
    group.go(wait=True)
    gripper(True)

    pressed = copy.deepcopy(above)
    pressed.position.z = part.z + CUP_ABOVE_CENTRE
    plan, fraction = group.compute_cartesian_path([pressed], 0.01, 0.0)
    rospy.loginfo("descent: %.0f %% of the path planned", 100 * fraction)
    execute(client, plan)
    rospy.sleep(0.3)

    plan, fraction = group.compute_cartesian_path([above], 0.01)  # MoveIt >= 1.1.15 form
    execute(client, plan)
    group.set_named_target("R2Place")
    group.go(wait=True)
    gripper(False)
    rospy.sleep(0.5)


if __name__ == "__main__":
    main()
