#!/usr/bin/env python
from flexbe_core import EventState, Logger
from flexbe_core.proxy import ProxyActionClient
from moveit_msgs.msg import Constraints, JointConstraint, MoveGroupAction, MoveGroupGoal, MoveItErrorCodes


class MoveJointsState(EventState):
    '''
    Plans and moves a group to joint values with MoveIt's move_group action.

    -- move_group       string  The group, e.g. robot1.
    -- action_topic     string  MoveIt's action, /move_group.
    -- velocity         float   Velocity scaling factor in (0, 1].

    ># joint_values     float[] Target joint values.
    ># joint_names      string[] Their names.

    <= reached                  The arm is there.
    <= planning_failed          MoveIt found no plan.
    <= control_failed           Executing the plan failed.
    '''

    def __init__(self, move_group, action_topic='/move_group', velocity=1.0):
        super(MoveJointsState, self).__init__(outcomes=['reached', 'planning_failed', 'control_failed'],
                                              input_keys=['joint_values', 'joint_names'])
        self._group = move_group
        self._topic = action_topic
        self._velocity = velocity
        self._client = ProxyActionClient({self._topic: MoveGroupAction})
        self._failed = None

    def on_enter(self, userdata):
        self._failed = None
        goal = MoveGroupGoal()
        goal.request.group_name = self._group
        goal.request.max_velocity_scaling_factor = self._velocity
        constraints = Constraints()
        for name, value in zip(userdata.joint_names, userdata.joint_values):
            constraints.joint_constraints.append(JointConstraint(joint_name=name, position=value, weight=1.0))
        goal.request.goal_constraints.append(constraints)
        try:
            self._client.send_goal(self._topic, goal)
        except Exception as e:
            Logger.logwarn('Could not send the goal of %s: %s' % (self._group, e))
            self._failed = 'planning_failed'

    def execute(self, userdata):
        if self._failed:
            return self._failed
        if not self._client.has_result(self._topic):
            return None
        code = self._client.get_result(self._topic).error_code.val
        if code == MoveItErrorCodes.SUCCESS:
            return 'reached'
        Logger.logwarn('%s: move_group answered error code %d' % (self._group, code))
        return 'control_failed' if code == MoveItErrorCodes.CONTROL_FAILED else 'planning_failed'

    def on_stop(self):
        if self._client.is_available(self._topic) and not self._client.has_result(self._topic):
            self._client.cancel(self._topic)
