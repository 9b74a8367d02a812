"""A bin is loaded as its file writes it, as Gazebo does: the course's bin (its visual and
two collision meshes, ``bin_bottom.dae`` + ``bin_sides.dae``; the course-layout fixture
``tests/fixtures/catkin_ws``) holds a part dropped in; a bin the student wrote with a
visual only holds nothing (Gazebo's parts fall through it), with one warning line naming
the launch line that spawned it."""

from __future__ import annotations

import shutil
from pathlib import Path

import numpy as np
import pytest
from camera_meshes import without_cameras

from omtp_drake.launch import own_cell

FIXTURES = Path(__file__).resolve().parent / "fixtures"
LAUNCH = "omtp_lecture6 lecture6_assignment1.launch"
#: Where the test's second bin (a visual only) stands, and the parts' half edge.
BIN_2, HALF = (-8.0, -3.2), 0.05


def _visual_only_bin(src: Path) -> Path:
    """The course's bin macro less its collisions, as ``bin_open.xacro``, spawned as bin_2_
    by the static objects' launch; returns that launch file."""
    bin_dir = src / "omtp_support" / "urdf" / "bin"
    text = (bin_dir / "bin.urdf.xacro").read_text()
    start, end = text.index("      <collision>"), text.rindex("</collision>") + len("</collision>\n")
    (bin_dir / "bin_open.urdf.xacro").write_text(
        (text[:start] + text[end:]).replace("bin_urdf", "bin_open_urdf")
    )
    (bin_dir / "bin_open.xacro").write_text(
        (bin_dir / "bin.xacro")
        .read_text()
        .replace("bin.urdf.xacro", "bin_open.urdf.xacro")
        .replace("xacro:bin_urdf", "xacro:bin_open_urdf")
    )
    launch = src / "omtp_gazebo" / "launch" / "spawn_static_world_objects.launch"
    spawn = f"""  <param name="bin_2_description"
         command="$(find xacro)/xacro '$(find omtp_support)/urdf/bin/bin_open.xacro' prefix:=bin_2_"/>
  <node name="bin_2_spawner" pkg="gazebo_ros" type="spawn_model" output="screen"
        args="-x {BIN_2[0]} -y {BIN_2[1]} -urdf -model bin_2_ -param bin_2_description"/>
</launch>"""
    launch.write_text(launch.read_text().replace("</launch>", spawn))
    return launch


@pytest.fixture(scope="module")
def loaded(tmp_path_factory):
    src = tmp_path_factory.mktemp("bins") / "src"
    shutil.copytree(FIXTURES / "catkin_ws" / "src", src)
    launch = _visual_only_bin(src)
    return own_cell(LAUNCH, workspace=[src], environ={}), launch


@pytest.fixture(scope="module")
def runtime(loaded):
    from omtp_drake.sim.runtime import FactoryRuntime

    cell, _ = loaded
    scenario = without_cameras(cell.scenario, spawner=None, part_pool=2, pool_part_size=2 * HALF)
    scenario.task = None
    runtime = FactoryRuntime(scenario, auto_spawn=False)
    yield runtime
    runtime.close()


def test_both_bins_are_loaded_as_written_the_open_one_with_one_warning(loaded):
    cell, launch = loaded
    bins = {b.name: b for b in cell.scenario.bins}
    assert bins["bin_1"].model == "bin_1_" and bins["bin_2"].model == "bin_2_"
    # The course's bin: its collision meshes' inside, the catalogue's numbers (the fixture's
    # meshes are sized so); the open one's inside measured on its visual, the same mesh.
    np.testing.assert_allclose(bins["bin_1"].walls, [0.19, 0.19, 0.12, 0.475], atol=1e-6)
    np.testing.assert_allclose(bins["bin_2"].walls, [0.19, 0.19, 0.12, 0.475], atol=1e-6)
    lines = [w for w in cell.warnings if "collision" in w and "bin" in w]
    assert len(lines) == 1, cell.warnings
    assert lines[0].startswith(f"{launch}:")
    assert "bin 'bin_2': link 'bin_2_base_link' has no <collision>" in lines[0]
    assert "a part dropped in falls through it" in lines[0]


def test_a_part_rests_in_the_courses_bin_and_falls_through_the_open_one(loaded, runtime):
    cell, _ = loaded
    held = runtime.spawn_part(xyz=[-8.0, -2.2, 0.7])
    fell = runtime.spawn_part(xyz=[*BIN_2, 0.7])
    runtime.advance(1.5)
    np.testing.assert_allclose(runtime.part_pose(held).translation(), [-8.0, -2.2, 0.12 + HALF], atol=0.01)
    p = runtime.part_pose(fell).translation()
    np.testing.assert_allclose(p, [*BIN_2, HALF], atol=0.01)  # on the ground plane, under its floor
    assert p[2] < cell.scenario.bin("bin_2").walls[2]
    ledger = runtime.ledger()
    assert ledger.parts[held] == "in_bin:bin_1" and ledger.parts[fell] != "in_bin:bin_2"
