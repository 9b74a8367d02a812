"""The script commander keeps its command in the Context (issue 46): two Contexts of one
diagram each play their own commanded trajectory, to the samples the servo was sent
before (the commanded tool within 1 mm), and rest at their own goals."""

import numpy as np
import pytest
from pydrake.systems.analysis import Simulator
from pydrake.systems.framework import DiagramBuilder

from omtp_drake.cell import arms
from omtp_drake.control.motion import ACCELERATION_LIMITS, time_parameterize
from omtp_drake.scenario import load_scenario
from omtp_drake.script.arm_commander import ArmCommander, JointCommand

h = 0.01  # the arm's command period (command_rate_hz 100)


@pytest.fixture(scope="module")
def rig():
    robot = load_scenario("lecture6_assignment4").robot("robot2")
    builder = DiagramBuilder()
    commander = builder.AddSystem(ArmCommander(robot))
    diagram = builder.Build()
    plant = arms.make_control_plant(robot, (0.0, 0.0, -9.81))
    return robot, commander, diagram, plant


def tip_position(plant, robot, q):
    context = plant.CreateDefaultContext()
    plant.SetPositions(context, q)
    return plant.GetFrameByName(f"{robot.gripper}_tip").CalcPoseInWorld(context).translation()


def rest_to_rest(robot, q0, q1):
    """A joint move as the planners time it (TOPP-RA within the arm's limits)."""
    limits = np.asarray(arms.VELOCITY_LIMITS[robot.model])
    return time_parameterize([q0, q1], 0.5 * limits, np.asarray(ACCELERATION_LIMITS[robot.model]))


def test_two_contexts_of_one_diagram_play_their_own_commands(rig):
    robot, commander, diagram, plant = rig
    sims = [Simulator(diagram, diagram.CreateDefaultContext()) for _ in range(2)]
    contexts = [commander.GetMyMutableContextFromRoot(s.get_mutable_context()) for s in sims]
    q0 = commander.commanded_position(contexts[0])
    goals = [
        q0 + np.array([0.4, -0.3, 0.3, 0.2, -0.2, 0.5]),
        q0 + np.array([-0.3, 0.2, -0.4, 0.0, 0.3, -0.6]),
    ]
    starts = [0.1, 0.137]  # one on the command grid, one between its ticks
    for sim, context, start, goal in zip(sims, contexts, starts, goals):
        sim.AdvanceTo(start)
        commander.command(context, JointCommand(q0, rest_to_rest(robot, q0, goal), start))
    worst = [0.0, 0.0]
    for k in range(1, 70):  # the two Contexts advanced in turns, half-way between ticks
        t = 0.145 + 0.03 * k
        for i, (sim, context) in enumerate(zip(sims, contexts)):
            sim.AdvanceTo(t)
            tick = h * np.floor(t / h)  # the last tick: the servo got the command's sample there
            sample = commander.current(context).at(tick)
            played = commander.commanded_position(context)
            gap = np.linalg.norm(tip_position(plant, robot, played) - tip_position(plant, robot, sample))
            worst[i] = max(worst[i], gap)
    assert max(worst) < 1e-3, worst
    for context, goal in zip(contexts, goals):
        assert np.allclose(commander.commanded_position(context), goal, atol=1e-9)
        assert np.allclose(commander.current(context).at(np.inf), goal)


def test_a_hold_takes_the_position_at_once_and_a_cloned_context_plays_on_alone(rig):
    robot, commander, diagram, _ = rig
    sim = Simulator(diagram, diagram.CreateDefaultContext())
    context = commander.GetMyMutableContextFromRoot(sim.get_mutable_context())
    q0 = commander.commanded_position(context)
    sim.AdvanceTo(0.2)
    commander.command(context, JointCommand(q0, rest_to_rest(robot, q0, q0 + 0.6), 0.2))
    sim.AdvanceTo(0.45)
    twin = Simulator(diagram, sim.get_context().Clone())  # mid-move: the same command goes on
    twin_context = commander.GetMyMutableContextFromRoot(twin.get_mutable_context())
    assert 0.05 < np.max(commander.commanded_position(twin_context) - q0) < 0.55  # on its way
    commander.hold(context, q0 - 0.2)
    assert np.allclose(commander.commanded_position(context), q0 - 0.2)
    sim.AdvanceTo(1.5)
    twin.AdvanceTo(1.5)
    assert np.allclose(commander.commanded_position(context), q0 - 0.2, atol=1e-12)
    assert np.allclose(commander.commanded_position(twin_context), q0 + 0.6, atol=1e-9)
