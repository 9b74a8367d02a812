"""The classic UR kinematics, the named poses and the position servo."""

import math

import numpy as np
import pytest
from pydrake.systems.analysis import Simulator
from pydrake.systems.framework import DiagramBuilder
from pydrake.systems.primitives import TrajectorySource

from omtp_drake.cell import arms
from omtp_drake.cell.station import build_station
from omtp_drake.errors import ConfigError, UnknownNameError
from omtp_drake.scenario import RobotConfig, load_scenario
from omtp_drake.ur_arms import model_rates

DH = {  # classic UR standard DH: d1, a2, a3, d4, d5, d6
    "ur10": (0.1273, -0.612, -0.5723, 0.163941, 0.1157, 0.0922),
    "ur5": (0.089159, -0.425, -0.39225, 0.10915, 0.09465, 0.0823),
}


def dh_fk(model, q):
    d1, a2, a3, d4, d5, d6 = DH[model]
    a = [0, a2, a3, 0, 0, 0]
    d = [d1, 0, 0, d4, d5, d6]
    alpha = [math.pi / 2, 0, 0, math.pi / 2, -math.pi / 2, 0]
    T = np.eye(4)
    for i in range(6):
        ct, st, ca, sa = math.cos(q[i]), math.sin(q[i]), math.cos(alpha[i]), math.sin(alpha[i])
        T = T @ np.array([[ct, -st * ca, st * sa, a[i] * ct],
                          [st, ct * ca, -ct * sa, a[i] * st],
                          [0, sa, ca, d[i]],
                          [0, 0, 0, 1]])
    return T


@pytest.mark.parametrize("model", ["ur10", "ur5"])
def test_forward_kinematics_matches_classic_dh(model):
    robot = RobotConfig(name="r", model=model, gripper="")
    plant = arms.make_control_plant(robot, [0.0, 0.0, -9.8])
    context = plant.CreateDefaultContext()
    # The DH base frame is ROS's `base` (base_link turned by pi about z); the DH
    # flange is tool0.
    base, tool0 = plant.GetFrameByName("r_base"), plant.GetFrameByName("r_tool0")
    rng = np.random.default_rng(7)
    for _ in range(50):
        q = rng.uniform(-math.pi, math.pi, 6)
        plant.SetPositions(context, q)
        X = tool0.CalcPose(context, base).GetAsMatrix4()
        np.testing.assert_allclose(X, dh_fk(model, q), atol=1e-6)


def test_named_pose_lookup_and_errors():
    r2 = RobotConfig(name="robot2", pose_prefix="R2")
    np.testing.assert_array_equal(arms.named_pose("Place", r2), arms.NAMED_POSES["R2Place"])
    np.testing.assert_array_equal(arms.named_pose("R1Up"), arms.NAMED_POSES["R1Up"])
    with pytest.raises(UnknownNameError, match="PreGrasp"):
        arms.named_pose("Pregrasp", r2)
    # Only robot 2's own poses are valid for robot 2 (and the message lists only them).
    with pytest.raises(UnknownNameError) as e:
        arms.named_pose("R2Pick", r2)
    assert "R2PreGrasp" in str(e.value) and "R1" not in str(e.value)
    with pytest.raises(UnknownNameError):
        arms.named_pose("R1Home", r2)


@pytest.mark.parametrize("q, words", [
    ([0.0] * 5, ["6 numbers", "got 5"]),
    ([0.0, 0.0, float("nan"), 0.0, 0.0, 0.0], ["finite"]),
    ([0.0, 0.0, 4.0, 0.0, 0.0, 0.0], ["elbow_joint", "4.0000", "[-3.1416, 3.1416]"]),
    ("home", ["6 numbers"]),
])
def test_joint_positions_are_checked(q, words):
    with pytest.raises(ConfigError) as e:
        arms.check_joint_positions(q, RobotConfig(name="robot1"))
    for word in words:
        assert word in str(e.value)


def test_servo_model_has_the_scenario_gravity():
    """Issue 10 bug 4: the servo compensates the scenario's gravity, not Drake's default."""
    from omtp_drake.scenario import load_scenario

    scenario = load_scenario("omtp_factory")
    scenario.gravity = [0.0, 0.0, -3.71]  # Mars
    station = build_station(scenario)
    for handles in station.arms.values():
        g = handles.control_plant.gravity_field().gravity_vector()
        np.testing.assert_allclose(np.linalg.norm(g), 3.71)
    context = station.create_context()
    start = _tool_positions(station, context)
    Simulator(station.diagram, context).AdvanceTo(1.0)
    end = _tool_positions(station, context)
    for name in station.arms:
        assert np.linalg.norm(end[name] - start[name]) < 1e-3


def test_joint_trajectory_respects_velocity_limits():
    robot = RobotConfig()
    trajectory = arms.joint_trajectory(robot, ["Home", "Place", "Up"], speed_fraction=0.5)
    t = np.linspace(trajectory.start_time(), trajectory.end_time(), 2000)
    v = np.abs(np.column_stack([trajectory.EvalDerivative(ti, 1) for ti in t]))
    assert np.all(v.max(axis=1) <= 0.5 * np.array(model_rates("ur10")[0]) + 1e-9)
    np.testing.assert_allclose(trajectory.value(trajectory.end_time()).ravel(),
                               arms.NAMED_POSES["R1Up"])
    with pytest.raises(ConfigError):
        arms.joint_trajectory(robot, ["Home"], speed_fraction=0)


def _tool_positions(station, context):
    plant = station.plant
    pc = plant.GetMyContextFromRoot(context)
    return {n: plant.GetFrameByName(f"{n}_tool0").CalcPoseInWorld(pc).translation()
            for n in station.arms}


def test_arms_hold_home_under_gravity(factory):
    context = factory.create_context()
    start = _tool_positions(factory, context)
    simulator = Simulator(factory.diagram, context)
    simulator.AdvanceTo(5.0)
    end = _tool_positions(factory, context)
    for name in factory.arms:
        drift = np.linalg.norm(end[name] - start[name])
        assert drift < 1e-3, f"{name} drifted {drift * 1e3:.3f} mm"


def test_commanded_move_settles():
    """A joint move Home -> Place (the course's named poses) settles within 1 mrad."""
    factory = build_station(load_scenario("omtp_factory"))  # embedded below: not the shared fixture
    builder = DiagramBuilder()
    builder.AddSystem(factory.diagram)
    end = 0.0
    for name, handles in factory.arms.items():
        trajectory = arms.joint_trajectory(handles.config, ["Home", "Place"], dwell=0.0)
        source = builder.AddSystem(TrajectorySource(trajectory))
        builder.Connect(source.get_output_port(), factory.diagram.GetInputPort(f"{name}.position"))
        end = max(end, trajectory.end_time())
    diagram = builder.Build()
    context = diagram.CreateDefaultContext()
    factory.initialize_context(context)
    Simulator(diagram, context).AdvanceTo(end + 1.0)
    pc = factory.plant.GetMyContextFromRoot(context)
    for name, handles in factory.arms.items():
        q = arms.named_pose("Place", handles.config)
        error = np.abs(factory.plant.GetPositions(pc, handles.arm) - q).max()
        assert error < 1e-3, f"{name} off by {error * 1e3:.3f} mrad"
