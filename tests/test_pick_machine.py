"""The pick-and-place state machine alone (omtp_drake.control.pick_and_place.machine):
plain inputs in, decisions out, no Drake system or simulation."""

import math

import numpy as np
import pytest
from pydrake.math import RigidTransform

from omtp_drake.cell import arms
from omtp_drake.cell.logical_camera import DetectedModel, LogicalCameraImage
from omtp_drake.cell.suction import GripperState
from omtp_drake.control.pick_and_place import ControlState, MachineInput, Mode, PickMachine
from omtp_drake.control.tool_paths import hold, tool_down
from omtp_drake.scenario import load_scenario

SIZE = 0.05
#: A part on the belt within robot 2's reach, and the tool 5 cm above its top face.
P_PART = np.array([-7.8, -0.95, 0.9])
X_ABOVE = tool_down(P_PART + [0.0, 0.0, SIZE / 2 + 0.05], 0.0)
FREE = GripperState(False, False, "", None, math.nan)


@pytest.fixture(scope="module")
def scenario():
    return load_scenario("lecture6_assignment4")


@pytest.fixture(scope="module")
def machine(scenario):
    task = scenario.required_task()
    robot = scenario.robot(task.robot)
    X_W_home = tool_down(np.array([-7.8, -1.0, 1.3]), 0.0)
    return PickMachine(task, robot, scenario.bin(task.bin), lambda name: SIZE, X_W_home)


@pytest.fixture(scope="module")
def task(scenario):
    return scenario.required_task()


def image(t, *parts):
    """The pick camera's image at ``t`` showing ``(name, p_WP)`` parts (camera at W)."""
    models = tuple(DetectedModel(name, "object", RigidTransform(p)) for name, p in parts)
    return LogicalCameraImage(t, "logical_camera_2", RigidTransform(), models)


def seen(t, gripper=FREE, X_WE=X_ABOVE, *parts):
    q = tuple(arms.named_pose("R2Home"))
    return MachineInput.seeing(t=t, X_WE=X_WE, gripper=gripper, q=q, pick_image=image(t, *parts))


def holding(part):
    return GripperState(True, True, part, RigidTransform([0, 0, SIZE / 2]), 1.0)


def test_no_part_seen_waits_then_records_it(machine, task):
    started = machine.step(seen(0.0), ControlState())
    assert started.mode is Mode.WAIT_PART and started.record is None and not started.vacuum
    waiting = machine.step(seen(task.detect_timeout - 1.0), started.control)
    assert waiting.mode is Mode.WAIT_PART and waiting.record is None
    stale = MachineInput.seeing(task.detect_timeout + 1.0, X_ABOVE, FREE, tuple(arms.named_pose("R2Home")),
                         pick_image=image(0.0))
    assert machine.step(stale, waiting.control).record is None  # no fresh image: no verdict
    late = machine.step(seen(task.detect_timeout + 1.0), waiting.control)
    assert late.mode is Mode.WAIT_PART
    assert late.record is not None and late.record.reason == "no_part" and not late.record.success


def test_a_part_at_rest_is_approached(machine):
    s = machine.step(seen(0.0), ControlState()).control
    first = machine.step(seen(0.05, FREE, X_ABOVE, ("object_1", P_PART)), s)
    assert first.mode is Mode.WAIT_PART  # seen once: it may still move
    second = machine.step(seen(0.10, FREE, X_ABOVE, ("object_1", P_PART)), first.control)
    assert second.mode is Mode.APPROACH and second.control.part == "object_1"
    end = second.path.pose_at(second.path.end_time)
    assert np.allclose(end.translation()[:2], P_PART[:2], atol=1e-6)
    assert end.translation()[2] > P_PART[2] + SIZE / 2


def attaching(t0=10.0, attempt=1):
    X_touch = tool_down(P_PART + [0.0, 0.0, SIZE / 2], 0.0)
    s = ControlState(mode=Mode.ATTACH, mode_start=t0, path=hold(t0, X_touch), suction=True,
                     part="object_1", X_WP=RigidTransform(P_PART), pick_start=5.0, attempt=attempt)
    return s, X_touch


def test_attach_within_the_timeout_lifts_towards_the_bin(machine, task, scenario):
    s, X_touch = attaching()
    d = machine.step(seen(10.2, holding("object_1"), X_touch), s)
    assert d.mode is Mode.TRANSFER and d.vacuum and d.record is None
    path = d.path
    z0 = X_touch.translation()[2]
    lifted = [path.pose_at(t).translation() for t in np.linspace(10.2, path.end_time, 400)]
    # Straight up by the approach height before any sideways motion.
    first_sideways = next(p for p in lifted if np.linalg.norm(p[:2] - P_PART[:2]) > 1e-3)
    assert first_sideways[2] >= z0 + task.approach_height - 1e-6
    assert scenario.bin(task.bin).contains(lifted[-1] - [0.0, 0.0, SIZE])


def test_attach_timeout_retries_then_gives_up_with_the_reason(machine, task):
    s, X_touch = attaching()
    t = 10.0 + task.attach_timeout + 0.05
    retry = machine.step(seen(t, FREE, X_touch), s)
    assert retry.mode is Mode.HOME and not retry.vacuum
    assert retry.record.reason == "attach_timeout" and not retry.record.given_up
    assert retry.control.part == "object_1" and retry.control.attempt == 2
    last, _ = attaching(attempt=task.max_attempts)
    given_up = machine.step(seen(t, FREE, X_touch), last)
    assert given_up.mode is Mode.HOME
    record = given_up.record
    assert record.reason == "attach_timeout" and record.given_up and record.attempt == task.max_attempts
    assert np.allclose(record.position, P_PART)
    assert given_up.control.part == "" and "object_1" in given_up.control.ignored


def _dropped(machine):
    """A part held in transit that the gripper no longer holds: the update that sees it."""
    X_WE = tool_down(np.array([-7.9, -1.6, 1.1]), 0.0)
    s = ControlState(mode=Mode.TRANSFER, mode_start=20.0, path=hold(20.0, X_WE), suction=True,
                     part="object_1", X_WP=RigidTransform(P_PART), pick_start=15.0)
    return machine.step(seen(20.5, FREE, X_WE), s), X_WE


def test_a_part_dropped_in_transit_is_one_record_that_says_where_it_landed(machine):
    d, X_WE = _dropped(machine)
    assert d.mode is Mode.HOME and not d.vacuum
    assert d.record is None  # not yet: where it comes to rest is not known
    # Last known: under the cup where it fell.
    assert np.allclose(d.control.X_WP.translation(), X_WE.translation() - [0.0, 0.0, SIZE / 2])
    s = d.control
    landing = np.array([-7.7, -1.0, SIZE / 2])
    records = []
    for t in np.arange(20.55, 26.0, 0.05):  # the tool follows its path (no tracking error)
        step = machine.step(seen(t, FREE, s.pose_at(t), ("object_1", landing)), s)
        s = step.control
        records += [step.record] if step.record is not None else []
        if s.mode is Mode.APPROACH:
            break
    [drop] = records  # the drop, once; the new attempt is not a record until it ends
    assert (drop.part, drop.reason, drop.attempt) == ("object_1", "dropped", 1)
    assert (drop.start, drop.end) == (15.0, 20.5)
    assert np.allclose(drop.position, landing) and not drop.given_up
    assert s.mode is Mode.APPROACH and s.attempt == 2
    assert s.pick_start > 20.5  # the second attempt starts once the part is seen at rest


def test_a_part_dropped_into_the_bin_is_that_drop_record_not_a_new_attempt(machine, scenario, task):
    d, _ = _dropped(machine)
    X_WBin = scenario.bin(task.bin).X_WB()
    in_bin = X_WBin.translation() + [0.0, 0.0, 0.2]
    s, records = d.control, []
    for t in np.arange(20.55, 26.0, 0.05):
        models = (
            DetectedModel(task.bin, "bin", X_WBin),
            DetectedModel("object_1", "object", RigidTransform(in_bin)),
        )
        bin_view = LogicalCameraImage(t, task.bin_camera, RigidTransform(), models)
        step = machine.step(MachineInput.seeing(t, s.pose_at(t), FREE, tuple(arms.named_pose("R2Home")),
                                         pick_image=image(t), bin_image=bin_view), s)
        s = step.control
        records += [step.record] if step.record is not None else []
    [drop] = records
    assert (drop.reason, drop.attempt, drop.end, drop.given_up) == ("dropped_into_bin", 1, 20.5, True)
    assert np.allclose(drop.position, in_bin)


def test_a_part_only_a_search_camera_sees_is_found(machine):
    """The pick camera shows nothing; another camera sees a part outside the bin (it
    fell out of view): once it is at rest there, it is approached."""
    s = machine.step(seen(0.0), ControlState()).control
    q = tuple(arms.named_pose("R2Home"))
    for t in (0.05, 0.10):
        search = image(t, ("object_3", P_PART))
        inputs = MachineInput.seeing(t, X_ABOVE, FREE, q, pick_image=image(t), search_images=(search,))
        d = machine.step(inputs, s)
        s = d.control
    assert d.mode is Mode.APPROACH and s.part == "object_3"


def test_tracking_error_is_measured_from_the_desired_pose_the_caller_gives(machine):
    """The controller hands the machine its path's pose at t from DiffIK's table;
    without one the machine evaluates the path itself: the same error either way."""
    from dataclasses import replace

    s = ControlState(mode=Mode.WAIT_PART, path=hold(0.0, X_ABOVE), last_seen=0.0)
    X_off = RigidTransform(X_ABOVE.rotation(), X_ABOVE.translation() + [0.003, 0.0, 0.004])
    own = machine.step(seen(0.05, FREE, X_off), s)
    assert own.tracking_error == pytest.approx(0.005, abs=1e-12)
    given = machine.step(replace(seen(0.05, FREE, X_off), X_WE_desired=X_ABOVE), s)
    assert given.tracking_error == own.tracking_error
    X_elsewhere = RigidTransform(X_ABOVE.translation() + [0.0, 0.002, 0.0])
    other = machine.step(replace(seen(0.05, FREE, X_off), X_WE_desired=X_elsewhere), s)
    assert other.tracking_error == pytest.approx(math.hypot(0.003, 0.002, 0.004), abs=1e-12)


def test_images_are_read_only_when_the_machine_looks(machine):
    """A moving arm follows its path without looking (no camera image is read, so no
    camera computes one); waiting for a part, it reads the pick camera's image."""
    reads = []

    def reading(name):
        def read():
            reads.append(name)
            return () if name == "search" else image(0.30, ("object_1", P_PART))
        return read

    def inputs(t, X_WE):
        return MachineInput(t, X_WE, FREE, tuple(arms.named_pose("R2Home")), reading("pick"),
                            reading("bin"), reading("search"))

    s = machine.step(seen(0.0), ControlState()).control
    s = machine.step(seen(0.05, FREE, X_ABOVE, ("object_1", P_PART)), s).control
    approach = machine.step(seen(0.10, FREE, X_ABOVE, ("object_1", P_PART)), s)
    assert approach.mode is Mode.APPROACH and approach.path.end_time > 0.3
    moving = machine.step(inputs(0.15, approach.path.pose_at(0.15)), approach.control)
    assert moving.mode is Mode.APPROACH and reads == []
    waiting = machine.step(inputs(0.30, X_ABOVE), ControlState(mode=Mode.WAIT_PART, path=hold(0.0, X_ABOVE)))
    assert waiting.record is None and "pick" in reads


def test_the_travel_check_passes_only_where_the_step_decides_nothing(machine, task):
    """Issue 46, item 2: an update while the arm travels runs only the checks of every mode
    (machine.travel_check); wherever it passes, the full step returns the control state
    itself, no record and the same tracking error; where the step would change anything
    (the path's end, a drop, a tracking error over the tolerance or counting, a DiffIK
    restart), it does not pass."""
    import itertools
    from dataclasses import replace

    from omtp_drake.control.pick_and_place.machine import travel_check
    from omtp_drake.control.tool_paths import Path, Segment, SegmentKind

    X_far = tool_down(P_PART + [0.3, 0.1, 0.3], 0.0)
    path = Path((Segment(SegmentKind.LINE, 1.0, 2.0, X_ABOVE, X_far),))
    offsets = (0.0, 0.5 * task.tracking_tolerance, 2.0 * task.tracking_tolerance)
    passed = 0
    for mode, t, grip, offset, reset, bad in itertools.product(
        (Mode.APPROACH, Mode.DESCEND, Mode.TRANSFER, Mode.HOME, Mode.WAIT_PART, Mode.RELEASE),
        (1.5, 2.95, 3.0, 3.5),
        (FREE, holding("object_1")),
        offsets,
        (False, True),
        (math.nan, 1.2),
    ):
        s = ControlState(mode=mode, mode_start=1.0, path=path, suction=mode is Mode.TRANSFER, part="object_1",
                         X_WP=RigidTransform(P_PART), pick_start=0.5, reset_ik=reset, bad_tracking_since=bad,
                         last_seen=t)
        X_now = RigidTransform(path.pose_at(t).rotation(), path.pose_at(t).translation() + [offset, 0.0, 0.0])
        inputs = replace(seen(t, grip, X_now), X_WE_desired=path.pose_at(t))
        reads: list[str] = []

        def read(what, value, reads=reads):
            return lambda: reads.append(what) or value

        error = travel_check(
            s, t, task.tracking_tolerance,
            read("gripper", grip.attached), read("desired", inputs.X_WE_desired), read("fk", X_now),
        )
        if error is None:
            continue
        passed += 1
        decision = machine.step(inputs, s)
        assert decision.control is s and decision.record is None, (mode, t, grip, offset, reset, bad)
        assert decision.tracking_error == error
        assert mode in (Mode.APPROACH, Mode.DESCEND, Mode.TRANSFER, Mode.HOME) and t < path.end_time
        assert not reset and math.isnan(bad) and (offset <= task.tracking_tolerance or mode is Mode.DESCEND)
        assert ("fk" in reads) == (mode is not Mode.DESCEND)
        assert ("gripper" in reads) == (mode is Mode.TRANSFER)
    # On time (t 1.5 or 2.95), no restart, no failure counting: APPROACH and HOME with the
    # tool within the tolerance (2 offsets, either gripper), DESCEND whatever the offset
    # (no tracking check while pressing), TRANSFER only while holding.
    assert passed == 2 * (2 * 2 * 2) + 2 * 2 * 3 + 2 * 1 * 2
