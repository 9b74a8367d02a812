"""The one place the ROS layer imports omtp_drake's core from (module paths may move):
every module of ``omtp_drake/ros`` imports the layers below it through this module (the
errors aside), which ``tests/test_layering.py`` checks."""

from __future__ import annotations

from typing import Any, Optional

from omtp_drake.assets import MODELS_DIR, expand_xacro, ur_urdf
from omtp_drake.cell.arms import JOINT_NAMES, NAMED_POSES, check_joint_positions, named_pose, tool_frame_names
from omtp_drake.cell.conveyor import BreakBeam
from omtp_drake.cell.depth_camera import DepthCamera
from omtp_drake.cell.gazebo_camera import GazeboCameraView
from omtp_drake.cell.gazebo_models import gazebo_models
from omtp_drake.cell.parts import spawn_pose
from omtp_drake.cell.poses import PoseStamped as CorePoseStamped
from omtp_drake.control.tool_paths import tool_down
from omtp_drake.scenario import Scenario, SpawnerConfig, check_in_cell, load_scenario, with_robot
from omtp_drake.scenario.latency import RosLatencyConfig, latency_names
from omtp_drake.script import Cell
from omtp_drake.script.arm import SETTLE_TIMEOUT, SETTLE_TOLERANCE, Arm, Plan, other_arm_positions
from omtp_drake.sim.driver import spawn
from omtp_drake.sim.joint_pose_trajectory import JointPoseTrajectory, PosePoint
from omtp_drake.sim.tf_broadcast import TfBroadcast, TfEdge

__all__ = [
    "JOINT_NAMES",
    "MODELS_DIR",
    "NAMED_POSES",
    "SETTLE_TIMEOUT",
    "SETTLE_TOLERANCE",
    "Arm",
    "BreakBeam",
    "Cell",
    "CorePoseStamped",
    "DepthCamera",
    "GazeboCameraView",
    "JointPoseTrajectory",
    "Plan",
    "PosePoint",
    "RosLatencyConfig",
    "Scenario",
    "SpawnerConfig",
    "TfBroadcast",
    "TfEdge",
    "check_in_cell",
    "check_joint_positions",
    "expand_xacro",
    "gazebo_models",
    "latency_names",
    "load_scenario",
    "named_pose",
    "other_arm_positions",
    "spawn",
    "spawn_pose",
    "tool_down",
    "tool_frame_names",
    "ur_urdf",
    "with_robot",
]


def batch_connect(workers: Optional[int]) -> Any:
    """The batch machinery's Dask client context (a local cluster of ``workers``)."""
    from omtp_drake.batch import connect

    return connect(workers)
