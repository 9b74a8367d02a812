"""/tf, /tf_static and /gazebo/model_states over ROS 2, by rclpy with tf2_msgs and gazebo_msgs
built here, or by Cyclone DDS beside rclpy where they cannot be built: the packed bytes are
those rclpy serializes, and a late plain rclpy reader in another process
(tests/ros2_scripts/rclpy_tf_reader.py) gets every link of the cell's URDF at the plant's pose
(1 mm) by either route (Cyclone's: a Fast DDS subscriber matching a Cyclone writer's
``sequence<struct>`` type). Loopback only, a domain of its own, nothing left behind.
"""

from __future__ import annotations

import json
import os
import shutil
import signal
import subprocess
import sys
import xml.etree.ElementTree as ET

import numpy as np
import pytest
from test_ros2 import (  # one home of the DDS tests' helpers
    PATIENCE,
    SCRIPTS,
    _dds_files,
    _end,
    _leaked_dds_files,
    _loopback_env,
    _session_members,
    domain,
    needs_ros2,
)

__all__ = ["domain"]  # the fixture, used by name

needs_compiler = pytest.mark.skipif(
    shutil.which("cc") is None or shutil.which("c++") is None,
    reason="no C/C++ compiler to build tf2_msgs and gazebo_msgs: apt-get install g++",
)


def _rclpy_pairs():
    """(mirror, an rclpy message of the same type with distinct values in every field)."""
    from builtin_interfaces.msg import Time
    from geometry_msgs.msg import Point, Pose, Quaternion, Transform, TransformStamped, Twist, Vector3
    from std_msgs.msg import Header

    from omtp_drake.ros2 import dds_types as d

    time = Time(sec=12, nanosec=345)
    header = Header(stamp=time, frame_id="robot1_base_link")
    vector, point = Vector3(x=0.1, y=-0.2, z=0.3), Point(x=1.5, y=2.5, z=-3.5)
    rotation = Quaternion(x=0.1, y=0.2, z=0.3, w=0.9)
    transform = Transform(translation=vector, rotation=rotation)
    pose = Pose(position=point, orientation=rotation)
    mirrors = {
        d.Time_: (time, d.Time_(12, 345)),
        d.Header_: (header, d.Header_(d.Time_(12, 345), "robot1_base_link")),
        d.Vector3_: (vector, d.Vector3_(0.1, -0.2, 0.3)),
        d.Point_: (point, d.Point_(1.5, 2.5, -3.5)),
        d.Quaternion_: (rotation, d.Quaternion_(0.1, 0.2, 0.3, 0.9)),
        d.Transform_: (
            transform,
            d.Transform_(d.Vector3_(0.1, -0.2, 0.3), d.Quaternion_(0.1, 0.2, 0.3, 0.9)),
        ),
        d.Pose_: (pose, d.Pose_(d.Point_(1.5, 2.5, -3.5), d.Quaternion_(0.1, 0.2, 0.3, 0.9))),
        d.Twist_: (
            Twist(linear=vector, angular=Vector3(z=4.0)),
            d.Twist_(d.Vector3_(0.1, -0.2, 0.3), d.Vector3_(0, 0, 4.0)),
        ),
    }
    stamped = TransformStamped(header=header, child_frame_id="a", transform=transform)
    mirrors[d.TransformStamped_] = (
        stamped,
        d.TransformStamped_(mirrors[d.Header_][1], "a", mirrors[d.Transform_][1]),
    )
    return mirrors


@needs_ros2
def test_every_mirror_serializes_as_rclpy_does():
    """Byte for byte (XCDR1, little endian), padding aside (rclpy leaves it uninitialized,
    Cyclone zeroes it); and each side reads the other's bytes back to the same message."""
    from rclpy.serialization import deserialize_message, serialize_message

    from omtp_drake.ros2.dds_types import ROS_TYPES

    pairs = _rclpy_pairs()
    assert set(pairs) == {
        m for m, name in ROS_TYPES.items() if not name.startswith(("tf2_msgs", "gazebo_msgs"))
    }
    for mirror, (message, value) in pairs.items():
        ours, theirs = value.serialize(use_version_2=False), serialize_message(message)
        assert len(ours) == len(theirs), mirror
        differ = [i for i in range(len(ours)) if ours[i] != theirs[i]]
        assert all(ours[i] == 0 for i in differ), (mirror, differ)
        assert len(differ) <= 6, (mirror, differ)  # at most the padding after two short strings
        assert deserialize_message(ours, type(message)) == message, mirror
        assert mirror.deserialize(theirs) == value, mirror


@needs_ros2
def test_the_mirrors_without_an_rclpy_type_match_their_msg_definitions():
    """TFMessage, ModelStates and LinkStates: Cyclone's bytes are those the bag's encoder writes from the
    .msg definitions (ROS 2's fields, in ROS 2's order)."""
    from mcap_ros2._dynamic import serialize_dynamic

    from omtp_drake.ros.bag.definitions import concatenated, installed_text
    from omtp_drake.ros2 import cdr
    from omtp_drake.ros2 import dds_types as d

    stamped = _rclpy_pairs()[d.TransformStamped_][1]
    twist, pose = _rclpy_pairs()[d.Twist_][1], _rclpy_pairs()[d.Pose_][1]
    tf = d.TFMessage_([stamped, stamped])
    states = d.ModelStates_(["a", "bc"], [pose, pose], [twist, twist])
    links = d.LinkStates_(["a::l", "bc::m"], [pose, pose], [twist, twist])
    for value in (tf, states, links):
        name = d.ROS_TYPES[type(value)]
        encode = serialize_dynamic(name, concatenated(name, installed_text))[name]
        assert value.serialize(use_version_2=False) == encode(value), name
    # What the node writes: the same bytes, packed at once (omtp_drake.ros2.cdr).
    numbers = (12, 345, 0.1, -0.2, 0.3, 0.1, 0.2, 0.3, 0.9)
    assert cdr.tf_message([("robot1_base_link", "a")] * 2, [numbers] * 2) == tf.serialize(use_version_2=False)
    poses, twists = [(1.5, 2.5, -3.5, 0.1, 0.2, 0.3, 0.9)] * 2, [(0.1, -0.2, 0.3, 0, 0, 4)] * 2
    assert cdr.model_states(["a", "bc"], poses, twists) == states.serialize(use_version_2=False)
    assert cdr.model_states(["a::l", "bc::m"], poses, twists) == links.serialize(use_version_2=False)
    assert cdr.model_states([], [], []) == d.ModelStates_().serialize(use_version_2=False)


@needs_ros2
@needs_compiler
def test_the_packed_bytes_are_what_rclpy_serializes_with_the_built_types(monkeypatch):
    """The rclpy route publishes the packed bytes as a serialized message: they are the bytes
    rclpy's type support (built here) writes for TFMessage and ModelStates, and read back."""
    from rclpy.serialization import deserialize_message, serialize_message

    from omtp_drake.ros2 import cdr
    from omtp_drake.ros2.interface_build import interfaces_path

    monkeypatch.syspath_prepend(str(interfaces_path()))
    from gazebo_msgs.msg import LinkStates, ModelStates
    from tf2_msgs.msg import TFMessage

    stamped = _rclpy_pairs()[_mirror("TransformStamped_")][0]
    numbers = (12, 345, 0.1, -0.2, 0.3, 0.1, 0.2, 0.3, 0.9)
    packed = cdr.tf_message([("robot1_base_link", "a")] * 2, [numbers] * 2)
    message = TFMessage(transforms=[stamped, stamped])
    assert deserialize_message(packed, TFMessage) == message
    _same_but_padding(packed, serialize_message(message))
    pose, twist = _rclpy_pairs()[_mirror("Pose_")][0], _rclpy_pairs()[_mirror("Twist_")][0]
    poses, twists = [(1.5, 2.5, -3.5, 0.1, 0.2, 0.3, 0.9)] * 2, [(0.1, -0.2, 0.3, 0, 0, 4)] * 2
    for kind, names in ((ModelStates, ["a", "bc"]), (LinkStates, ["a::l", "bc::m"])):
        packed = cdr.model_states(names, poses, twists)
        message = kind(name=names, pose=[pose, pose], twist=[twist, twist])
        assert deserialize_message(packed, kind) == message
        _same_but_padding(packed, serialize_message(message))


def _same_but_padding(ours: bytes, theirs: bytes) -> None:
    """Byte for byte where rclpy writes values; where it leaves padding uninitialized, ours is 0
    (the values themselves: the callers read the bytes back)."""
    assert len(ours) == len(theirs)
    differ = [i for i in range(len(ours)) if ours[i] != theirs[i]]
    assert all(ours[i] == 0 for i in differ), differ


def _mirror(name: str) -> type:
    from omtp_drake.ros2 import dds_types

    return getattr(dds_types, name)


def _chain(name: str, edges: dict[str, tuple[str, np.ndarray]]) -> np.ndarray:
    """X_W<name> (4x4) composed from the parent -> child transforms."""
    X = np.eye(4)
    while name != "world":
        name, X_PC = edges[name]
        X = X_PC @ X
    return X


def _matrix(t: dict) -> np.ndarray:
    from pydrake.common.eigen_geometry import Quaternion
    from pydrake.math import RigidTransform

    x, y, z, w = t["xyzw"]
    return RigidTransform(Quaternion(w, x, y, z), t["xyz"]).GetAsMatrix4()


def _without_the_built_types(tmp_path, env: dict[str, str]) -> None:
    """``env`` as a machine's where tf2_msgs and gazebo_msgs cannot be built: no compiler on PATH,
    and a model cache without them (the real cache's other entries, linked)."""
    from omtp_drake.assets import cache_dir

    real = cache_dir()
    cache = tmp_path / "cache" / real.name
    cache.mkdir(parents=True)
    for entry in real.iterdir():
        if not entry.name.startswith("ros2_interfaces"):
            (cache / entry.name).symlink_to(entry)
    (tmp_path / "bin").mkdir()
    env.update(OMTP_DRAKE_CACHE=str(cache.parent), PATH=str(tmp_path / "bin"))


@needs_ros2
@needs_compiler
@pytest.mark.parametrize("route", ["rclpy", "cyclone"])
def test_a_late_rclpy_reader_gets_every_link_of_the_urdf_at_the_plants_pose(tmp_path, domain, route):
    """A plain rclpy node in another process (tf2_msgs and gazebo_msgs built here on its
    PYTHONPATH) joins late: /tf_static (transient local), /tf and /gazebo/model_states, whichever
    route writes them: rclpy with the built types (the node ``omtp_cell`` publishes /tf), or
    Cyclone DDS where they cannot be built (forced here as the no-compiler test forces it: one
    warning, and /tf has no ROS node). ``--bag`` records them either way."""
    from omtp_drake.ros2.interface_build import interfaces_path
    from omtp_drake.ros2.packed_topics import BY_CYCLONE

    env = _loopback_env(domain)
    env["PYTHONPATH"] = os.pathsep.join(p for p in (str(interfaces_path()), env.get("PYTHONPATH")) if p)
    cell_env = dict(env)
    if route == "cyclone":
        _without_the_built_types(tmp_path, cell_env)
    out = tmp_path / "tf.json"
    shm_before = _dds_files()
    spawn = dict(stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, start_new_session=True)
    # Paced (--realtime): the reader needs a few /tf messages, not a cell running flat out (and
    # recording all of it) while the reader starts and waits for the /tf publishers' names.
    cell = subprocess.Popen(
        [sys.executable, "-m", "omtp_drake.cli", "ros2", "lecture6_assignment1", "--domain-id", str(domain)]
        + ["--bag", str(tmp_path / "run.mcap"), "--realtime"],
        env=cell_env,
        **spawn,  # type: ignore[call-overload]
    )
    reader = None
    try:
        assert cell.stdout is not None
        first = cell.stdout.readline()  # the node is up: /tf_static went out before this line
        assert "as node /omtp_cell" in first, first + (cell.stderr.read() if cell.poll() is not None else "")
        reader = subprocess.Popen(
            [sys.executable, str(SCRIPTS / "rclpy_tf_reader.py"), str(out)],
            env=env,
            **spawn,  # type: ignore[call-overload]
        )
        _, reader_err = reader.communicate(timeout=PATIENCE)
        cell.send_signal(signal.SIGINT)
        _, cell_err = cell.communicate(timeout=PATIENCE)
    finally:
        for process in (reader, cell):
            if process is not None:
                _end(process)
    assert reader.returncode == 0, reader_err[-3000:]
    assert cell.returncode == 0, cell_err[-3000:]
    assert not _session_members(cell.pid) and not _session_members(reader.pid)
    assert not _leaked_dds_files(shm_before, domain), "Fast DDS left shared memory behind"
    seen = json.loads(out.read_text())
    assert seen["types"]["/tf"] == ["tf2_msgs/msg/TFMessage"]
    assert seen["types"]["/tf_static"] == ["tf2_msgs/msg/TFMessage"]
    assert seen["types"]["/gazebo/model_states"] == ["gazebo_msgs/msg/ModelStates"]
    warned = [line for line in cell_err.splitlines() if BY_CYCLONE in line]
    if route == "rclpy":
        assert seen["tf_publishers"] == ["omtp_cell"] and not warned
    else:
        assert seen["tf_publishers"] != ["omtp_cell"]
        assert len(warned) == 1 and "no cc or c++ compiler on PATH" in warned[0], cell_err[-3000:]
    _check_links(seen)
    _check_bag(tmp_path / "run.mcap", seen)
    models = dict(zip(seen["models"]["name"], seen["models"]["xyz"]))
    assert np.allclose(models["object_1"][:2], [1.2, 1.8], atol=0.01), models


def _check_links(seen: dict) -> None:
    """Every link of /robot_description, composed from /tf_static and one /tf message, is
    where the plant has it at that message's stamp (1 mm, 1 mrad)."""
    from omtp_drake.cell.frames import FrameTree
    from omtp_drake.scenario import load_scenario
    from omtp_drake.sim.runtime import FactoryRuntime

    links = [link.get("name") for link in ET.fromstring(seen["description"]).iter("link")]
    message = seen["tf"][-1]
    # The models a logical camera sees, stamped with the camera's image: camera 1 sees the part.
    detected = [t for t in message if t["child"].startswith(t["parent"].removesuffix("frame"))]
    moving = [t for t in message if t not in detected]
    stamp = moving[0]["stamp"]
    assert all(t["stamp"] == stamp for t in moving) and stamp > 0
    # The last image the tf buffer holds: at most a camera period (0.1 s) and a tick (0.1 s) old.
    assert all(stamp - 0.2 - 1e-6 <= t["stamp"] <= stamp + 1e-6 for t in detected), (stamp, detected)
    assert all(t["stamp"] == 0.0 for t in seen["static"])
    edges = {t["child"]: (t["parent"], _matrix(t)) for t in seen["static"] + message}
    assert len(edges) == len(seen["static"]) + len(message), "a frame is both static and moving"
    X_WP = _chain("logical_camera_1_object_1_frame", edges)
    assert np.allclose(X_WP[:2, 3], [1.2, 1.8], atol=0.01), X_WP
    runtime = FactoryRuntime(load_scenario("lecture6_assignment1"))
    runtime.advance_to(stamp)
    tree = FrameTree(runtime.station.plant)
    plant_context = runtime.station.plant.GetMyContextFromRoot(runtime.context)
    missing = [link for link in links if link != "world" and link not in edges]
    assert not missing, missing
    for link in links:
        X_expected = tree.frame(link).CalcPoseInWorld(plant_context).GetAsMatrix4()
        X = _chain(link, edges)
        assert np.linalg.norm(X[:3, 3] - X_expected[:3, 3]) < 1e-3, link
        assert np.allclose(X[:3, :3], X_expected[:3, :3], atol=1e-3), link


def _check_bag(path, seen: dict) -> None:
    """``--bag``: what the reader got, in a ROS 2 bag."""
    from mcap.reader import make_reader
    from mcap_ros2.decoder import DecoderFactory

    with path.open("rb") as f:
        reader = make_reader(f, decoder_factories=[DecoderFactory()])
        summary = reader.get_summary()
        channels = {c.topic: c for c in summary.channels.values()}
        types = {topic: summary.schemas[c.schema_id].name for topic, c in channels.items()}
        assert types["/tf"] == "tf2_msgs/msg/TFMessage" and types["/clock"] == "rosgraph_msgs/msg/Clock"
        assert types["/joint_states"] == "sensor_msgs/msg/JointState"
        assert "durability: 1" in channels["/robot_description"].metadata["offered_qos_profiles"]
        static = next(m for _, _, _, m in reader.iter_decoded_messages(topics=["/tf_static"]))
        assert sorted(t.child_frame_id for t in static.transforms) == sorted(
            t["child"] for t in seen["static"]
        )
        stamps = [m.publish_time for _, _, m in reader.iter_messages(topics=["/tf"])]
        assert len(stamps) >= 5 and stamps == sorted(stamps)
