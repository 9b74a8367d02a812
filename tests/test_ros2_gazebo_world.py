"""Gazebo's world over both transports, from one plugin layer: a plain rclpy peer in another
process starts the course's spawner under ``omtp-drake ros2 lecture7_conveyor`` and sees the
part appear in /gazebo/model_states and /gazebo/link_states (raw Cyclone readers: no
gazebo_msgs wheel); a course-style rospy script does the same under ros-run; both see the
same models and links, the part 3 s (the spawner's period) after the call. Loopback only,
a domain of its own (the DDS helper holds it), nothing left behind.
"""

from __future__ import annotations

import json

import pytest
from test_ros2 import SCRIPTS, domain, needs_ros2, run_cell_with_node

__all__ = ["domain"]  # the fixture, used by name

SCENARIO = "lecture7_conveyor"
#: lecture7_conveyor's spawner: period (s), the part's resting place on the belt.
PERIOD = 3.0
SPAWN_XY = (1.2, 2.5)


@pytest.fixture(scope="module")
def ros1_seen(tmp_path_factory):
    from omtp_drake.ros import run_script

    out = tmp_path_factory.mktemp("ros1") / "seen.json"
    report = run_script(SCRIPTS / "ros1_spawner_script.py", [str(out)], scenario=SCENARIO, timeout=30.0)
    assert report.ok, report.summary()
    return json.loads(out.read_text())


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
def test_both_transports_give_the_same_models_and_links(tmp_path, domain, ros1_seen):
    out = tmp_path / "seen.json"
    _, cell_err = run_cell_with_node(
        [SCENARIO], [str(SCRIPTS / "spawner_node.py"), str(domain), str(out)], domain
    )
    seen = json.loads(out.read_text())
    _check(seen)
    part = seen["models"].index(next(n for n in seen["models"] if n.startswith("object_")))
    assert seen["object_xyz"][part][:2] == pytest.approx(SPAWN_XY, abs=0.05)
    for key in ("before", "models", "links"):
        assert seen[key] == ros1_seen[key], key
    # Gazebo's model services are served (gazebo_msgs built here; tests/test_ros2_gazebo_services.py).
    assert "not served on ROS 2" not in cell_err, cell_err[-2000:]
