#!/usr/bin/env python
# The requests of plugins_node.py (rclpy), written for ROS 1 as the course's scripts are:
# read the beam, switch gripper 1 on and off and read its state after each, power the belt,
# wait for the beam to see the part, stop the belt.
import json
import sys

import rospy
from omtp_gazebo.msg import ConveyorBeltState, Proximity, VacuumGripperState
from omtp_gazebo.srv import ConveyorBeltControl, VacuumGripperControl


def gripper_state():
    state = rospy.wait_for_message("/gripper1/state", VacuumGripperState, timeout=5.0)
    return {"enabled": state.enabled, "attached": state.attached}


if __name__ == "__main__":
    rospy.init_node("plugins_student")
    out = sys.argv[1]
    changes = []
    rospy.Subscriber("/break_beam_sensor_change", Proximity, changes.append)
    beam = rospy.wait_for_message("/break_beam_sensor", Proximity, timeout=5.0)
    rospy.wait_for_service("/gripper1/control", timeout=5.0)
    gripper = rospy.ServiceProxy("/gripper1/control", VacuumGripperControl)
    conveyor = rospy.ServiceProxy("/omtp/conveyor/control", ConveyorBeltControl)
    seen = {"beam_before": beam.object_detected}
    seen["gripper_on"] = {"success": gripper(enable=True).success, **gripper_state()}
    seen["gripper_off"] = {"success": gripper(enable=False).success, **gripper_state()}
    seen["conveyor_on"] = conveyor(ConveyorBeltState(power=100.0)).success
    on_at = rospy.get_time()
    while not changes and not rospy.is_shutdown():
        rospy.sleep(0.05)
    seen["beam_changes"] = [m.object_detected for m in changes[:1]]  # the first: the part seen
    seen["conveyor_off"] = conveyor(ConveyorBeltState(power=0.0)).success
    seen["change_after_s"] = changes[0].header.stamp.to_sec() - on_at
    seen["change"] = {
        "frame_id": changes[0].header.frame_id,
        "stamp": changes[0].header.stamp.to_sec(),
        "min_range": changes[0].min_range,
        "max_range": changes[0].max_range,
    }
    seen["bad_power"] = conveyor(ConveyorBeltState(power=150.0)).success
    with open(out, "w") as f:
        json.dump(seen, f)
