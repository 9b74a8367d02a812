#!/usr/bin/env python
import rospy
from flexbe_core import EventState, Logger
from omtp_gazebo.msg import ConveyorBeltState
from omtp_gazebo.srv import ConveyorBeltControl, ConveyorBeltControlRequest
from std_srvs.srv import Empty


class StartLineState(EventState):
	'''
	Starts the belt and the part spawner.

	-- power	float	The belt power, 0 to 100.

	<= done			Both are running.
	<= failed		A service call failed.
	'''

	def __init__(self, power=100.0):
		super(StartLineState, self).__init__(outcomes=['done', 'failed'])
		self._power = power
		self._ok = False

	def on_enter(self, userdata):
		try:
			rospy.wait_for_service('/omtp/conveyor/control', 2.0)
			belt = rospy.ServiceProxy('/omtp/conveyor/control', ConveyorBeltControl)
			self._ok = belt(ConveyorBeltControlRequest(state=ConveyorBeltState(power=self._power))).success
			rospy.ServiceProxy('/start_spawn', Empty)()
		except rospy.ServiceException, e:
			print "service call failed: %s" % e
			self._ok = False
	        print "belt power", self._power

	def execute(self, userdata):
		if self._ok:
			return 'done'
		return 'failed'
