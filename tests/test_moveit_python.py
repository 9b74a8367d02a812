"""moveit_python and move_group's kinematics services on the cell: a course-style FlexBE
behaviour whose state does what the course's MoveitToJointsDynState does (FK of a grasp
configuration, moveit_python's moveToPose above it, the /compute_cartesian_path service
down onto the part, execute_trajectory), and the services' and interfaces' answers."""

from __future__ import annotations

import json
import textwrap
from pathlib import Path

import numpy as np
import pytest
from test_flexbe_run import _package  # one writer of a FlexBE workspace's catkin package

from omtp_drake.ros import run_script
from omtp_drake.ros.flexbe import run_behavior

ROOT = Path(__file__).resolve().parents[1]
EXAMPLE = ROOT / "examples" / "flexbe"
SCENARIO = "lecture7_flexbe"

# A student's state in the course's style (tabs, Python 2-compatible, moveit_python's star
# import): FK of the grasp configuration, a pre-grasp pose above it with moveit_python,
# a straight approach with the Cartesian service, executed through execute_trajectory.
DYN_STATE = """\
#!/usr/bin/env python
import copy

import rospy
import actionlib
import moveit_msgs.msg
import sensor_msgs.msg
from moveit_python import *
from flexbe_core import EventState, Logger
from flexbe_core.proxy import ProxyActionClient, ProxyServiceCaller
from moveit_msgs.msg import MoveGroupAction, MoveItErrorCodes, RobotState
from moveit_msgs.srv import GetPositionFK, GetPositionFKRequest
from moveit_msgs.srv import GetCartesianPath, GetCartesianPathRequest


class ApproachDynState(EventState):
\t'''
\tMoves the tool above a grasp configuration, then straight down onto it.

\t-- move_group\tstring\tThe group, e.g. robot1.
\t-- approach\tfloat\tHeight of the pre-grasp pose above the grasp pose (m).
\t-- tool_link\tstring\tThe tool link, e.g. vacuum_gripper1_suction_cup.

\t># joint_values\tfloat[]\tThe grasp configuration.
\t># joint_names\tstring[]\tIts joint names.

\t<= reached\t\tThe tool is at the grasp pose.
\t<= planning_failed\tNo FK, pre-grasp plan or full straight path.
\t<= control_failed\tThe approach did not execute.
\t'''

\tdef __init__(self, move_group, approach, tool_link, action_topic='/move_group'):
\t\tsuper(ApproachDynState, self).__init__(outcomes=['reached', 'planning_failed', 'control_failed'],
\t\t\t\t\t\t\t\t\t\t\tinput_keys=['joint_values', 'joint_names'])
\t\tself._group = move_group
\t\tself._approach = approach
\t\tself._tool_link = tool_link
\t\tself._action_topic = action_topic
\t\tself._fk_topic = '/compute_fk'
\t\tself._path_topic = '/compute_cartesian_path'
\t\tself._client = ProxyActionClient({self._action_topic: MoveGroupAction})
\t\tself._fk = ProxyServiceCaller({self._fk_topic: GetPositionFK})
\t\tself._path = ProxyServiceCaller({self._path_topic: GetCartesianPath})
\t\tself._traj_client = actionlib.SimpleActionClient('execute_trajectory',
\t\t\tmoveit_msgs.msg.ExecuteTrajectoryAction)
\t\tself._traj_client.wait_for_server()
\t\tself._outcome = None

\tdef on_enter(self, userdata):
\t\tself._outcome = None
\t\tstate = RobotState()
\t\tstate.joint_state.name = copy.deepcopy(userdata.joint_names)
\t\tstate.joint_state.position = copy.deepcopy(userdata.joint_values)
\t\tfk_request = GetPositionFKRequest()
\t\tfk_request.header.frame_id = 'world'
\t\tfk_request.header.stamp = rospy.Time.now()
\t\tfk_request.fk_link_names = [self._tool_link]
\t\tfk_request.robot_state = state
\t\ttry:
\t\t\tfk_result = self._fk.call(self._fk_topic, fk_request)
\t\texcept Exception as e:
\t\t\tLogger.logwarn('FK failed: ' + str(e))
\t\t\tself._outcome = 'planning_failed'
\t\t\treturn
\t\tgrasp = fk_result.pose_stamped[0]
\t\tp = grasp.pose.position
\t\tLogger.loginfo('grasp at %.3f %.3f %.3f' % (p.x, p.y, p.z))

\t\tpre_grasp = copy.deepcopy(grasp)
\t\tpre_grasp.pose.position.z += self._approach
\t\tmover = MoveGroupInterface(self._group, self._group + '_base_link')
\t\tmoved = mover.moveToPose(pre_grasp, self._tool_link)
\t\tif moved.error_code.val != MoveItErrorCodes.SUCCESS:
\t\t\tLogger.logwarn('pre-grasp failed: %d' % moved.error_code.val)
\t\t\tself._outcome = 'planning_failed'
\t\t\treturn

\t\tpath_request = GetCartesianPathRequest()
\t\tpath_request.start_state.joint_state = rospy.wait_for_message(self._group + '/joint_states',
\t\t\tsensor_msgs.msg.JointState)
\t\tpath_request.header.stamp = rospy.Time.now()
\t\tpath_request.header.frame_id = 'world'
\t\tpath_request.group_name = self._group
\t\tpath_request.link_name = self._tool_link
\t\tpath_request.max_step = 0.01
\t\tpath_request.jump_threshold = 0
\t\tpath_request.avoid_collisions = True
\t\tpath_request.waypoints.append(grasp.pose)
\t\tpath = self._path.call(self._path_topic, path_request)
\t\tpoints = path.solution.joint_trajectory.points
\t\tLogger.loginfo('path fraction %.2f, %d points' % (path.fraction, len(points)))
\t\tif path.fraction < 1.0:
\t\t\tself._outcome = 'planning_failed'
\t\t\treturn
\t\tgoal = moveit_msgs.msg.ExecuteTrajectoryGoal()
\t\tgoal.trajectory = path.solution
\t\tself._traj_client.send_goal(goal)
\t\tself._traj_client.wait_for_result()
\t\tresult = self._traj_client.get_result()
\t\tself._outcome = 'reached' if result.error_code.val == MoveItErrorCodes.SUCCESS else 'control_failed'

\tdef execute(self, userdata):
\t\treturn self._outcome
"""

DYN_BEHAVIOR = """\
#!/usr/bin/env python
from flexbe_core import Behavior, Autonomy, OperatableStateMachine, Logger
from flexbe_states.subscriber_state import SubscriberState
from flexbe_states.decision_state import DecisionState
from flexbe_states.wait_state import WaitState
from omtp_pick_flexbe_states.conveyor_power_state import ConveyorPowerState
from omtp_pick_flexbe_states.feeder_state import FeederState
from omtp_pick_flexbe_states.grasp_ik_state import GraspIKState
from omtp_pick_flexbe_states.gripper_state import GripperState
from omtp_pick_flexbe_states.named_pose_state import NamedPoseState
from omtp_pick_flexbe_states.part_pose_state import PartPoseState
from dyn_flexbe_states.approach_dyn_state import ApproachDynState


class DynPickSM(Behavior):
\t'''
\tPicks the part the break beam stops, approaching it with ApproachDynState.
\t'''

\tdef __init__(self):
\t\tsuper(DynPickSM, self).__init__()
\t\tself.name = 'Dyn Pick'

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
\t\t\t\ttransitions={'continue': 'gripper on', 'failed': 'failed'},
\t\t\t\tautonomy={'continue': Autonomy.Off, 'failed': Autonomy.Off},
\t\t\t\tremapping={'pose': 'part_pose', 'joint_values': 'joint_values', 'joint_names': 'joint_names'})
\t\t\tOperatableStateMachine.add('gripper on', GripperState(enable=True, service_name="/gripper1/control"),
\t\t\t\ttransitions={'continue': 'approach', 'failed': 'failed'},
\t\t\t\tautonomy={'continue': Autonomy.Off, 'failed': Autonomy.Off})
\t\t\tOperatableStateMachine.add('approach',
\t\t\t\tApproachDynState(move_group="robot1", approach=0.3, tool_link=tool_link),
\t\t\t\ttransitions={'reached': 'attach', 'planning_failed': 'failed', 'control_failed': 'failed'},
\t\t\t\tautonomy={'reached': Autonomy.Off, 'planning_failed': Autonomy.Off, 'control_failed': Autonomy.Off},
\t\t\t\tremapping={'joint_values': 'joint_values', 'joint_names': 'joint_names'})
\t\t\tOperatableStateMachine.add('attach', WaitState(wait_time=0.3),
\t\t\t\ttransitions={'done': 'home'}, autonomy={'done': Autonomy.Off})
\t\t\tOperatableStateMachine.add('home', NamedPoseState(config_name="R1Home", move_group="robot1"),
\t\t\t\ttransitions={'reached': 'finished', 'planning_failed': 'failed', 'control_failed': 'failed',
\t\t\t\t\t'param_error': 'failed'},
\t\t\t\tautonomy={'reached': Autonomy.Off, 'planning_failed': Autonomy.Off, 'control_failed': Autonomy.Off,
\t\t\t\t\t'param_error': Autonomy.Off})
\t\treturn _state_machine
"""

MANIFEST = """<?xml version="1.0" encoding="UTF-8"?>
<behavior name="{name}">
\t<executable package_path="{module}" class="{cls}" />
</behavior>
"""



def _dyn_workspace(src: Path) -> Path:
    _package(src, "dyn_flexbe_states", {"src/dyn_flexbe_states/approach_dyn_state.py": DYN_STATE})
    manifest = MANIFEST.format(name="Dyn Pick", module="dyn_flexbe_behaviors.dyn_pick_sm", cls="DynPickSM")
    _package(
        src,
        "dyn_flexbe_behaviors",
        {"manifest/dyn_pick.xml": manifest, "src/dyn_flexbe_behaviors/dyn_pick_sm.py": DYN_BEHAVIOR},
    )
    return src


def test_a_moveit_to_joints_dyn_style_state_picks_the_part(tmp_path):
    src = _dyn_workspace(tmp_path / "src")
    report = run_behavior("Dyn Pick", [EXAMPLE, src], scenario=SCENARIO, timeout=60.0)
    assert report.outcome == "finished", report.summary()
    assert report.ok and not report.bounds_fixed
    done = [(t["state"], t["outcome"]) for t in report.trace]
    assert ("/approach", "reached") in done and done[-1] == ("/home", "reached")
    texts = [x["text"] for x in report.logs]
    assert any(t.startswith("path fraction 1.00, ") for t in texts), texts
    # The part the beam stopped is on the cup, carried home.
    assert report.ledger["held"]["robot1"] == 1 and report.ledger["parts"] == {"object_1": "held:robot1"}


SERVICES_SCRIPT = """
    import copy, json, sys
    import rospy, tf2_ros
    from geometry_msgs.msg import Pose
    from moveit_msgs.msg import RobotState
    from moveit_msgs.srv import GetCartesianPath, GetCartesianPathRequest, GetPositionFK, GetPositionFKRequest
    from sensor_msgs.msg import JointState

    rospy.init_node('kinematics_services')
    fk = rospy.ServiceProxy('/compute_fk', GetPositionFK)
    path = rospy.ServiceProxy('/compute_cartesian_path', GetCartesianPath)
    buffer = tf2_ros.Buffer()
    out = {}

    def xyz(p):
        return [p.position.x, p.position.y, p.position.z]

    cup = buffer.lookup_transform('world', 'vacuum_gripper1_suction_cup', rospy.Time(0)).transform.translation
    out['tf_cup'] = [cup.x, cup.y, cup.z]
    req = GetPositionFKRequest(fk_link_names=['vacuum_gripper1_suction_cup', 'robot1_tool0', 'no_link'])
    res = fk(req)
    out['now'] = [res.error_code.val, res.fk_link_names, xyz(res.pose_stamped[0].pose),
                  res.pose_stamped[0].header.frame_id]
    state = RobotState()
    state.joint_state.name = ['robot1_shoulder_pan_joint', 'robot1_wrist_3_joint']
    state.joint_state.position = [0.5, 3.2]  # FK does not check the bounds
    req = GetPositionFKRequest(fk_link_names=['vacuum_gripper1_suction_cup'], robot_state=state)
    out['turned_world'] = xyz(fk(req).pose_stamped[0].pose)
    req.header.frame_id = 'robot1_base_link'
    res = fk(req)
    base = buffer.lookup_transform('world', 'robot1_base_link', rospy.Time(0)).transform.translation
    answer = res.pose_stamped[0]
    out['turned_base'] = [res.error_code.val, answer.header.frame_id, xyz(answer.pose),
                          [base.x, base.y, base.z]]
    req.header.frame_id = 'nowhere'
    out['bad_frame'] = fk(req).error_code.val
    out['no_links'] = fk(GetPositionFKRequest()).error_code.val
    state.joint_state.name = ['robot9_elbow_joint']
    state.joint_state.position = [0.0]
    try:
        fk(GetPositionFKRequest(fk_link_names=['robot1_tool0'], robot_state=state))
    except rospy.ServiceException as e:
        out['bad_joint'] = str(e)

    def cartesian(waypoints, frame='world', group='robot1', link='vacuum_gripper1_suction_cup', step=0.01):
        c = GetCartesianPathRequest(group_name=group, link_name=link, max_step=step, avoid_collisions=True)
        c.header.frame_id = frame
        c.start_state.joint_state = rospy.wait_for_message('/robot1/joint_states', JointState)
        c.waypoints = waypoints
        return path(c)

    down = Pose()
    down.position.x, down.position.y, down.position.z = cup.x, cup.y, cup.z - 0.1
    now = buffer.lookup_transform('world', 'vacuum_gripper1_suction_cup', rospy.Time(0))
    down.orientation = now.transform.rotation
    res = cartesian([down])
    points = res.solution.joint_trajectory.points
    end = RobotState()
    end.joint_state.name = res.solution.joint_trajectory.joint_names
    end.joint_state.position = points[-1].positions
    end_cup = fk(GetPositionFKRequest(fk_link_names=['vacuum_gripper1_suction_cup'], robot_state=end))
    out['down'] = [res.error_code.val, res.fraction, list(res.start_state.joint_state.position),
                   list(points[0].positions), xyz(end_cup.pose_stamped[0].pose),
                   points[-1].time_from_start.to_sec(), list(points[-1].positions)]
    in_base = copy.deepcopy(down)
    in_base.position.x -= base.x
    in_base.position.y -= base.y
    in_base.position.z -= base.z
    res = cartesian([in_base], frame='robot1_base_link')  # the base frame is not turned in this cell
    last = res.solution.joint_trajectory.points[-1]
    out['in_base'] = [res.error_code.val, res.fraction, list(last.positions)]
    far = copy.deepcopy(down)
    far.position.z += 5.0
    res = cartesian([down, far])
    out['far'] = [res.error_code.val, res.fraction]
    out['errors'] = [cartesian([down], group='robot7').error_code.val,
                     cartesian([down], step=0.0).error_code.val,
                     cartesian([down], link='no_link').error_code.val,
                     cartesian([down], frame='nowhere').error_code.val]
    res = cartesian([])
    out['empty'] = [res.error_code.val, res.fraction, len(res.solution.joint_trajectory.points)]
    json.dump(out, open(sys.argv[1], 'w'))
"""


def test_compute_fk_and_compute_cartesian_path(tmp_path):
    script = tmp_path / "kinematics_services.py"
    script.write_text(textwrap.dedent(SERVICES_SCRIPT))
    out = tmp_path / "out.json"
    report = run_script(script, [str(out)], scenario=SCENARIO, timeout=30.0)
    assert report.ok, report.summary()
    r = json.loads(out.read_text())
    code, links, cup, frame = r["now"]
    assert code == -18 and links == ["vacuum_gripper1_suction_cup", "robot1_tool0"]  # INVALID_LINK_NAME
    assert cup == pytest.approx(r["tf_cup"], abs=1e-9) and frame == "world"
    code, frame, in_base, base = r["turned_base"]
    assert code == 1 and frame == "robot1_base_link"
    assert np.add(in_base, base) == pytest.approx(r["turned_world"], abs=1e-9)
    assert r["turned_world"] != pytest.approx(r["tf_cup"], abs=1e-2)  # the given joints, not the arm's
    assert r["bad_frame"] == -21 and r["no_links"] == -18  # FRAME_TRANSFORM_FAILURE, INVALID_LINK_NAME
    assert r["bad_joint"].startswith(
        "service [/compute_fk] failed: Variable 'robot9_elbow_joint' is not known"
    )
    code, fraction, start, first, end, duration, down_last = r["down"]
    assert code == 1 and fraction == 1.0 and first == pytest.approx(start, abs=1e-12)
    assert end == pytest.approx(np.add(r["tf_cup"], [0, 0, -0.1]), abs=1e-3) and duration > 0.1 / 0.25
    code, fraction, last = r["in_base"]
    assert code == 1 and fraction == 1.0 and last == pytest.approx(down_last, abs=1e-6)
    code, fraction = r["far"]
    # MoveIt's fraction: the first waypoint reached (0.5) and part of the way to the second.
    assert code == 1 and 0.5 < fraction < 0.75
    assert r["errors"] == [
        -15,
        99999,
        99999,
        -21,
    ]  # INVALID_GROUP_NAME, FAILURE, FAILURE, FRAME_TRANSFORM_FAILURE
    assert r["empty"] == [1, 0.0, 0]


INTERFACES_SCRIPT = """
    import json, sys
    import rospy
    from moveit_msgs.srv import GetPositionFK, GetPositionFKRequest
    from moveit_msgs.msg import RobotState
    from moveit_python import MoveGroupInterface, PlanningSceneInterface
    from sensor_msgs.msg import JointState

    rospy.init_node('moveit_python_probe')
    names = ['robot1_shoulder_pan_joint', 'robot1_shoulder_lift_joint', 'robot1_elbow_joint',
             'robot1_wrist_1_joint', 'robot1_wrist_2_joint', 'robot1_wrist_3_joint']
    target = [0.3, -1.2, 1.4, -1.8, -1.5708, 0.2]
    move = MoveGroupInterface('robot1', 'world')
    scene = PlanningSceneInterface('world')
    out = {}
    state = RobotState()
    state.joint_state.name, state.joint_state.position = names, target
    fk = rospy.ServiceProxy('/compute_fk', GetPositionFK)
    answer = fk(GetPositionFKRequest(fk_link_names=['vacuum_gripper1_suction_cup'], robot_state=state))
    cup = answer.pose_stamped[0]
    p = cup.pose.position
    scene.addBox('crate', 0.2, 0.2, 0.2, p.x, p.y, p.z)
    out['known'] = scene.getKnownCollisionObjects()
    result = move.moveToJointPosition(names, target, tolerance=0.01, unknown_option=1)
    out['blocked'] = result.error_code.val
    scene.removeCollisionObject('crate')
    scene.removeCollisionObject('never_added')
    out['after_remove'] = scene.getKnownCollisionObjects()
    result = move.moveToJointPosition(names, target, plan_only=True)
    out['plan_only'] = [result.error_code.val, len(result.planned_trajectory.joint_trajectory.points),
                        len(result.executed_trajectory.joint_trajectory.points)]
    out['wait_false'] = move.moveToJointPosition(names, target, wait=False)
    move.get_move_action().wait_for_result()
    at = rospy.wait_for_message('/robot1/joint_states', JointState).position
    out['reached'] = [move.get_move_action().get_result().error_code.val, at]
    cup.pose.position.z += 0.1
    out['pose'] = move.moveToPose(cup, 'vacuum_gripper1_suction_cup').error_code.val
    scene.attachBox('tool_box', 0.05, 0.05, 0.05, 0.0, 0.0, 0.05, 'vacuum_gripper1_suction_cup')
    out['attached'] = scene.getKnownAttachedObjects()
    scene.removeAttachedObject('tool_box')
    out['detached'] = [scene.getKnownAttachedObjects(), scene.getKnownCollisionObjects()]
    scene.setColor('crate', 1.0, 0.0, 0.0)
    scene.sendColors()
    scene.waitForSync()
    try:
        scene.addSphere('ball', 0.1, 0.0, 0.0, 1.0)
    except Exception as e:
        out['sphere'] = '%s: %s' % (type(e).__name__, e)
    json.dump(out, open(sys.argv[1], 'w'))
"""


def test_moveit_python_interfaces(tmp_path):
    script = tmp_path / "moveit_python_probe.py"
    script.write_text(textwrap.dedent(INTERFACES_SCRIPT))
    out = tmp_path / "out.json"
    report = run_script(script, [str(out)], scenario=SCENARIO, timeout=60.0)
    assert report.ok, report.summary()
    r = json.loads(out.read_text())
    assert r["known"] == ["crate"] and r["blocked"] == -12  # GOAL_IN_COLLISION
    assert r["after_remove"] == []
    assert r["plan_only"][0] == 1 and r["plan_only"][1] >= 2 and r["plan_only"][2] == 0
    assert r["wait_false"] is None
    code, at = r["reached"]
    assert code == 1 and at == pytest.approx([0.3, -1.2, 1.4, -1.8, -1.5708, 0.2], abs=2e-3)
    assert r["pose"] == 1
    # MoveIt puts a detached object back into the world.
    assert r["attached"] == ["tool_box"] and r["detached"] == [[], ["tool_box"]]
    assert r["sphere"].startswith(
        "NotSupportedError: moveit_python PlanningSceneInterface.addSphere is not supported"
    )
