"""A student group's catkin workspace (tests/fixtures/group_ws, the course's layout with
their edits): their world with the cameras they placed, their bin next to robot 1
(spawn_static_world_objects.launch), their conveyor_objects.yaml (a box and a crate,
each its own mesh, lateral 0.2 m, yaw and timing variances). Their launch runs; their
robot-1 belt script puts parts in their bin; the same seed gives the same spawns."""

from __future__ import annotations

import dataclasses
import json
import math
from pathlib import Path

import numpy as np
import pytest

from omtp_drake.launch import own_cell
from omtp_drake.sim.runtime import FactoryRuntime

WORKSPACE = Path(__file__).resolve().parent / "fixtures" / "group_ws" / "src"
LAUNCH = "omtp_lecture6 lecture6_assignment1.launch"
SCRIPT = WORKSPACE / "omtp_lecture6" / "scripts" / "belt_to_bin_robot1.py"


@pytest.fixture(scope="module")
def group_cell():
    return own_cell(LAUNCH, workspace=[WORKSPACE], environ={})


def test_their_launch_loads_their_spawner_cameras_and_bin(group_cell):
    spawner = group_cell.scenario.spawner
    assert [o.name for o in spawner.objects] == ["box", "crate"]
    box, crate = spawner.objects
    assert box.mesh_file.endswith("omtp_gazebo/meshes/conveyor_objects/box.stl")
    assert (box.lateral_variance, box.timing_variance) == (0.2, 1.5)
    assert box.yaw_variance == pytest.approx(math.pi / 2)
    assert crate.yaw_variance == pytest.approx(math.pi / 4) and crate.rpy[2] == pytest.approx(0.3927)
    assert (spawner.period, spawner.randomization_seed) == (10.0, 4)
    assert spawner.start_service == "/spawn_object_once"
    cameras = {c.name: c for c in group_cell.scenario.cameras}
    np.testing.assert_allclose(cameras["logical_camera_1"].xyz, [1.2, 2.0, 1.95])
    assert {b.name: b.xyz for b in group_cell.scenario.bins}["bin_2"] == [-0.1, 2.5, 0.0]


def _spawns(scenario, seed: int, n: int = 4) -> list[tuple[str, np.ndarray]]:
    """The first ``n`` spawns of the group's spawner at ``seed``: each part's object and pose."""
    runtime = FactoryRuntime(dataclasses.replace(scenario, seed=seed), auto_spawn=False)
    try:
        out = []
        for _ in range(n):
            part = runtime.spawn_part()
            X_WP = runtime.pool.events[-1].pose
            pose = np.hstack([X_WP.translation(), X_WP.rotation().ToQuaternion().wxyz()])
            out.append((runtime.station.pool_kinds[part], pose))
        return out
    finally:
        runtime.close()


def test_the_same_seed_gives_the_same_spawns_another_seed_others(group_cell):
    scenario = group_cell.scenario
    first, again, other = _spawns(scenario, 11), _spawns(scenario, 11), _spawns(scenario, 12)
    assert [k for k, _ in first] == [k for k, _ in again]
    for (_, a), (_, b) in zip(first, again):
        np.testing.assert_array_equal(a, b)
    assert any(not np.allclose(a, b) for (_, a), (_, b) in zip(first, other))
    # within the group's ranges: on the belt's centre line, y 2.0 +/- 0.2
    for _, pose in first + other:
        assert pose[0] == pytest.approx(1.2) and abs(pose[1] - 2.0) <= 0.2 + 1e-9


def test_their_belt_script_puts_parts_in_their_bin_next_to_robot_1(tmp_path):
    from omtp_drake.cli import main

    out = tmp_path / "report.json"
    argv = ["ros-run", str(SCRIPT), "2", "--launch", LAUNCH, "--workspace", str(WORKSPACE)]
    assert main([*argv, "--timeout", "60", "--json", str(out), "-q"]) == 0
    report = json.loads(out.read_text())
    assert report["exception"] is None, report["traceback"]
    assert report["ledger"]["in_bin"]["bin_2"] >= 2, report["ledger"]
