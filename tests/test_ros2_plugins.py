"""The course's vacuum gripper, conveyor and break beam plugins, defined once in
``omtp_drake/gazebo/`` and served over both transports: a plain rclpy node in another
process (tests/ros2_scripts/plugins_node.py) under ``omtp-drake ros2`` and a rospy script
(tests/ros2_scripts/ros1_plugins_script.py) under ``ros-run`` make the same requests (read
the beam, switch gripper 1 on and off, power the belt, wait for the beam to see the part it
carries, stop the belt) and get the same answers.

DDS stays on loopback, in a domain of the test's own, and no process is left behind.
"""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from test_ros2 import hold_domain, needs_ros2, run_cell_with_node

SCRIPTS = Path(__file__).parent / "ros2_scripts"
#: The factory cell with a part on the belt upstream of the beam (beam at y = 1.9; the part's
#: leading face at y = 2.2, 0.3 m away: 1.5 s at full power, 0.2 m/s).
SCENARIO = """\
base: omtp_factory
parts:
  - {name: object_1, xyz: [1.2, 2.3, 1.021], rpy: [0.0, 0.0, 0.0], size: 0.2, mass: 0.2}
"""
#: What each request gets, the same on both transports.
EXPECTED = {
    "beam_before": False,
    "gripper_on": {"success": True, "enabled": True, "attached": False},
    "gripper_off": {"success": True, "enabled": False, "attached": False},
    "conveyor_on": True,
    "beam_changes": [True],
    "conveyor_off": True,
}


@pytest.fixture(scope="module")
def runs(tmp_path_factory):
    """(what the rclpy node saw, what the rospy script saw)."""
    from omtp_drake.ros.run.runner import run_script

    tmp = tmp_path_factory.mktemp("plugins")
    scenario = tmp / "belt_part.yaml"
    scenario.write_text(SCENARIO)
    ros2_out, ros1_out = tmp / "ros2.json", tmp / "ros1.json"
    with hold_domain() as domain:
        run_cell_with_node([str(scenario)], [str(SCRIPTS / "plugins_node.py"), str(ros2_out)], domain)
    report = run_script(SCRIPTS / "ros1_plugins_script.py", [str(ros1_out)], scenario=scenario, timeout=10.0)
    assert report.exception is None, report.exception
    return json.loads(ros2_out.read_text()), json.loads(ros1_out.read_text())


@needs_ros2
def test_one_request_sequence_gives_the_same_results_on_both_transports(runs):
    ros2, ros1 = runs
    assert {k: ros2[k] for k in EXPECTED} == EXPECTED
    assert {k: ros1[k] for k in EXPECTED} == EXPECTED


@needs_ros2
def test_the_beam_sees_the_part_when_the_belt_brings_it(runs):
    """The change's stamp is a scan of the beam (10 Hz), 1.5 s of belt travel after the belt
    started (within a scan and the belt's start), in the sensor's frame and range. (ROS 2's
    view has no stamp: that the change came after the belt started is the sequence above.)"""
    _, ros1 = runs
    change = ros1["change"]
    assert change["frame_id"] == "break_beam_sensor_frame"
    assert abs(change["stamp"] * 10 - round(change["stamp"] * 10)) < 1e-6
    assert (change["min_range"], change["max_range"]) == pytest.approx((0.1, 0.6))
    assert 1.3 < ros1["change_after_s"] < 1.8


@needs_ros2
def test_the_course_types_are_on_the_ros2_graph(runs):
    """The plugins' own topics keep the course's names and types (written by Cyclone DDS)."""
    ros2, _ = runs
    assert ros2["types"] == {
        "/gripper1/state": ["omtp_gazebo/msg/VacuumGripperState"],
        "/break_beam_sensor": ["omtp_gazebo/msg/Proximity"],
        "/break_beam_sensor_change": ["omtp_gazebo/msg/Proximity"],
    }


@needs_ros2
def test_a_power_outside_0_100_is_refused_on_ros1(runs):
    _, ros1 = runs
    assert ros1["bad_power"] is False


@needs_ros2
def test_the_course_type_mirrors_write_ros2s_bytes():
    """Each Cyclone mirror of an ``omtp_gazebo`` message serializes to the bytes ROS 2's CDR
    gives its ``.msg`` definition (mcap-ros2-support's encoder of the course's text, as a bag
    stores it): what a ROS 2 node with the type reads."""
    from mcap_ros2._dynamic import serialize_dynamic

    from omtp_drake.gazebo.proximity_ray import Proximity
    from omtp_drake.gazebo.vacuum_gripper import VacuumGripperState
    from omtp_drake.ros.bag.definitions import concatenated
    from omtp_drake.ros.bag.ros1 import ros2_text
    from omtp_drake.ros.comm import interfaces  # noqa: F401  (declares the course's types)
    from omtp_drake.ros2.course_topics import COURSE_TYPES
    from omtp_drake.ros2.course_types import ros_type

    cases = [
        (VacuumGripperState(1.25, True, False), {"enabled": True, "attached": False}),
        (
            Proximity(1.8, "break_beam_sensor_frame", True, 0.1, 0.6),
            {
                "header": {
                    "stamp": {"sec": 1, "nanosec": 800_000_000},
                    "frame_id": "break_beam_sensor_frame",
                },
                "object_detected": True,
                "min_range": 0.1,
                "max_range": 0.6,
            },
        ),
    ]
    for message, fields in cases:
        kind = COURSE_TYPES[type(message)]
        name = ros_type(kind.mirror)
        encode = serialize_dynamic(name, concatenated(name, ros2_text))[name]
        assert kind.convert(message).serialize(use_version_2=False) == encode(fields), name
        assert kind.data(message) == encode(fields), name
