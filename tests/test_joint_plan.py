"""Joint plans integrated ahead (issue 46): the B-spline a decided tool path becomes,
the C++ stream that plays it, and plans that live in the Context."""

import numpy as np
from pydrake.systems.analysis import Simulator

from omtp_drake.control.joint_plan import JointPlan, jerk_dynamics
from omtp_drake.control.pick_and_place import Mode
from omtp_drake.control.pick_and_place.controller_state import ControlState
from omtp_drake.tasks.run import TaskRun, prepare

H, h = 0.05, 0.01


def cubic(t):
    return np.column_stack([0.3 + 0.5 * t - 0.2 * t**2 + 0.1 * t**3, -1.0 + 0.05 * t**3])


def test_a_plan_starts_where_the_command_is_goes_through_the_knots_and_ends_at_rest():
    t0 = 0.01
    times = t0 + H * np.arange(1, 21)
    knots = cubic(times)
    q0, v0, a0 = cubic(np.array([t0]))[0], np.array([0.4, 0.0]), np.array([0.0, 0.3])
    plan = JointPlan.through(t0, H, np.concatenate([q0, v0, a0]), knots)
    assert np.allclose(plan.state(t0), np.concatenate([q0, v0, a0]), atol=1e-12)
    # The quasi-interpolant reproduces a cubic: exact at the knots away from the start
    # (which blends from the given state) and the end (where the plan comes to rest).
    for t, k in zip(times[2:-2], knots[2:-2]):
        assert np.allclose(plan.state(t)[:2], k, atol=1e-12)
    assert plan.end_time == t0 + (len(knots) + 2) * H
    assert np.allclose(plan.state(plan.end_time + 1.0), np.concatenate([knots[-1], np.zeros(4)]), atol=1e-12)
    assert not plan.jerk(plan.end_time).any()
    trajectory = plan.trajectory()  # the same plan as a PiecewisePolynomial
    for t in np.linspace(t0, plan.end_time, 57):
        assert np.allclose(trajectory.value(t).ravel(), plan.state(t)[:2], atol=1e-12)


def test_the_jerk_of_each_piece_integrated_at_the_stream_step_is_the_plan():
    plan = JointPlan.through(0.0, H, np.array([0.1, 0.0, 0.5, 0.0, 0.0, 1.0]), cubic(H * np.arange(1, 11)))
    A, B = jerk_dynamics(2, h)
    x = plan.state(0.0)
    for k in range(int(round((plan.end_time + 0.2) / h))):
        x = A @ x + B @ plan.jerk(k * h)
        assert np.allclose(x, plan.state((k + 1) * h), atol=1e-10)


def test_two_contexts_of_one_diagram_play_their_own_plans():
    """The plan is the controller's abstract state: each Context plays its own."""
    run = TaskRun(prepare("lecture6_assignment4", parts=1))
    rt, controller = run.runtime, run.controller
    diagram = rt.simulator.get_system()
    q0 = rt.joint_positions("robot2")
    plans, simulators = [], []
    for dq in (0.2, -0.3):
        context = diagram.CreateDefaultContext()
        free = [rt.station.diagram.GetInputPort(name) for name in sorted(rt._free_inputs)]
        rt.station.initialize_context(context, hold=free)
        own = controller.GetMyMutableContextFromRoot(context)
        plan = JointPlan.through(0.01, H, np.concatenate([q0, np.zeros(12)]), np.tile(q0 + dq, (4, 1)))
        own.SetAbstractState(0, ControlState(mode=Mode.BIN_FULL))  # the machine decides nothing
        own.SetAbstractState(2, plan)
        plans.append(plan)
        simulators.append(Simulator(diagram, context))
    for simulator in simulators:
        simulator.AdvanceTo(0.6)
    for plan, simulator in zip(plans, simulators):
        context = simulator.get_context()
        assert controller.joint_plan_output_port().Eval(controller.GetMyContextFromRoot(context)) is plan
        q = rt.station.plant.GetPositions(
            rt.station.plant.GetMyContextFromRoot(context), rt.station.arm("robot2").arm
        )
        assert np.allclose(q, plan.state(0.6)[:6], atol=2e-3)  # the arm got there
    run.close()
