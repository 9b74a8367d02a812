"""Plots of a run: tool tracking, detections, cycle times, the ledger, seed statistics.

:class:`RunRecorder` samples a running task once per runtime tick (cheap: one
forward-kinematics evaluation, one image per camera and the ledger). The
``plot_*`` functions take what it recorded (or :class:`~omtp_drake.tasks.TaskResult`
objects) and return a matplotlib :class:`~matplotlib.figure.Figure`; they use
the object-oriented API only (no pyplot state), so they work headless and in
notebooks alike (there, the Figure is the cell's value, or ``display(fig)``).

Example::

    from omtp_drake.tasks.plots import RunRecorder, plot_tracking_error
    from omtp_drake.tasks.run import run_task

    recorders = []
    result = run_task("lecture6_assignment4", parts=1,
                      on_start=lambda run: recorders.append(RunRecorder.attach(run)))
    plot_tracking_error(recorders[0]).savefig("tracking.png")
"""

from __future__ import annotations

import logging
import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Optional

import numpy as np
from matplotlib.figure import Figure
from pydrake.math import RigidTransform

from omtp_drake.cell.logical_camera import model_type
from omtp_drake.control.pick_and_place import ControlState
from omtp_drake.errors import ConfigError, StateError

if TYPE_CHECKING:
    from matplotlib.axes import Axes

    from omtp_drake.sim.runtime import FactoryRuntime
    from omtp_drake.tasks.run import TaskResult, TaskRun

_log = logging.getLogger(__name__)

#: Colours of successful and failed picks.
OK_COLOUR, FAIL_COLOUR = "tab:green", "tab:red"
#: Ledger categories in stacking order (bins are inserted after "held").
_LEDGER_ORDER = ("on_belt", "on_floor", "elsewhere", "held")


@dataclass
class RunRecording:
    """What a :class:`RunRecorder` sampled; one entry per sample in every list.

    Positions are the cup face's (``<gripper>_tip``) in the world [m]; the
    desired position is NaN while the controller has no path.
    """

    robot: str
    time: list[float] = field(default_factory=list)
    desired: list[np.ndarray] = field(default_factory=list)
    actual: list[np.ndarray] = field(default_factory=list)
    mode: list[str] = field(default_factory=list)
    #: camera -> number of parts it reports, per sample.
    detections: dict[str, list[int]] = field(default_factory=dict)
    #: ledger category (``on_belt``, ``on_floor``, ``elsewhere``, ``held``, ``in_bin:<bin>``,
    #: ``disposed``)
    #: -> count, per sample.
    ledger: dict[str, list[int]] = field(default_factory=dict)
    #: Break beam state and conveyor power [%] per sample (empty without them).
    beam: list[bool] = field(default_factory=list)
    conveyor_power: list[float] = field(default_factory=list)

    def __len__(self) -> int:
        return len(self.time)

    @property
    def t(self) -> np.ndarray:
        return np.asarray(self.time, dtype=float)

    @property
    def desired_xyz(self) -> np.ndarray:
        """(n, 3) desired cup-face positions."""
        return np.asarray(self.desired, dtype=float).reshape(-1, 3)

    @property
    def actual_xyz(self) -> np.ndarray:
        """(n, 3) measured cup-face positions (forward kinematics of the encoders)."""
        return np.asarray(self.actual, dtype=float).reshape(-1, 3)

    @property
    def tracking_error(self) -> np.ndarray:
        """|desired - actual| [m] per sample (NaN without a desired pose)."""
        return np.linalg.norm(self.desired_xyz - self.actual_xyz, axis=1)


class RunRecorder:
    """Samples a run at every runtime tick (``runtime.on_tick(recorder)``).

    Args:
        runtime: the runtime to sample.
        robot: the arm whose tool is tracked (default: the scenario's task robot).
        status: returns the robot's controller status (for the desired tool
            pose); ``None`` records no desired pose (NaN).
        period: sample at most every ``period`` s of simulated time (default:
            every tick).
    """

    def __init__(
        self,
        runtime: FactoryRuntime,
        *,
        robot: Optional[str] = None,
        status: Optional[Callable[[], ControlState]] = None,
        period: float = 0.0,
    ):
        if robot is None:
            task = runtime.scenario.task
            if task is None:
                raise ConfigError(f"scenario {runtime.scenario.name!r} has no task: name the robot to record")
            robot = task.robot
        if period < 0:
            raise ConfigError(f"period must be >= 0 s, got {period}")
        station = runtime.station
        handles = station.arm(robot)
        if not handles.config.gripper:
            raise ConfigError(f"{robot} has no gripper: no tool to track")
        self._runtime = runtime
        self._status = status
        self._period = period
        self._next = -math.inf
        self._tip = station.plant.GetFrameByName(f"{handles.config.gripper}_tip")
        self._cameras = sorted(station.cameras)
        self._part_types = {model_type(n) for n in station.parts}
        self._belt = station.conveyor is not None and station.break_beam is not None
        self.recording = RunRecording(robot=robot, detections={c: [] for c in self._cameras})

    @classmethod
    def attach(cls, run: TaskRun, *, period: float = 0.0) -> RunRecorder:
        """A recorder of ``run``'s task robot, sampling from the next tick on."""
        recorder = cls(
            run.runtime, robot=run.scenario.required_task().robot, status=run.control, period=period
        )
        run.runtime.on_tick(recorder)
        return recorder

    def __call__(self, runtime: FactoryRuntime) -> None:
        t = runtime.time
        if t < self._next - 1e-9:
            return
        self._next = t + self._period
        rec = self.recording
        rec.time.append(t)
        rec.actual.append(self._tool_position(runtime))
        X_desired: Optional[RigidTransform] = None
        mode = ""
        if self._status is not None:
            status = self._status()
            X_desired = status.pose_at(t)
            mode = status.mode.value
        rec.desired.append(X_desired.translation().copy() if X_desired is not None else np.full(3, math.nan))
        rec.mode.append(mode)
        for camera in self._cameras:
            image = runtime.camera_image(camera)
            rec.detections[camera].append(sum(1 for m in image.models if m.type in self._part_types))
        ledger = runtime.ledger()
        counts = {
            "on_belt": ledger.on_belt,
            "on_floor": ledger.on_floor,
            "elsewhere": ledger.elsewhere,
            "held": sum(ledger.held.values()),
            "disposed": ledger.disposed,
        }
        counts.update({f"in_bin:{b}": n for b, n in ledger.in_bin.items()})
        n = len(rec.time) - 1
        for key, value in counts.items():
            rec.ledger.setdefault(key, [0] * n).append(int(value))
        if self._belt:
            rec.beam.append(runtime.break_beam()[0])
            rec.conveyor_power.append(runtime.conveyor_power())

    def _tool_position(self, runtime: FactoryRuntime) -> np.ndarray:
        plant_context = runtime.station.plant.GetMyContextFromRoot(runtime.context)
        return self._tip.CalcPoseInWorld(plant_context).translation().copy()


def _need_samples(rec: RunRecording) -> None:
    if len(rec) == 0:
        raise StateError("the recording is empty: advance the runtime after attaching the recorder")


def plot_tracking_error(rec: RunRecording | RunRecorder) -> Figure:
    """Desired vs measured cup-face position (x, y, z) and the error norm over time.

    Axes: ``x``, ``y``, ``z`` [m] (solid: measured, dashed: desired) and
    ``error`` [mm].
    """
    rec = _recording(rec)
    _need_samples(rec)
    fig = Figure(figsize=(9, 7), layout="constrained")
    axes = fig.subplots(4, 1, sharex=True)
    t, desired, actual = rec.t, rec.desired_xyz, rec.actual_xyz
    for i, (ax, label) in enumerate(zip(axes, "xyz")):
        ax.plot(t, actual[:, i], color="tab:blue", label="measured")
        ax.plot(t, desired[:, i], color="tab:orange", linestyle="--", label="desired")
        ax.set_ylabel(f"{label} [m]")
    axes[0].legend(loc="upper right")
    axes[0].set_title(f"{rec.robot}: cup-face position, desired vs measured")
    error_mm = 1000.0 * rec.tracking_error
    axes[3].plot(t, error_mm, color="tab:red", label="|desired - measured|")
    if np.isfinite(error_mm).any():
        axes[3].axhline(
            float(np.nanmedian(error_mm)),
            color="grey",
            linestyle=":",
            label=f"median {np.nanmedian(error_mm):.1f} mm",
        )
    axes[3].set_ylabel("error [mm]")
    axes[3].set_xlabel("simulated time [s]")
    axes[3].legend(loc="upper right")
    return fig


def _label_part_counts(ax: Axes, ylabel: str, title: str, legend: str) -> None:
    """Labels ``ax``, numbers of parts (whole numbers) over simulated time, its legend at ``legend``."""
    ax.set_xlabel("simulated time [s]")
    ax.set_ylabel(ylabel)
    ax.set_title(title)
    ax.yaxis.get_major_locator().set_params(integer=True)
    ax.legend(loc=legend)


def plot_detections(rec: RunRecording | RunRecorder) -> Figure:
    """Number of parts each logical camera reports over time (one step line per camera)."""
    rec = _recording(rec)
    _need_samples(rec)
    fig = Figure(figsize=(9, 3.5), layout="constrained")
    ax = fig.add_subplot()
    for k, (camera, counts) in enumerate(sorted(rec.detections.items())):
        # A small offset per camera keeps overlapping lines visible.
        ax.step(rec.t, np.asarray(counts) + 0.04 * k, where="post", label=camera)
    _label_part_counts(ax, "parts in view", "logical cameras: parts reported", "upper right")
    return fig


def plot_conveyor(rec: RunRecording | RunRecorder) -> Figure:
    """Lecture 7: the break beam's state and the conveyor's power over time."""
    rec = _recording(rec)
    _need_samples(rec)
    if not rec.beam:
        raise ConfigError("the recording has no break beam and conveyor (not a conveyor scenario)")
    fig = Figure(figsize=(9, 4), layout="constrained")
    top, bottom = fig.subplots(2, 1, sharex=True)
    top.step(
        rec.t, np.asarray(rec.beam, dtype=float), where="post", color="tab:purple", label="object detected"
    )
    top.set_yticks([0, 1], ["clear", "broken"])
    top.set_ylabel("break beam")
    top.set_title("lecture 7: break beam and conveyor")
    bottom.step(rec.t, rec.conveyor_power, where="post", color="tab:brown", label="power")
    bottom.set_ylabel("conveyor power [%]")
    bottom.set_xlabel("simulated time [s]")
    return fig


def plot_cycle_times(result: TaskResult) -> Figure:
    """One bar per pick attempt (cycle time), green if it succeeded, red (with the
    reason) if it failed; the mean cycle time of the successes as a line."""
    fig = Figure(figsize=(9, 3.5), layout="constrained")
    ax = fig.add_subplot()
    picks = [p for p in result.picks if p.part]
    labels = [f"{p.part}\n#{p.attempt}" for p in picks]
    cycles = [p.cycle_time for p in picks]
    colours = [OK_COLOUR if p.success else FAIL_COLOUR for p in picks]
    bars = ax.bar(range(len(picks)), cycles, color=colours, width=0.6)
    ax.set_xlim(-0.7, max(len(picks) - 0.3, 1.7))
    for bar, pick in zip(bars, picks):
        if not pick.success:
            ax.annotate(
                pick.reason,
                (bar.get_x() + bar.get_width() / 2, bar.get_height()),
                ha="center",
                va="bottom",
                fontsize=8,
                color=FAIL_COLOUR,
            )
    ax.set_xticks(range(len(picks)), labels, fontsize=8)
    good = [p.cycle_time for p in picks if p.success]
    if good:
        mean = sum(good) / len(good)
        ax.axhline(mean, color="grey", linestyle=":", label=f"mean of successes {mean:.2f} s")
        ax.legend(loc="upper right")
    ax.set_ylabel("cycle time [s]")
    ok = sum(p.success for p in picks)
    ax.set_title(f"{result.scenario} (seed {result.seed}): {ok} picks ok, {len(picks) - ok} failed")
    return fig


def plot_ledger(rec: RunRecording | RunRecorder) -> Figure:
    """Where the spawned parts are over time (stacked: belt, floor, held, each bin, disposed)."""
    rec = _recording(rec)
    _need_samples(rec)
    keys = [k for k in _LEDGER_ORDER if k in rec.ledger]
    keys += sorted(k for k in rec.ledger if k.startswith("in_bin:"))
    keys += [k for k in ("disposed",) if k in rec.ledger]
    fig = Figure(figsize=(9, 3.5), layout="constrained")
    ax = fig.add_subplot()
    ax.stackplot(
        rec.t,
        *[np.asarray(rec.ledger[k]) for k in keys],
        labels=[k.replace("in_bin:", "in ") for k in keys],
        step="post",
    )
    _label_part_counts(ax, "parts", "ledger: where the spawned parts are", "upper left")
    return fig


def plot_seed_stats(results: Sequence[TaskResult]) -> Figure:
    """A statistics run over seeds: parts in the bin per seed (green: success,
    red: failure) and the cycle times of each seed's successful picks."""
    if not results:
        raise ConfigError("plot_seed_stats needs at least one result")
    fig = Figure(figsize=(9, 6), layout="constrained")
    top, bottom = fig.subplots(2, 1, sharex=True)
    seeds = [r.seed for r in results]
    x = np.arange(len(results))
    top.bar(
        x,
        [r.summary["in_bin"] for r in results],
        width=0.6,
        color=[OK_COLOUR if r.success else FAIL_COLOUR for r in results],
    )
    top.plot(x, [r.parts for r in results], "k_", markersize=20, label="parts asked")
    top.set_ylabel("parts in the bin")
    ok = sum(r.success for r in results)
    top.set_title(f"{results[0].scenario}: {ok}/{len(results)} seeds succeeded")
    top.legend(loc="lower right")
    cycles = [[p.cycle_time for p in r.picks if p.part and p.success] for r in results]
    for xi, c in zip(x, cycles):
        bottom.scatter(np.full(len(c), xi), c, color="tab:blue", s=12, alpha=0.7)
    means = [float(np.mean(c)) if c else math.nan for c in cycles]
    bottom.plot(x, means, "D", color="tab:orange", label="mean")
    bottom.set_ylabel("cycle time [s]")
    bottom.set_xlabel("seed")
    bottom.set_xticks(x, [str(s) for s in seeds])
    bottom.legend(loc="upper right")
    return fig


def _recording(rec: RunRecording | RunRecorder) -> RunRecording:
    if isinstance(rec, RunRecorder):
        return rec.recording
    if isinstance(rec, RunRecording):
        return rec
    raise ConfigError(f"expected a RunRecording or RunRecorder, got {type(rec).__name__}")
