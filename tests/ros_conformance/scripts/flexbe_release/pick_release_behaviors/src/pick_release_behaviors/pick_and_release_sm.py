#!/usr/bin/env python
# -*- coding: utf-8 -*-
###########################################################
#               WARNING: Generated code!                  #
#              **************************                 #
# Manual changes may get lost if file is generated again. #
# Only code inside the [MANUAL] tags will be kept.        #
###########################################################

from flexbe_core import Behavior, Autonomy, OperatableStateMachine, ConcurrencyContainer, PriorityContainer, Logger
from flexbe_states.decision_state import DecisionState
from flexbe_states.subscriber_state import SubscriberState
from flexbe_states.wait_state import WaitState
from omtp_pick_flexbe_states.conveyor_power_state import ConveyorPowerState
from omtp_pick_flexbe_states.feeder_state import FeederState
from omtp_pick_flexbe_states.grasp_ik_state import GraspIKState
from omtp_pick_flexbe_states.gripper_state import GripperState
from omtp_pick_flexbe_states.move_joints_state import MoveJointsState
from omtp_pick_flexbe_states.named_pose_state import NamedPoseState
from omtp_pick_flexbe_states.part_pose_state import PartPoseState


'''
Created on Fri Nov 27 2026
@author: student
'''
class PickAndReleaseSM(Behavior):
	'''
	Robot 1 picks the part the break beam stops, turns to R1Place and lets it go.
	'''


	def __init__(self):
		super(PickAndReleaseSM, self).__init__()
		self.name = 'Pick And Release'


	def create(self):
		tool_link = "vacuum_gripper1_suction_cup"
		# x:930 y:540, x:130 y:540
		_state_machine = OperatableStateMachine(outcomes=['finished', 'failed'])
		_state_machine.userdata.conveyor_speed = 100

		with _state_machine:
			# x:30 y:40
			OperatableStateMachine.add('go home',
										NamedPoseState(config_name="R1Home", move_group="robot1", action_topic='/move_group'),
										transitions={'reached': 'start conveyor', 'planning_failed': 'failed', 'control_failed': 'failed', 'param_error': 'failed'},
										autonomy={'reached': Autonomy.Off, 'planning_failed': Autonomy.Off, 'control_failed': Autonomy.Off, 'param_error': Autonomy.Off})

			# x:230 y:40
			OperatableStateMachine.add('start conveyor',
										ConveyorPowerState(stop=False),
										transitions={'succeeded': 'start feeder', 'failed': 'failed'},
										autonomy={'succeeded': Autonomy.Off, 'failed': Autonomy.Off},
										remapping={'speed': 'conveyor_speed'})

			# x:430 y:40
			OperatableStateMachine.add('start feeder',
										FeederState(start=True),
										transitions={'succeeded': 'feed one part', 'failed': 'failed'},
										autonomy={'succeeded': Autonomy.Off, 'failed': Autonomy.Off})

			# x:630 y:40
			OperatableStateMachine.add('feed one part',
										WaitState(wait_time=1.5),
										transitions={'done': 'stop feeder'},
										autonomy={'done': Autonomy.Off})

			# x:830 y:40
			OperatableStateMachine.add('stop feeder',
										FeederState(start=False),
										transitions={'succeeded': 'wait for beam', 'failed': 'failed'},
										autonomy={'succeeded': Autonomy.Off, 'failed': Autonomy.Off})

			# x:830 y:140
			OperatableStateMachine.add('wait for beam',
										SubscriberState(topic="/break_beam_sensor", blocking=True, clear=True),
										transitions={'received': 'beam broken?', 'unavailable': 'failed'},
										autonomy={'received': Autonomy.Off, 'unavailable': Autonomy.Off},
										remapping={'message': 'beam'})

			# x:630 y:140
			OperatableStateMachine.add('beam broken?',
										DecisionState(outcomes=["yes", "no"], conditions=lambda m: "yes" if m.object_detected else "no"),
										transitions={'yes': 'settle', 'no': 'wait for beam'},
										autonomy={'yes': Autonomy.Off, 'no': Autonomy.Off},
										remapping={'input_value': 'beam'})

			# x:430 y:140
			OperatableStateMachine.add('settle',
										WaitState(wait_time=0.5),
										transitions={'done': 'detect part'},
										autonomy={'done': Autonomy.Off})

			# x:230 y:140
			OperatableStateMachine.add('detect part',
										PartPoseState(ref_frame="world", camera_topic="/omtp/logical_camera", camera_frame="logical_camera_frame"),
										transitions={'continue': 'gripper on', 'failed': 'failed'},
										autonomy={'continue': Autonomy.Off, 'failed': Autonomy.Off},
										remapping={'pose': 'part_pose'})

			# x:230 y:240
			OperatableStateMachine.add('gripper on',
										GripperState(enable=True, service_name="/gripper1/control"),
										transitions={'continue': 'above part', 'failed': 'failed'},
										autonomy={'continue': Autonomy.Off, 'failed': Autonomy.Off})

			# x:430 y:240
			OperatableStateMachine.add('above part',
										self._move_above(0.4, tool_link),
										transitions={'reached': 'onto part', 'planning_failed': 'failed', 'control_failed': 'failed'},
										autonomy={'reached': Autonomy.Inherit, 'planning_failed': Autonomy.Inherit, 'control_failed': Autonomy.Inherit},
										remapping={'pose': 'part_pose'})

			# x:630 y:240
			OperatableStateMachine.add('onto part',
										self._move_above(0.16, tool_link),
										transitions={'reached': 'attach', 'planning_failed': 'failed', 'control_failed': 'failed'},
										autonomy={'reached': Autonomy.Inherit, 'planning_failed': Autonomy.Inherit, 'control_failed': Autonomy.Inherit},
										remapping={'pose': 'part_pose'})

			# x:830 y:240
			OperatableStateMachine.add('attach',
										WaitState(wait_time=0.3),
										transitions={'done': 'lift'},
										autonomy={'done': Autonomy.Off})

			# x:830 y:340
			OperatableStateMachine.add('lift',
										self._move_above(0.5, tool_link),
										transitions={'reached': 'go to place', 'planning_failed': 'failed', 'control_failed': 'failed'},
										autonomy={'reached': Autonomy.Inherit, 'planning_failed': Autonomy.Inherit, 'control_failed': Autonomy.Inherit},
										remapping={'pose': 'part_pose'})

			# x:630 y:440
			OperatableStateMachine.add('go to place',
										NamedPoseState(config_name="R1Place", move_group="robot1", action_topic='/move_group'),
										transitions={'reached': 'gripper off', 'planning_failed': 'failed', 'control_failed': 'failed', 'param_error': 'failed'},
										autonomy={'reached': Autonomy.Off, 'planning_failed': Autonomy.Off, 'control_failed': Autonomy.Off, 'param_error': Autonomy.Off})

			# x:830 y:440
			OperatableStateMachine.add('gripper off',
										GripperState(enable=False, service_name="/gripper1/control"),
										transitions={'continue': 'finished', 'failed': 'failed'},
										autonomy={'continue': Autonomy.Off, 'failed': Autonomy.Off})


		return _state_machine


	def _move_above(self, offset, tool_link):
		_sm = OperatableStateMachine(outcomes=['reached', 'planning_failed', 'control_failed'], input_keys=['pose'])

		with _sm:
			OperatableStateMachine.add('ik',
										GraspIKState(group="robot1", offset=offset, tool_link=tool_link),
										transitions={'continue': 'move', 'failed': 'planning_failed'},
										autonomy={'continue': Autonomy.Off, 'failed': Autonomy.Off},
										remapping={'pose': 'pose', 'joint_values': 'joint_values', 'joint_names': 'joint_names'})

			OperatableStateMachine.add('move',
										MoveJointsState(move_group="robot1", action_topic='/move_group'),
										transitions={'reached': 'reached', 'planning_failed': 'planning_failed', 'control_failed': 'control_failed'},
										autonomy={'reached': Autonomy.Off, 'planning_failed': Autonomy.Off, 'control_failed': Autonomy.Off},
										remapping={'joint_values': 'joint_values', 'joint_names': 'joint_names'})

		return _sm
