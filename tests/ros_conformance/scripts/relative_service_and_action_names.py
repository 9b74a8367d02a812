#!/usr/bin/env python
# Services and actions by relative names with trailing slashes, as rospy resolves them.
import json
import sys

import actionlib
import rospy
from moveit_msgs.msg import ExecuteTrajectoryAction
from omtp_gazebo.msg import VacuumGripperState
from omtp_gazebo.srv import VacuumGripperControl

if __name__ == "__main__":
    rospy.init_node("gripper_check")
    rospy.wait_for_service("gripper2/control/", timeout=1.0)
    gripper = rospy.ServiceProxy("gripper2//control", VacuumGripperControl)
    response = gripper(True)
    rospy.sleep(0.2)
    state = rospy.wait_for_message("gripper2/state/", VacuumGripperState, timeout=1.0)
    client = actionlib.SimpleActionClient("execute_trajectory/", ExecuteTrajectoryAction)
    try:
        actionlib.SimpleActionClient("~execute_trajectory", ExecuteTrajectoryAction)
        private_action = "accepted"
    except Exception as e:
        private_action = str(e)
    with open(sys.argv[1], "w") as f:
        json.dump(
            {
                "service": gripper.resolved_name,
                "success": response.success,
                "enabled": state.enabled,
                "attached": state.attached,
                "server": client.wait_for_server(rospy.Duration(1.0)),
                "private_action": private_action,
            },
            f,
        )
