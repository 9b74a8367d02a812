#!/usr/bin/env python
# A Melodic-era course script (Python 2.7): robot 2 to its place pose through the
# execute_trajectory action, the gripper switched off with a Python 2 except clause.
import sys
import json
import rospy
import moveit_commander
import moveit_msgs.msg
import actionlib
from omtp_gazebo.srv import VacuumGripperControl


def gripper(on):
    rospy.wait_for_service('/gripper2/control')
    try:
        control = rospy.ServiceProxy('/gripper2/control', VacuumGripperControl)
        control(on)
    except rospy.ServiceException, e:
        print "Service call failed: %s" % e


if __name__ == '__main__':
    moveit_commander.roscpp_initialize(sys.argv)
    rospy.init_node('melodic_place', anonymous=True)
    robot2_group = moveit_commander.MoveGroupCommander("robot2")
    client = actionlib.SimpleActionClient('execute_trajectory', moveit_msgs.msg.ExecuteTrajectoryAction)
    client.wait_for_server()
    robot2_group.set_named_target("R2Place")
    plan = robot2_group.plan()
    goal = moveit_msgs.msg.ExecuteTrajectoryGoal()
    goal.trajectory = plan
    client.send_goal(goal)
    client.wait_for_result()
    gripper(False)
    seen = {}
    if not seen.has_key('joints'):
        seen['joints'] = robot2_group.get_current_joint_values()
    print "done at", rospy.get_time()
    json.dump(seen, open(sys.argv[1], 'w'))
    moveit_commander.roscpp_shutdown()
