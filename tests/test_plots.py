"""Plots of a run (omtp_drake.tasks.plots): the recorder samples sane data, each figure shows it."""


import numpy as np
import pytest
from matplotlib.colors import to_rgba
from matplotlib.figure import Figure

from omtp_drake.control.pick_and_place import PickFailure, PickRecord
from omtp_drake.errors import ConfigError, StateError
from omtp_drake.tasks.plots import (
    FAIL_COLOUR,
    OK_COLOUR,
    RunRecorder,
    RunRecording,
    plot_conveyor,
    plot_cycle_times,
    plot_detections,
    plot_ledger,
    plot_seed_stats,
    plot_tracking_error,
)
from omtp_drake.tasks.run import run_task


@pytest.fixture(scope="module")
def one_pick():
    """lecture6_assignment4 with one part (about 2 s), recorded."""
    recorders: list[RunRecorder] = []
    result = run_task("lecture6_assignment4", parts=1,
                      on_start=lambda run: recorders.append(RunRecorder.attach(run)))
    return result, recorders[0].recording


def test_recorder_samples_every_tick_with_sane_data(one_pick):
    result, rec = one_pick
    assert result.success
    assert rec.robot == "robot2"
    t = rec.t
    assert len(rec) == len(rec.desired) == len(rec.actual) == len(rec.mode)
    assert np.allclose(np.diff(t), 0.05)                # one sample per 50 ms tick
    assert t[-1] == pytest.approx(result.sim_time_s)
    error = rec.tracking_error
    assert np.isfinite(error).sum() > 0.9 * len(rec)    # the controller has a path almost always
    assert np.nanmedian(error) < 0.05
    assert np.nanmax(error) < 0.1
    # Robot 2's cup face goes from near its base down to the part and then over bin 1.
    assert np.linalg.norm(rec.actual_xyz[-1, :2] - np.array([-8.0, -2.2])) < 0.1
    assert rec.actual_xyz[:, 2].min() < 0.35            # reached down to the 0.2 m part
    # Camera 2 saw the part before the pick; the bin camera sees it at the end.
    assert max(rec.detections["logical_camera_2"]) == 1
    assert rec.detections["logical_camera_bin_1"][0] == 0
    assert rec.detections["logical_camera_bin_1"][-1] == 1
    assert set(rec.mode) >= {"WAIT_PART", "APPROACH", "DESCEND", "TRANSFER"}
    # Ledger: one part, first falling (elsewhere), on the floor, then held, finally in bin 1;
    # conserved throughout.
    totals = np.sum([rec.ledger[k] for k in rec.ledger], axis=0)
    assert set(totals.tolist()) == {1}
    assert max(rec.ledger["held"]) == 1 and rec.ledger["held"][-1] == 0
    assert rec.ledger["in_bin:bin_1"][-1] == 1 and rec.ledger["elsewhere"][0] == 1
    assert max(rec.ledger["on_floor"]) == 1


def test_recorder_period_thins_samples(one_pick):
    recorders: list[RunRecorder] = []
    run_task("lecture6_assignment4", parts=1, duration=1.0,
             on_start=lambda run: recorders.append(RunRecorder.attach(run, period=0.2)))
    t = recorders[0].recording.t
    assert len(t) == 5 and np.allclose(np.diff(t), 0.2)


def test_tracking_plot_has_xyz_and_error_axes(one_pick):
    _, rec = one_pick
    fig = plot_tracking_error(rec)
    assert isinstance(fig, Figure)
    axes = fig.get_axes()
    assert [a.get_ylabel() for a in axes] == ["x [m]", "y [m]", "z [m]", "error [mm]"]
    for ax, i in zip(axes[:3], range(3)):
        measured, desired = ax.get_lines()
        assert np.array_equal(measured.get_ydata(), rec.actual_xyz[:, i])
        assert np.array_equal(desired.get_ydata(), rec.desired_xyz[:, i], equal_nan=True)
    error_line = axes[3].get_lines()[0]
    assert np.allclose(error_line.get_ydata(), 1000 * rec.tracking_error, equal_nan=True)


def test_detection_plot_has_one_line_per_camera(one_pick):
    _, rec = one_pick
    ax, = plot_detections(rec).get_axes()
    assert sorted(line.get_label() for line in ax.get_lines()) == sorted(rec.detections)


def test_ledger_plot_stacks_every_category(one_pick):
    _, rec = one_pick
    ax, = plot_ledger(rec).get_axes()
    labels = [t.get_text() for t in ax.get_legend().get_texts()]
    assert labels == ["on_belt", "on_floor", "elsewhere", "held", "in bin_1", "disposed"]
    assert len(ax.collections) == 6
    assert ax.get_ylim()[1] >= 1


def test_cycle_time_bars_colour_failures(one_pick):
    result, _ = one_pick
    ax, = plot_cycle_times(result).get_axes()
    assert [p.get_height() for p in ax.patches] == pytest.approx(
        [p.cycle_time for p in result.picks if p.part])
    assert all(p.get_facecolor() == to_rgba(OK_COLOUR) for p in ax.patches)
    failed = PickRecord("object_2", 1.0, 3.0, False, PickFailure.ATTACH_TIMEOUT, 1)
    result.picks.append(failed)
    try:
        ax, = plot_cycle_times(result).get_axes()
    finally:
        result.picks.remove(failed)
    assert ax.patches[-1].get_facecolor() == to_rgba(FAIL_COLOUR)
    assert ax.patches[-1].get_height() == pytest.approx(2.0)
    assert "attach_timeout" in [t.get_text() for t in ax.texts]


def test_seed_stats_bars_and_cycle_times(one_pick):
    result, _ = one_pick
    top, bottom = plot_seed_stats([result, result]).get_axes()
    assert [p.get_height() for p in top.patches] == [1, 1]
    assert len(bottom.collections) == 2             # one scatter of cycle times per seed
    means = bottom.get_lines()[0].get_ydata()
    assert means == pytest.approx([result.summary["mean_cycle_time_s"]] * 2)


def test_conveyor_plot_shows_the_beam_stopping_the_belt():
    recorders: list[RunRecorder] = []
    run_task("lecture7_conveyor_pick", parts=1, duration=4.0,
             on_start=lambda run: recorders.append(RunRecorder.attach(run, period=0.1)))
    rec = recorders[0].recording
    assert rec.conveyor_power[0] == 100.0 and any(rec.beam)
    first_broken = rec.beam.index(True)
    assert rec.conveyor_power[first_broken + 1] == 0.0   # the beam stops the belt
    beam_ax, power_ax = plot_conveyor(rec).get_axes()
    assert np.array_equal(beam_ax.get_lines()[0].get_ydata(), np.asarray(rec.beam, float))
    assert np.array_equal(power_ax.get_lines()[0].get_ydata(), rec.conveyor_power)


def test_wrong_inputs_raise_config_errors_and_an_empty_recording_a_state_error():
    with pytest.raises(ConfigError, match="the recording has no break beam and conveyor"):
        plot_conveyor(RunRecording(robot="robot2", time=[0.0]))  # no beam recorded
    with pytest.raises(StateError, match="the recording is empty: advance the runtime after attaching"):
        plot_tracking_error(RunRecording(robot="robot2"))
    with pytest.raises(ConfigError, match="plot_seed_stats needs at least one result"):
        plot_seed_stats([])
    with pytest.raises(ConfigError, match="expected a RunRecording or RunRecorder, got str"):
        plot_ledger("not a recording")
