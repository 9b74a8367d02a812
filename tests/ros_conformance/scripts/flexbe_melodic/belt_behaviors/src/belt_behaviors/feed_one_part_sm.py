#!/usr/bin/env python
# -*- coding: utf-8 -*-
###########################################################
#               WARNING: Generated code!                  #
#              **************************                 #
# Manual changes may get lost if file is generated again. #
# Only code inside the [MANUAL] tags will be kept.        #
###########################################################

from flexbe_core import Behavior, Autonomy, OperatableStateMachine, ConcurrencyContainer, PriorityContainer, Logger
from belt_states.beam_state import BeamState
from belt_states.start_line_state import StartLineState
# Additional imports can be added inside the following tags
# [MANUAL_IMPORT]

# [/MANUAL_IMPORT]


'''
Created on Fri Nov 27 2026
@author: student
'''
class FeedOnePartSM(Behavior):
	'''
	Starts the belt and the spawner and waits for the break beam.
	'''


	def __init__(self):
		super(FeedOnePartSM, self).__init__()
		self.name = 'Feed One Part'


	def create(self):
		# x:630 y:140, x:130 y:240
		_state_machine = OperatableStateMachine(outcomes=['finished', 'failed'])

		with _state_machine:
			# x:30 y:40
			OperatableStateMachine.add('start line',
										StartLineState(power=100.0),
										transitions={'done': 'wait for beam', 'failed': 'failed'},
										autonomy={'done': Autonomy.Off, 'failed': Autonomy.Off})

			# x:330 y:40
			OperatableStateMachine.add('wait for beam',
										BeamState(),
										transitions={'seen': 'finished'},
										autonomy={'seen': Autonomy.Off},
										remapping={'seen_at': 'seen_at'})

		return _state_machine
