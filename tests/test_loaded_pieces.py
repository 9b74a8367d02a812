"""The belt, the spawner's resting point, the break beam and the spawner's mesh parts as a
student's files load them (issue 43): a tilted belt carries its parts along its slope; the
spawner's stand-in parts rest on the belt where it was moved to; a moved beam's Gazebo model
is where its spawn put it; a mesh part of its own size is counted in the bin it lies in.
The course's workspace (``tests/fixtures/catkin_ws``) with the student's edits made here."""

from __future__ import annotations

import dataclasses
import shutil
from pathlib import Path

import numpy as np
import pytest
from camera_meshes import without_cameras

from omtp_drake.cell.gazebo_camera import GazeboCameraView
from omtp_drake.cell.gazebo_models import gazebo_models
from omtp_drake.launch import own_cell
from omtp_drake.scenario import BinConfig, Scenario, SpawnerConfig
from omtp_drake.scenario.conveyor_spawner import SpawnObjectConfig
from omtp_drake.sim.runtime import FactoryRuntime

FIXTURES = Path(__file__).resolve().parent / "fixtures"
LAUNCH = "omtp_lecture6 lecture6_assignment1.launch"
WORLD = "omtp_gazebo/worlds/lecture6_assignment1.world"
OBJECTS = "omtp_gazebo/config/conveyor_objects.yaml"
COURSE_BELT = "<pose>1.2 5 0 0 0 -1.5708</pose>"


def _cell(tmp_path: Path, edits: list[tuple[str, str, str]]):
    src = tmp_path / "src"
    shutil.copytree(FIXTURES / "catkin_ws" / "src", src)
    for file, old, new in edits:
        text = (src / file).read_text()
        assert old in text
        (src / file).write_text(text.replace(old, new))
    return own_cell(LAUNCH, workspace=[src], environ={})


def _runtime(cell, **changes) -> FactoryRuntime:
    scenario = without_cameras(cell.scenario, part_pool=2, **changes)
    scenario.task = None
    return FactoryRuntime(scenario, auto_spawn=False)


def _ride(rt: FactoryRuntime, seconds: float) -> tuple[np.ndarray, np.ndarray]:
    """Spawns the spawner's part, lets it settle, runs the belt at full power for
    ``seconds``: the part's centre before and after."""
    part = rt.spawn_part()
    rt.advance(0.5)
    before = rt.part_pose(part).translation().copy()
    rt.set_conveyor_power(100)
    rt.advance(seconds)
    assert rt.ledger().parts[part] == "on_belt"
    return before, rt.part_pose(part).translation()


def test_a_tilted_belt_carries_the_spawned_parts_along_its_slope(tmp_path):
    # The student raised the conveyor 0.25 m, pitched it 0.05 rad (about the model's y: its
    # downstream end lower) and rolled it 0.04 rad (about the way it runs); the spawner's
    # box (a stand-in: no package has its mesh) starts on the tilted belt.
    cell = _cell(
        tmp_path,
        [
            (WORLD, COURSE_BELT, "<pose>1.2 5 0.25 0.04 0.05 -1.5708</pose>"),
            (OBJECTS, "position: [1.2, 1.8, 1.0]", "position: [1.2, 1.8, 1.05]"),
        ],
    )
    conveyor = cell.scenario.conveyor
    assert (conveyor.roll, conveyor.pitch) != (0.0, 0.0)
    rt = _runtime(cell)
    try:
        belt = rt.station.belt
        # The belt runs toward -y, 0.05 rad downhill; its top leans 0.04 rad sideways.
        np.testing.assert_allclose(belt.direction, [0.0, -np.cos(0.05), -np.sin(0.05)], atol=2e-3)
        assert abs(belt.normal[0]) == pytest.approx(np.sin(0.04), abs=2e-3)
        start = np.array(cell.scenario.spawner.objects[0].xyz)
        # A level box's lowest corner 1 mm over the tilted top: its reach along the normal.
        reach = 0.1 * np.abs(belt.normal).sum()
        assert belt.height(start) == pytest.approx(reach + 0.001, abs=1e-6)
        before, after = _ride(rt, 2.0)
        assert belt.height(before) == pytest.approx(0.101, abs=2e-3)  # settled flat on the slope
        travel = after - before
        # Along the belt's tilted axis at 0.2 m/s, within 2 cm; nothing sideways or off the top.
        assert travel @ belt.direction == pytest.approx(0.4, abs=0.02)
        assert np.linalg.norm(travel - (travel @ belt.direction) * belt.direction) < 5e-3
        assert after[2] < before[2] - 0.015  # downhill: 0.4 m x sin(0.05) = 2 cm lower
    finally:
        rt.close()


SPAWNS = "omtp_gazebo/launch/spawn_static_world_objects.launch"
COURSE_BELT_INCLUDE = f"""    <include>
      <uri>model://conveyor</uri>
      {COURSE_BELT}
    </include>
"""


def test_a_belt_tilted_by_spawn_model_carries_its_parts_along_its_slope(tmp_path):
    # The same tilt given the launch way: the student took the conveyor out of the world
    # and spawns it from their launch with spawn_model -x -y -z -R -P -Y.
    spawn = (
        '  <node name="conveyor_spawner" pkg="gazebo_ros" type="spawn_model" output="screen"\n'
        '        args="-sdf -model conveyor -file $(find omtp_gazebo)/models/conveyor/model.sdf\n'
        '              -x 1.2 -y 5 -z 0.25 -R 0.04 -P 0.05 -Y -1.5708"/>\n</launch>'
    )
    cell = _cell(
        tmp_path,
        [
            (WORLD, COURSE_BELT_INCLUDE, ""),
            (SPAWNS, "</launch>", spawn),
            (OBJECTS, "position: [1.2, 1.8, 1.0]", "position: [1.2, 1.8, 1.05]"),
        ],
    )
    rt = _runtime(cell)
    try:
        belt = rt.station.belt  # as the world case: 0.05 rad downhill toward -y, 0.04 sideways
        np.testing.assert_allclose(belt.direction, [0.0, -np.cos(0.05), -np.sin(0.05)], atol=2e-3)
        assert abs(belt.normal[0]) == pytest.approx(np.sin(0.04), abs=2e-3)
        before, after = _ride(rt, 2.0)
        assert belt.height(before) == pytest.approx(0.101, abs=2e-3)
        travel = after - before
        assert travel @ belt.direction == pytest.approx(0.4, abs=0.02)
        assert np.linalg.norm(travel - (travel @ belt.direction) * belt.direction) < 5e-3
        assert after[2] < before[2] - 0.015
    finally:
        rt.close()


def test_the_spawners_parts_rest_on_the_belt_where_the_student_moved_it(tmp_path):
    # The conveyor moved 0.8 m along x and raised 0.3 m; the spawner's point moved with it.
    cell = _cell(
        tmp_path,
        [
            (WORLD, COURSE_BELT, "<pose>2.0 5 0.3 0 0 -1.5708</pose>"),
            (OBJECTS, "position: [1.2, 1.8, 1.0]", "position: [2.0, 1.8, 1.3]"),
        ],
    )
    assert cell.scenario.conveyor.xyz == pytest.approx([2.0, 0.0, 0.3], abs=1e-3)
    # On the raised belt (top 1.22), not on the course's (1.021, inside the moved belt).
    assert cell.scenario.spawner.objects[0].xyz == pytest.approx([2.0, 1.8, 1.22 + 0.1 + 0.001])
    rt = _runtime(cell)
    try:
        before, after = _ride(rt, 1.0)
        np.testing.assert_allclose(before, [2.0, 1.8, 1.321], atol=2e-3)
        np.testing.assert_allclose(after, [2.0, 1.8 - 0.2, 1.321], atol=0.02)
    finally:
        rt.close()


def test_a_moved_beams_gazebo_model_is_where_its_spawn_put_it(tmp_path):
    # The beam spawned 2.9 m down the belt, a logical camera above it.
    cell = _cell(
        tmp_path,
        [
            (
                "omtp_gazebo/launch/spawn_static_world_objects.launch",
                'args="-urdf -model $(arg break_beam)',
                'args="-y -2.9 -urdf -model $(arg break_beam)',
            ),
            (WORLD, "<pose>1.2 1.8 2.0 0 1.5708 0</pose>", "<pose>1.4 -1.0 1.6 0 1.5708 0</pose>"),
        ],
    )
    scenario = dataclasses.replace(cell.scenario, part_pool=1)
    scenario.task = None
    rt = FactoryRuntime(scenario, auto_spawn=False)
    try:
        (beam,) = [m for m in gazebo_models(rt.station.plant, scenario) if m.name == "break_beam_"]
        np.testing.assert_allclose(beam.X_WM.translation(), [0.0, -2.9, 0.0], atol=1e-9)
        rt.advance(0.2)
        # The course's logical camera plugin's model list (the ROS image) names the beam
        # at its model's origin.
        image = GazeboCameraView(rt.station, "logical_camera_1").image(rt.context)
        (seen,) = [m for m in image.models if m.name == "break_beam_"]
        np.testing.assert_allclose((image.X_WC @ seen.X_CM).translation(), [0.0, -2.9, 0.0], atol=1e-6)
    finally:
        rt.close()


def _bar_mesh(path: Path) -> Path:
    """A 0.36 x 0.12 x 0.08 m bar whose origin is 0.35 m from its middle (as a CAD export
    may have it), as the spawner's ``.stl``."""
    import trimesh

    bar = trimesh.creation.box(extents=[0.36, 0.12, 0.08])
    bar.apply_translation([0.35, 0.0, 0.04])
    bar.export(path)
    return path


def test_a_mesh_part_of_its_own_size_is_counted_in_its_bin(tmp_path):
    mesh = _bar_mesh(tmp_path / "bar.stl")
    bar = SpawnObjectConfig(name="bar", mesh_file=str(mesh), xyz=[0.0, 0.0, 0.5])
    scenario = Scenario(
        name="bar_in_bin",
        bins=[BinConfig(name="bin_1", xyz=[0.0, 0.0, 0.0])],
        part_pool=1,
        spawner=SpawnerConfig(objects=[bar]),
    )
    assert scenario.part_size("object_1") == pytest.approx(0.36)
    centre, half = scenario.part_box("object_1")
    np.testing.assert_allclose(centre, [0.35, 0.0, 0.04], atol=1e-9)
    np.testing.assert_allclose(half, [0.18, 0.06, 0.04], atol=1e-9)
    rt = FactoryRuntime(scenario, auto_spawn=False)
    try:
        # Its origin 0.35 m off the bin's middle, outside its walls; the bar itself inside.
        part = rt.spawn_part(xyz=[-0.35, 0.0, 0.2], yaw=0.0)
        rt.advance(1.0)
        p = rt.part_pose(part).translation()
        assert p[2] < 0.2 and abs(p[0] + 0.35) < 0.02  # it fell into the bin and lies there
        ledger = rt.ledger()
        assert ledger.in_bin == {"bin_1": 1} and ledger.parts[part] == "in_bin:bin_1"
        assert ledger.balanced
    finally:
        rt.close()
