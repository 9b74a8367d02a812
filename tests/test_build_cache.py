"""What a command's first build reads from the model cache instead of computing again: a
workspace's xacro expansions and Drake's verdict on a world's model folders, each kept by the
content of the files it read and used only while they are unchanged."""

from __future__ import annotations

import shutil
from pathlib import Path

import pytest

from omtp_drake.launch import sdf_world
from omtp_drake.workspace import Workspace, expand_xacro_in, xacro_files

FIXTURES = Path(__file__).parent / "fixtures"


@pytest.fixture(autouse=True)
def own_cache(tmp_path: Path, monkeypatch):
    monkeypatch.setenv("OMTP_DRAKE_CACHE", str(tmp_path / "cache"))


def _next_process(monkeypatch):
    """What a new process lacks: the expansions kept in this one."""
    monkeypatch.setattr(xacro_files, "_EXPANDED", {})


def test_a_new_process_reads_an_expansion_until_an_included_file_changes(tmp_path: Path, monkeypatch):
    import xacro

    src = tmp_path / "ws" / "src" / "cell_description"
    (src / "urdf").mkdir(parents=True)
    (src / "package.xml").write_text(
        '<?xml version="1.0"?><package format="2"><name>cell_description</name>'
        "<version>0.0.1</version></package>"
    )
    (src / "urdf" / "leg.xacro").write_text(
        '<robot xmlns:xacro="http://www.ros.org/wiki/xacro"><xacro:macro name="leg" params="n">'
        '<link name="leg_${n}"/></xacro:macro></robot>'
    )
    top = src / "urdf" / "table.urdf.xacro"
    top.write_text(
        '<robot xmlns:xacro="http://www.ros.org/wiki/xacro" name="table">'
        '<xacro:include filename="$(find cell_description)/urdf/leg.xacro"/>'
        '<xacro:leg n="$(arg first)"/><xacro:leg n="2"/></robot>'
    )
    ws = Workspace.from_dirs([src.parent], environ={})
    first = expand_xacro_in(ws, top, {"first": "1"})
    assert '<link name="leg_1"/>' in first and '<link name="leg_2"/>' in first

    calls: list[tuple] = []
    process_file = xacro.process_file
    monkeypatch.setattr(xacro, "process_file", lambda *a, **k: calls.append(a) or process_file(*a, **k))
    _next_process(monkeypatch)
    assert expand_xacro_in(ws, top, {"first": "1"}) == first and not calls  # read from the cache
    _next_process(monkeypatch)
    assert '<link name="leg_9"/>' in expand_xacro_in(ws, top, {"first": "9"}) and len(calls) == 1

    leg = src / "urdf" / "leg.xacro"
    leg.write_text(leg.read_text().replace('<link name="leg_${n}"/>', '<link name="foot_${n}"/>'))
    _next_process(monkeypatch)
    again = expand_xacro_in(ws, top, {"first": "1"})
    assert '<link name="foot_1"/>' in again and "leg_1" not in again and len(calls) == 2


def test_a_new_process_reads_drakes_verdict_on_a_world_until_a_model_file_changes(
    tmp_path: Path, monkeypatch
):
    shutil.copytree(FIXTURES / "world_ws", tmp_path / "world_ws")
    src = tmp_path / "world_ws" / "src"
    ws = Workspace.from_dirs([src], environ={})
    world = src / "my_cell" / "worlds" / "table_cube.world"
    parses: list[object] = []
    refusal = sdf_world._drake_refusal
    monkeypatch.setattr(sdf_world, "_drake_refusal", lambda *a: parses.append(a) or refusal(*a))

    first = sdf_world.read_world(world, ws)  # the included folders at once, then the inline cube
    assert len(parses) == 2 and any(m.name == "table" for m in first.models)
    again = sdf_world.read_world(world, ws)
    assert len(parses) == 3 and [m.name for m in again.models] == [m.name for m in first.models]

    table = src / "my_cell" / "models" / "work_table" / "model.sdf"
    table.write_text(table.read_text().replace("</model>", "<!-- moved --></model>"))
    sdf_world.read_world(world, ws)
    assert len(parses) == 5  # a file of an included model changed: Drake is asked again
