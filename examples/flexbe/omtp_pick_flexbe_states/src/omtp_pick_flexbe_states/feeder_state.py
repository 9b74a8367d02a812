#!/usr/bin/env python
from flexbe_core import EventState, Logger
from flexbe_core.proxy import ProxyServiceCaller
from std_srvs.srv import Empty, EmptyRequest


class FeederState(EventState):
    '''
    Starts or stops the conveyor spawner (/start_spawn, /stop_spawn).

    -- start    bool    True starts the spawner, False stops it.

    <= succeeded        Done.
    <= failed           The service is missing or failed.
    '''

    def __init__(self, start):
        super(FeederState, self).__init__(outcomes=['succeeded', 'failed'])
        self._service = '/start_spawn' if start else '/stop_spawn'
        self._client = ProxyServiceCaller({self._service: Empty})
        self._ok = False

    def on_enter(self, userdata):
        try:
            self._client.call(self._service, EmptyRequest())
            self._ok = True
        except Exception as e:
            Logger.logwarn('Feeder service %s failed: %s' % (self._service, e))
            self._ok = False

    def execute(self, userdata):
        return 'succeeded' if self._ok else 'failed'
