"""Graph names as rospy resolves them (ros_comm: rosgraph/names.py, rospy/names.py):
canonical names, relative/private/global resolution, command-line remappings,
``__ns``/``__name``, private parameters ``_x:=v`` and ``rospy.myargv``."""

import pytest

from omtp_drake.ros.comm.names import (
    NodeNames,
    canonicalize,
    namespace_of,
    private_params,
    resolve,
    strip_remaps,
)


@pytest.mark.parametrize(
    "name, canonical",
    [
        ("omtp/logical_camera_1/", "omtp/logical_camera_1"),
        ("/omtp//logical_camera_1//", "/omtp/logical_camera_1"),
        ("//a", "/a"),
        ("/", "/"),
        ("~rate/", "~rate"),
        ("", ""),
    ],
)
def test_canonical_names_drop_doubled_and_trailing_slashes(name, canonical):
    assert canonicalize(name) == canonical


def test_namespace_of_a_name():
    assert namespace_of("/robots/reader") == "/robots/"
    assert namespace_of("/reader") == "/"
    assert namespace_of("/") == "/"


@pytest.mark.parametrize(
    "name, caller_id, resolved",
    [
        ("omtp/logical_camera_1/", "/lecture6", "/omtp/logical_camera_1"),
        ("omtp/logical_camera_1", "/robots/lecture6", "/robots/omtp/logical_camera_1"),
        ("/omtp/logical_camera_1", "/robots/lecture6", "/omtp/logical_camera_1"),
        ("~rate", "/robots/lecture6", "/robots/lecture6/rate"),
        ("~/rate/", "/lecture6", "/lecture6/rate"),
        ("", "/robots/lecture6", "/robots/"),
    ],
)
def test_resolution_against_the_node(name, caller_id, resolved):
    assert resolve(name, caller_id) == resolved


def test_an_invalid_name_raises_naming_it():
    with pytest.raises(ValueError, match="a~b"):
        resolve("a~b", "/node")
    with pytest.raises(TypeError, match="str"):
        resolve(3, "/node")


def test_remaps_ns_and_name_from_the_command_line():
    argv = [
        "script.py",
        "out.json",
        "camera:=/omtp/logical_camera_2",
        "_rate:=5",
        "__ns:=robots",
        "__name:=r",
    ]
    names = NodeNames.from_argv(argv, "reader")
    assert names.caller_id == "/robots/r"
    assert names.namespace == "/robots/"
    # Both sides resolve in the node's namespace; the remapped name is the resolved source.
    assert names.remappings == {"/robots/camera": "/omtp/logical_camera_2"}
    assert names.resolve("camera") == "/omtp/logical_camera_2"
    assert names.resolve("/robots/camera/") == "/omtp/logical_camera_2"
    assert names.resolve("/camera") == "/camera"
    assert names.resolve("~rate") == "/robots/r/rate"


def test_private_params_and_myargv():
    argv = ["script.py", "out.json", "_rate:=5", "_frame:=world", "_gains:=[1, 2.5]", "a:=b", "__log:=x"]
    assert private_params(argv) == {"rate": 5, "frame": "world", "gains": [1, 2.5]}
    assert strip_remaps(argv) == ["script.py", "out.json"]


def test_a_relative_name_with_a_trailing_slash_receives_the_camera(course_run):
    report, data = course_run(
        "relative_camera_subscriber.py", scenario="omtp_factory", out_arg=True, timeout=10
    )
    assert report.exception is None
    assert data["topic"] == "/omtp/logical_camera_1"
    # 10 Hz for 1 s; camera 1 hangs at x = 1.2.
    assert 9 <= len(data["images"]) <= 11
    assert data["images"][-1] == pytest.approx(1.2)


def test_private_param_remap_and_myargv_from_script_args(course_run):
    report, data = course_run(
        "node_params_and_remaps.py",
        scenario="omtp_factory",
        out_arg=True,
        args=["extra", "_rate:=5", "omtp/logical_camera:=/omtp/logical_camera_2"],
        timeout=10,
    )
    assert report.exception is None
    assert data["args"] == ["extra"]
    assert data["rate"] == 5
    assert data["seen_param"] is True
    assert (data["name"], data["namespace"]) == ("/camera_reader", "/")
    # Without the remap the lecture's camera here is camera 1 (x = 1.2): camera 2 hangs at x = -8.3.
    assert data["resolved"] == "/omtp/logical_camera_2"
    assert data["camera_x"] == pytest.approx(-8.3)


def test_a_namespaced_node_resolves_relative_names_in_its_namespace(course_run):
    report, data = course_run(
        "node_params_and_remaps.py",
        scenario="omtp_factory",
        out_arg=True,
        args=[
            "__ns:=/cell",
            "__name:=reader",
            "_rate:=2",
            "/cell/omtp/logical_camera:=/omtp/logical_camera_1",
        ],
        timeout=10,
    )
    assert report.exception is None
    assert (data["name"], data["namespace"]) == ("/cell/reader", "/cell/")
    assert data["rate"] == 2
    assert data["resolved"] == "/omtp/logical_camera_1"
    assert data["camera_x"] == pytest.approx(1.2)


def test_without_the_remap_a_namespaced_relative_name_has_no_publisher(course_run):
    report, _data = course_run(
        "node_params_and_remaps.py", scenario="omtp_factory", out_arg=True, args=["__ns:=/cell"], timeout=10
    )
    assert "timeout exceeded while waiting for message on topic /cell/omtp/logical_camera" in str(
        report.exception
    )


def test_services_topics_and_actions_resolve_alike(course_run):
    report, data = course_run(
        "relative_service_and_action_names.py", scenario="lecture6_assignment4", out_arg=True, timeout=10
    )
    assert report.exception is None
    assert data["service"] == "/gripper2/control" and data["success"] is True
    # The gripper plugin's state topic (gripper2/state) answers with the suction on, nothing held.
    assert (data["enabled"], data["attached"]) == (True, False)
    assert data["server"] is True
    # ~execute_trajectory is /gripper_check/execute_trajectory: no such server.
    assert "/gripper_check/execute_trajectory" in data["private_action"]


def test_params_resolve_like_topics_and_form_a_tree(course_run):
    report, data = course_run("param_tree.py", scenario="omtp_factory", out_arg=True, timeout=10)
    assert report.exception is None
    assert data["leaf"] == 1.0
    assert data["namespace"] == {"bin_1": {"x": -8.0, "y": -2.2, "drop": {"z": 1.0}}}
    assert data["private"] == 0.5
    assert {"param_user", "place"} <= set(data["all_keys"])
    assert data["has"] == [True, False]
    assert data["default"] == "none"
    assert data["after_delete"] is False
    assert "/place" in data["error"]
