#!/usr/bin/env python
import rospy
from flexbe_core import EventState, Logger
from flexbe_core.proxy import ProxyServiceCaller
from omtp_gazebo.msg import ConveyorBeltState
from omtp_gazebo.srv import ConveyorBeltControl, ConveyorBeltControlRequest


class ConveyorPowerState(EventState):
    '''
    Sets the conveyor belt's power (0 stops it, 100 is full speed).

    -- stop     bool    True: stop the belt, ignoring the speed input key.

    ># speed    float   The power to set, in [0, 100].

    <= succeeded        The belt took the new power.
    <= failed           The service refused it or is missing.
    '''

    def __init__(self, stop):
        super(ConveyorPowerState, self).__init__(outcomes=['succeeded', 'failed'], input_keys=['speed'])
        self._stop = stop
        self._service = '/omtp/conveyor/control'
        self._client = ProxyServiceCaller({self._service: ConveyorBeltControl})
        self._ok = False

    def on_enter(self, userdata):
        power = 0.0 if self._stop else float(userdata.speed)
        request = ConveyorBeltControlRequest(state=ConveyorBeltState(power=power))
        try:
            self._ok = self._client.call(self._service, request).success
        except Exception as e:
            Logger.logwarn('Could not set the conveyor power: %s' % e)
            self._ok = False
        rospy.loginfo('conveyor power %.0f: %s', power, 'ok' if self._ok else 'failed')

    def execute(self, userdata):
        return 'succeeded' if self._ok else 'failed'
