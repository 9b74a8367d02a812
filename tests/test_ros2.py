"""``omtp-drake ros2``: the cell in one process and a student's plain rclpy node in
another (tests/ros2_scripts/student_node.py, nothing of ours imported), over Fast
DDS on loopback in a domain of their own: /clock and /joint_states arrive,
/logical_camera_1/points lies on the part in view, the gripper's service
answers. Every process ends and leaves nothing behind.

Without the ``ros2`` extra these tests skip (and the command says which extra).
"""

from __future__ import annotations

import contextlib
import fcntl
import json
import os
import signal
import socket
import subprocess
import sys
import threading
from collections.abc import Iterator
from pathlib import Path

import numpy as np
import pytest

from omtp_drake.errors import ConfigError, MissingExtraError
from omtp_drake.ros2.network import Ros2Network, choose_network

SCRIPTS = Path(__file__).parent / "ros2_scripts"
#: Upper bounds only (a slow machine passes as a fast one does): wall-clock seconds.
PATIENCE = 600

#: lecture6_assignment1 with camera 1's RGB-D view: it looks down at the 0.2 m part on the belt.
RGBD_SCENARIO = """\
base: lecture6_assignment1
cameras: [{name: logical_camera_1, rgbd: true}]
"""
#: The part's top face (world z, m) and centre (x, y) in lecture6_assignment1.
PART_TOP_Z = 1.121
PART_XY = (1.2, 1.8)

try:
    from omtp_drake.ros2.network import import_rclpy

    import_rclpy()
    HAVE_ROS2 = True
except MissingExtraError:
    HAVE_ROS2 = False

needs_ros2 = pytest.mark.skipif(
    not HAVE_ROS2, reason='the ros2 extra is not installed: pip install -e ".[ros2]"'
)


@contextlib.contextmanager
def hold_domain() -> Iterator[int]:
    """A ROS 2 domain no other test of this machine holds while the block runs: the first
    free one from a pid-based start (xdist workers, other runs), held by binding an
    abstract Unix socket named after it (Linux; it leaves no file behind)."""
    start = os.getpid() % 101
    for i in range(101):
        candidate = 1 + (start + i) % 101
        holder = socket.socket(socket.AF_UNIX, socket.SOCK_STREAM)
        try:
            holder.bind(f"\0omtp_drake_test_ros2_domain_{candidate}")
        except OSError:
            holder.close()
            continue
        try:
            yield candidate
        finally:
            holder.close()
        return
    pytest.fail("every ROS 2 domain 1..101 is held by another test")


@pytest.fixture
def domain() -> Iterator[int]:
    with hold_domain() as held:
        yield held


@pytest.fixture
def network(monkeypatch) -> Iterator[Ros2Network]:
    """A network of a domain of the test's own, for a cell in this process: the variables the
    node writes into the environment (and the paths it adds for the packages it builds) are
    restored after the test."""
    with hold_domain() as domain:
        network = Ros2Network(domain)
        for name, value in network.environment().items():
            monkeypatch.setenv(name, value)  # restored after the test (the node writes them)
        # The node puts the packages it builds on both (interface_build.activate): restored too.
        monkeypatch.setenv("PYTHONPATH", os.environ.get("PYTHONPATH", ""))
        monkeypatch.setattr(sys, "path", list(sys.path))
        yield network


def _loopback_env(domain: int) -> dict[str, str]:
    env = dict(os.environ)
    env.update(Ros2Network(domain).environment())
    return env


def _session_members(sid: int) -> list[int]:
    """The processes still alive in session ``sid``."""
    alive = []
    for stat in Path("/proc").glob("[0-9]*/stat"):
        try:
            fields = stat.read_text().rsplit(")", 1)[1].split()
        except OSError:
            continue
        if int(fields[3]) == sid and fields[0] != "Z":
            alive.append(int(stat.parent.name))
    return alive


def _dds_files() -> set[str]:
    """Fast DDS's shared-memory segments and locks in /dev/shm."""
    shm = Path("/dev/shm")
    return {p.name for p in shm.iterdir() if "fast" in p.name.lower()} if shm.is_dir() else set()


def _domain_dds_files(domain: int) -> set[str]:
    """Fast DDS's shared-memory port files of ``domain`` (its ports: 7400 + 250 * domain
    onwards): a port's segment ``fastdds_portN``, its lock ``fastdds_portN_el`` and its mutex
    ``sem.fastdds_portN_mutex``. Another worker's DDS test runs on another domain, so on other
    ports. (Each rclpy participant's discovery-info reader also takes a port of 7000-7399, Fast
    DDS's unique-flow range, shared by all domains: those are nobody's domain, not counted.)"""
    low = 7400 + 250 * domain
    return {
        name
        for name in _dds_files()
        if (port := name.removeprefix("sem.").removeprefix("fastdds_port").split("_")[0]).isdigit()
        and low <= int(port) < low + 250
    }


def _unowned(lock: Path) -> bool:
    """Whether the lock file ``lock`` (a port's ``_el``) is held by no process: Fast DDS's own test
    for a zombie port. The port's listener holds it (flock) while it lives and removes it when it
    closes the port, so an unheld one outlives a listener that ended without closing (killed)."""
    try:
        fd = os.open(lock, os.O_RDONLY)
    except FileNotFoundError:
        return False
    try:
        fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
    except BlockingIOError:
        return False
    else:
        fcntl.flock(fd, fcntl.LOCK_UN)
        return True
    finally:
        os.close(fd)


def _leaked_dds_files(before: set[str], domain: int) -> set[str]:
    """``domain``'s Fast DDS ports, new since ``before``, whose listener ended without closing
    them: their ``_el`` lock left behind, held by nobody (Fast DDS's own zombie test). Called once
    every process of the test ended, after its exit codes and sessions were checked.

    A port's segment without its lock is not counted: its listener closed it, and Fast DDS keeps
    the segment while it still counts a user (its last user removes it) or after its watchdog
    marked the port unhealthy (a listener seen stalled on a busy machine; the next participant
    on that port resets it). Measured here: a cell and a node that end by themselves or on
    Ctrl-C leave nothing of their domain; a node killed with SIGKILL leaves the port of the peer
    it sent to without its lock (``fastdds_port7663``, the shape of CI's ``fastdds_port15161``,
    whose processes all had exited 0), its own ports reset by the peer. A killed process is the
    exit codes' to catch; ports of another domain (another worker's test) are never counted."""
    shm = Path("/dev/shm")
    return {
        name.removesuffix("_el")
        for name in _domain_dds_files(domain) - before
        if name.endswith("_el") and _unowned(shm / name)
    }


def _end(process: subprocess.Popen) -> None:
    """Stops ``process``'s whole session (it was started as its leader) and reaps it."""
    if process.poll() is None:
        os.killpg(process.pid, signal.SIGKILL)
    process.wait(timeout=PATIENCE)


def run_cell_with_node(
    cell_args: list[str], node_args: list[str], domain: int, env: dict[str, str] | None = None
) -> tuple[str, str]:
    """``omtp-drake ros2 CELL_ARGS`` and the node ``python NODE_ARGS`` on ``domain`` (loopback),
    each in its own session: the node runs to its end, then the cell gets Ctrl-C. Both must
    exit 0 and leave no process and none of the domain's Fast DDS shared memory behind.
    Returns the cell's (stdout, stderr)."""
    return run_cell_with_nodes(cell_args, [node_args], domain, env)


def run_cell_with_nodes(
    cell_args: list[str], nodes: list[list[str]], domain: int, env: dict[str, str] | None = None
) -> tuple[str, str]:
    """As :func:`run_cell_with_node`, with the nodes ``python NODES[i]`` run one after another
    against the one cell (each to its end, the next started then), every one in its own session
    (``env``: extra environment variables of the cell and the nodes)."""
    env = {**_loopback_env(domain), **(env or {})}
    shm_before = _dds_files()
    spawn = dict(env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, start_new_session=True)
    cell_command = [sys.executable, "-m", "omtp_drake.cli", "ros2", *cell_args, "--domain-id", str(domain)]
    cell = subprocess.Popen(cell_command, **spawn)  # type: ignore[call-overload]
    ran: list[subprocess.Popen] = []
    try:
        for node_args in nodes:
            ran.append(subprocess.Popen([sys.executable, *node_args], **spawn))  # type: ignore[call-overload]
            _, node_err = ran[-1].communicate(timeout=PATIENCE)
            assert ran[-1].returncode == 0, node_err[-3000:]
        cell.send_signal(signal.SIGINT)  # Ctrl-C
        cell_out, cell_err = cell.communicate(timeout=PATIENCE)
    finally:
        for process in ran:
            _end(process)
        _end(cell)
    assert cell.returncode == 0, cell_err[-3000:]
    assert not _session_members(cell.pid) and not any(_session_members(p.pid) for p in ran)
    assert not _leaked_dds_files(shm_before, domain), "Fast DDS left shared memory behind"
    return cell_out, cell_err


def run_cell_until(
    cell_args: list[str],
    until: str,
    domain: int,
    patience: float = PATIENCE,
    node_args: list[str] | None = None,
) -> str:
    """``omtp-drake ros2 CELL_ARGS`` on ``domain`` (loopback) in its own session until a line
    of its output holds ``until`` (at most ``patience`` wall seconds), then Ctrl-C: it must exit 0
    and leave no process (nor any node it started) and none of the domain's Fast DDS shared
    memory behind. With ``node_args``, the node ``python NODE_ARGS`` runs beside the cell in its
    own session and must end by itself with 0 before the Ctrl-C. Returns the cell's output
    (stdout and stderr)."""
    shm_before = _dds_files()
    env = _loopback_env(domain)
    command = [sys.executable, "-m", "omtp_drake.cli", "ros2", *cell_args, "--domain-id", str(domain)]
    cell = subprocess.Popen(
        command, env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, start_new_session=True
    )  # fmt: skip
    node = None
    if node_args is not None:
        node = subprocess.Popen(
            [sys.executable, *node_args], env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
            start_new_session=True,
        )  # fmt: skip
    lines: list[str] = []
    seen = threading.Event()

    def read() -> None:
        for line in cell.stdout or ():
            lines.append(line)
            if until in line:
                seen.set()

    reader = threading.Thread(target=read, daemon=True)
    reader.start()
    try:
        if node is not None:
            _, node_err = node.communicate(timeout=patience)
            assert node.returncode == 0, node_err[-3000:]
        seen.wait(timeout=patience)
        cell.send_signal(signal.SIGINT)  # Ctrl-C
        cell.wait(timeout=PATIENCE)
        reader.join(timeout=PATIENCE)
    finally:
        if node is not None:
            _end(node)
        _end(cell)
    out = "".join(lines)
    assert cell.returncode == 0, out[-3000:]
    assert not _session_members(cell.pid) and (node is None or not _session_members(node.pid))
    assert not _leaked_dds_files(shm_before, domain), "Fast DDS left shared memory behind"
    return out


@needs_ros2
def test_a_students_rclpy_node_drives_and_watches_the_cell(tmp_path, domain):
    scenario = tmp_path / "rgbd.yaml"
    scenario.write_text(RGBD_SCENARIO)
    out = tmp_path / "seen.json"
    cell_out, _ = run_cell_with_node([str(scenario)], [str(SCRIPTS / "student_node.py"), str(out)], domain)
    assert f"ROS_DOMAIN_ID={domain}" in cell_out and "stopped at t=" in cell_out
    seen = json.loads(out.read_text())
    _check_clock_and_joints(seen)
    _check_cloud(seen["cloud"], scenario)
    assert seen["gripper"]["success"] is True and seen["gripper"]["message"].startswith("vacuum on")
    assert seen["conveyor"] == {"success": True, "message": "conveyor power 100"}
    _check_logical_camera(seen["logical_camera"])
    urdf = seen["description"]
    assert urdf.startswith("<?xml") and 'name="omtp"' in urdf and 'filename="file:///' in urdf
    assert all(f'name="robot1_{j}_joint"' in urdf for j in ("shoulder_pan", "elbow", "wrist_3"))


def _check_clock_and_joints(seen: dict) -> None:
    clocks = seen["clocks"]
    assert clocks == sorted(clocks) and clocks[-1] > clocks[0], clocks[:10]
    # /clock is published at every 10 ms step of simulated time.
    assert np.allclose(np.round(np.array(clocks) / 0.01) * 0.01, clocks, atol=1e-6), clocks[:10]
    assert seen["now"] > 0.0  # the node's clock is /clock (use_sim_time)
    # robot1 starts at the scenario's initial pose.
    from omtp_drake.cell import arms
    from omtp_drake.scenario import load_scenario

    robot = next(r for r in load_scenario("lecture6_assignment1").robots if r.name == "robot1")
    assert np.allclose(seen["joints_before"], arms.named_pose(robot.initial_pose, robot), atol=2e-3)


def _check_logical_camera(camera: dict) -> None:
    """Camera 1 reports the part (among the cell's models) where it rests, in the camera's frame."""
    from omtp_drake.scenario import load_scenario
    from omtp_drake.sim.runtime import FactoryRuntime

    assert camera["frame_id"] == "logical_camera_1_frame"
    assert "object_1" in camera["labels"]
    runtime = FactoryRuntime(load_scenario("lecture6_assignment1"))
    runtime.advance_to(0.5)
    p_CM = runtime.camera_image("logical_camera_1").pose_of("object_1").pose.translation()
    assert min(np.linalg.norm(np.array(camera["positions"]) - p_CM, axis=1)) < 0.01
    # /omtp/parts: the one part, resting on the belt, in world.
    assert camera["parts_frame"] == "world" and len(camera["parts"]) == 1
    assert np.allclose(camera["parts"][0], [*PART_XY, PART_TOP_Z - 0.1], atol=0.01), camera["parts"]


def _check_cloud(cloud: dict, scenario: Path) -> None:
    """The points, in the camera's optical frame, lie on the part's top face in the world
    and within 1 cm of the cell's geometry."""
    from omtp_drake.cell.logical_camera import X_CameraOptical
    from omtp_drake.scenario import load_scenario
    from omtp_drake.sim.runtime import FactoryRuntime

    assert cloud["frame_id"] == "logical_camera_1_optical_frame"
    assert (cloud["height"], cloud["width"]) == (213, 320)
    p_O = np.array(cloud["points"])
    assert len(p_O) > 1000
    runtime = FactoryRuntime(load_scenario(scenario))
    runtime.advance_to(cloud["stamp"])
    X_WO = runtime.camera_image("logical_camera_1").X_WC @ X_CameraOptical()
    p_W = (X_WO.GetAsMatrix34() @ np.c_[p_O, np.ones(len(p_O))].T).T
    assert np.all(np.abs(p_W[:, 2] - PART_TOP_Z) < 0.01), np.percentile(p_W[:, 2], [0, 50, 100])
    assert np.all(np.abs(p_W[:, :2] - PART_XY) < 0.1 + 0.01)
    plant = runtime.station.plant
    query = plant.get_geometry_query_input_port().Eval(plant.GetMyContextFromRoot(runtime.context))
    distance = [
        min((abs(d.distance) for d in query.ComputeSignedDistanceToPoint(p, 0.05)), default=1.0) for p in p_W
    ]
    assert max(distance) < 0.01


def test_the_network_stays_on_loopback_unless_asked():
    network = choose_network(42)
    assert network.environment() == {
        "ROS_DOMAIN_ID": "42",
        "ROS_AUTOMATIC_DISCOVERY_RANGE": "LOCALHOST",
        "ROS_LOCALHOST_ONLY": "1",
    }
    assert choose_network(42, subnet=True).environment()["ROS_AUTOMATIC_DISCOVERY_RANGE"] == "SUBNET"
    with pytest.raises(ConfigError, match="0..232, got 233"):
        Ros2Network(233)


def test_a_domain_above_101_is_taken_with_one_warning(caplog):
    """rclpy takes 0-232; ROS 2's docs warn of Linux's ephemeral ports above 101, and so
    does the network, once."""
    with caplog.at_level("WARNING", logger="omtp_drake.ros2.network"):
        assert Ros2Network(150).domain_id == 150
        Ros2Network(150)
    warnings = [r.getMessage() for r in caplog.records if r.levelname == "WARNING"]
    assert len(warnings) == 1 and "ROS_DOMAIN_ID=150" in warnings[0] and "ephemeral" in warnings[0]
    caplog.clear()
    with caplog.at_level("WARNING", logger="omtp_drake.ros2.network"):
        Ros2Network(101)
    assert not caplog.records


def test_the_domain_comes_from_the_environment_when_not_given(monkeypatch):
    monkeypatch.setenv("ROS_DOMAIN_ID", "17")
    assert choose_network().domain_id == 17
    monkeypatch.setenv("ROS_DOMAIN_ID", "seventeen")
    with pytest.raises(ConfigError, match="'seventeen'"):
        choose_network()
    monkeypatch.delenv("ROS_DOMAIN_ID")
    assert 1 <= choose_network().domain_id <= 101


@pytest.mark.parametrize("missing", ["rclpy", "builtin_interfaces"])
def test_without_the_extra_the_command_names_it(tmp_path, missing):
    """A Python whose rclpy (or a message package the bridge imports first) cannot be
    imported: one error line naming the extra."""
    blocker = tmp_path / f"{missing}.py"
    blocker.write_text("raise ImportError('librmw_fastrtps_cpp.so: cannot open shared object file')\n")
    env = dict(os.environ, PYTHONPATH=str(tmp_path))
    done = subprocess.run(
        [sys.executable, "-m", "omtp_drake.cli", "ros2", "lecture6_assignment1", "--timeout", "1"],
        env=env,
        capture_output=True,
        text=True,
        timeout=PATIENCE,
    )
    assert done.returncode == 2
    lines = done.stderr.strip().splitlines()
    assert len(lines) == 1 and "ros2 extra" in lines[0] and ".[ros2]" in lines[0], done.stderr


@needs_ros2
def test_timeout_ends_a_realtime_run_at_that_simulated_time(network, capsys):
    """``omtp-drake ros2 --timeout S --realtime``: the paced run ends at S simulated seconds, exit 0.
    In-process, through the command line's own ``main`` (its parser, ``cmd_ros2``, ``run_ros2``):
    the process boundary (signals, exit codes, what a process leaves behind) is the other tests'."""
    from omtp_drake.cli import main

    argv = ["ros2", "lecture6_assignment1", "--timeout", "0.25", "--realtime"]
    assert main([*argv, "--domain-id", str(network.domain_id)]) == 0
    out = capsys.readouterr().out
    assert f"ROS_DOMAIN_ID={network.domain_id}" in out and "stopped at t=0.25 s" in out, out


def test_set_joint_values_puts_the_arm_there_and_holds_it():
    """Gazebo's SetPosition: the arm is there at once, at rest, and its servo keeps it there."""
    from omtp_drake.errors import UnreachableError
    from omtp_drake.script import Cell

    q = [0.4, -1.4, 1.2, -1.4, -1.57, 0.2]
    with Cell("lecture6_assignment1") as cell:
        arm = cell.arm("robot1")
        arm.set_joint_values(q)
        assert np.allclose(arm.joint_values(), q, atol=1e-12)
        cell.wait(1.0)
        assert np.allclose(arm.joint_values(), q, atol=1e-3)
        with pytest.raises(UnreachableError, match="outside the joint limits"):
            arm.set_joint_values([0.0, 0.0, 10.0, 0.0, 0.0, 0.0])
        assert np.allclose(arm.joint_values(), q, atol=1e-3)  # nothing half-done
