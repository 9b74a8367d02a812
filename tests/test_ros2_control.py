"""``omtp-drake ros2`` on a ros2_control robot written here (two joints with ``initial_value``\\ s,
a trajectory controller and a broadcaster in its YAML), with a plain rclpy node in another
process (tests/ros2_scripts/ros2_control_node.py) on loopback, in a domain of its own: the
joints start at their initial values, follow a trajectory sent to
``/arm_controller/joint_trajectory`` within the controller's tolerances, and ``/joint_states``
comes from the broadcaster at the YAML's rate (counted over simulated time); the trajectory
controller's ``~/controller_state`` follows the trajectory at each controller update; then a
second node's FollowJointTrajectory goal is followed. One cell serves both nodes, one after the
other (the module's fixture ``runs``): the tests only read what the nodes saw."""

from __future__ import annotations

import json
import os
import shutil
from pathlib import Path

import numpy as np
import pytest
from test_ros2 import SCRIPTS, hold_domain, needs_ros2, run_cell_with_nodes

ROBOT = (
    Path(__file__).parent
    / "fixtures"
    / "control_ws"
    / "src"
    / "two_joint_ros2"
    / "urdf"
    / "two_joint.urdf.xacro"
)
#: The YAML's constraints (goal) and initial values; the trajectory's last point.
GOAL_TOLERANCE = {"shoulder_joint": 0.01, "slide_joint": 0.005}
INITIAL = {"shoulder_joint": 0.3, "slide_joint": 0.05}
LAST = {"shoulder_joint": 0.8, "slide_joint": 0.1}
BROADCASTER_HZ = 25.0
#: The controller manager's update_rate: the trajectory controller's state rate on ROS 2 (the YAML's
#: Humble-era state_publish_rate: 50 is ignored, as ros2_controllers ignores it since Iron).
UPDATE_HZ = 100.0

HAVE_COMPILER = shutil.which("cc") is not None and shutil.which("c++") is not None
needs_compiler = pytest.mark.skipif(not HAVE_COMPILER, reason="no compiler: apt-get install g++")


@pytest.fixture(scope="module")
def runs(tmp_path_factory) -> dict:
    """One cell of ROBOT, and in turn: a student's node sending a trajectory on
    ~/joint_trajectory and watching /joint_states (and, with control_msgs built here, the
    controller's state); then, with control_msgs, a student's FollowJointTrajectory client.
    What each saw, by name ("joints", "controller_state", "action"), and the cell's stderr."""
    tmp = tmp_path_factory.mktemp("ros2_control")
    paths = {name: tmp / f"{name}.json" for name in ("joints", "controller_state", "action")}
    nodes = [[str(SCRIPTS / "ros2_control_node.py"), str(paths["joints"])]]
    env = {}
    if HAVE_COMPILER:
        from omtp_drake.ros2 import interface_build

        built = (str(interface_build.interfaces_path()), os.environ.get("PYTHONPATH", ""))
        env["PYTHONPATH"] = os.pathsep.join(p for p in built if p)
        nodes[0].append(str(paths["controller_state"]))
        nodes.append([str(SCRIPTS / "follow_joint_trajectory_node.py"), str(paths["action"])])
    with hold_domain() as domain:
        _, cell_err = run_cell_with_nodes([str(ROBOT)], nodes, domain, env)
    seen = {name: json.loads(path.read_text()) for name, path in paths.items() if path.exists()}
    return {**seen, "cell_err": cell_err}


@needs_ros2
def test_a_ros2_control_robot_follows_a_trajectory_and_broadcasts_its_joints(runs):
    result = runs["joints"]
    states = [(t, dict(zip(names, q))) for t, names, q in result["states"]]
    assert all(list(q) == ["shoulder_joint", "slide_joint"] for _, q in states)

    before = dict(zip(result["before"][1], result["before"][2]))
    for joint, value in INITIAL.items():
        assert before[joint] == pytest.approx(value, abs=GOAL_TOLERANCE[joint])

    start = result["start"]
    end = [q for t, q in states if t >= start + 2.5]
    assert end, "no joint states after the trajectory's end"
    for joint, value in LAST.items():
        assert end[-1][joint] == pytest.approx(value, abs=GOAL_TOLERANCE[joint])
    # The first point (1 s in): shoulder -0.5, slide 0.15, within the trajectory tolerances.
    _, at_first = min(states, key=lambda s: abs(s[0] - (start + 1.0)))
    assert at_first["shoulder_joint"] == pytest.approx(-0.5, abs=0.2)
    assert at_first["slide_joint"] == pytest.approx(0.15, abs=0.05)

    stamps = np.array([t for t, _ in states])
    window = stamps[(stamps >= start) & (stamps < start + 3.0)]
    assert len(window) == pytest.approx(3.0 * BROADCASTER_HZ, abs=1)
    assert np.allclose(np.diff(stamps), 1.0 / BROADCASTER_HZ, atol=1e-6)


def test_a_launch_files_spawners_activate_the_controllers_in_their_order(tmp_path):
    """sim.launch.py (a ros2_control demo's form): the broadcaster's spawner, then the arm's once
    it has exited. The launch's order is the active order (the YAML declares the arm first);
    a launch that spawns only the broadcaster leaves the arm controller inactive; a spawner of
    a controller no plugin declares is one warning line, and the launch goes on."""
    import shutil

    from omtp_drake.launch import own_cell

    src = Path(__file__).parent / "fixtures" / "control_ws" / "src"

    def active(workspace: Path) -> tuple[list[str], list[str]]:
        cell = own_cell("two_joint_ros2 sim.launch.py", workspace=[workspace], environ={})
        (model,) = cell.scenario.models
        return [c.name for c in model.gazebo.ros_control.controllers], cell.warnings

    assert active(src) == (["joint_state_broadcaster", "arm_controller"], [])
    package = tmp_path / "two_joint_ros2"
    shutil.copytree(src / "two_joint_ros2", package)
    launch = package / "launch" / "sim.launch.py"
    text = launch.read_text()
    launch.write_text(text.replace('arguments=["arm_controller"]', 'arguments=["gripper_controller"]'))
    names, warnings = active(tmp_path)
    assert names == ["joint_state_broadcaster"]
    assert (
        len(warnings) == 1
        and "'gripper_controller' is declared by no gazebo_ros2_control plugin" in warnings[0]
    )


@needs_ros2
@needs_compiler
def test_a_follow_joint_trajectory_goal_is_followed_within_the_goal_tolerances(runs):
    """A student's rclpy action client (control_msgs built here): a goal naming an unknown joint is
    rejected; a good one succeeds (status 4, SUCCESSFUL) with feedback at the action monitor rate,
    and the joints end at its last point within the controller's goal tolerances. (The joints
    start where the first node's trajectory left them: its last point.)"""
    seen, cell_err = runs["action"], runs["cell_err"]
    assert seen["bad_accepted"] is False
    assert "goal rejected" in cell_err and "elbow_joint" in cell_err, cell_err[-2000:]
    assert seen["accepted"] is True
    assert (seen["status"], seen["error_code"]) == (4, 0)  # GoalStatus.STATUS_SUCCEEDED, SUCCESSFUL
    # 2 s of trajectory judged at 20 Hz: up to about 40 feedback messages before the end, stamped
    # on the monitor's 50 ms grid. The cell runs as fast as it can, so a busy client may lose some
    # from its feedback queue (KEEP_LAST): the stamps say the rate, not the count received.
    stamps = seen["feedback_stamps"]
    assert 2 <= len(stamps) <= 50 and seen["feedback_joints"] == ["shoulder_joint", "slide_joint"]
    # The first at the goal's acceptance, the rest on the cell's 50 ms ticks.
    ticks = [t / 0.05 for t in stamps[1:]]
    assert all(abs(k - round(k)) < 1e-3 for k in ticks), stamps
    assert all(b > a for a, b in zip(stamps, stamps[1:])), stamps
    assert stamps[-1] - stamps[0] <= 2.0 + 0.1, stamps  # the 2 s, up to the tick after its end
    for joint, value in LAST.items():
        assert seen["after"][joint] == pytest.approx(value, abs=GOAL_TOLERANCE[joint])


@needs_ros2
@needs_compiler
def test_the_controller_state_follows_a_trajectory_at_each_update(runs):
    """A student's rclpy node on /arm_controller/controller_state (control_msgs built here) while a
    trajectory sent on ~/joint_trajectory plays: the controller's joints, a reference moving from
    where the joints were to the trajectory's points, a feedback following it and within the goal
    tolerances at the end, error = reference - feedback, stamped on the update rate's grid."""
    seen = runs["controller_state"]
    states, start = seen["states"], seen["start"]
    joints = ["shoulder_joint", "slide_joint"]
    assert all(s["joint_names"] == joints for s in states)
    # The cell runs as fast as it can and the client's queue is 10 deep, so it loses states: the
    # stamps say the rate (every one on the 10 ms grid, increasing), not the count received.
    stamps = np.array([s["stamp"] for s in states])
    assert np.all(np.diff(stamps) > 0), stamps
    assert np.allclose(stamps * UPDATE_HZ, np.round(stamps * UPDATE_HZ), atol=1e-6), stamps
    # Every update, not the YAML's state_publish_rate (50 Hz): two states received 10 ms apart.
    assert np.diff(stamps).min() == pytest.approx(1.0 / UPDATE_HZ, abs=1e-6), stamps
    for s in states:
        assert s["error"] == pytest.approx(np.subtract(s["reference"], s["feedback"]), abs=1e-12)
        assert s["output"] == s["reference"] and s["speed_scaling_factor"] == 1.0
    before = dict(zip(joints, seen["before"]["feedback"]))
    for joint, value in INITIAL.items():
        assert before[joint] == pytest.approx(value, abs=GOAL_TOLERANCE[joint])
    # Through the first point (1 s in: shoulder -0.5, slide 0.15) to the last (2 s in), then held.
    during = [s for s in states if start < s["stamp"] < start + 2.0]
    assert during, "no state while the trajectory played"
    # The reference left `before` between the last state received at rest and the first moved one
    # (`start`): when a busy client lost the states between them, "1 s in" is known only to that gap.
    at_rest = [s["stamp"] for s in states if s["stamp"] < start]
    start_known = bool(at_rest) and start - max(at_rest) < 1.5 / UPDATE_HZ
    near = min(during, key=lambda s: abs(s["stamp"] - (start + 1.0)))
    if start_known and abs(near["stamp"] - (start + 1.0)) < 0.02:  # or lost the states there
        assert near["reference"] == pytest.approx([-0.5, 0.15], abs=0.05)
    after = [s for s in states if s["stamp"] > start + 2.5]
    assert after, "no state after the trajectory's end"
    assert after[-1]["reference"] == pytest.approx([LAST[j] for j in joints], abs=1e-9)
    for k, joint in enumerate(joints):
        assert after[-1]["feedback"][k] == pytest.approx(LAST[joint], abs=GOAL_TOLERANCE[joint])
    # Toward the goal: the feedback ends nearer the last point than it started.
    distance = [np.abs(np.subtract(s["feedback"], [LAST[j] for j in joints])).max() for s in states]
    assert distance[-1] < distance[0]
