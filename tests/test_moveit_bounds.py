"""MoveIt's joint bounds as move_group applies them: a grasp with the wrist written as
3.1416 (a hair above pi) is planned to the bound and the next joint goal plans; a start
state just outside the bounds is fixed (FixStartStateBounds) and the report says so; one
beyond the bounds error is refused with START_STATE_INVALID; commander targets within
goal_joint_tolerance of a bound are accepted, farther ones refused."""

from __future__ import annotations

import json
import math
import textwrap
from pathlib import Path

import pytest

from omtp_drake.ros import run_script
from omtp_drake.ros.flexbe import run_behavior

ROOT = Path(__file__).resolve().parents[1]
EXAMPLE = ROOT / "examples" / "flexbe"
SCENARIO = "lecture7_flexbe"

PACKAGE_XML = """<?xml version="1.0"?>
<package format="2"><name>{name}</name><version>0.0.1</version><description>test</description>
<maintainer email="s@example.org">student</maintainer><license>BSD</license></package>
"""
MANIFEST = """<?xml version="1.0" encoding="UTF-8"?>
<behavior name="Turn Pick">
\t<executable package_path="turn_flexbe_behaviors.turn_pick_sm" class="TurnPickSM" />
</behavior>
"""

# A student's behaviour in the course's generated layout: the grasp configuration from
# IK with the cup turned to +pi "3.1416" (written to four decimals), the grasp, then a
# joint goal (the SRDF's R1Home) with the part on the cup.
TURN_PICK = """\
#!/usr/bin/env python
from flexbe_core import Behavior, Autonomy, OperatableStateMachine, Logger
from flexbe_states.calculation_state import CalculationState
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


class TurnPickSM(Behavior):
\t'''
\tPicks the part with the cup turned to +pi, then goes home.
\t'''

\tdef __init__(self):
\t\tsuper(TurnPickSM, self).__init__()
\t\tself.name = 'Turn Pick'

\tdef create(self):
\t\ttool_link = "vacuum_gripper1_suction_cup"
\t\t_state_machine = OperatableStateMachine(outcomes=['finished', 'failed'])
\t\t_state_machine.userdata.speed = 100

\t\twith _state_machine:
\t\t\tOperatableStateMachine.add('start conveyor', ConveyorPowerState(stop=False),
\t\t\t\ttransitions={'succeeded': 'start feeder', 'failed': 'failed'},
\t\t\t\tautonomy={'succeeded': Autonomy.Off, 'failed': Autonomy.Off}, remapping={'speed': 'speed'})
\t\t\tOperatableStateMachine.add('start feeder', FeederState(start=True),
\t\t\t\ttransitions={'succeeded': 'one part', 'failed': 'failed'},
\t\t\t\tautonomy={'succeeded': Autonomy.Off, 'failed': Autonomy.Off})
\t\t\tOperatableStateMachine.add('one part', WaitState(wait_time=3.5),
\t\t\t\ttransitions={'done': 'stop feeder'}, autonomy={'done': Autonomy.Off})
\t\t\tOperatableStateMachine.add('stop feeder', FeederState(start=False),
\t\t\t\ttransitions={'succeeded': 'wait for beam', 'failed': 'failed'},
\t\t\t\tautonomy={'succeeded': Autonomy.Off, 'failed': Autonomy.Off})
\t\t\tOperatableStateMachine.add('wait for beam',
\t\t\t\tSubscriberState(topic="/break_beam_sensor", blocking=True, clear=True),
\t\t\t\ttransitions={'received': 'beam?', 'unavailable': 'failed'},
\t\t\t\tautonomy={'received': Autonomy.Off, 'unavailable': Autonomy.Off}, remapping={'message': 'beam'})
\t\t\tOperatableStateMachine.add('beam?',
\t\t\t\tDecisionState(outcomes=["yes", "no"], conditions=lambda m: "yes" if m.object_detected else "no"),
\t\t\t\ttransitions={'yes': 'detect part', 'no': 'wait for beam'},
\t\t\t\tautonomy={'yes': Autonomy.Off, 'no': Autonomy.Off}, remapping={'input_value': 'beam'})
\t\t\tOperatableStateMachine.add('detect part',
\t\t\t\tPartPoseState(ref_frame="world", camera_topic="/omtp/logical_camera",
\t\t\t\t\tcamera_frame="logical_camera_frame"),
\t\t\t\ttransitions={'continue': 'grasp ik', 'failed': 'failed'},
\t\t\t\tautonomy={'continue': Autonomy.Off, 'failed': Autonomy.Off}, remapping={'pose': 'part_pose'})
\t\t\tOperatableStateMachine.add('grasp ik', GraspIKState(group="robot1", offset=0.16, tool_link=tool_link),
\t\t\t\ttransitions={'continue': 'turn cup', 'failed': 'failed'},
\t\t\t\tautonomy={'continue': Autonomy.Off, 'failed': Autonomy.Off},
\t\t\t\tremapping={'pose': 'part_pose', 'joint_values': 'joint_values', 'joint_names': 'joint_names'})
\t\t\tOperatableStateMachine.add('turn cup', CalculationState(calculation=lambda q: list(q[:5]) + [3.1416]),
\t\t\t\ttransitions={'done': 'gripper on'}, autonomy={'done': Autonomy.Off},
\t\t\t\tremapping={'input_value': 'joint_values', 'output_value': 'joint_values'})
\t\t\tOperatableStateMachine.add('gripper on', GripperState(enable=True, service_name="/gripper1/control"),
\t\t\t\ttransitions={'continue': 'grasp', 'failed': 'failed'},
\t\t\t\tautonomy={'continue': Autonomy.Off, 'failed': Autonomy.Off})
\t\t\tOperatableStateMachine.add('grasp', MoveJointsState(move_group="robot1"),
\t\t\t\ttransitions={'reached': 'attach', 'planning_failed': 'failed', 'control_failed': 'failed'},
\t\t\t\tautonomy={'reached': Autonomy.Off, 'planning_failed': Autonomy.Off, 'control_failed': Autonomy.Off},
\t\t\t\tremapping={'joint_values': 'joint_values', 'joint_names': 'joint_names'})
\t\t\tOperatableStateMachine.add('attach', WaitState(wait_time=0.3),
\t\t\t\ttransitions={'done': 'lift ik'}, autonomy={'done': Autonomy.Off})
\t\t\tOperatableStateMachine.add('lift ik', GraspIKState(group="robot1", offset=0.5, tool_link=tool_link),
\t\t\t\ttransitions={'continue': 'lift', 'failed': 'failed'},
\t\t\t\tautonomy={'continue': Autonomy.Off, 'failed': Autonomy.Off},
\t\t\t\tremapping={'pose': 'part_pose', 'joint_values': 'joint_values', 'joint_names': 'joint_names'})
\t\t\tOperatableStateMachine.add('lift', MoveJointsState(move_group="robot1"),
\t\t\t\ttransitions={'reached': 'home', 'planning_failed': 'failed', 'control_failed': 'failed'},
\t\t\t\tautonomy={'reached': Autonomy.Off, 'planning_failed': Autonomy.Off, 'control_failed': Autonomy.Off},
\t\t\t\tremapping={'joint_values': 'joint_values', 'joint_names': 'joint_names'})
\t\t\tOperatableStateMachine.add('home', NamedPoseState(config_name="R1Home", move_group="robot1"),
\t\t\t\ttransitions={'reached': 'finished', 'planning_failed': 'failed', 'control_failed': 'failed',
\t\t\t\t\t'param_error': 'failed'},
\t\t\t\tautonomy={'reached': Autonomy.Off, 'planning_failed': Autonomy.Off, 'control_failed': Autonomy.Off,
\t\t\t\t\t'param_error': Autonomy.Off})
\t\treturn _state_machine
"""


def _workspace(src: Path) -> Path:
    folder = src / "turn_flexbe_behaviors"
    (folder / "src" / "turn_flexbe_behaviors").mkdir(parents=True)
    (folder / "manifest").mkdir()
    (folder / "package.xml").write_text(PACKAGE_XML.format(name="turn_flexbe_behaviors"))
    (folder / "manifest" / "turn_pick.xml").write_text(MANIFEST)
    (folder / "src" / "turn_flexbe_behaviors" / "__init__.py").write_text("")
    (folder / "src" / "turn_flexbe_behaviors" / "turn_pick_sm.py").write_text(TURN_PICK)
    return src


def test_a_grasp_with_the_wrist_at_pi_then_a_joint_goal(tmp_path):
    report = run_behavior(
        "Turn Pick", [EXAMPLE, _workspace(tmp_path / "src")], scenario=SCENARIO, timeout=60.0
    )
    assert report.outcome == "finished", report.summary()
    done = [(t["state"], t["outcome"]) for t in report.trace]
    assert ("/grasp", "reached") in done and done[-1] == ("/home", "reached")
    # IK seeded with the wrist measured beyond pi, then a joint goal from there.
    assert ("/lift ik", "continue") in done and ("/lift", "reached") in done
    assert report.ledger["held"]["robot1"] == 1 and report.ledger["parts"] == {"object_1": "held:robot1"}
    # MoveIt's JointConstraint: a goal beyond the bound by more than its tolerance (0) is put
    # on the bound, with its warning; the report lists it.
    assert any(
        "Joint robot1_wrist_3_joint is constrained to be above the maximum bounds 3.141593 "
        "(goal 3.141600 rad). Assuming maximum bounds instead." in line
        for line in report.bounds_fixed
    ), report.bounds_fixed
    # The grasp leaves the wrist measured a hair above pi (3.141602 rad): MoveIt's
    # FixStartStateBounds plans the lift from the bound, and the report says so.
    assert any(
        "Starting state is just outside bounds (joint 'robot1_wrist_3_joint' at 3.1416" in line
        and line.endswith("Assuming within bounds.")
        for line in report.bounds_fixed
    ), report.bounds_fixed
    assert "moveit bounds: " in report.summary()


START_SCRIPT = """
    import json, sys
    import actionlib, rospy
    from moveit_msgs.msg import Constraints, JointConstraint, MoveGroupAction, MoveGroupGoal
    from moveit_msgs.srv import GetPositionIK, GetPositionIKRequest
    from sensor_msgs.msg import JointState

    rospy.init_node('start_state_probe')
    client = actionlib.SimpleActionClient('move_group', MoveGroupAction)
    client.wait_for_server()
    now = rospy.wait_for_message('/robot1/joint_states', JointState)
    out = {}
    for wrist in [3.1416, 3.1416 + 0.09, 3.1416 + 0.11, -3.1416 - 0.2]:
        goal = MoveGroupGoal()
        goal.request.group_name = 'robot1'
        goal.request.start_state.joint_state.name = ['robot1_wrist_3_joint']
        goal.request.start_state.joint_state.position = [wrist]
        goal.request.goal_constraints.append(Constraints(joint_constraints=[
            JointConstraint(joint_name='robot1_wrist_3_joint', position=1.0, weight=1.0)]))
        goal.planning_options.plan_only = True
        client.send_goal(goal)
        client.wait_for_result()
        result = client.get_result()
        points = result.planned_trajectory.joint_trajectory.points
        out[repr(wrist)] = [result.error_code.val, [p.positions[5] for p in points[:2]],
                            result.trajectory_start.joint_state.position[5]]
    # An IK request seeded beyond the bound (MoveIt's solvers start from any seed).
    ik = rospy.ServiceProxy('/compute_ik', GetPositionIK)
    request = GetPositionIKRequest()
    request.ik_request.group_name = 'robot1'
    request.ik_request.robot_state.joint_state.name = ['robot1_wrist_3_joint']
    request.ik_request.robot_state.joint_state.position = [3.1416]
    request.ik_request.pose_stamped.header.frame_id = 'world'
    request.ik_request.pose_stamped.pose.position.x = 0.9
    request.ik_request.pose_stamped.pose.position.y = 2.0
    request.ik_request.pose_stamped.pose.position.z = 1.4
    request.ik_request.pose_stamped.pose.orientation.x = 1.0
    out['ik_seed_beyond'] = ik(request).error_code.val
    # Executing a plan that starts somewhere else than the arm is refused by MoveIt's
    # trajectory execution (the start deviates from the current state).
    goal.request.start_state.joint_state.position = [3.1416]
    goal.planning_options.plan_only = False
    client.send_goal(goal)
    client.wait_for_result()
    out['execute'] = client.get_result().error_code.val
    out['wrist'] = rospy.wait_for_message('/robot1/joint_states', JointState).position[5]
    json.dump(out, open(sys.argv[1], 'w'))
"""


def test_start_states_outside_the_bounds(tmp_path):
    script = tmp_path / "start_state_probe.py"
    script.write_text(textwrap.dedent(START_SCRIPT))
    out = tmp_path / "out.json"
    report = run_script(script, [str(out)], scenario=SCENARIO, timeout=30.0)
    assert report.exception is None, report.summary()
    r = json.loads(out.read_text())
    # Just outside (within the course's start_state_max_bounds_error, 0.1 rad): planned from
    # the bound; the plan begins at the given start (MoveIt's prefix waypoint).
    code, (first, second), start = r["3.1416"]
    assert code == 1 and first == pytest.approx(3.1416) and second == pytest.approx(math.pi)
    assert start == pytest.approx(3.1416)
    assert r[repr(3.1416 + 0.09)][0] == 1
    # Beyond it, on either side: OMPL's invalid start, START_STATE_INVALID.
    assert r[repr(3.1416 + 0.11)] == [-26, [], pytest.approx(3.1416 + 0.11)]
    assert r[repr(-3.1416 - 0.2)][0] == -26
    assert r["ik_seed_beyond"] == 1
    assert r["execute"] == -4 and r["wrist"] == pytest.approx(0.0, abs=1e-3)  # CONTROL_FAILED, not moved
    fixed = [line for line in report.bounds_fixed if "Starting state is just outside bounds" in line]
    assert len(fixed) == 3  # 3.1416 twice (plan only, then execute) and 3.2316
    assert "joint 'robot1_wrist_3_joint' at 3.141600 rad, bounds [-3.141593, 3.141593]" in fixed[0]
    assert fixed[0].endswith("Assuming within bounds.")


COMMANDER_SCRIPT = """
    import json, sys
    import rospy, moveit_commander

    rospy.init_node('commander_bounds')
    group = moveit_commander.MoveGroupCommander('robot1')
    q = group.get_current_joint_values()
    out = {}
    q[5] = 3.14165  # within goal_joint_tolerance (1e-4) of pi
    out['near'] = group.go(q, wait=True)
    out['at'] = group.get_current_joint_values()[5]
    q[5] = 3.2
    try:
        group.set_joint_value_target(q)
        out['far'] = 'accepted'
    except moveit_commander.MoveItCommanderException as e:
        out['far'] = str(e)
    q[5] = 0.0
    out['back'] = group.go(q, wait=True)
    json.dump(out, open(sys.argv[1], 'w'))
"""


def test_commander_targets_within_the_goal_joint_tolerance(tmp_path):
    script = tmp_path / "commander_bounds.py"
    script.write_text(textwrap.dedent(COMMANDER_SCRIPT))
    out = tmp_path / "out.json"
    report = run_script(script, [str(out)], scenario=SCENARIO, timeout=60.0)
    assert report.ok, report.summary()
    r = json.loads(out.read_text())
    assert r["near"] is True and r["at"] == pytest.approx(math.pi, abs=2e-3)
    assert r["far"].startswith("error setting joint target: joint wrist_3_joint of robot1 at 3.2000 rad")
    assert r["back"] is True
