"""A belt, break beam and deletion wall the student moved stand where their files put them,
with their plugin's behaviour there: the turned belt carries parts along its new axis, the
moved beam stops them where it now stands, the moved wall deletes where it stands. The
course's workspace (``tests/fixtures/catkin_ws``) with the student's edits made here."""

from __future__ import annotations

import dataclasses
import math
import shutil
from pathlib import Path

import numpy as np
import pytest
from camera_meshes import without_cameras

from omtp_drake.launch import own_cell
from omtp_drake.sim.runtime import FactoryRuntime

FIXTURES = Path(__file__).resolve().parent / "fixtures"
LAUNCH = "omtp_lecture6 lecture6_assignment1.launch"
REST_Z = 0.92 + 0.1 + 0.001  # belt top + half a part + the 1 mm corner spheres


def _edit(path: Path, old: str, new: str) -> None:
    text = path.read_text()
    assert old in text
    path.write_text(text.replace(old, new))


def _cell(tmp_path: Path, edits: list[tuple[str, str, str]]):
    src = tmp_path / "src"
    shutil.copytree(FIXTURES / "catkin_ws" / "src", src)
    for file, old, new in edits:
        _edit(src / file, old, new)
    return own_cell(LAUNCH, workspace=[src], environ={})


def _runtime(cell, **changes):
    scenario = without_cameras(cell.scenario, spawner=None, part_pool=2, **changes)
    scenario.task = None
    return FactoryRuntime(scenario)


WORLD = "omtp_gazebo/worlds/lecture6_assignment1.world"


def test_the_course_files_keep_the_course_poses(tmp_path):
    """And the course's 1 m wall is the cell's own box: a part dropped on the line of its
    top 0.8 m off the belt's axis falls past it (test_their_wider_wall_... widens it)."""
    cell = own_cell(LAUNCH, workspace=[FIXTURES / "catkin_ws" / "src"], environ={})
    conveyor = cell.scenario.conveyor
    assert conveyor is not None and conveyor.xyz == [1.2, 0.0, 0.0] and conveyor.yaw == 0.0
    assert cell.scenario.break_beam_pose == [] and cell.scenario.deletion_wall_pose == []
    _drop_on_the_wall(cell, disposed=0)


def test_a_turned_belt_carries_parts_along_its_axis_to_the_moved_wall(tmp_path):
    # The student turned the conveyor a quarter (its upstream end now at x = -3.8, running
    # toward +x) and put the deletion wall at its new downstream end.
    cell = _cell(
        tmp_path,
        [
            (WORLD, "<pose>1.2 5 0 0 0 -1.5708</pose>", "<pose>-3.8 0 0 0 0 0</pose>"),
            (WORLD, "<pose>1.2 -5.1 1.425 0 0 1.5708</pose>", "<pose>6.3 0 1.425 0 0 0</pose>"),
        ],
    )
    conveyor = cell.scenario.conveyor
    assert conveyor.xyz == pytest.approx([1.2, 0.0, 0.0]) and conveyor.yaw == pytest.approx(math.pi / 2)
    assert cell.scenario.deletion_wall_pose == pytest.approx([6.3, 0.0, 1.425, 0.0, 0.0, 0.0])
    rt = _runtime(cell)
    riding = rt.spawn_part(xyz=[5.2, 0.0, REST_Z])
    rt.advance(0.5)
    rt.set_conveyor_power(100)
    rt.advance(1.0)
    p = rt.part_pose(riding).translation()
    assert p[0] == pytest.approx(5.2 + 0.2 * 1.0, abs=0.02)  # along +x, the belt's new axis
    assert abs(p[1]) < 1e-3 and p[2] == pytest.approx(REST_Z, abs=2e-3)
    rt.advance(5.0)  # at the wall (its face at x = 6.25) after 4.25 s more, deleted by its 5 Hz check
    assert riding not in rt.parts_in_world()
    assert rt.ledger().disposed == 1 and rt.ledger().balanced


def test_a_moved_break_beam_stops_the_belt_where_it_now_stands(tmp_path):
    # The break beam spawned 2.9 m further down the belt (spawn_model -y -2.9).
    cell = _cell(
        tmp_path,
        [
            (
                "omtp_gazebo/launch/spawn_static_world_objects.launch",
                'args="-urdf -model $(arg break_beam)',
                'args="-y -2.9 -urdf -model $(arg break_beam)',
            )
        ],
    )
    assert cell.scenario.break_beam_pose == pytest.approx([1.6, -1.0, 0.925, 0.0, 0.0, math.pi], abs=1e-6)
    rt = _runtime(cell, conveyor=dataclasses.replace(cell.scenario.conveyor, stop_on_beam=True))
    beam = rt.station.break_beam
    np.testing.assert_allclose(beam.p_WE, [1.575, -1.0, 0.925], atol=1e-9)
    part = rt.spawn_part(xyz=[1.2, -0.3, REST_Z])
    rt.advance(0.5)
    rt.set_conveyor_power(100)
    rt.advance(4.0)  # its front edge (y - 0.1) reaches the beam at y = -1.0 after 3 s
    assert rt.conveyor_power() == 0.0 and rt.break_beam()[0]
    # Stopped at the beam: its front edge past y = -1.0 by at most the travel of the beam's
    # and the stop helper's 10 Hz checks (2 x 2 cm) and the stop; not at the course's beam.
    assert -1.0 - 0.06 <= rt.part_pose(part).translation()[1] - 0.1 <= -1.0


WALL = "omtp_gazebo/models/deletion_wall/model.sdf"


def _drop_on_the_wall(cell, disposed: int) -> None:
    """A part dropped 1 cm onto the deletion wall's top, 0.8 m along it from its middle:
    ``disposed`` (1) or falling past it (0)."""
    assert cell.scenario.deletion_wall
    assert cell.scenario.deletion_wall_model == ("deletion_wall" if disposed else "")
    assert not [w for w in cell.warnings if "sensing_link" in w], cell.warnings
    rt = _runtime(cell)
    try:
        assert rt.station.plant.HasBodyNamed("deletion_wall") == (not disposed)
        # The wall across the belt's end (0.1 m thick along y, its top at z 1.925): a part
        # dropped 1 cm onto its top, 0.8 m along it from its middle (x 1.2).
        part = rt.spawn_part(xyz=[2.0, -5.1, 1.925 + 0.1 + 0.01])
        rt.advance(0.5)
        assert (part not in rt.parts_in_world()) == bool(disposed)
        assert rt.ledger().disposed == disposed
    finally:
        rt.close()


def test_their_wider_wall_is_loaded_as_written_and_disposes_where_it_reaches(tmp_path):
    """The student widened the wall's collision to 2 m: the wall is their model as written
    (the cell's 1 m box is not built) and a part dropped on its top 0.8 m off the belt's
    axis is disposed of; with the course's 1 m wall the same part falls past it (in
    test_the_course_files_keep_the_course_poses, on the unedited workspace)."""
    cell = _cell(tmp_path, [(WALL, "<size>0.1 1 1</size>", "<size>0.1 2 1</size>")])
    _drop_on_the_wall(cell, disposed=1)


CONVEYOR = "omtp_gazebo/models/conveyor/model.sdf"


def test_their_shorter_wider_belt_carries_parts_to_its_own_end(tmp_path):
    """The student's belt is 4 m long (from the course's upstream end, world y 5 ... 1) and
    1 m wide: the cell's belt is theirs, as the world writes it, and the conveyor plugin
    moves its parts there: a part 0.35 m off the centre line rests on it (beyond the
    course's belt and frame, 0.3 and 0.35 m), one riding it goes along its axis and falls
    off where it ends, onto the floor (on the course's 10 m belt it would still ride)."""
    cell = _cell(
        tmp_path,
        [
            (CONVEYOR, "<size>10 0.6 0.01</size>", "<size>4 1.0 0.01</size>"),
            (CONVEYOR, "<pose>5 0 -0.005 0 0 0</pose>", "<pose>2 0 -0.005 0 0 0</pose>"),
        ],
    )
    assert not [w for w in cell.warnings if "belt_collision" in w], cell.warnings
    conveyor = cell.scenario.conveyor
    assert conveyor.belt_size == pytest.approx([4.0, 1.0])
    assert conveyor.xyz == pytest.approx([1.2, 3.0, 0.0], abs=1e-3)
    rt = _runtime(cell)
    belt = rt.station.belt
    assert (belt.half_length, belt.half_width) == pytest.approx((2.0, 0.5))
    riding = rt.spawn_part(xyz=[1.2, 1.6, REST_Z])
    wide = rt.spawn_part(xyz=[1.2 + 0.35, 3.0, REST_Z])
    rt.advance(0.5)
    assert rt.part_pose(wide).translation()[2] == pytest.approx(REST_Z, abs=2e-3)  # on their wider belt
    rt.set_conveyor_power(100)
    rt.advance(1.0)
    p = rt.part_pose(riding).translation()
    assert p[1] == pytest.approx(1.6 - 0.2, abs=0.02) and p[2] == pytest.approx(REST_Z, abs=2e-3)
    assert abs(p[0] - 1.2) < 1e-3  # along the belt's axis
    rt.advance(5.0)
    p = rt.part_pose(riding).translation()
    assert 0.3 < p[1] < 1.0 and p[2] < 0.15, p  # off its end (y 1.0), on the floor
    assert rt.part_pose(wide).translation()[2] == pytest.approx(REST_Z, abs=2e-3)


@pytest.mark.parametrize("size", [[0.1, 0.6], [10.0, 0.0], [10.0], [float("nan"), 0.6]])
def test_a_belt_size_out_of_reach_is_one_error_naming_it(size):
    from omtp_drake.errors import ConfigError
    from omtp_drake.scenario import ConveyorConfig

    with pytest.raises(ConfigError, match=r"conveyor\.belt_size"):
        ConveyorConfig(belt_size=size).validate()


LEDGE = """      <collision name="ledge">
        <pose>0 0.85 0.55 0 0 0</pose>
        <geometry><box><size>0.4 0.3 0.1</size></box></geometry>
      </collision>
      <sensor name="disposal_contact\""""


def test_only_the_collision_their_walls_contact_sensor_watches_disposes(tmp_path):
    """Their wall, widened to 1.2 m, with a ledge beside it (a second collision): Gazebo's
    disposal plugin acts on the contacts of the one collision its contact sensor watches
    (``collision``), so a part resting on the ledge stays; one dropped on the wall goes."""
    wider = (WALL, "<size>0.1 1 1</size>", "<size>0.1 1.2 1</size>")
    cell = _cell(tmp_path, [wider, (WALL, '      <sensor name="disposal_contact"', LEDGE)])
    assert cell.scenario.deletion_wall_model == "deletion_wall"
    assert cell.scenario.deletion_wall_collision == "sensing_link::collision"
    rt = _runtime(cell)
    try:
        # The wall turned a quarter: its y is the world's -x; the ledge's top at z 2.025.
        on_ledge = rt.spawn_part(xyz=[1.2 - 0.85, -5.1, 2.025 + 0.1 + 0.01])
        on_wall = rt.spawn_part(xyz=[1.2, -5.1, 1.925 + 0.1 + 0.01])
        rt.advance(1.0)
        assert on_wall not in rt.parts_in_world() and rt.ledger().disposed == 1
        p = rt.part_pose(on_ledge).translation()
        np.testing.assert_allclose(p, [0.35, -5.1, 2.025 + 0.1], atol=0.01)
    finally:
        rt.close()


def test_a_disposal_sensor_that_is_not_there_is_one_error_one_watching_two_a_warning(tmp_path):
    from omtp_drake.errors import WorkspaceError

    renamed = (WALL, "<contact_sensor_name>disposal_contact<", "<contact_sensor_name>wall_contact<")
    expected = r"<contact_sensor_name> 'wall_contact': no contact sensor .*valid: disposal_contact"
    with pytest.raises(WorkspaceError, match=expected) as e:
        _cell(tmp_path / "a", [renamed])
    assert "deletion_wall/model.sdf" in str(e.value) and "\n" not in str(e.value)
    two = (WALL, "<contact><collision>collision</collision></contact>",
           "<contact><collision>collision</collision><collision>collision</collision></contact>")
    cell = _cell(tmp_path / "b", [two])
    assert not cell.scenario.deletion_wall and cell.scenario.deletion_wall_model == "deletion_wall"
    (line,) = [w for w in cell.warnings if "ObjectDisposalPlugin" in w]
    assert "watches no single collision" in line and "disposes of nothing" in line
