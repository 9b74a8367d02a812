#!/usr/bin/env python
# Lecture 7 habit: the lecture's single camera (/omtp/logical_camera, frame
# logical_camera_frame) and the plugin's frame of the part it lists.
import json
import sys

import rospy
import tf2_ros
from omtp_gazebo.msg import LogicalCameraImage, Proximity
from std_srvs.srv import Empty

if __name__ == "__main__":
    rospy.init_node("part_frame")
    tf_buffer = tf2_ros.Buffer()
    listener = tf2_ros.TransformListener(tf_buffer)
    rospy.ServiceProxy("/start_spawn", Empty)()  # the first part one period (3 s) later
    rospy.wait_for_message("/break_beam_sensor_change", Proximity, timeout=20.0)
    rospy.ServiceProxy("/stop_spawn", Empty)()  # one part (the next would come 0.5 s later)
    rospy.sleep(1.0)
    image = rospy.wait_for_message("/omtp/logical_camera", LogicalCameraImage)
    part = [m for m in image.models if m.type == "object"][-1]
    t = tf_buffer.lookup_transform(
        "world", "logical_camera_object_1_frame", rospy.Time(0), rospy.Duration(1.0)
    )
    cam = tf_buffer.lookup_transform("logical_camera_frame", "logical_camera_object_1_frame", rospy.Time(0))
    with open(sys.argv[1], "w") as f:
        json.dump(
            {
                "types": [m.type for m in image.models],
                "world": [t.transform.translation.x, t.transform.translation.y, t.transform.translation.z],
                "in_camera": [
                    cam.transform.translation.x,
                    cam.transform.translation.y,
                    cam.transform.translation.z,
                ],
                "message": [part.pose.position.x, part.pose.position.y, part.pose.position.z],
            },
            f,
        )
