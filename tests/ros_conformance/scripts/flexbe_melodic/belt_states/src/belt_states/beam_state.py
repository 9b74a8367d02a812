#!/usr/bin/env python
import rospy
from flexbe_core import EventState, Logger
from omtp_gazebo.msg import Proximity


class BeamState(EventState):
	'''
	Waits until the break beam sees a part.

	#> seen_at	float	When it did (s).

	<= seen			A part broke the beam.
	'''

	def __init__(self):
		super(BeamState, self).__init__(outcomes=['seen'], output_keys=['seen_at'])
		self._beam = []
		rospy.Subscriber('/break_beam_sensor', Proximity, self._on_beam)

	def _on_beam(self, msg):
		if msg.object_detected:
			self._beam.append(rospy.get_time())

	def execute(self, userdata):
		if self._beam:
			userdata.seen_at = map(float, self._beam)[0]
			Logger.loginfo('beam broken at %.2f s' % userdata.seen_at)
			return 'seen'
