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
from fixture_reports import assert_as_recorded

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
    assert_as_recorded("group_ws belt_to_bin_robot1.py 2", report)


SPAWN_WATCH = """
    import json, sys
    import rospy
    from gazebo_msgs.srv import GetLinkState, SpawnModel
    from geometry_msgs.msg import Pose
    from std_msgs.msg import Header
    from std_srvs.srv import Empty

    CRATE = '''<robot name="crate"><link name="crate_base_link">
      <visual><geometry><mesh filename="package://omtp_gazebo/meshes/conveyor_objects/crate.stl"/></geometry></visual>
      <collision><geometry><mesh filename="package://omtp_gazebo/meshes/conveyor_objects/crate.stl"/></geometry></collision>
      <inertial><mass value="0.2"/><inertia ixx="1" iyy="1" izz="1" ixy="0" iyz="0" ixz="0"/></inertial>
    </link></robot>'''

    spawned = []
    rospy.init_node("spawn_watch")
    rospy.Subscriber("/spawned_part", Header, lambda h: spawned.append([h.seq, h.frame_id, h.stamp.to_sec()]))
    rospy.ServiceProxy("/spawn_object_once", Empty)()
    while len(spawned) < 2 and rospy.get_time() < 25.0:  # (the second is due by 21.5 s)
        rospy.sleep(0.05)
    link_state = rospy.ServiceProxy("/gazebo/get_link_state", GetLinkState)
    links = [link_state("object_%d::%s_base_link" % (k, kind), "world").success for k, (_, kind, _) in
             enumerate(spawned, start=1)]
    pose = Pose()
    pose.position.x, pose.position.y, pose.position.z, pose.orientation.w = -0.1, 2.5, 1.5, 1.0
    crate = rospy.ServiceProxy("/gazebo/spawn_urdf_model", SpawnModel)("my_crate", CRATE, "", pose, "world")
    json.dump({"spawned": spawned, "links": links, "crate": crate.success}, open(sys.argv[1], "w"))
"""


def test_the_spawner_node_spawns_their_objects_at_their_delays(group_cell, tmp_path):
    """/spawned_part names each drawn object; each comes its drawn delay after its tick;
    a part's link is named after its object; their crate URDF spawns as a crate."""
    import textwrap

    from omtp_drake.cli import main
    from omtp_drake.scenario.conveyor_spawner import draw

    script = tmp_path / "spawn_watch.py"
    script.write_text(textwrap.dedent(SPAWN_WATCH))
    out, report = tmp_path / "out.json", tmp_path / "report.json"
    argv = ["ros-run", str(script), str(out), "--launch", LAUNCH, "--workspace", str(WORKSPACE)]
    assert main([*argv, "--timeout", "40", "--json", str(report), "-q"]) == 0
    assert json.loads(report.read_text())["exception"] is None
    data = json.loads(out.read_text())
    spawner = group_cell.scenario.spawner
    draws = [draw(spawner, 0, k) for k in range(2)]
    kinds = [spawner.objects[d.kind].name for d in draws]
    assert [s[:2] for s in data["spawned"]] == [[1, kinds[0]], [2, kinds[1]]]
    for k, (_, _, stamp) in enumerate(data["spawned"]):
        assert stamp == pytest.approx(10.0 * (k + 1) + draws[k].delay, abs=0.021)  # the next plant steps
    assert data["links"] == [True, True] and data["crate"] is True


def test_a_spawner_reference_frame_is_a_gazebo_model_or_link(group_cell):
    from omtp_drake.errors import SimulationError
    from omtp_drake.scenario.conveyor_spawner import draw, object_pose
    from omtp_drake.sim.driver import reference_pose

    spawner = dataclasses.replace(group_cell.scenario.spawner, reference_frame="bin_2_")
    runtime = FactoryRuntime(dataclasses.replace(group_cell.scenario, spawner=spawner), auto_spawn=False)
    try:
        X_WR = reference_pose(runtime.station, runtime.context, "bin_2_")
        np.testing.assert_allclose(X_WR.translation(), [-0.1, 2.5, 0.0], atol=1e-9)
        X_WL = reference_pose(runtime.station, runtime.context, "bin_2_::bin_2_drop_point")
        assert X_WL.translation()[2] > X_WR.translation()[2]
        runtime.spawn_part()
        expected = X_WR @ object_pose(spawner, draw(spawner, 0, 0))
        spawned = runtime.pool.events[-1].pose
        np.testing.assert_allclose(spawned.GetAsMatrix4(), expected.GetAsMatrix4(), atol=1e-9)
        with pytest.raises(SimulationError, match="reference frame 'bin_9_' not found"):
            reference_pose(runtime.station, runtime.context, "bin_9_")
    finally:
        runtime.close()


def test_their_worlds_stray_urdf_lines_are_one_warning_each(group_cell):
    """Their world keeps two lines of their URDF work: a ``<xacro:...>`` macro call and a
    ``<joint>`` under ``<world>``. sdformat warns about each ("not defined in SDF") and loads
    the rest: so does the cell, naming the file and the line."""
    world = WORKSPACE / "omtp_gazebo" / "worlds" / "lecture6_assignment1.world"
    lines = world.read_text().splitlines()
    xacro_line = next(i for i, t in enumerate(lines, 1) if "<xacro:omtp_workcell" in t)
    joint_line = next(i for i, t in enumerate(lines, 1) if '<joint name="world_to_workcell"' in t)
    stray = [w for w in group_cell.warnings if "under <world>" in w]
    assert len(stray) == 2, group_cell.warnings
    assert any(f"{world}:{xacro_line}:" in w and "not defined in SDF" in w for w in stray), stray
    assert any(f"{world}:{joint_line}:" in w and "<joint>" in w for w in stray), stray
