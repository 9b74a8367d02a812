"""Gazebo's world over both transports, from one plugin layer: a plain rclpy peer in another
process starts the course's spawner under ``omtp-drake ros2 lecture7_conveyor`` and sees the
part appear in /gazebo/model_states and /gazebo/link_states (raw Cyclone readers: no
gazebo_msgs wheel); a course-style rospy script does the same under ros-run; both see the
same models and links, the part 3 s (the spawner's period) after the call. Before that peer,
on the same cell, a student's plain rclpy client of Gazebo's model services (``gazebo_msgs``
built here, tests/ros2_scripts/gazebo_services_node.py) spawns a course box, reads its state,
moves it and deletes it (tests/test_ros2_gazebo_services.py has the rest of those services).
One cell serves both peers, one after the other (the module's fixture ``ros2_seen``): the
tests only read what the peers saw. Loopback only, a domain of its own (the DDS helper holds
it), nothing left behind.
"""

from __future__ import annotations

import json
import os
import shutil

import pytest
from test_ros2 import SCRIPTS, hold_domain, needs_ros2, run_cell_with_nodes

SCENARIO = "lecture7_conveyor"
#: lecture7_conveyor's spawner: period (s), the part's resting place on the belt.
PERIOD = 3.0
SPAWN_XY = (1.2, 2.5)

HAVE_COMPILER = shutil.which("cc") is not None and shutil.which("c++") is not None
needs_compiler = pytest.mark.skipif(
    not HAVE_COMPILER, reason="no C/C++ compiler to build gazebo_msgs: apt-get install g++"
)


@pytest.fixture(scope="module")
def ros1_seen(tmp_path_factory):
    from omtp_drake.ros import run_script

    out = tmp_path_factory.mktemp("ros1") / "seen.json"
    report = run_script(SCRIPTS / "ros1_spawner_script.py", [str(out)], scenario=SCENARIO, timeout=30.0)
    assert report.ok, report.summary()
    return json.loads(out.read_text())


@pytest.fixture(scope="module")
def ros2_seen(tmp_path_factory) -> dict:
    """One ``omtp-drake ros2 lecture7_conveyor`` cell, and in turn: (with gazebo_msgs built here)
    a student's client of Gazebo's model services, whose box is deleted again when it ends; then
    the course's spawner started by a peer watching Gazebo's states. What each saw, by name
    ("services", "spawner"), and the cell's stderr."""
    tmp = tmp_path_factory.mktemp("gazebo_world")
    paths = {name: tmp / f"{name}.json" for name in ("services", "spawner")}
    env = {}
    nodes = []
    with hold_domain() as domain:
        if HAVE_COMPILER:
            from omtp_drake.ros2 import interface_build

            built = (str(interface_build.interfaces_path()), os.environ.get("PYTHONPATH", ""))
            env["PYTHONPATH"] = os.pathsep.join(p for p in built if p)
            nodes.append([str(SCRIPTS / "gazebo_services_node.py"), str(domain), str(paths["services"])])
        nodes.append([str(SCRIPTS / "spawner_node.py"), str(domain), str(paths["spawner"])])
        _, cell_err = run_cell_with_nodes([SCENARIO], nodes, domain, env)
    seen = {name: json.loads(path.read_text()) for name, path in paths.items() if path.exists()}
    return {**seen, "cell_err": cell_err}


def _check(seen: dict) -> None:
    """The part the spawner made, in both topics, after one period."""
    (part,) = [n for n in seen["models"] if n not in seen["before"]]
    assert part.startswith("object_")
    assert seen["models"] == seen["before"] + [part]  # the fixed models, then the part
    assert f"{part}::box_base_link" in seen["links"]
    assert all(f"{m}::" in " ".join(seen["links"]) for m in seen["before"])
    assert seen["spawned"]["frame_id"] == "box"
    assert seen["spawned"]["stamp"] >= seen["called"] + PERIOD - 0.011


def test_ros1_spawner_parts_appear_in_model_and_link_states(ros1_seen):
    _check(ros1_seen)
    # Under ros-run the call is at a simulated instant: the part comes one period after it.
    assert ros1_seen["spawned"]["stamp"] == pytest.approx(ros1_seen["called"] + PERIOD, abs=0.011)


@needs_ros2
def test_both_transports_give_the_same_models_and_links(ros2_seen, ros1_seen):
    seen, cell_err = ros2_seen["spawner"], ros2_seen["cell_err"]
    _check(seen)
    part = seen["models"].index(next(n for n in seen["models"] if n.startswith("object_")))
    assert seen["object_xyz"][part][:2] == pytest.approx(SPAWN_XY, abs=0.05)
    # The same models and links, the part's number aside: on this cell the services peer's box
    # took a part of the pool before the spawner's (object_2 here, object_1 under ros-run).
    (ros1_part,) = [n for n in ros1_seen["models"] if n not in ros1_seen["before"]]
    ros2_part = seen["models"][part]

    def numbered_as_ros1(names: list[str]) -> list[str]:
        return [ros1_part + n.removeprefix(ros2_part) if n.split("::")[0] == ros2_part else n for n in names]

    assert seen["before"] == ros1_seen["before"]
    assert numbered_as_ros1(seen["models"]) == ros1_seen["models"]
    assert numbered_as_ros1(seen["links"]) == ros1_seen["links"]
    # Gazebo's model services are served (gazebo_msgs built here; tests/test_ros2_gazebo_services.py).
    assert "not served on ROS 2" not in cell_err, cell_err[-2000:]


@needs_ros2
@needs_compiler
def test_a_students_rclpy_client_spawns_moves_and_deletes_a_box(ros2_seen):
    from omtp_drake.ros2 import gazebo_services

    seen, cell_err = ros2_seen["services"], ros2_seen["cell_err"]
    assert seen["spawn"] == [True, "SpawnModel: Successfully spawned entity"]
    # Any other model: refused with the layer's one message (what is supported).
    assert seen["spawn_other"][0] is False
    assert "this cell spawns the course's parts only" in seen["spawn_other"][1]
    # Asked at z 1.3 above the belt: there, or falling onto it (x, y as asked).
    assert seen["spawned"]["success"]
    assert seen["spawned"]["xyz"][:2] == pytest.approx([1.2, 2.5], abs=0.01)
    assert 0.9 < seen["spawned"]["xyz"][2] <= 1.3 + 1e-6
    assert seen["link"]["success"] and seen["link"]["frame_id"] == "world"
    assert seen["set"] is True
    assert seen["moved"]["xyz"][:2] == pytest.approx([1.2, 2.0], abs=0.01)
    assert 0.9 < seen["moved"]["xyz"][2] <= 1.6 + 1e-6
    assert seen["delete"] == [True, "DeleteModel: successfully deleted model"]
    assert seen["deleted"]["success"] is False
    assert seen["delete_unknown"] == [False, "DeleteModel: model does not exist"]
    # /pause_physics: /clock stands still for 1 s of wall time; /unpause_physics: it runs again.
    assert seen["paused_clock"][0] == seen["paused_clock"][1]
    assert seen["unpaused_clock"] > seen["paused_clock"][1]
    assert gazebo_services.NOT_SERVED not in cell_err
    # /reset_simulation: answered, refused in one error line (the layer's, as ROS 1's
    # NotSupportedError), and time did not go back.
    refused = [line for line in cell_err.splitlines() if "/reset_simulation" in line]
    assert len(refused) == 1, cell_err[-3000:]
    assert "(Gazebo sets simulated time back to 0) is not supported" in refused[0]
    assert "/reset_world puts the parts back" in refused[0]
    assert seen["after_reset_simulation"] >= seen["unpaused_clock"]
