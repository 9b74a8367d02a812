"""The ``fill_bin`` job in PyBullet, ravens-style, at PyBullet's defaults (240 Hz).

Robot 2 (example-robot-data's UR5 and the vacuum gripper, :func:`peer_job.arm_urdf`) stands
on its pedestal at our cell's base pose; the floor is PyBullet's plane, bin 1 five boxes;
as in our cell, the arm does not collide with its pedestal.
The arm replays our run's joint commands (:class:`peer_job.FillBinJob`) through PyBullet's
position motors (``POSITION_CONTROL``, the URDF's effort limits as their forces), the
commands changing when our servo's samples do (100 Hz). Suction as in ravens: while
commanded on and holding nothing, a part in contact with the cup is held by a fixed
constraint created at that step with its pose in the cup; the command off removes it.
Each part appears when and where ours did (a box created at the spawner's pose, which
then falls to the floor as ours does). Nothing else of PyBullet is changed from its
defaults (time step, solver iterations, damping, friction, sleeping).
"""

from __future__ import annotations

import tempfile
import time
from dataclasses import dataclass, field, replace
from typing import Optional

import pybullet as pb
from peer_job import FillBinJob, arm_urdf, replay, static_boxes

from omtp_drake.cell.arms import JOINT_NAMES as JOINTS


def _static_box(client: int, half: tuple[float, float, float], xyz) -> int:
    shape = pb.createCollisionShape(pb.GEOM_BOX, halfExtents=half, physicsClientId=client)
    return pb.createMultiBody(0, shape, -1, list(xyz), physicsClientId=client)


@dataclass
class PyBulletCell:
    """A PyBullet world (its own DIRECT client) with robot 2, its pedestal, bin 1 and the
    floor; parts are added with :meth:`add_part`. ``close`` frees the client."""

    job: FillBinJob
    client: int = -1
    arm: int = -1
    cup: int = -1
    joints: list[int] = field(default_factory=list)
    forces: list[float] = field(default_factory=list)
    parts: list[int] = field(default_factory=list)
    held: Optional[int] = None
    constraint: Optional[int] = None
    _box_shape: int = -1

    def __post_init__(self) -> None:
        job = self.job
        self.client = pb.connect(pb.DIRECT)
        c = self.client
        pb.setGravity(0, 0, -9.81, physicsClientId=c)
        plane = pb.createCollisionShape(pb.GEOM_PLANE, physicsClientId=c)
        pb.createMultiBody(0, plane, physicsClientId=c)
        pedestal, *_bin = [_static_box(c, half, xyz) for half, xyz in static_boxes(job)]
        with tempfile.TemporaryDirectory() as tmp:
            self.arm = pb.loadURDF(
                str(arm_urdf(tmp)),
                job.base_xyz,
                pb.getQuaternionFromEuler((0, 0, job.base_yaw)),
                useFixedBase=True,
                physicsClientId=c,
            )
        names = {
            pb.getJointInfo(self.arm, j, physicsClientId=c)[1].decode(): j
            for j in range(pb.getNumJoints(self.arm, physicsClientId=c))
        }
        links = {
            pb.getJointInfo(self.arm, j, physicsClientId=c)[12].decode(): j
            for j in range(pb.getNumJoints(self.arm, physicsClientId=c))
        }
        self.joints = [names[n] for n in JOINTS]
        self.forces = [pb.getJointInfo(self.arm, j, physicsClientId=c)[10] for j in self.joints]
        self.cup = links["cup"]
        for link in range(-1, pb.getNumJoints(self.arm, physicsClientId=c)):  # as our cell filters them
            pb.setCollisionFilterPair(self.arm, pedestal, link, -1, 0, physicsClientId=c)
        q0, _ = job.command(0.0)
        for j, q in zip(self.joints, q0):
            pb.resetJointState(self.arm, j, q, physicsClientId=c)
        self.command(q0)
        half = self.job.part_size / 2
        self._box_shape = pb.createCollisionShape(pb.GEOM_BOX, halfExtents=[half] * 3, physicsClientId=c)

    def close(self) -> None:
        pb.disconnect(self.client)

    def command(self, q) -> None:
        pb.setJointMotorControlArray(
            self.arm,
            self.joints,
            pb.POSITION_CONTROL,
            targetPositions=list(q),
            forces=self.forces,
            physicsClientId=self.client,
        )

    def add_part(self, xyz, yaw: float = 0.0, mass: Optional[float] = None) -> int:
        body = pb.createMultiBody(
            self.job.part_mass if mass is None else mass,
            self._box_shape,
            -1,
            list(xyz),
            pb.getQuaternionFromEuler((0, 0, yaw)),
            physicsClientId=self.client,
        )
        self.parts.append(body)
        return body

    def suction(self, on: bool) -> None:
        """Ravens' suction: attach a part touching the cup, release when off."""
        c = self.client
        if not on:
            if self.constraint is not None:
                pb.removeConstraint(self.constraint, physicsClientId=c)
                self.constraint, self.held = None, None
            return
        if self.held is not None:
            return
        for contact in pb.getContactPoints(bodyA=self.arm, linkIndexA=self.cup, physicsClientId=c):
            part = contact[2]
            if part in self.parts:
                cup_pose = pb.getLinkState(self.arm, self.cup, physicsClientId=c)[4:6]
                part_pose = pb.getBasePositionAndOrientation(part, physicsClientId=c)
                inv = pb.invertTransform(*cup_pose)
                X_CP = pb.multiplyTransforms(inv[0], inv[1], *part_pose)
                self.constraint = pb.createConstraint(
                    self.arm,
                    self.cup,
                    part,
                    -1,
                    pb.JOINT_FIXED,
                    (0, 0, 0),
                    X_CP[0],
                    (0, 0, 0),
                    X_CP[1],
                    physicsClientId=c,
                )
                self.held = part
                return

    def positions(self) -> list[tuple[float, float, float]]:
        return [pb.getBasePositionAndOrientation(p, physicsClientId=self.client)[0] for p in self.parts]


def run_fill_bin(job: FillBinJob, duration: Optional[float] = None) -> tuple[float, int, float]:
    """Replays ``job`` in a new :class:`PyBulletCell` for ``duration`` (default the job's):
    (CPU seconds per simulated second of the loop, parts in the bin at the end, the
    build's CPU seconds)."""
    build = time.process_time()
    cell = PyBulletCell(job)
    build = time.process_time() - build
    try:
        dt = pb.getPhysicsEngineParameters(physicsClientId=cell.client)["fixedTimeStep"]
        end = job.duration if duration is None else duration
        cpu = replay(
            job,
            dt,
            end,
            cell.add_part,
            lambda k: cell.command(job.q[k]),
            cell.suction,
            lambda: pb.stepSimulation(physicsClientId=cell.client),
        )
        in_bin = sum(job.in_bin_box(p) for p in cell.positions())
    finally:
        cell.close()
    return cpu, in_bin, build


def resting_cpu(
    job: FillBinJob, slots, seconds: float, sleep: bool = False, size: float = 0.05
) -> tuple[float, int]:
    """CPU seconds per simulated second of the cell with a part (a ``size`` cube, 0.2 kg)
    resting at each of ``slots`` (the arm held at its first pose, nothing commanded on),
    after 1 s of settling; ``sleep``: Bullet's sleeping enabled on the parts. Also how
    many parts are in the bin at the end."""
    cell = PyBulletCell(replace(job, part_size=size, part_mass=0.2))
    try:
        for xyz in slots:
            body = cell.add_part(xyz)
            if sleep:
                pb.changeDynamics(
                    body, -1, activationState=pb.ACTIVATION_STATE_ENABLE_SLEEPING, physicsClientId=cell.client
                )
        dt = pb.getPhysicsEngineParameters(physicsClientId=cell.client)["fixedTimeStep"]
        for _ in range(int(round(1.0 / dt))):
            pb.stepSimulation(physicsClientId=cell.client)
        steps = int(round(seconds / dt))
        cpu = time.process_time()
        for _ in range(steps):
            pb.stepSimulation(physicsClientId=cell.client)
        cpu = (time.process_time() - cpu) / (steps * dt)
        return cpu, sum(job.in_bin_box(p) for p in cell.positions())
    finally:
        cell.close()
