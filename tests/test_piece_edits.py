"""What a student writes in a course piece the cell builds from its catalogue is not dropped
(tests/fixtures/gripper_edits laid over a copy of tests/fixtures/group_ws, and their robot 2
unlimited as ur_description's ``joint_limited="false"`` makes it):

- a second visual and a second collision in the vacuum gripper's ``base_link`` are loaded as
  written, on the cell's link; the course's own geometry of the link stays the catalogue's
  (URDF visuals are unnamed: the course's files give that link one of each, so the second of
  each is theirs);
- an arm's joint limits are the cell's arm's (symmetric ones; others are one warning)."""

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
    system = src / "omtp_support" / "urdf" / "robot_system" / "robot_system.urdf.xacro"
    text = system.read_text()
    system.write_text(text.replace('<xacro:ur5_robot prefix="${robot_prefix}" joint_limited="true"/>',
                                   '<xacro:ur5_robot prefix="${robot_prefix}" joint_limited="false"/>'))
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
        # Robot 2 unlimited as ur_description makes it (+/- 2 pi, the elbow +/- pi), robot 1
        # the course's +/- pi.
        for robot, joint_name, limit in (
            ("robot1", "shoulder_pan", np.pi),
            ("robot2", "shoulder_pan", 2 * np.pi),
            ("robot2", "elbow", np.pi),
            ("robot2", "wrist_3", 2 * np.pi),
        ):
            joint = plant.GetJointByName(f"{robot}_{joint_name}_joint")
            assert joint.position_upper_limits()[0] == pytest.approx(limit)
            assert joint.position_lower_limits()[0] == pytest.approx(-limit)
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


def test_their_unlimited_arm_is_the_scenarios(cell):
    robot1, robot2 = cell.scenario.robots
    assert robot1.joint_limits == [] and robot1.joint_limit == pytest.approx(np.pi)
    unlimited = [2 * np.pi, 2 * np.pi, np.pi, 2 * np.pi, 2 * np.pi, 2 * np.pi]
    assert robot2.joint_limits == pytest.approx(unlimited)
    assert not [w for w in cell.warnings if "joint limits" in w]


def test_limits_that_are_not_one_symmetric_limit_are_one_warning():
    from arm_text import arm_with_limits

    from omtp_drake.launch.pieces import arm_joint_limit

    model = arm_with_limits(
        lambda k: f'lower="{-1.5 if k == 0 else -3.14}" upper="3.14" effort="1" velocity="1"'
    )
    limits, (line,) = arm_joint_limit(model, "r_", "spawn.launch:9")
    assert limits == {}
    assert line.startswith("spawn.launch:9: arm 'r': joint limits shoulder_pan_joint [-1.5, 3.14], ")
    assert line.endswith("keeps the course's +/-3.14159")


def test_a_collision_in_a_link_the_course_leaves_bare_is_theirs_where_they_put_it(cell):
    """The beam's ``optical_link`` is a bare frame in the course's files: the lens cap they
    wrote in it (a visual and a collision) is loaded, hung on the cell's link, its box 1 cm
    behind the emitter; the beam still senses from where it was."""
    from pydrake.geometry import Box, Role

    from omtp_drake.sim.runtime import FactoryRuntime

    own = {m.name: m for m in cell.scenario.models}["break_beam_optical_link_own"]
    assert own.parent == "break_beam_optical_link"
    (link,) = ET.fromstring(own.description).iter("link")
    assert [c.find("geometry/box").get("size") for c in link.iter("collision")] == ["0.02 0.06 0.06"]
    runtime = FactoryRuntime(cell.scenario, auto_spawn=False)
    try:
        station = runtime.station
        plant, inspector = station.plant, station.scene_graph.model_inspector()
        context = plant.GetMyContextFromRoot(runtime.context)
        X_WO = plant.GetFrameByName("break_beam_optical_link").CalcPoseInWorld(context)
        body = plant.GetBodyByName("break_beam_optical_link_own")
        (geometry,) = inspector.GetGeometries(plant.GetBodyFrameIdOrThrow(body.index()), Role.kProximity)
        shape = inspector.GetShape(geometry)
        assert isinstance(shape, Box) and (shape.width(), shape.depth(), shape.height()) == (0.02, 0.06, 0.06)
        X_WG = body.EvalPoseInWorld(context) @ inspector.GetPoseInFrame(geometry)
        expected = X_WO.GetAsMatrix4() @ np.array([-0.01, 0.0, 0.0, 1.0])
        np.testing.assert_allclose(X_WG.translation(), expected[:3], atol=1e-6)
        np.testing.assert_allclose(station.break_beam.p_WE, X_WO.translation(), atol=1e-6)
    finally:
        runtime.close()


def test_a_collision_added_beside_the_grippers_own_is_theirs(tmp_path):
    """The workspaces' gripper gives its base_link a visual and a collision, as the
    course's file does: one collision more of theirs (a bumper plate, nothing else
    changed) is loaded on the cell's gripper, the course's pair is not."""
    src = tmp_path / "src"
    shutil.copytree(FIXTURES / "group_ws" / "src", src)
    gripper = src / "omtp_support" / "urdf" / "vacuum_gripper" / "vacuum_gripper.urdf.xacro"
    text = gripper.read_text()
    plate = '<collision><origin xyz="0 0 0.05"/><geometry><box size="0.09 0.09 0.01"/></geometry></collision>'
    gripper.write_text(text.replace("      <inertial>", f"      {plate}\n      <inertial>", 1))
    models = {m.name: m for m in own_cell(LAUNCH, workspace=[src], environ={}).scenario.models}
    for n in (1, 2):
        (link,) = ET.fromstring(models[f"vacuum_gripper{n}_base_link_own"].description).iter("link")
        assert [c.find("geometry/box").get("size") for c in link.iter("collision")] == ["0.09 0.09 0.01"]
        assert list(link.iter("visual")) == []


def test_a_gripper_file_with_no_collision_is_loaded_so_and_grasps_nothing(tmp_path):
    """Their gripper's base_link without its collision (its suction_cup has none): the
    course's VacuumGripperPlugin attaches on contacts of its suction cup link's collisions,
    so in Gazebo nothing touches the cup and it grasps nothing. Here: one warning line per
    gripper at its spawn line, the cell's gripper without collisions, and pressed on a part
    with its vacuum on it holds nothing (with them, the same press holds the part)."""
    from pydrake.multibody.parsing import Parser
    from pydrake.multibody.plant import MultibodyPlant
    from suction_rig import PRESS, TOP, build_rig, hold, tool_q

    from omtp_drake.cell.arms import add_arm_models

    src = tmp_path / "src"
    shutil.copytree(FIXTURES / "group_ws" / "src", src)
    gripper = src / "omtp_support" / "urdf" / "vacuum_gripper" / "vacuum_gripper.urdf.xacro"
    text = gripper.read_text()
    start, end = text.index("      <!-- Its collision"), text.index("</collision>") + len("</collision>\n")
    gripper.write_text(text[:start] + text[end:])
    cell = own_cell(LAUNCH, workspace=[src], environ={})
    lines = [w for w in cell.warnings if "no <collision>" in w]
    assert [line.split(": ", 1)[0].rsplit(":", 1)[0] for line in lines] == [
        str(src / "omtp_gazebo" / "launch" / "spawn_robots.launch")
    ] * 2, lines
    assert "vacuum_gripper1_suction_cup" in lines[0] and "grasps nothing" in lines[0]
    robot = cell.scenario.robots[0]
    assert not robot.gripper_collision
    plant = MultibodyPlant(0.01)
    _, instance = add_arm_models(Parser(plant), robot)
    bodies = [plant.get_body(b) for b in plant.GetBodyIndices(instance)]
    assert bodies and not any(plant.GetCollisionGeometriesForBody(b) for b in bodies)
    for collision, held in ((True, True), (False, False)):
        rig = build_rig("weld", hold(tool_q(0.0, 0, TOP - PRESS)), log=False, collision=collision)
        rig.command(True)
        rig.advance_to(0.3)
        assert rig.state().attached is held, collision


def test_the_planner_takes_their_bumper_for_the_grippers_geometry(cell):
    """Their bumper (a box in the gripper's link) is robot geometry to the planner, as a
    link's collisions are to MoveIt: a 1 cm block touching only its corner at robot 1's
    start is a collision named after it (as environment, the checker would never test it)."""
    from pydrake.geometry import Role
    from pydrake.math import RigidTransform

    from omtp_drake.control.motion.collision import CollisionModel

    model = CollisionModel(cell.scenario, "robot1", margin=0.0, edge_step=0.05, self_collisions=False)
    plant, checker = model.checker.plant(), model.checker
    bumper = plant.GetBodyByName("vacuum_gripper1_base_link_own")
    assert checker.IsPartOfRobot(bumper)
    full = model.full(model.q_initial)
    plant_context = checker.UpdatePositions(full)  # (the checker's plant's context)
    inspector = checker.model().scene_graph().model_inspector()
    (box,) = inspector.GetGeometries(plant.GetBodyFrameIdOrThrow(bumper.index()), Role.kProximity)
    X_WB = bumper.EvalPoseInWorld(plant_context) @ inspector.GetPoseInFrame(box)
    p_WO = X_WB @ np.array([0.045 + 0.004, 0.045 + 0.004, 0.0])  # outside the box's corner by 4 mm
    assert model.config_free(full)
    model.scene.set_obstacles([(RigidTransform(p_WO), 0.01)], ["block"])  # reaches 1 mm into it
    assert not model.config_free(full)
    assert model.pairs(full) == [("vacuum_gripper1_base_link_own", "block")]
