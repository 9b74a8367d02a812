#!/usr/bin/env python3
"""Lecture 6, assignment 3: the part's pose, seen by logical camera 2, in the
vacuum_gripper2_suction_cup frame (course style: rospy, tf2).

    omtp-drake ros-run examples/ros/lecture6_assignment3.py --scenario lecture6_assignment3
"""

import rospy
import tf2_geometry_msgs  # noqa: F401  (registers PoseStamped transforms in ROS)
import tf2_ros
from geometry_msgs.msg import PoseStamped
from omtp_gazebo.msg import LogicalCameraImage


def main():
    rospy.init_node("lecture6_assignment3")
    tf_buffer = tf2_ros.Buffer(rospy.Duration(10.0))
    tf2_ros.TransformListener(tf_buffer)
    rospy.sleep(1.5)  # the part falls to the floor and settles

    image = rospy.wait_for_message("/omtp/logical_camera_2", LogicalCameraImage, timeout=2.0)
    part = next(model for model in image.models if model.type == "object")
    seen = PoseStamped()
    seen.header.frame_id = "logical_camera_2_frame"
    seen.header.stamp = rospy.Time.now()
    seen.pose = part.pose

    in_cup = tf_buffer.transform(seen, "vacuum_gripper2_suction_cup", rospy.Duration(1.0))
    p = in_cup.pose.position
    print(f"part in vacuum_gripper2_suction_cup: ({p.x:.4f}, {p.y:.4f}, {p.z:.4f})")


if __name__ == "__main__":
    try:
        main()
    except rospy.ROSInterruptException:
        pass
