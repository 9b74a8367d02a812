"""More of the course cell's topics, by the names its Gazebo world and controllers use.

- ``/break_beam_sensor`` (``omtp_gazebo/Proximity``): the beam's state at the
  beam's own rate (the proximity-ray plugin publishes every update), and
  ``/break_beam_sensor_change``: only when it changes. Lecture 7's FlexBE
  behaviours subscribe to these names.
- ``/robotN/joint_states`` (``sensor_msgs/JointState``): each arm's joint
  positions and velocities at the controllers' state rate, and ``/joint_states``
  (both arms, as the launch file's joint_state_publisher merges them).
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

from omtp_drake.ros._core import JOINT_NAMES
from omtp_drake.ros.messages import Header, JointState, Time
from omtp_drake.ros.topics import BreakBeamSource, Source

if TYPE_CHECKING:
    from omtp_drake.script import Cell

#: The course's joint trajectory controllers publish their state at 50 Hz.
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


class BeamStateSource(PeriodicSource):
    """``/break_beam_sensor``: the beam's state, every sample."""

    def __init__(self, cell: Cell, period: float):
        super().__init__(cell, period)
        self.msg_class = BreakBeamSource.msg_class

    def message(self) -> Any:
        header = Header(stamp=Time(self._cell.time), frame_id="break_beam_optical_link")
        return self.msg_class(header=header, object_detected=bool(self._cell.break_beam()))


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


def beam_period(cell: Cell) -> float:
    """The break beam's sample period (its system's periodic update)."""
    beam = cell.station.break_beam
    timing = beam.GetUniquePeriodicDiscreteUpdateAttribute() if beam is not None else None
    if timing is None:
        raise ValueError("the cell's break beam has no periodic update")
    return float(timing.period_sec())


def course_sources(cell: Cell) -> dict[str, Source]:
    """Topic name -> source of the topics above that ``cell`` has."""
    sources: dict[str, Source] = {}
    if cell.station.break_beam is not None:
        sources["/break_beam_sensor"] = BeamStateSource(cell, beam_period(cell))
        sources["/break_beam_sensor_change"] = BreakBeamSource(cell)
    arms = list(cell.station.arms)
    for robot in arms:
        sources[f"/{robot}/joint_states"] = JointStateSource(cell, [robot])
    if arms:
        sources["/joint_states"] = JointStateSource(cell, arms)
    return sources
