"""ROS messages made from their definitions (omtp_drake.ros.comm.messages): the .msg / .srv /
.action text is the data, one factory makes the classes with genpy's shapes."""

import pytest

from omtp_drake.ros.comm.messages import Duration, Message, Pose, Time, action, message, service


def test_a_message_from_its_definition_has_genpys_fields_defaults_and_constants():
    Probe = message(
        "test_msgs/Probe",
        """
        Header header          # a comment
        geometry_msgs/Pose pose
        float64[] values
        uint8 kind
        string name
        duration wait
        uint8 BOX=1
        float64 LIMIT=2.5
        string LABEL=box here
        """,
    )
    probe = Probe(name="a")
    assert Probe.__slots__ == ("header", "pose", "values", "kind", "name", "wait")
    assert Probe._type == "test_msgs/Probe" and Probe.__module__ == __name__
    assert probe.header.stamp == Time(0) and probe.pose == Pose() and probe.values == []
    assert (probe.kind, probe.name, probe.wait) == (0, "a", Duration(0))
    assert (Probe.BOX, Probe.LIMIT, Probe.LABEL) == (1, 2.5, "box here")
    assert isinstance(probe, Message) and Probe().values is not Probe().values
    with pytest.raises(AttributeError, match="test_msgs/Probe has no field 'nmae'; fields: header, pose"):
        probe.nmae  # noqa: B018


def test_services_and_actions_name_their_parts_as_genpy():
    Ping, PingRequest, PingResponse = service("test_msgs/Ping", "string text\n---\nbool ok")
    assert (Ping._type, PingRequest._type, PingResponse._type) == (
        "test_msgs/Ping", "test_msgs/PingRequest", "test_msgs/PingResponse")  # fmt: skip
    assert Ping._request_class is PingRequest and PingResponse(True).ok is True
    Go, GoGoal, GoResult, GoFeedback = action("test_msgs/Go", "int32 n\n---\n---\nstring s")
    assert Go._type == "test_msgs/GoAction" and (Go._goal_class, Go._result_class) == (GoGoal, GoResult)
    assert GoGoal(3).n == 3 and GoResult.__slots__ == () and GoFeedback().s == ""


def test_a_definition_naming_a_type_not_made_yet_is_refused():
    with pytest.raises(NameError, match="names test_msgs/Nowhere, not defined yet"):
        message("test_msgs/Lost", "Nowhere where")
