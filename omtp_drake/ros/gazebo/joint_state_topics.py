"""The arms' joint states, by the names the course's controllers use.

- ``/robotN/joint_states`` (``sensor_msgs/JointState``): each arm's joint
  positions, and ``/joint_states`` (both arms, as the launch file's
  joint_state_publisher merges them). Sources are polled once per cell tick, so
  they publish at the tick's rate, at most the controllers' state rate.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

from omtp_drake.ros.comm._core import JOINT_NAMES
from omtp_drake.ros.comm.messages import Header, JointState, Time
from omtp_drake.ros.gazebo.sensor_topics import Source

if TYPE_CHECKING:
    from omtp_drake.ros.comm._core import Cell

#: The course's joint trajectory controllers publish their state at 50 Hz: the cap here.
JOINT_STATE_RATE_HZ = 50.0


class PeriodicSource(Source):
    """A message every ``period`` s of simulated time (polled on the cell's ticks)."""

    def __init__(self, cell: Cell, period: float):
        self._cell = cell
        self._period = float(period)
        self._next = 0.0

    def message(self) -> Any:
        raise NotImplementedError

    def poll(self) -> list[tuple[float, Any]]:
        now = self._cell.time
        if now < self._next - 1e-9:
            return []
        self._next = max(self._next + self._period, now)
        return [(now, self.message())]


class JointStateSource(PeriodicSource):
    """``/robotN/joint_states`` (one arm) or ``/joint_states`` (all)."""

    msg_class = JointState

    def __init__(self, cell: Cell, robots: list[str]):
        super().__init__(cell, 1.0 / JOINT_STATE_RATE_HZ)
        self._robots = robots

    def message(self) -> Any:
        names: list[str] = []
        positions: list[float] = []
        for robot in self._robots:
            names += [f"{robot}_{name}" for name in JOINT_NAMES]
            positions += [float(x) for x in self._cell.arm(robot).joint_values()]
        header = Header(stamp=Time(self._cell.time))
        return JointState(header=header, name=names, position=positions)


def joint_state_sources(cell: Cell) -> dict[str, Source]:
    """Topic name -> source of the topics above that ``cell`` has."""
    sources: dict[str, Source] = {}
    arms = list(cell.station.arms)
    for robot in arms:
        sources[f"/{robot}/joint_states"] = JointStateSource(cell, [robot])
    if arms:
        sources["/joint_states"] = JointStateSource(cell, arms)
    return sources
