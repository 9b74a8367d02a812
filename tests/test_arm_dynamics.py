"""An arm's joint velocity and effort limits, inertia and geometry as the student's URDF writes them
(tests/fixtures/group_ws with a ur_description of their own in its workspace, found before
the project's stand-in, whose UR5 they slowed down and weakened, with a heavier forearm
and flange, and a box for the forearm's visual):

- the scenario's robot 2 carries them, robot 1 (a UR10: only its forearm's visual changed) the
  model's (empty fields);
- the plant's joints and actuators take them (Drake clamps the actuation to the efforts,
  as Gazebo truncates a joint's force to its effort limit);
- the plant's arm and its servo's model have their links' inertia: the arm holds its pose;
- DiffIK's bounds and the planners' timing stay within the velocities, as MoveIt's
  (no joint_limits.yaml) and the course's trajectories do."""

from __future__ import annotations

import dataclasses
import shutil
from pathlib import Path

import numpy as np
import pytest

from omtp_drake.launch import own_cell
from omtp_drake.launch.standins import STANDINS_DIR, standin_dirs

FIXTURES = Path(__file__).resolve().parent / "fixtures"
LAUNCH = "omtp_lecture6 lecture6_assignment1.launch"
SLOW = [1.0, 1.0, 1.2, 1.5, 1.5, 1.5]
WEAK = [100.0, 100.0, 90.0, 20.0, 20.0, 20.0]


@pytest.fixture(scope="module")
def cell(tmp_path_factory):
    src = tmp_path_factory.mktemp("rates_ws") / "src"
    shutil.copytree(FIXTURES / "group_ws" / "src", src)
    own = src / "ur_description"
    shutil.copytree(STANDINS_DIR / "ur_description", own)
    (own / "meshes").symlink_to(standin_dirs()[0] / "ur_description" / "meshes")
    ur5 = own / "urdf" / "ur5.urdf.xacro"
    text = ur5.read_text()
    assert 'efforts="150 150 150 28 28 28" velocities="3.15 3.15 3.15 3.2 3.2 3.2"' in text
    assert 'masses="4.0 3.7 8.393 2.275 1.219 1.219 0.1879"' in text
    ur5.write_text(
        text.replace(
            'efforts="150 150 150 28 28 28" velocities="3.15 3.15 3.15 3.2 3.2 3.2"',
            f'efforts="{" ".join(map(str, WEAK))}" velocities="{" ".join(map(str, SLOW))}"',
        ).replace('masses="4.0 3.7 8.393 2.275 1.219 1.219 0.1879"',
                  'masses="4.0 3.7 8.393 3.5 1.219 1.219 0.5"')
    )
    # Their forearm's visual: a box of their own in place of ur_description's mesh.
    arm = own / "urdf" / "ur_arm.xacro"
    line = ('<xacro:omtp_standin_ur_link name="${prefix}forearm_link" mesh="forearm" '
            'model="${model}" mass="${m[3]}"/>')
    assert line in arm.read_text()
    arm.write_text(arm.read_text().replace(line, FOREARM.replace("{inertial}", _inertial(3))))
    # Their wrist 1: its visual mesh scaled up, its collision wrist 2's mesh file.
    line = ('<xacro:omtp_standin_ur_link name="${prefix}wrist_1_link" mesh="wrist1" '
            'model="${model}" mass="${m[4]}"/>')
    assert line in arm.read_text()
    arm.write_text(arm.read_text().replace(line, WRIST_1.replace("{inertial}", _inertial(4))))
    return own_cell(LAUNCH, workspace=[src], environ={})


def _inertial(i: int) -> str:
    """The inertial the stand-in gives the arm's link ``i`` (its mass ``m[i]``), as written there."""
    return (
        f'<inertial><mass value="${{m[{i}]}}"/><origin xyz="0 0 0" rpy="0 0 0"/>'
        f'<inertia ixx="${{m[{i}] * 0.01}}" ixy="0" ixz="0" iyy="${{m[{i}] * 0.01}}" iyz="0" '
        f'izz="${{m[{i}] * 0.01}}"/>'
        "</inertial>"
    )


FOREARM = """
    <link name="${prefix}forearm_link">
      <visual><origin xyz="0 0 0.2"/><geometry><box size="0.07 0.07 0.4"/></geometry></visual>
      <collision>
        <geometry>
          <mesh filename="package://ur_description/meshes/${model}/collision/forearm.stl"
                scale="1.2 1.2 1.2"/>
        </geometry>
      </collision>
      {inertial}
    </link>"""


def test_their_slower_weaker_arm_is_the_scenarios(cell):
    robot1, robot2 = cell.scenario.robots
    assert (robot1.velocity_limits, robot1.effort_limits) == ([], [])
    assert robot2.velocity_limits == pytest.approx(SLOW)
    assert robot2.effort_limits == pytest.approx(WEAK)
    assert not [w for w in cell.warnings if "limits" in w or "inertial" in w]
    assert robot1.inertials == {}
    assert sorted(robot2.inertials) == ["forearm_link", "wrist_3_link"]
    assert robot2.inertials["forearm_link"] == pytest.approx([3.5, 0, 0, 0, 0.035, 0.035, 0.035, 0, 0, 0])
    assert robot2.inertials["wrist_3_link"][0] == pytest.approx(0.5)


def test_the_plant_diffik_and_the_timing_keep_within_them(cell):
    from omtp_drake.cell import arms
    from omtp_drake.control.joint_plan import diffik_parameters
    from omtp_drake.sim.runtime import FactoryRuntime

    robot1, robot2 = cell.scenario.robots
    runtime = FactoryRuntime(cell.scenario, auto_spawn=False)
    try:
        plant = runtime.station.plant
        for k, joint_name in enumerate(arms.JOINT_NAMES):
            joint = plant.GetJointByName(f"robot2_{joint_name}")
            assert joint.velocity_upper_limits()[0] == pytest.approx(SLOW[k])
            actuator = next(
                plant.get_joint_actuator(i)
                for i in plant.GetJointActuatorIndices()
                if plant.get_joint_actuator(i).joint().index() == joint.index()
            )
            assert actuator.effort_limit() == pytest.approx(WEAK[k])
        context = plant.GetMyContextFromRoot(runtime.context)
        assert plant.GetBodyByName("robot2_forearm_link").get_mass(context) == pytest.approx(3.5)
        assert plant.GetBodyByName("robot1_forearm_link").get_mass(context) != pytest.approx(3.5)
        q0 = plant.GetPositions(context, plant.GetModelInstanceByName("robot2")).copy()
        runtime.advance_to(1.0)
        q1 = plant.GetPositions(context, plant.GetModelInstanceByName("robot2"))
        assert np.abs(q1 - q0).max() < 1e-3, q1 - q0
        pan1 = plant.GetJointByName("robot1_shoulder_pan_joint")
        assert pan1.velocity_upper_limits()[0] == pytest.approx(2.16)
    finally:
        runtime.close()
    lower, upper = diffik_parameters(robot2, 6, 0.01).get_joint_velocity_limits()
    np.testing.assert_allclose(upper, SLOW)
    np.testing.assert_allclose(lower, -np.array(SLOW))
    # The same move, timed within their limits and within the model's: slower, and never
    # faster than half their limit (the trajectory's speed_fraction) on any joint.
    theirs = arms.joint_trajectory(robot2, ["R2Home", "R2Place"], dwell=0.0)
    as_model = dataclasses.replace(robot2, velocity_limits=[])
    model = arms.joint_trajectory(as_model, ["R2Home", "R2Place"], dwell=0.0)
    assert theirs.end_time() > model.end_time() * 1.5
    speeds = np.abs(np.hstack([theirs.EvalDerivative(t) for t in np.linspace(0, theirs.end_time(), 200)]))
    assert np.all(speeds.max(axis=1) <= 0.5 * np.array(SLOW) * (1 + 1e-6))


def test_a_limit_that_is_no_number_above_zero_is_one_warning_and_the_models_are_kept():
    from arm_text import arm_with_limits

    from omtp_drake.launch.arm_dynamics import arm_joint_rates

    model = arm_with_limits(
        lambda k: f'lower="-3.14" upper="3.14" effort="{-5 if k == 2 else 40}" velocity="2"'
    )
    rates, (line,) = arm_joint_rates(model, "r_", "ur5", "spawn.launch:9")
    assert rates == {"velocity_limits": [2.0] * 6}
    assert line.startswith("spawn.launch:9: arm 'r': effort limits shoulder_pan_joint 40, ")
    assert "elbow_joint -5" in line and line.endswith("keeps ur5's 150 150 150 28 28 28")


def test_an_inertial_no_body_can_have_is_one_warning_and_the_models_is_kept():
    from omtp_drake.launch.arm_dynamics import arm_inertials
    from omtp_drake.launch.urdf_model import UrdfModel

    inertial = ('<inertial><mass value="{}"/>'
                '<inertia ixx="{}" iyy="1" izz="1" ixy="0" ixz="0" iyz="0"/></inertial>')
    links = (
        f'<link name="r_forearm_link">{inertial.format(-2, 1)}</link>'
        f'<link name="r_wrist_1_link">{inertial.format(1, 5)}</link>'
        f'<link name="r_wrist_2_link">{inertial.format(2, 1)}</link>'
        '<joint name="a" type="fixed"><parent link="r_forearm_link"/><child link="r_wrist_1_link"/></joint>'
        '<joint name="b" type="fixed"><parent link="r_wrist_1_link"/><child link="r_wrist_2_link"/></joint>'
    )
    model = UrdfModel.from_text(f'<robot name="r">{links}</robot>', "arm.urdf")
    found, lines = arm_inertials(model, "r_", "ur10", "spawn.launch:9")
    assert found == {"inertials": {"wrist_2_link": [2.0, 0, 0, 0, 1.0, 1.0, 1.0, 0, 0, 0]}}
    named = [line.split(": ")[2].split("'s")[0] for line in lines]
    assert named == ["link forearm_link", "link wrist_1_link"]
    assert all(line.endswith("the cell's arm keeps ur10's") for line in lines)


@pytest.mark.parametrize("field, value, message", [
    ("velocity_limits", [1.0] * 5, "robots[robot1].velocity_limits must be 6 finite limits > 0"),
    ("effort_limits", [1.0, 1.0, 0.0, 1.0, 1.0, 1.0], "robots[robot1].effort_limits must be 6 finite"),
    ("inertials", {"elbow_link": [1.0] + [0.0] * 9}, "unknown link in robots[robot1].inertials 'elbow_link'"),
    ("inertials", {"forearm_link": [0.0] * 10}, "robots[robot1].inertials[forearm_link] must be [mass > 0"),
])
def test_a_bad_field_is_one_error_naming_it(field, value, message):
    from omtp_drake.errors import OmtpError
    from omtp_drake.scenario import RobotConfig

    with pytest.raises(OmtpError) as raised:
        RobotConfig(**{field: value}).validate()
    assert message in str(raised.value) and "\n" not in str(raised.value)


WRIST_1 = """
    <link name="${prefix}wrist_1_link">
      <visual>
        <geometry>
          <mesh filename="package://ur_description/meshes/${model}/visual/wrist1.dae" scale="1.5 1.5 1.5"/>
        </geometry>
      </visual>
      <collision>
        <geometry><mesh filename="package://ur_description/meshes/${model}/collision/wrist2.stl"/></geometry>
      </collision>
      {inertial}
    </link>"""


def _hull_extents(shape, unscaled: bool = False) -> np.ndarray:
    """The extents of a mesh shape's convex hull (its file's, without its scale if ``unscaled``)."""
    hull = (type(shape)(str(shape.source().path()), 1.0) if unscaled else shape).GetConvexHull()
    vertices = np.array([hull.vertex(i) for i in range(hull.num_vertices())])
    return vertices.max(0) - vertices.min(0)


def test_their_forearm_visual_replaces_the_models(cell):
    """The box they wrote in place of the forearm's visual mesh is loaded (on the cell's
    forearm), and the cell's arm has no visual of its own there; its collision is the
    course's mesh, kept."""
    from omtp_drake.sim.runtime import FactoryRuntime

    mine = ["forearm_link/visual", "forearm_link/collision", "wrist_1_link/visual", "wrist_1_link/collision"]
    for robot in cell.scenario.robots:
        assert robot.own_geometry == mine
    models = {m.name: m for m in cell.scenario.models}
    own = models["robot2_forearm_link_own"]
    assert own.parent == "robot2_forearm_link"
    runtime = FactoryRuntime(cell.scenario, auto_spawn=False)
    try:
        from pydrake.geometry import Role

        plant, inspector = runtime.station.plant, runtime.station.scene_graph.model_inspector()

        def geometries(body: str, role) -> list:
            frame = plant.GetBodyFrameIdOrThrow(plant.GetBodyByName(body).index())
            return [inspector.GetShape(g) for g in inspector.GetGeometries(frame, role)]

        def shapes(body: str, role) -> list[str]:
            return [shape.__class__.__name__ for shape in geometries(body, role)]

        assert shapes("robot2_forearm_link", Role.kIllustration) == []
        assert shapes("robot2_forearm_link_own", Role.kIllustration) == ["Box"]
        assert shapes("robot2_upper_arm_link", Role.kIllustration) != []
        # Their scaled meshes at their scale, another ur_description file as that file: the
        # cell's arm has none of its own there.
        for link in ("robot2_forearm_link", "robot2_wrist_1_link"):
            assert shapes(link, Role.kIllustration) == shapes(link, Role.kProximity) == []
        (forearm,) = geometries("robot2_forearm_link_own", Role.kProximity)
        np.testing.assert_allclose(_hull_extents(forearm), 1.2 * _hull_extents(forearm, unscaled=True))
        (wrist,) = geometries("robot2_wrist_1_link_own", Role.kIllustration)
        np.testing.assert_allclose(_hull_extents(wrist), 1.5 * _hull_extents(wrist, unscaled=True))
        (theirs,) = geometries("robot2_wrist_1_link_own", Role.kProximity)
        (wrist_2,) = geometries("robot2_wrist_2_link", Role.kProximity)  # the cell's, the course's mesh
        np.testing.assert_allclose(_hull_extents(theirs), _hull_extents(wrist_2), atol=1e-9)
    finally:
        runtime.close()
