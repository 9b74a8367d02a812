"""The one place the ROS layer imports omtp_drake's core from (module paths may move):
every module of ``omtp_drake/ros`` imports the layers below it through this module (the
errors aside), which ``tests/test_layering.py`` checks."""

from __future__ import annotations

from typing import Any, Optional

from omtp_drake.assets import MODELS_DIR, expand_xacro
from omtp_drake.cell.arms import (
    JOINT_NAMES,
    NAMED_POSES,
    arm_urdf,
    check_joint_positions,
    gripper_urdf,
    named_pose,
    tool_frame_names,
)
from omtp_drake.cell.conveyor import BreakBeam
from omtp_drake.cell.gazebo_camera import GazeboCameraView
from omtp_drake.cell.gazebo_models import gazebo_models
from omtp_drake.cell.poses import PoseStamped as CorePoseStamped
from omtp_drake.control.tool_paths import tool_down
from omtp_drake.gazebo import conveyor as plugin_conveyor
from omtp_drake.gazebo import messages as gazebo_messages
from omtp_drake.gazebo import proximity_ray as plugin_proximity_ray
from omtp_drake.gazebo import vacuum_gripper as plugin_gripper
from omtp_drake.gazebo.joint_states import JOINT_STATE_RATE_HZ
from omtp_drake.gazebo.logical_camera import camera_views, logical_camera_publications, single_camera
from omtp_drake.gazebo.model_states import LINK_STATES, MODEL_STATES, state_publications
from omtp_drake.gazebo.plugins import gazebo_plugins, unknown_plugins
from omtp_drake.gazebo.schedule import Publication
from omtp_drake.gazebo.schedule import topic as gazebo_topic
from omtp_drake.gazebo.services import PluginService
from omtp_drake.gazebo.spawn import ServiceCallFailed
from omtp_drake.gazebo.spawner import SPAWNED_PART, spawner
from omtp_drake.gazebo.world import GazeboWorld
from omtp_drake.gazebo.world_services import WorldServices
from omtp_drake.scenario import Scenario, load_scenario, with_robot
from omtp_drake.scenario.conveyor_spawner import ROBOT_NAMESPACE, WORLD_FRAMES
from omtp_drake.scenario.latency import RosLatencyConfig, latency_names
from omtp_drake.scenario.ros_control_parse import spawn_controllers
from omtp_drake.script import Cell
from omtp_drake.script.arm import SETTLE_TIMEOUT, SETTLE_TOLERANCE, Arm, Plan, other_arm_positions
from omtp_drake.sim.ros_control import Controller, RosControl
from omtp_drake.sim.tf_broadcast import TfBroadcast, TfEdge
from omtp_drake.sim.trajectory_goals import Goal, GoalOutcome, start_goal
from omtp_drake.sim.trajectory_request import RequestPoint, TrajectoryRequest, trajectory_request

__all__ = [
    "JOINT_NAMES",
    "JOINT_STATE_RATE_HZ",
    "MODELS_DIR",
    "NAMED_POSES",
    "SETTLE_TIMEOUT",
    "arm_urdf",
    "gripper_urdf",
    "SETTLE_TOLERANCE",
    "Arm",
    "BreakBeam",
    "Cell",
    "Controller",
    "CorePoseStamped",
    "GazeboCameraView",
    "GazeboWorld",
    "LINK_STATES",
    "MODEL_STATES",
    "SPAWNED_PART",
    "ServiceCallFailed",
    "WorldServices",
    "spawner",
    "state_publications",
    "Goal",
    "GoalOutcome",
    "Plan",
    "PluginService",
    "Publication",
    "ROBOT_NAMESPACE",
    "RequestPoint",
    "RosControl",
    "RosLatencyConfig",
    "WORLD_FRAMES",
    "Scenario",
    "TfBroadcast",
    "TfEdge",
    "TrajectoryRequest",
    "camera_views",
    "check_joint_positions",
    "expand_xacro",
    "gazebo_messages",
    "gazebo_plugins",
    "gazebo_topic",
    "gazebo_models",
    "latency_names",
    "load_scenario",
    "logical_camera_publications",
    "named_pose",
    "other_arm_positions",
    "plugin_conveyor",
    "plugin_gripper",
    "plugin_proximity_ray",
    "single_camera",
    "spawn_controllers",
    "start_goal",
    "tool_down",
    "unknown_plugins",
    "tool_frame_names",
    "trajectory_request",
    "with_robot",
]


def batch_connect(workers: Optional[int]) -> Any:
    """The batch machinery's Dask client context (a local cluster of ``workers``)."""
    from omtp_drake.batch import connect

    return connect(workers)
