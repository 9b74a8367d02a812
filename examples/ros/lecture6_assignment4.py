#!/usr/bin/env python3
"""Lecture 6, assignment 4, in a loop: robot 2 picks each part spawned next to it from the
floor and drops it into bin 1. Course style: MoveIt commander, the gripper and spawner
services, logical camera 2 and tf2; the suction cup is pressed onto the part (its frame
0.16 m above the part's centre: the cup face 7.5 mm into the top face) and suction
attaches on contact.

    omtp-drake ros-run examples/ros/lecture6_assignment4.py [PARTS] --scenario lecture6_assignment4
"""

import sys

import moveit_commander
import rospy
import tf2_ros
from geometry_msgs.msg import Pose, PoseStamped
from omtp_gazebo.msg import LogicalCameraImage
from omtp_gazebo.srv import VacuumGripperControl
from std_srvs.srv import Empty

CUP_ABOVE_CENTRE = 0.16  # the course's value: a 0.2 m part, the cup pressed onto its top
APPROACH = 0.35


def part_in_world(tf_buffer):
    """The first part logical camera 2 sees, as a pose in world."""
    image = rospy.wait_for_message("/omtp/logical_camera_2", LogicalCameraImage, timeout=5.0)
    part = next(model for model in image.models if model.type == "object")
    seen = PoseStamped()
    seen.header.frame_id = "logical_camera_2_frame"
    seen.header.stamp = rospy.Time.now()
    seen.pose = part.pose
    return tf_buffer.transform(seen, "world", rospy.Duration(1.0)).pose


def cup_pose_above(part, height, orientation):
    pose = Pose()
    pose.position.x = part.position.x
    pose.position.y = part.position.y
    pose.position.z = part.position.z + height
    pose.orientation = orientation
    return pose


def go_to(group, target):
    if isinstance(target, str):
        group.set_named_target(target)
    else:
        group.set_pose_target(target)
    ok = group.go(wait=True)
    group.stop()
    group.clear_pose_targets()
    if not ok:
        raise RuntimeError(f"robot2 could not reach {target if isinstance(target, str) else 'the pose'}")


def main():
    parts = int(sys.argv[1]) if len(sys.argv) > 1 else 2
    moveit_commander.roscpp_initialize(sys.argv)
    rospy.init_node("lecture6_assignment4", anonymous=True)
    robot2 = moveit_commander.MoveGroupCommander("robot2")
    tf_buffer = tf2_ros.Buffer(rospy.Duration(10.0))
    tf2_ros.TransformListener(tf_buffer)
    rospy.wait_for_service("/gripper2/control")
    gripper = rospy.ServiceProxy("/gripper2/control", VacuumGripperControl)
    spawn = rospy.ServiceProxy("/spawn_object_at_robot2", Empty)

    go_to(robot2, "R2Home")
    tool_down = robot2.get_current_pose().pose.orientation  # the cup points straight down at R2Home
    for i in range(parts):
        spawn()
        rospy.sleep(1.5)  # it falls and settles
        part = part_in_world(tf_buffer)
        go_to(robot2, cup_pose_above(part, APPROACH, tool_down))
        gripper(True)
        go_to(robot2, cup_pose_above(part, CUP_ABOVE_CENTRE, tool_down))
        rospy.sleep(0.3)  # suction attaches on contact
        go_to(robot2, "R2Home")
        go_to(robot2, "R2Place")
        gripper(False)
        rospy.sleep(0.5)  # it drops into the bin
        go_to(robot2, "R2Home")
        rospy.loginfo("part %d placed", i + 1)
    moveit_commander.roscpp_shutdown()


if __name__ == "__main__":
    try:
        main()
    except rospy.ROSInterruptException:
        pass
