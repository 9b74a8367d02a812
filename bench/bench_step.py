"""The plant's time step against suction outcomes (issue 20: 5, 8 or 10 ms?).

Scene (tests/suction_rig.py, the rig the suction tests use): a world floor,
0.2 m cube parts, a tool on stiff SAP-PD joints carrying the course's vacuum
gripper, SAP point contact; only the plant's step changes between rows. A driver
loop advances in 50 ms ticks and calls ``sync_weld`` after each, as the runtime does.
Per step and suction backend (weld, force):

- carry: the 1 kg part of ``test_holds_a_1kg_part_through_a_fast_move_then_releases``
  (``pick_motion``: lift 0.3 m, carry 0.6 m, turn, carry back, at 1 m/s with
  20 m/s^2 ramps). Drift = the part's pose in the cup frame against the X_CP
  captured at attach, worst over every logged step from the lift's start to 0.2 s
  after the tool stops: position [mm] and angle [deg]. "held" = still attached at
  the end. v peak = the cup's fastest step (displacement / step) [m/s].
- contact: the cup pressed PRESS (2 mm) into the centre of a 0.2 kg part, suction
  off for 0.3 s, then on (as ``test_attach_does_not_snap_an_offset_yawed_part``,
  centred, no yaw). t attach = from the command to the attach (the check for
  force, the tick's sync for weld) [s]; pts = cup-part contact points per plant
  step while pressing before the attach (min-max); pen. = the cup face's depth
  below the part's nominal top, TOP - z of the cup face (the cup body's origin is
  its face: tool0 + CUP_OFFSET), worst while pressing before the attach [mm];
  into part = the same against the part's actual top (its centre + SIZE / 2: the
  part also sinks into the floor under the press) [mm];
  snap = the part's displacement across the first step after the attach [mm];
  jump = its worst per-step displacement within +-0.1 s of the attach [mm].
- cpu: CPU time (time.process_time) per simulated second over both runs'
  simulation (not the builds) [s/s].

Numbers only, no pass/fail:

    python bench/bench_step.py [--configs 5:1.0,5:0.5,8:0.5,10:0.5,10:1.0]
"""

import argparse
import logging
import math
import sys
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from pydrake.math import RigidTransform, RotationMatrix
from pydrake.systems.framework import Context

from omtp_drake.cell.suction import contact_points
from omtp_drake.scenario import SuctionConfig, load_scenario
from omtp_drake.script import Cell

# The suction rig lives with the tests that use it (tests/suction_rig.py).
sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "tests"))

from suction_rig import (  # noqa: E402
    PRESS,
    SIZE,
    TOP,
    build_rig,
    hold,
    logged_at,
    pick_motion,
    pose_change,
    tool_q,
)

logging.getLogger("drake").setLevel(logging.ERROR)
logging.getLogger("omtp_drake").setLevel(logging.WARNING)

BACKENDS = ("weld", "force")
T_ON = 0.3  # contact run: suction on after the press has settled [s]
WINDOW = 0.1  # +- around the attach for the per-step jump [s]


@dataclass
class Carry:
    drift_mm: float
    drift_deg: float
    held: bool
    v_peak: float
    sim: float  # simulated [s]
    cpu: float  # process time [s]


@dataclass
class Press:
    t_attach: float
    points: tuple[int, int]
    pen_mm: float
    into_mm: float
    snap_mm: float
    jump_mm: float
    sim: float
    cpu: float


def carry(backend: str, dt: float, beta: float) -> Carry:
    motion, t_moving, t_stop = pick_motion(accel=20.0)
    rig = build_rig(
        backend,
        motion,
        mass=1.0,
        config=SuctionConfig(backend=backend),
        time_step=dt,
        near_rigid_threshold=beta,
    )
    cpu = time.process_time()
    rig.command(True)
    rig.advance_to(t_moving)
    X_CP = rig.state().X_CP
    rig.advance_to(t_stop + 0.2)
    cpu = time.process_time() - cpu
    held = rig.state().attached
    if X_CP is None:  # never attached: no drift to speak of
        drift_mm = drift_deg = math.nan
    else:
        steps = [pose_change(X_CP, X_WC.InvertAndCompose(X_WP)) for t, X_WP, X_WC in rig.log if t >= t_moving]
        drift_mm = 1e3 * max(d for d, _ in steps)
        drift_deg = max(a for _, a in steps)
    v_peak = max(
        float(np.linalg.norm(b[2].translation() - a[2].translation())) / rig.time_step
        for a, b in zip(rig.log, rig.log[1:])
    )
    return Carry(drift_mm, drift_deg, held, v_peak, rig.time, cpu)


def press(backend: str, dt: float, beta: float) -> Press:
    rig = build_rig(backend, hold(tool_q(0.0, 0.0, TOP - PRESS)), time_step=dt, near_rigid_threshold=beta)
    contacts: list[tuple[float, int]] = []  # (time, cup-part contact points) per step
    log_poses = rig.simulator.get_monitor()

    def monitor(root: Context):
        contacts.append((root.get_time(), rig.cup_part_contacts()))
        return log_poses(root)

    rig.simulator.set_monitor(monitor)
    cpu = time.process_time()
    rig.advance_to(T_ON)
    rig.command(True)
    rig.advance_to(T_ON + 0.3)
    while not rig.state().attached and rig.time < T_ON + 1.0:
        rig.advance_to(rig.time + 0.05)
    rig.advance_to(rig.time + WINDOW + 0.05)  # the window after the attach
    cpu = time.process_time() - cpu
    if not rig.state().attached:
        nan = math.nan
        return Press(nan, (0, 0), nan, nan, nan, nan, rig.time, cpu)
    t_attach = rig.state().since
    pressing = [n for t, n in contacts if 0 < t <= t_attach + 1e-9]
    pressed = [(X_WP, X_WC) for t, X_WP, X_WC in rig.log if 0 < t <= t_attach + 1e-9]
    pen = max(TOP - X_WC.translation()[2] for _, X_WC in pressed)
    into = max(X_WP.translation()[2] + SIZE / 2 - X_WC.translation()[2] for X_WP, X_WC in pressed)
    before, _ = logged_at(rig, t_attach)
    after = next(X_WP for t, X_WP, _ in rig.log if t > t_attach + 1e-9)
    window = [X_WP for t, X_WP, _ in rig.log if abs(t - t_attach) <= WINDOW + 1e-9]
    jump = max(pose_change(a, b)[0] for a, b in zip(window, window[1:]))
    return Press(
        t_attach - T_ON,
        (min(pressing), max(pressing)),
        1e3 * pen,
        1e3 * into,
        1e3 * pose_change(before, after)[0],
        1e3 * jump,
        rig.time,
        cpu,
    )


@dataclass
class Descent:
    travel_mm: float
    sink_mm: float
    into_mm: float


def descent(dt: float, beta: float) -> Descent:
    """The cell's own arm (lecture6_assignment4, weld suction) lowering the cup onto a
    0.2 m part at 0.05 m/s until it attaches, as ``tests/test_script.py`` does."""
    scenario = load_scenario("lecture6_assignment4").with_time_step(dt)
    scenario.plant_config.sap_near_rigid_threshold = beta
    cell = Cell(scenario, auto_spawn=False)
    arm, vacuum = cell.arm("robot2"), cell.gripper("robot2")
    arm.go("Home")
    part = cell.spawn_part()
    cell.wait(1.5)
    p = cell.part_pose(part).translation()
    down = RotationMatrix.MakeXRotation(math.pi)
    arm.move_to(RigidTransform(down, p + [0, 0, 0.2]))
    vacuum.on()
    first: list[np.ndarray] = []

    def attached() -> bool:
        if not first and cup_touches(cell, part):
            first.append(arm.tool_pose().translation())
        return vacuum.attached

    arm.move_linear(RigidTransform(down, p), speed=0.05, until=attached)
    travel = float(np.linalg.norm(arm.tool_pose().translation() - first[0])) if first else math.nan
    cell.wait(0.5)
    p_part, p_cup = cell.part_pose(part).translation(), arm.tool_pose().translation()
    return Descent(1e3 * travel, 1e3 * (p[2] - p_part[2]), 1e3 * (p_part[2] + SIZE / 2 - p_cup[2]))


def cup_touches(cell: Cell, part: str) -> bool:
    """Robot 2's cup and ``part`` are in contact (the plant's contact results)."""
    plant = cell.station.plant
    cup = plant.GetBodyByName(f"{cell.scenario.robot('robot2').gripper}_cup").index()
    plant_context = plant.GetMyContextFromRoot(cell.runtime.context)
    return contact_points(plant, plant_context, cup, plant.GetBodyByName(part).index()) > 0


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument(
        "--configs",
        default="5:1.0,5:0.5,8:0.5,10:0.5,10:1.0",
        help="step [ms]:SAP near-rigid threshold pairs, comma separated",
    )
    args = parser.parse_args()
    configs = [(1e-3 * float(a), float(b)) for a, b in (c.split(":") for c in args.configs.split(","))]
    print(
        "| step [ms] | near-rigid | backend | drift [mm] | drift [deg] | held | v peak [m/s] "
        "| t attach [s] | pts | pen. [mm] | into part [mm] | snap [mm] | jump [mm] | cpu [s/s] |"
    )
    print("|" + "---|" * 14)
    for dt, beta in configs:
        for backend in BACKENDS:
            c, p = carry(backend, dt, beta), press(backend, dt, beta)
            cpu = (c.cpu + p.cpu) / (c.sim + p.sim)
            print(
                f"| {1e3 * dt:g} | {beta:g} | {backend} | {c.drift_mm:.3f} | {c.drift_deg:.3f} "
                f"| {'yes' if c.held else 'NO'} | {c.v_peak:.3f} | {p.t_attach:.3f} "
                f"| {p.points[0]}-{p.points[1]} | {p.pen_mm:.2f} | {p.into_mm:.2f} "
                f"| {p.snap_mm:.4f} | {p.jump_mm:.4f} | {cpu:.3f} |"
            )
    print("\nThe cell's arm lowering the cup onto a part until it attaches (weld):\n")
    print(
        "| step [ms] | near-rigid | travel after first touch [mm] | part pushed into the floor [mm] "
        "| cup face into the part, 0.5 s later [mm] |"
    )
    print("|---|---|---|---|---|")
    for dt, beta in configs:
        d = descent(dt, beta)
        print(f"| {1e3 * dt:g} | {beta:g} | {d.travel_mm:.2f} | {d.sink_mm:.2f} | {d.into_mm:.2f} |")


if __name__ == "__main__":
    main()
