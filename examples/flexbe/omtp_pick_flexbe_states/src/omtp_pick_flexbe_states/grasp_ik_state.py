#!/usr/bin/env python
import copy
import math

import rospy
from flexbe_core import EventState, Logger
from flexbe_core.proxy import ProxyServiceCaller
from geometry_msgs.msg import Quaternion
from moveit_msgs.srv import GetPositionIK, GetPositionIKRequest
from sensor_msgs.msg import JointState
from tf.transformations import quaternion_from_euler


class GraspIKState(EventState):
    '''
    Joint values that put the tool, pointing down, offset above a pose (MoveIt's /compute_ik).

    -- group        string      The move group, e.g. robot1.
    -- offset       float       Height of the tool link above the pose (m).
    -- tool_link    string      The tool link, e.g. vacuum_gripper1_suction_cup.

    ># pose         PoseStamped The pose to grasp (any frame).
    #> joint_values float[]     The joint values.
    #> joint_names  string[]    Their joint names.

    <= continue                 IK found a solution.
    <= failed                   It did not.
    '''

    def __init__(self, group, offset, tool_link):
        super(GraspIKState, self).__init__(outcomes=['continue', 'failed'], input_keys=['pose'],
                                           output_keys=['joint_values', 'joint_names'])
        self._group = group
        self._offset = offset
        self._tool_link = tool_link
        self._service = '/compute_ik'
        self._ik = ProxyServiceCaller({self._service: GetPositionIK})
        self._response = None

    def on_enter(self, userdata):
        target = copy.deepcopy(userdata.pose)
        target.pose.position.z += self._offset
        target.pose.orientation = Quaternion(*quaternion_from_euler(math.pi, 0.0, 0.0))
        request = GetPositionIKRequest()
        request.ik_request.group_name = self._group
        request.ik_request.robot_state.joint_state = rospy.wait_for_message(
            '/' + self._group + '/joint_states', JointState, timeout=1.0)
        request.ik_request.ik_link_name = self._tool_link
        request.ik_request.pose_stamped = target
        request.ik_request.avoid_collisions = True
        try:
            self._response = self._ik.call(self._service, request)
        except Exception as e:
            Logger.logwarn('Could not call IK: %s' % e)
            self._response = None

    def execute(self, userdata):
        if self._response is None or self._response.error_code.val != 1:
            Logger.logwarn('no IK solution (%s)' % (self._response.error_code.val if self._response else 'no answer'))
            return 'failed'
        solution = self._response.solution.joint_state
        userdata.joint_names = list(solution.name)
        userdata.joint_values = list(solution.position)
        return 'continue'
