#!/usr/bin/env python
# -*- coding: utf-8 -*-
###########################################################
#               WARNING: Generated code!                  #
#              **************************                 #
# Manual changes may get lost if file is generated again. #
# Only code inside the [MANUAL] tags will be kept.        #
###########################################################

from flexbe_core import Behavior, Autonomy, OperatableStateMachine, ConcurrencyContainer, PriorityContainer, Logger
from flexbe_states.calculation_state import CalculationState
from flexbe_states.check_condition_state import CheckConditionState
from flexbe_states.decision_state import DecisionState
from flexbe_states.log_key_state import LogKeyState
from flexbe_states.subscriber_state import SubscriberState
from flexbe_states.wait_state import WaitState
from omtp_pick_flexbe_states.conveyor_power_state import ConveyorPowerState
from omtp_pick_flexbe_states.feeder_state import FeederState
from omtp_pick_flexbe_states.frame_pose_state import FramePoseState
from omtp_pick_flexbe_states.grasp_ik_state import GraspIKState
from omtp_pick_flexbe_states.gripper_state import GripperState
from omtp_pick_flexbe_states.move_joints_state import MoveJointsState
from omtp_pick_flexbe_states.named_pose_state import NamedPoseState
from omtp_pick_flexbe_states.part_pose_state import PartPoseState
# Additional imports can be added inside the following tags
# [MANUAL_IMPORT]

# [/MANUAL_IMPORT]


'''
Created on Tue Nov 24 2026
@author: omtp_drake
'''
class ConveyorPickSM(Behavior):
	'''
	Robot 1 picks the parts the break beam stops on the belt and drops them into bin 2.
	'''


	def __init__(self):
		super(ConveyorPickSM, self).__init__()
		self.name = 'Conveyor Pick'

		# parameters of this behavior
		self.add_parameter('parts', 1)
		self.add_parameter('conveyor_speed', 100)

		# references to used behaviors

		# Additional initialization code can be added inside the following tags
		# [MANUAL_INIT]

		# [/MANUAL_INIT]

		# Behavior comments:



	def create(self):
		tool_link = "vacuum_gripper1_suction_cup"
		# x:1130 y:640, x:130 y:640
		_state_machine = OperatableStateMachine(outcomes=['finished', 'failed'])
		_state_machine.userdata.conveyor_speed = self.conveyor_speed
		_state_machine.userdata.picked = 0

		# Additional creation code can be added inside the following tags
		# [MANUAL_CREATE]

		# [/MANUAL_CREATE]

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

			# x:530 y:40
			OperatableStateMachine.add('feed one part',
										WaitState(wait_time=3.5),
										transitions={'done': 'stop feeder'},
										autonomy={'done': Autonomy.Off})

			# x:630 y:40
			OperatableStateMachine.add('wait for beam',
										SubscriberState(topic="/break_beam_sensor", blocking=True, clear=True),
										transitions={'received': 'beam broken?', 'unavailable': 'failed'},
										autonomy={'received': Autonomy.Off, 'unavailable': Autonomy.Off},
										remapping={'message': 'beam'})

			# x:830 y:40
			OperatableStateMachine.add('beam broken?',
										DecisionState(outcomes=["yes", "no"], conditions=lambda m: "yes" if m.object_detected else "no"),
										transitions={'yes': 'settle', 'no': 'wait for beam'},
										autonomy={'yes': Autonomy.Off, 'no': Autonomy.Off},
										remapping={'input_value': 'beam'})

			# x:1030 y:40
			OperatableStateMachine.add('stop feeder',
										FeederState(start=False),
										transitions={'succeeded': 'wait for beam', 'failed': 'failed'},
										autonomy={'succeeded': Autonomy.Off, 'failed': Autonomy.Off})

			# x:1030 y:140
			OperatableStateMachine.add('settle',
										WaitState(wait_time=0.5),
										transitions={'done': 'detect part'},
										autonomy={'done': Autonomy.Off})

			# x:1030 y:240
			OperatableStateMachine.add('detect part',
										PartPoseState(ref_frame="world", camera_topic="/omtp/logical_camera", camera_frame="logical_camera_frame"),
										transitions={'continue': 'log pose', 'failed': 'failed'},
										autonomy={'continue': Autonomy.Off, 'failed': Autonomy.Off},
										remapping={'pose': 'part_pose'})

			# x:1030 y:340
			OperatableStateMachine.add('log pose',
										LogKeyState(text="part at {}", severity=Logger.REPORT_HINT),
										transitions={'done': 'gripper on'},
										autonomy={'done': Autonomy.Off},
										remapping={'data': 'part_pose'})

			# x:830 y:340
			OperatableStateMachine.add('gripper on',
										GripperState(enable=True, service_name="/gripper1/control"),
										transitions={'continue': 'above part', 'failed': 'failed'},
										autonomy={'continue': Autonomy.Off, 'failed': Autonomy.Off})

			# x:630 y:340
			OperatableStateMachine.add('above part',
										self._move_above(0.4, tool_link),
										transitions={'reached': 'onto part', 'planning_failed': 'failed', 'control_failed': 'failed'},
										autonomy={'reached': Autonomy.Inherit, 'planning_failed': Autonomy.Inherit, 'control_failed': Autonomy.Inherit},
										remapping={'pose': 'part_pose'})

			# x:630 y:440
			OperatableStateMachine.add('onto part',
										self._move_above(0.16, tool_link),
										transitions={'reached': 'attach', 'planning_failed': 'failed', 'control_failed': 'failed'},
										autonomy={'reached': Autonomy.Inherit, 'planning_failed': Autonomy.Inherit, 'control_failed': Autonomy.Inherit},
										remapping={'pose': 'part_pose'})

			# x:630 y:540
			OperatableStateMachine.add('attach',
										WaitState(wait_time=0.3),
										transitions={'done': 'lift'},
										autonomy={'done': Autonomy.Off})

			# x:430 y:540
			OperatableStateMachine.add('lift',
										self._move_above(0.5, tool_link),
										transitions={'reached': 'bin pose', 'planning_failed': 'failed', 'control_failed': 'failed'},
										autonomy={'reached': Autonomy.Inherit, 'planning_failed': Autonomy.Inherit, 'control_failed': Autonomy.Inherit},
										remapping={'pose': 'part_pose'})

			# x:230 y:540
			OperatableStateMachine.add('bin pose',
										FramePoseState(frame="bin_2_base_link", ref_frame="world"),
										transitions={'continue': 'over bin', 'failed': 'failed'},
										autonomy={'continue': Autonomy.Off, 'failed': Autonomy.Off},
										remapping={'pose': 'bin_pose'})

			# x:230 y:440
			OperatableStateMachine.add('over bin',
										self._move_above(0.8, tool_link),
										transitions={'reached': 'gripper off', 'planning_failed': 'failed', 'control_failed': 'failed'},
										autonomy={'reached': Autonomy.Inherit, 'planning_failed': Autonomy.Inherit, 'control_failed': Autonomy.Inherit},
										remapping={'pose': 'bin_pose'})

			# x:230 y:340
			OperatableStateMachine.add('gripper off',
										GripperState(enable=False, service_name="/gripper1/control"),
										transitions={'continue': 'drop', 'failed': 'failed'},
										autonomy={'continue': Autonomy.Off, 'failed': Autonomy.Off})

			# x:230 y:240
			OperatableStateMachine.add('drop',
										WaitState(wait_time=0.5),
										transitions={'done': 'count'},
										autonomy={'done': Autonomy.Off})

			# x:430 y:240
			OperatableStateMachine.add('count',
										CalculationState(calculation=lambda n: n + 1),
										transitions={'done': 'log count'},
										autonomy={'done': Autonomy.Off},
										remapping={'input_value': 'picked', 'output_value': 'picked'})

			# x:430 y:140
			OperatableStateMachine.add('log count',
										LogKeyState(text="parts in bin 2: {}", severity=Logger.REPORT_INFO),
										transitions={'done': 'enough?'},
										autonomy={'done': Autonomy.Off},
										remapping={'data': 'picked'})

			# x:630 y:140
			OperatableStateMachine.add('enough?',
										CheckConditionState(predicate=lambda n: n >= self.parts),
										transitions={'true': 'back home', 'false': 'start conveyor'},
										autonomy={'true': Autonomy.Off, 'false': Autonomy.Off},
										remapping={'input_value': 'picked'})

			# x:830 y:640
			OperatableStateMachine.add('back home',
										NamedPoseState(config_name="R1Home", move_group="robot1", action_topic='/move_group'),
										transitions={'reached': 'finished', 'planning_failed': 'failed', 'control_failed': 'failed', 'param_error': 'failed'},
										autonomy={'reached': Autonomy.Off, 'planning_failed': Autonomy.Off, 'control_failed': Autonomy.Off, 'param_error': Autonomy.Off})


		return _state_machine


	# Private functions can be added inside the following tags
	# [MANUAL_FUNC]
	def _move_above(self, offset, tool_link):
		# IK for the tool pointing down, offset above the pose; then MoveIt moves there
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
	# [/MANUAL_FUNC]
