"""gazebo_msgs: the messages and services of Gazebo's ROS API (gazebo_ros_pkgs' shapes).

Fields in the order of ``gazebo_msgs/msg/*.msg`` and ``srv/*.srv``: ``ModelState``,
``ModelStates``, ``LinkState``, ``LinkStates``; the services ``GetModelState``,
``SetModelState``, ``GetLinkState``, ``SpawnModel`` and ``DeleteModel``.
"""

from __future__ import annotations

from omtp_drake.ros.comm.interfaces import ServiceType
from omtp_drake.ros.comm.messages import Header, Message, Pose, Twist


class ModelState(Message):
    __slots__ = ("model_name", "pose", "twist", "reference_frame")
    _type = "gazebo_msgs/ModelState"
    _defaults = (str, Pose, Twist, str)


class ModelStates(Message):
    __slots__ = ("name", "pose", "twist")
    _type = "gazebo_msgs/ModelStates"
    _defaults = (list, list, list)


class LinkState(Message):
    __slots__ = ("link_name", "pose", "twist", "reference_frame")
    _type = "gazebo_msgs/LinkState"
    _defaults = (str, Pose, Twist, str)


class LinkStates(Message):
    __slots__ = ("name", "pose", "twist")
    _type = "gazebo_msgs/LinkStates"
    _defaults = (list, list, list)


class GetModelStateRequest(Message):
    __slots__ = ("model_name", "relative_entity_name")
    _type = "gazebo_msgs/GetModelStateRequest"
    _defaults = (str, str)


class GetModelStateResponse(Message):
    __slots__ = ("header", "pose", "twist", "success", "status_message")
    _type = "gazebo_msgs/GetModelStateResponse"
    _defaults = (Header, Pose, Twist, bool, str)


class GetModelState(ServiceType):
    _type = "gazebo_msgs/GetModelState"
    _request_class = GetModelStateRequest
    _response_class = GetModelStateResponse


class SetModelStateRequest(Message):
    __slots__ = ("model_state",)
    _type = "gazebo_msgs/SetModelStateRequest"
    _defaults = (ModelState,)


class SetModelStateResponse(Message):
    __slots__ = ("success", "status_message")
    _type = "gazebo_msgs/SetModelStateResponse"
    _defaults = (bool, str)


class SetModelState(ServiceType):
    _type = "gazebo_msgs/SetModelState"
    _request_class = SetModelStateRequest
    _response_class = SetModelStateResponse


class GetLinkStateRequest(Message):
    __slots__ = ("link_name", "reference_frame")
    _type = "gazebo_msgs/GetLinkStateRequest"
    _defaults = (str, str)


class GetLinkStateResponse(Message):
    __slots__ = ("link_state", "success", "status_message")
    _type = "gazebo_msgs/GetLinkStateResponse"
    _defaults = (LinkState, bool, str)


class GetLinkState(ServiceType):
    _type = "gazebo_msgs/GetLinkState"
    _request_class = GetLinkStateRequest
    _response_class = GetLinkStateResponse


class SpawnModelRequest(Message):
    __slots__ = ("model_name", "model_xml", "robot_namespace", "initial_pose", "reference_frame")
    _type = "gazebo_msgs/SpawnModelRequest"
    _defaults = (str, str, str, Pose, str)


class SpawnModelResponse(Message):
    __slots__ = ("success", "status_message")
    _type = "gazebo_msgs/SpawnModelResponse"
    _defaults = (bool, str)


class SpawnModel(ServiceType):
    _type = "gazebo_msgs/SpawnModel"
    _request_class = SpawnModelRequest
    _response_class = SpawnModelResponse


class DeleteModelRequest(Message):
    __slots__ = ("model_name",)
    _type = "gazebo_msgs/DeleteModelRequest"
    _defaults = (str,)


class DeleteModelResponse(Message):
    __slots__ = ("success", "status_message")
    _type = "gazebo_msgs/DeleteModelResponse"
    _defaults = (bool, str)


class DeleteModel(ServiceType):
    _type = "gazebo_msgs/DeleteModel"
    _request_class = DeleteModelRequest
    _response_class = DeleteModelResponse
