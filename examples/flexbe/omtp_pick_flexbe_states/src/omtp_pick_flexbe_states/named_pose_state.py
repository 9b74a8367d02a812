#!/usr/bin/env python
import xml.etree.ElementTree as ET

import rospy
from flexbe_core import EventState, Logger
from flexbe_core.proxy import ProxyActionClient
from moveit_msgs.msg import Constraints, JointConstraint, MoveGroupAction, MoveGroupGoal, MoveItErrorCodes


class NamedPoseState(EventState):
    '''
    Moves a group to a named pose (group_state) of the SRDF on /robot_description_semantic.

    -- config_name      string  The named pose, e.g. R1Home.
    -- move_group       string  The group, e.g. robot1.
    -- action_topic     string  MoveIt's action, /move_group.

    <= reached                  The arm is there.
    <= planning_failed          No plan.
    <= control_failed           Execution failed.
    <= param_error              No SRDF, or no such named pose in it.
    '''

    def __init__(self, config_name, move_group, action_topic='/move_group'):
        super(NamedPoseState, self).__init__(
            outcomes=['reached', 'planning_failed', 'control_failed', 'param_error'])
        self._config = config_name
        self._group = move_group
        self._topic = action_topic
        self._client = ProxyActionClient({self._topic: MoveGroupAction})
        self._srdf = rospy.get_param('/robot_description_semantic', None)
        self._failed = None

    def _joints(self):
        root = ET.fromstring(self._srdf)
        for state in root.iter('group_state'):
            if state.get('name') == self._config and state.get('group') == self._group:
                return [(j.get('name'), float(j.get('value'))) for j in state.iter('joint')]
        return None

    def on_enter(self, userdata):
        self._failed = None
        joints = self._joints() if self._srdf else None
        if not joints:
            Logger.logwarn('No named pose %s of %s in the SRDF' % (self._config, self._group))
            self._failed = 'param_error'
            return
        goal = MoveGroupGoal()
        goal.request.group_name = self._group
        constraints = Constraints()
        for name, value in joints:
            constraints.joint_constraints.append(JointConstraint(joint_name=name, position=value, weight=1.0))
        goal.request.goal_constraints.append(constraints)
        self._client.send_goal(self._topic, goal)

    def execute(self, userdata):
        if self._failed:
            return self._failed
        if not self._client.has_result(self._topic):
            return None
        code = self._client.get_result(self._topic).error_code.val
        if code == MoveItErrorCodes.SUCCESS:
            return 'reached'
        return 'control_failed' if code == MoveItErrorCodes.CONTROL_FAILED else 'planning_failed'
