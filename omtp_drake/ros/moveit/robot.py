"""moveit_commander's RobotCommander and roscpp_initialize (``moveit_commander.robot``)."""

from __future__ import annotations

from typing import Any

from omtp_drake.ros.comm.interfaces import RobotState
from omtp_drake.ros.comm.messages import Header, JointState, Message
from omtp_drake.ros.comm.rostime import Time
from omtp_drake.ros.comm.session import current
from omtp_drake.ros.comm.unsupported import not_supported
from omtp_drake.ros.moveit.commander import MoveGroupCommander
from omtp_drake.ros.moveit.config import semantics
from omtp_drake.ros.moveit.trajectories import joint_names


def roscpp_initialize(args: Any = None) -> None:
    """Nothing to start: the cell is the robot."""
    current()


def roscpp_shutdown() -> None:
    current()


class RobotCommander:
    """moveit_commander.RobotCommander: the groups, the planning frame, the state."""

    def __init__(self, robot_description: str = "robot_description", ns: str = ""):
        self._session = current()
        self._groups: dict[str, MoveGroupCommander] = {}

    def get_group_names(self) -> list[str]:
        """The SRDF's groups (move groups and end-effector groups)."""
        return list(semantics(self._session).groups)

    def get_group(self, name: str) -> MoveGroupCommander:
        if name not in self._groups:
            self._groups[name] = MoveGroupCommander(name)
        return self._groups[name]

    def get_planning_frame(self) -> str:
        return "world"

    def get_current_state(self) -> Message:
        names: list[str] = []
        positions: list[float] = []
        for robot in self._session.cell.station.arms:
            names += joint_names(robot)
            positions += [float(x) for x in self._session.cell.arm(robot).joint_values()]
        header = Header(stamp=Time.now(), frame_id="world")
        return RobotState(joint_state=JointState(header=header, name=names, position=positions))

    def __getattr__(self, name: str) -> Any:
        if name.startswith("_"):
            raise AttributeError(name)
        not_supported(f"RobotCommander.{name}")
