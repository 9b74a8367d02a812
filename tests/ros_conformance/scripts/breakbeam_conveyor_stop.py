#!/usr/bin/env python
# Stops the conveyor when the break beam sees a part (the course's lecture 7 helper),
# then reports where the part stopped, as camera 1 sees it, in the world frame.
import json

import rospy
import tf2_geometry_msgs  # noqa: F401
import tf2_ros
from geometry_msgs.msg import PoseStamped
from omtp_gazebo.msg import ConveyorBeltState, LogicalCameraImage, Proximity
from omtp_gazebo.srv import ConveyorBeltControl
from std_srvs.srv import Empty

stops = []


def handler(msg, svc_conveyor_control):
    rospy.loginfo(
        "State change in msg {}: object {}".format(
            msg.header.seq, "detected" if msg.object_detected else "not detected"
        )
    )
    if msg.object_detected:
        svc_conveyor_control(ConveyorBeltState(power=0.0))
        stops.append(msg.header.stamp.to_sec())
        rospy.loginfo("Stopped conveyor, waiting for next object ..")


if __name__ == "__main__":
    rospy.init_node("breakbeam_conveyor_stop")
    out = rospy.myargv()[1]
    try:
        rospy.wait_for_service("/omtp/conveyor/control", timeout=5.0)
    except Exception as e:
        rospy.logerror(f"A required service is not available, exiting: {e}")
    svc_conveyor_control = rospy.ServiceProxy("/omtp/conveyor/control", ConveyorBeltControl)
    rospy.Subscriber("/break_beam_sensor_change", Proximity, handler, callback_args=svc_conveyor_control)

    tf_buffer = tf2_ros.Buffer()
    listener = tf2_ros.TransformListener(tf_buffer)
    rospy.ServiceProxy("/start_spawn", Empty)()
    svc_conveyor_control(ConveyorBeltState(power=100.0))
    while not stops and not rospy.is_shutdown():
        rospy.sleep(0.1)
    rospy.ServiceProxy("/stop_spawn", Empty)()
    rospy.sleep(2.0)

    state = rospy.wait_for_message("/break_beam_sensor", Proximity, timeout=1.0)
    image = rospy.wait_for_message("/omtp/logical_camera_1", LogicalCameraImage, timeout=1.0)
    part = PoseStamped()
    part.header.frame_id = "logical_camera_1_frame"
    part.header.stamp = rospy.Time.now()
    part.pose = [m for m in image.models if m.type == "object"][-1].pose
    world = tf_buffer.transform(part, "world", rospy.Duration(1.0))
    with open(out, "w") as f:
        json.dump(
            {
                "stops": stops,
                "part_world_xyz": [world.pose.position.x, world.pose.position.y, world.pose.position.z],
                "beam": {
                    "object_detected": state.object_detected,
                    "min_range": state.min_range,
                    "max_range": state.max_range,
                    "frame_id": state.header.frame_id,
                    "stamp": state.header.stamp.to_sec(),
                },
                "t_end": rospy.get_time(),
            },
            f,
        )
