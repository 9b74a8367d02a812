"""The ``fill_bin`` job in MuJoCo, at MuJoCo's defaults (2 ms step, Euler, Newton).

Robot 2 (example-robot-data's UR5 and the vacuum gripper, :func:`peer_job.arm_urdf`, read
by MuJoCo's own URDF compiler into an ``MjSpec``) stands on its pedestal at our cell's
base pose; the floor is a plane, bin 1 five boxes. As in our cell, the arm collides with
neither itself nor its pedestal (contact bits). Position actuators drive the joints:
kp 2000 / kv 400 on the three large joints and 500 / 100 on the wrists, joint armature
0.1, force limits the URDF's efforts (the gains and armature of MuJoCo Menagerie's UR5e,
MuJoCo's own model of a UR arm; a position actuator's default kp of 1 cannot hold an
arm), the arm's links gravity-compensated (``gravcomp``, MuJoCo's own, as our servo's
inverse dynamics compensates gravity). The actuators replay our run's joint commands
(:class:`peer_job.FillBinJob`), each target led by the command's velocity (see
:func:`control`: without it, kv's pull toward zero speed lags the arm 0.46 rad).

Suction: a weld equality per part between the cup and the part, all off; while the
suction is commanded on and holds nothing, a part in contact with the cup is held by
switching its weld on with the pose it has in the cup at that step; the command off
switches it off. Parts wait parked (far away, floating: gravity compensated, no
contact bits) and appear when and where ours did. Everything else is MuJoCo's default.
"""

from __future__ import annotations

import tempfile
import time
from dataclasses import replace
from typing import Optional

import mujoco
import numpy as np
from peer_job import FillBinJob, arm_urdf, replay, static_boxes

from omtp_drake.cell.arms import JOINT_NAMES as JOINTS

#: (kp, kv, force limit) per joint: Menagerie's UR5e gains, the URDF's efforts.
GAINS = ((2000, 400, 150),) * 3 + ((500, 100, 28),) * 3
#: Contact bits: the world and parts collide with everything; the arm with the world and
#: parts only (not itself), the pedestal with parts only (not the arm).
_WORLD, _ARM, _PEDESTAL = (1, 1), (2, 1), (4, 1)
_PART = (1, 3)
_PARK = np.array([50.0, 50.0, 1.0])


def _box(body, half, xyz, bits=_WORLD, name: str = ""):
    return body.add_geom(
        name=name,
        type=mujoco.mjtGeom.mjGEOM_BOX,
        size=list(half),
        pos=list(xyz),
        contype=bits[0],
        conaffinity=bits[1],
    )


def build_model(job: FillBinJob, parts: int, sleep: bool = False) -> mujoco.MjModel:
    """The cell with ``parts`` parked parts (``part0``...), each with its weld ``weld<k>``."""
    with tempfile.TemporaryDirectory() as tmp:
        spec = mujoco.MjSpec.from_file(str(arm_urdf(tmp, mujoco=True)))  # its meshes: absolute paths
    spec.compiler.discardvisual = False  # (URDF's default; else it drops the parked parts' geoms)
    world = spec.worldbody
    world.add_geom(type=mujoco.mjtGeom.mjGEOM_PLANE, size=[0, 0, 1], contype=1, conaffinity=1)
    (pedestal, *bin_boxes) = static_boxes(job)
    _box(world, *pedestal, _PEDESTAL)
    for half, xyz in bin_boxes:
        _box(world, half, xyz)
    base = spec.body("base_link")
    base.pos = list(job.base_xyz)
    base.quat = [np.cos(job.base_yaw / 2), 0, 0, np.sin(job.base_yaw / 2)]
    for geom in spec.geoms:
        if geom.name not in ("cup",) and _in_arm(spec, geom):
            geom.contype, geom.conaffinity = _ARM
    spec.geom("cup").contype, spec.geom("cup").conaffinity = _ARM
    for joint in JOINTS:
        spec.joint(joint).armature = 0.1
    for body in spec.bodies:
        if body.name not in ("world", ""):
            body.gravcomp = 1.0  # as our servo's inverse dynamics compensates gravity
    for joint, (kp, kv, force) in zip(JOINTS, GAINS):
        act = spec.add_actuator(name=joint, target=joint, trntype=mujoco.mjtTrn.mjTRN_JOINT)
        act.set_to_position(kp=kp, kv=kv)
        act.forcelimited = mujoco.mjtLimited.mjLIMITED_TRUE
        act.forcerange = [-force, force]
    half = job.part_size / 2
    for k in range(parts):
        body = world.add_body(name=f"part{k}", pos=list(_PARK + [0.5 * k, 0, 0]), gravcomp=1.0)
        body.add_freejoint()
        _box(body, (half,) * 3, (0, 0, 0), (0, 0), name=f"part{k}")
        spec.geom(f"part{k}").mass = job.part_mass
        spec.add_equality(
            name=f"weld{k}",
            type=mujoco.mjtEq.mjEQ_WELD,
            objtype=mujoco.mjtObj.mjOBJ_BODY,
            name1="cup",
            name2=f"part{k}",
            active=False,
        )
    model = spec.compile()
    if sleep:
        model.opt.enableflags |= mujoco.mjtEnableBit.mjENBL_SLEEP
    return model


def _in_arm(spec, geom) -> bool:
    return geom.parent.name not in ("world", "") and not geom.parent.name.startswith("part")


class MujocoCell:
    """A compiled :func:`build_model` and its data, with the suction and the parts' spawns."""

    def __init__(self, job: FillBinJob, parts: int, sleep: bool = False):
        self.job = job
        self.model = build_model(job, parts, sleep)
        self.data = mujoco.MjData(self.model)
        m = self.model
        self.cup_geom = mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_GEOM, "cup")
        self.cup_body = mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_BODY, "cup")
        self.part_geoms = {
            mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_GEOM, f"part{k}"): k for k in range(parts)
        }
        self.part_bodies = [mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_BODY, f"part{k}") for k in range(parts)]
        self.welds = [mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_EQUALITY, f"weld{k}") for k in range(parts)]
        self.qadr = [m.jnt_qposadr[mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_JOINT, j)] for j in JOINTS]
        self.spawned = 0
        self.held: Optional[int] = None
        q0, _ = job.command(0.0)
        self.data.qpos[self.qadr] = q0
        self.data.ctrl[:] = q0
        mujoco.mj_forward(m, self.data)

    def spawn(self, xyz, yaw: float = 0.0) -> int:
        """Unparks the next part at ``xyz``, turned ``yaw`` about z, at rest."""
        k = self.spawned
        self.spawned += 1
        m, d = self.model, self.data
        body, geom = self.part_bodies[k], next(g for g, j in self.part_geoms.items() if j == k)
        m.body_gravcomp[body] = 0.0
        m.geom_contype[geom], m.geom_conaffinity[geom] = _PART
        m.body_contype[body], m.body_conaffinity[body] = _PART  # (the broad phase's per-body bits)
        adr = m.jnt_qposadr[m.body_jntadr[body]]
        d.qpos[adr : adr + 3] = xyz
        d.qpos[adr + 3 : adr + 7] = [np.cos(yaw / 2), 0, 0, np.sin(yaw / 2)]
        d.qvel[m.jnt_dofadr[m.body_jntadr[body]] : m.jnt_dofadr[m.body_jntadr[body]] + 6] = 0
        return k

    def suction(self, on: bool) -> None:
        """Switches a touching part's weld on (with its pose in the cup), or the held one off."""
        d = self.data
        if not on:
            if self.held is not None:
                d.eq_active[self.welds[self.held]] = 0
                self.held = None
            return
        if self.held is not None:
            return
        for i in range(d.ncon):
            contact = d.contact[i]
            pair = (contact.geom1, contact.geom2)
            if self.cup_geom not in pair:
                continue
            other = pair[1] if pair[0] == self.cup_geom else pair[0]
            if other in self.part_geoms:
                k = self.part_geoms[other]
                self._weld(k)
                return

    def _weld(self, k: int) -> None:
        """Switches weld ``k`` on with the part's present pose in the cup (no jump)."""
        m, d = self.model, self.data
        c, p = self.cup_body, self.part_bodies[k]
        R_WC = d.xmat[c].reshape(3, 3)
        relpos = R_WC.T @ (d.xpos[p] - d.xpos[c])
        q_CW = np.empty(4)
        mujoco.mju_negQuat(q_CW, d.xquat[c])
        relquat = np.empty(4)
        mujoco.mju_mulQuat(relquat, q_CW, d.xquat[p])
        eq = m.eq_data[self.welds[k]]
        eq[0:3] = 0.0  # anchor: the part's origin
        eq[3:6] = relpos
        eq[6:10] = relquat
        d.eq_active[self.welds[k]] = 1
        self.held = k

    def part_positions(self) -> list[np.ndarray]:
        return [self.data.xpos[b].copy() for b in self.part_bodies[: self.spawned]]


#: kv / kp of each actuator: a target ahead of the command by this times its velocity
#: makes the actuator's force kp (q_cmd - q) + kv (v_cmd - v), as our servo tracks
#: the command's position and velocity.
_LEAD = np.array([kv / kp for kp, kv, _ in GAINS])


def control(job: FillBinJob, k: int) -> np.ndarray:
    """The actuators' targets for command sample ``k``: the command led by its velocity
    (the backward difference of the samples, as our servo's sampler takes it)."""
    if k == 0:
        return job.q[0]
    v = (job.q[k] - job.q[k - 1]) / (job.times[k] - job.times[k - 1])
    return job.q[k] + _LEAD * v


def run_fill_bin(job: FillBinJob, duration: Optional[float] = None) -> tuple[float, int, float]:
    """Replays ``job`` in a new :class:`MujocoCell` for ``duration`` (default the job's):
    (CPU seconds per simulated second of the loop, parts in the bin at the end, the
    build's CPU seconds)."""
    build = time.process_time()
    cell = MujocoCell(job, len(job.spawns))
    build = time.process_time() - build
    m, d = cell.model, cell.data

    def command(k: int) -> None:
        d.ctrl[:] = control(job, k)

    end = job.duration if duration is None else duration
    cpu = replay(job, m.opt.timestep, end, cell.spawn, command, cell.suction, lambda: mujoco.mj_step(m, d))
    in_bin = sum(job.in_bin_box(p) for p in cell.part_positions())
    return cpu, in_bin, build


def resting_cpu(
    job: FillBinJob, slots, seconds: float, sleep: bool = False, size: float = 0.05
) -> tuple[float, int]:
    """CPU seconds per simulated second of the cell with a part (a ``size`` cube, 0.2 kg)
    resting at each of ``slots`` (the arm held at its first pose), after 1 s of
    settling; ``sleep``: MuJoCo's sleeping flag on. Also how many parts are in the bin
    at the end."""
    cell = MujocoCell(replace(job, part_size=size, part_mass=0.2), len(slots), sleep)
    for xyz in slots:
        cell.spawn(xyz)
    m, d = cell.model, cell.data
    for _ in range(int(round(1.0 / m.opt.timestep))):
        mujoco.mj_step(m, d)
    steps = int(round(seconds / m.opt.timestep))
    cpu = time.process_time()
    for _ in range(steps):
        mujoco.mj_step(m, d)
    cpu = (time.process_time() - cpu) / (steps * m.opt.timestep)
    return cpu, sum(job.in_bin_box(p) for p in cell.part_positions())
