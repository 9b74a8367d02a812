#!/usr/bin/env python
# Lecture 6 habit: logical camera 2's callback reads data.models[-1] while robot 2 moves
# between its named poses; writes what the camera lists at each pose and where tf puts
# the camera's model frames.
import json
import sys

import moveit_commander
import rospy
import tf2_ros
from omtp_gazebo.msg import LogicalCameraImage

object_found = False
callbacks = 0


def logical_camera2_callback(data):
    global object_found, callbacks
    callbacks += 1
    if data.models[-1].type == "object":
        object_found = True


def frame_in_world(tf_buffer, frame):
    try:
        t = tf_buffer.lookup_transform("world", frame, rospy.Time(0), rospy.Duration(1.0))
    except (tf2_ros.LookupException, tf2_ros.ExtrapolationException):
        return None
    return [t.transform.translation.x, t.transform.translation.y, t.transform.translation.z]


if __name__ == "__main__":
    moveit_commander.roscpp_initialize(sys.argv)
    rospy.init_node("lecture6_assignment4", anonymous=True)
    tf_buffer = tf2_ros.Buffer()
    listener = tf2_ros.TransformListener(tf_buffer)
    robot2_group = moveit_commander.MoveGroupCommander("robot2")
    rospy.Subscriber("omtp/logical_camera_2", LogicalCameraImage, logical_camera2_callback)

    result = {}
    for pose in ["R2PreGrasp", "R2Place"]:
        robot2_group.set_named_target(pose)
        robot2_group.go(wait=True)
        robot2_group.stop()
        rospy.sleep(2.0)
        image = rospy.wait_for_message("/omtp/logical_camera_2", LogicalCameraImage, timeout=1.0)
        result[pose] = {
            "types": [m.type for m in image.models],
            "robot2_frame": frame_in_world(tf_buffer, "logical_camera_2_robot2_frame"),
            "gripper_frame": frame_in_world(tf_buffer, "logical_camera_2_vacuum_gripper2_frame"),
            "workcell_frame": frame_in_world(tf_buffer, "logical_camera_2_workcell__frame"),
            "conveyor_frame": frame_in_world(tf_buffer, "logical_camera_2_conveyor_belt_frame"),
            "nested_frame": frame_in_world(tf_buffer, "logical_camera_2_conveyor_belt_fixed_frame"),
        }
    result["callbacks"] = callbacks
    result["object_found"] = object_found
    with open(sys.argv[1], "w") as f:
        json.dump(result, f)
