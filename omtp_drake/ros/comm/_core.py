"""The one place the ROS layer imports the core from (module paths may move)."""

from __future__ import annotations

from typing import Any, Optional

from omtp_drake.cell.arms import JOINT_NAMES, check_joint_positions, named_pose, tool_frame_names
from omtp_drake.cell.gazebo_models import gazebo_models
from omtp_drake.cell.poses import PoseStamped as CorePoseStamped
from omtp_drake.control.tool_paths import tool_down
from omtp_drake.scenario import load_scenario
from omtp_drake.script import Cell
from omtp_drake.script.arm import SETTLE_TIMEOUT, SETTLE_TOLERANCE, Arm, Plan

__all__ = [
    "SETTLE_TIMEOUT",
    "SETTLE_TOLERANCE",
    "JOINT_NAMES",
    "Arm",
    "Cell",
    "CorePoseStamped",
    "Plan",
    "check_joint_positions",
    "gazebo_models",
    "load_scenario",
    "named_pose",
    "tool_down",
    "tool_frame_names",
]


def batch_connect(workers: Optional[int]) -> Any:
    """The batch machinery's Dask client context (a local cluster of ``workers``)."""
    from omtp_drake.batch import connect

    return connect(workers)
