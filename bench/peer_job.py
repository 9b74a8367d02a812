"""The ``fill_bin`` job as the peer cells (PyBullet, MuJoCo) replay it: what our run did.

:func:`record_fill_bin` runs our ``fill_bin`` task once and records what the peers need
to do the same job with the same motion: robot 2's joint position commands as its servo
sampled them (``command_rate_hz``, 100 Hz), the suction command at the same instants,
when and where each part appeared (the spawner drops them one at a time), and the
cell's fixed facts (robot 2's base pose, its pedestal, bin 1, the part size and mass,
the vacuum gripper on the flange). :func:`bin_slots` is the
layout of the cost-growth rows (parts resting in a bin).

Frames: ``W`` the world, ``B`` robot 2's ``base_link``, ``T`` its ``tool0``.
"""

from __future__ import annotations

import time
from dataclasses import dataclass
from typing import Optional

import numpy as np

#: The vacuum gripper (models/vacuum_gripper.urdf.xacro): a 0.06 x 0.075 x 0.0625 box on
#: tool0, then a cup (cylinder, radius 0.02, 0.015 long) whose face is 0.0775 out along z.
GRIPPER_BOX = (0.06, 0.075, 0.0625)
CUP_RADIUS, CUP_LENGTH = 0.02, 0.015
#: bin_1 (models/bin.urdf.xacro): outer 0.40 x 0.40 x 0.475, floor top 0.12, walls 0.01.
BIN_OUTER, BIN_HEIGHT, BIN_FLOOR_TOP, BIN_WALL = 0.40, 0.475, 0.12, 0.01
#: The pedestal: a 0.3 x 0.3 box from the floor to the arm's base.
PEDESTAL_SIDE = 0.3


@dataclass(frozen=True)
class FillBinJob:
    """What one run of our ``fill_bin`` did, for a peer to replay.

    ``times[k]`` = k / command_rate: the instants robot 2's servo sampled ``q[k]`` (6 joint
    positions) and the gripper's command ``suction[k]`` (on/off); ``spawns``: (time, xyz,
    yaw) of each part as it appeared (dropped from the spawner); ``duration``: the run's
    simulated seconds; ``in_bin``: how many parts our run left in bin 1.
    """

    times: np.ndarray
    q: np.ndarray
    suction: np.ndarray
    spawns: tuple[tuple[float, tuple[float, float, float], float], ...]
    duration: float
    in_bin: int
    base_xyz: tuple[float, float, float]
    base_yaw: float
    bin_xyz: tuple[float, float, float]
    part_size: float
    part_mass: float
    #: our run's CPU seconds (this process) per simulated second, recorder included
    recorded_cpu: float = float("nan")

    def command(self, t: float) -> tuple[np.ndarray, bool]:
        """The arm's position command and the suction command in force at ``t`` (a
        zero-order hold of the samples, as our servo's sampler holds them)."""
        k = min(int(np.searchsorted(self.times, t + 1e-9, side="right")) - 1, len(self.times) - 1)
        k = max(k, 0)
        return self.q[k], bool(self.suction[k])

    def in_bin_box(self, xyz) -> bool:
        """Whether a part's centre ``xyz`` lies inside bin 1 (between its inner walls,
        above its floor, below its rim)."""
        inner = BIN_OUTER / 2 - BIN_WALL
        dx, dy = xyz[0] - self.bin_xyz[0], xyz[1] - self.bin_xyz[1]
        dz = xyz[2] - self.bin_xyz[2]
        return abs(dx) < inner and abs(dy) < inner and BIN_FLOOR_TOP < dz < BIN_HEIGHT


def replay(job: FillBinJob, dt: float, duration: float, spawn, command, suction, step) -> float:
    """Replays ``job`` for ``duration`` simulated seconds at a step ``dt``: before each
    ``step()``, ``spawn(xyz, yaw)`` for each part due, ``command(k)`` when the command
    sample ``k`` in force changes, ``suction(on)``. Returns CPU seconds per simulated
    second of the loop."""
    steps = int(round(duration / dt))
    spawns = list(job.spawns)
    last = -1
    cpu = time.process_time()
    for n in range(steps):
        t = n * dt
        while spawns and spawns[0][0] <= t + 1e-9:
            _, xyz, yaw = spawns.pop(0)
            spawn(xyz, yaw)
        k = max(int(np.searchsorted(job.times, t + 1e-9, side="right")) - 1, 0)
        if k != last:
            command(k)
            last = k
        suction(bool(job.suction[k]))
        step()
    return (time.process_time() - cpu) / (steps * dt)


def static_boxes(job: FillBinJob) -> list[tuple[tuple[float, float, float], tuple[float, float, float]]]:
    """(half extents, centre) in W of the peers' fixed boxes: robot 2's pedestal (the
    first) and bin 1's floor and four walls (models/bin.urdf.xacro)."""
    bx, by, bz = job.base_xyz
    boxes = [((PEDESTAL_SIDE / 2, PEDESTAL_SIDE / 2, bz / 2), (bx, by, bz / 2))]
    x, y, z = job.bin_xyz
    o, w, h, f = BIN_OUTER, BIN_WALL, BIN_HEIGHT, BIN_FLOOR_TOP
    wall_z = z + (h + f) / 2
    boxes.append(((o / 2, o / 2, f / 2), (x, y, z + f / 2)))
    for s in (1, -1):
        boxes.append(((w / 2, o / 2, (h - f) / 2), (x + s * (o - w) / 2, y, wall_z)))
        boxes.append((((o - 2 * w) / 2, w / 2, (h - f) / 2), (x, y + s * (o - w) / 2, wall_z)))
    return boxes


def record_fill_bin(parts: Optional[int] = None) -> FillBinJob:
    """Runs our ``fill_bin`` (``parts`` parts, default the task's 10) and records it."""
    from omtp_drake.tasks.run import prepare, run_task

    scenario = prepare("fill_bin", parts=parts)
    task = scenario.required_task()
    samples: list[tuple[float, np.ndarray, bool]] = []
    spawns: dict[str, tuple[float, tuple[float, float, float], float]] = {}
    facts: dict[str, object] = {}

    def start(run) -> None:
        station = run.runtime.station
        plant, diagram = station.plant, station.diagram
        robot = station.scenario.robots[[r.name for r in station.scenario.robots].index(task.robot)]
        period = 1.0 / robot.command_rate_hz
        position = diagram.GetInputPort(f"{task.robot}.position")
        suction = diagram.GetInputPort(f"{station.suction_name(task.robot)}.command")
        waiting = dict(station.parts)
        base = plant.GetBodyByName(f"{task.robot}_base_link")
        plant_context = plant.GetMyContextFromRoot(run.runtime.context)
        X_WB = plant.EvalBodyPoseInWorld(plant_context, base)
        facts["base_xyz"] = tuple(X_WB.translation())
        facts["base_yaw"] = float(np.arctan2(X_WB.rotation().matrix()[1, 0], X_WB.rotation().matrix()[0, 0]))
        facts["bin_xyz"] = tuple(station.bin_pose(run.runtime.context, task.bin).translation())
        base_xy = X_WB.translation()[:2]

        def monitor(root_context):
            t = root_context.get_time()
            k = round(t / period)
            if abs(t - k * period) > 1e-9 or (samples and k * period <= samples[-1][0] + 1e-9):
                return _succeeded()
            station_context = diagram.GetMyContextFromRoot(root_context)
            on = float(np.asarray(suction.Eval(station_context)).ravel()[0]) > 0.5
            samples.append((k * period, np.array(position.Eval(station_context)), on))
            pc = plant.GetMyContextFromRoot(root_context)
            for name, instance in waiting.items():
                if name in spawns:
                    continue
                q = plant.GetPositions(pc, instance)  # (qw, qx, qy, qz, x, y, z)
                if np.linalg.norm(q[4:6] - base_xy) < 5.0:  # unparked: within the cell
                    yaw = np.arctan2(2 * (q[0] * q[3] + q[1] * q[2]), 1 - 2 * (q[2] ** 2 + q[3] ** 2))
                    spawns[name] = (k * period, tuple(float(v) for v in q[4:7]), float(yaw))
            return _succeeded()

        monitor(run.runtime.context)
        run.runtime.simulator.set_monitor(monitor)

    cpu = time.process_time()
    result = run_task(scenario, on_start=start)
    cpu = (time.process_time() - cpu) / result.sim_time_s
    times = np.array([s[0] for s in samples])
    return FillBinJob(
        times=times,
        q=np.stack([s[1] for s in samples]),
        suction=np.array([s[2] for s in samples]),
        spawns=tuple(sorted(spawns.values())),
        duration=result.sim_time_s,
        in_bin=result.ledger.in_bin.get(task.bin, 0),
        base_xyz=facts["base_xyz"],  # type: ignore[arg-type]
        base_yaw=facts["base_yaw"],  # type: ignore[arg-type]
        bin_xyz=facts["bin_xyz"],  # type: ignore[arg-type]
        part_size=scenario.pool_part_size,
        part_mass=scenario.pool_part_mass,
        recorded_cpu=cpu,
    )


def _succeeded():
    from pydrake.systems.framework import EventStatus

    return EventStatus.Succeeded()


def bin_slots(
    count: int, size: float, bins: list[tuple[float, float, float]]
) -> list[tuple[float, float, float]]:
    """Centres of ``count`` cubes of edge ``size`` resting in layers on a grid in the
    bins at ``bins`` (each bin's floor frame), filled bin after bin, each a little
    apart (2 mm) so that none starts in contact with another. Raises ValueError when
    they do not fit."""
    inner = BIN_OUTER - 2 * BIN_WALL
    per_row = int(inner // (size + 0.002))
    layers = int((BIN_HEIGHT - BIN_FLOOR_TOP) // (size + 0.001))
    per_bin = per_row * per_row * layers
    if count > per_bin * len(bins):
        raise ValueError(f"{count} parts of {size} m do not fit in {len(bins)} bins ({per_bin} each)")
    pitch = size + 0.002
    offset = -(per_row - 1) * pitch / 2
    slots = []
    for k in range(count):
        b, r = divmod(k, per_bin)
        layer, cell = divmod(r, per_row * per_row)
        i, j = divmod(cell, per_row)
        x, y, z = bins[b]
        slots.append(
            (
                x + offset + i * pitch,
                y + offset + j * pitch,
                z + BIN_FLOOR_TOP + size / 2 + layer * (size + 0.001),
            )
        )
    return slots


def arm_urdf(directory, mujoco: bool = False):
    """Writes robot 2 for a peer into ``directory`` and returns its path: example-robot-data's
    UR5 (the file our cell loads) with its collision meshes only (no visuals: nothing is
    rendered), its joints at robot 2's +/-2 pi, without the ``world`` link and ``ee_link``'s
    1 cm box (as our cell drops them), and the vacuum gripper fixed on ``tool0``: links
    ``gripper`` (its box) and ``cup`` (the cylinder, frame at the cup face). ``mujoco``:
    with MuJoCo's compiler element (absolute mesh paths, no link fusing)."""
    import xml.etree.ElementTree as ET
    from pathlib import Path

    from omtp_drake.ur_arms import ur_description_dir

    root = ET.parse(ur_description_dir() / "urdf" / "ur5_robot.urdf").getroot()
    package = "package://example-robot-data/robots/ur_description/"
    for el in root.findall("gazebo") + root.findall("transmission"):
        root.remove(el)
    for joint in root.findall("joint"):
        parent = joint.find("parent")
        if parent is not None and parent.get("link") == "world":
            root.remove(joint)
        limit = joint.find("limit")
        if limit is not None and joint.get("type") == "revolute":
            limit.set("lower", repr(-2 * np.pi))
            limit.set("upper", repr(2 * np.pi))
    for link in root.findall("link"):
        if link.get("name") == "world":
            root.remove(link)
            continue
        for visual in link.findall("visual"):
            link.remove(visual)
        if link.get("name") == "ee_link":
            for collision in link.findall("collision"):
                link.remove(collision)
        for mesh in link.iterfind("collision/geometry/mesh"):
            mesh.set("filename", str(ur_description_dir() / mesh.get("filename", "")[len(package) :]))
    bx, by, bz = GRIPPER_BOX
    root.append(_link("gripper", f'<box size="{bx} {by} {bz}"/>', (0, 0, bz / 2), 0.3))
    root.append(_fixed("tool0", "gripper", (0, 0, 0)))
    cylinder = f'<cylinder radius="{CUP_RADIUS}" length="{CUP_LENGTH}"/>'
    root.append(_link("cup", cylinder, (0, 0, -CUP_LENGTH / 2), 0.02))
    root.append(_fixed("gripper", "cup", (0, 0, bz + CUP_LENGTH)))
    if mujoco:
        ET.SubElement(ET.SubElement(root, "mujoco"), "compiler", strippath="false", fusestatic="false")
    path = Path(directory) / ("ur5_gripper_mujoco.urdf" if mujoco else "ur5_gripper.urdf")
    ET.ElementTree(root).write(path)
    return path


def _link(name: str, geometry: str, xyz, mass: float):
    import xml.etree.ElementTree as ET

    x, y, z = xyz
    i = mass * 1e-3
    return ET.fromstring(
        f'<link name="{name}"><collision name="{name}"><origin xyz="{x} {y} {z}"/><geometry>{geometry}'
        f'</geometry></collision><inertial><origin xyz="{x} {y} {z}"/><mass value="{mass}"/>'
        f'<inertia ixx="{i}" iyy="{i}" izz="{i}" ixy="0" ixz="0" iyz="0"/></inertial></link>'
    )


def _fixed(parent: str, child: str, xyz):
    import xml.etree.ElementTree as ET

    x, y, z = xyz
    return ET.fromstring(
        f'<joint name="{parent}_{child}" type="fixed"><parent link="{parent}"/><child link="{child}"/>'
        f'<origin xyz="{x} {y} {z}"/></joint>'
    )
