"""What a student adds *inside* a link of a course piece the cell builds (a second visual and
a second collision in the vacuum gripper's ``base_link``: tests/fixtures/gripper_edits laid
over a copy of tests/fixtures/group_ws) is loaded as written, on the cell's link; the
course's own geometry of the link stays the catalogue's (URDF visuals are unnamed: the
course's files give that link one of each, so the second of each is theirs)."""

from __future__ import annotations

import shutil
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np
import pytest

from omtp_drake.launch import own_cell
from omtp_drake.launch.own_links import inner_additions
from omtp_drake.launch.urdf_model import UrdfModel

FIXTURES = Path(__file__).resolve().parent / "fixtures"
LAUNCH = "omtp_lecture6 lecture6_assignment1.launch"


@pytest.fixture(scope="module")
def cell(tmp_path_factory):
    src = tmp_path_factory.mktemp("gripper_ws") / "src"
    shutil.copytree(FIXTURES / "group_ws" / "src", src)
    shutil.copytree(FIXTURES / "gripper_edits", src, dirs_exist_ok=True)
    return own_cell(LAUNCH, workspace=[src], environ={})


def test_their_led_ring_and_bumper_are_a_model_hung_on_each_gripper(cell):
    models = {m.name: m for m in cell.scenario.models}
    for n in (1, 2):
        own = models[f"vacuum_gripper{n}_base_link_own"]
        assert own.parent == f"vacuum_gripper{n}_base_link"
        (link,) = ET.fromstring(own.description).iter("link")
        assert [v.find("geometry/cylinder").get("radius") for v in link.iter("visual")] == ["0.04"]
        assert [c.find("geometry/box").get("size") for c in link.iter("collision")] == ["0.09 0.09 0.01"]


def test_they_stand_on_the_cells_gripper_where_the_file_puts_them(cell):
    from omtp_drake.sim.runtime import FactoryRuntime

    runtime = FactoryRuntime(cell.scenario, auto_spawn=False)
    try:
        plant = runtime.station.plant
        context = plant.GetMyContextFromRoot(runtime.context)
        for n in (1, 2):
            X_WG = plant.GetBodyByName(f"vacuum_gripper{n}_base_link").EvalPoseInWorld(context)
            X_WO = plant.GetBodyByName(f"vacuum_gripper{n}_base_link_own").EvalPoseInWorld(context)
            np.testing.assert_allclose(X_WO.GetAsMatrix4(), X_WG.GetAsMatrix4(), atol=1e-9)
    finally:
        runtime.close()


def _link(body: str) -> UrdfModel:
    return UrdfModel.from_text(f'<robot name="r"><link name="g">{body}</link></robot>', "g.urdf")


MESH = '<{0}><geometry><mesh filename="package://omtp_support/meshes/vacuum_gripper/{0}/g.dae"/></geometry></{0}>'
BOX = '<{0}><geometry><box size="0.1 0.1 0.1"/></geometry></{0}>'


def test_the_courses_mesh_is_told_apart_by_its_file_wherever_it_stands():
    """Theirs written first, the course's mesh after it: theirs is still theirs."""
    model = _link(BOX.format("visual") + MESH.format("visual") + MESH.format("collision"))
    (extra,) = inner_additions(model, ["g"])["g"]
    assert extra.find("geometry/box") is not None
    # One of each kind: the course's (or its stand-in); nothing of theirs.
    assert inner_additions(_link(BOX.format("visual") + BOX.format("collision")), ["g"]) == {}
