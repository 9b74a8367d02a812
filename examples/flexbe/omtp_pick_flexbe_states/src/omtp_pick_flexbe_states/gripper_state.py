#!/usr/bin/env python
from flexbe_core import EventState, Logger
from flexbe_core.proxy import ProxyServiceCaller
from omtp_gazebo.srv import VacuumGripperControl, VacuumGripperControlRequest


class GripperState(EventState):
    '''
    Switches a vacuum gripper on or off.

    -- enable           bool    True: suction on.
    -- service_name     string  The gripper's service, e.g. /gripper1/control.

    <= continue                 The gripper switched.
    <= failed                   It did not.
    '''

    def __init__(self, enable, service_name='/gripper1/control'):
        super(GripperState, self).__init__(outcomes=['continue', 'failed'])
        self._service = service_name
        self._client = ProxyServiceCaller({self._service: VacuumGripperControl})
        self._request = VacuumGripperControlRequest(enable=bool(enable))
        self._ok = False

    def on_enter(self, userdata):
        try:
            self._ok = self._client.call(self._service, self._request).success
        except Exception as e:
            Logger.logwarn('Could not switch the gripper: %s' % e)
            self._ok = False

    def execute(self, userdata):
        return 'continue' if self._ok else 'failed'
