"""gazebo_msgs: the messages and services of Gazebo's ROS API (gazebo_ros_pkgs' shapes),
declared from their ``.msg`` / ``.srv`` text (:mod:`omtp_drake.ros.comm.messages`'s factory).

Fields in the order of ``gazebo_msgs/msg/*.msg`` and ``srv/*.srv``: ``ModelState``,
``ModelStates``, ``LinkState``, ``LinkStates``; the services ``GetModelState``,
``SetModelState``, ``GetLinkState``, ``SpawnModel`` and ``DeleteModel``.
"""

from __future__ import annotations

from omtp_drake.ros.comm.messages import message, service

_STATE = "geometry_msgs/Pose pose\ngeometry_msgs/Twist twist\nstring reference_frame"
_STATES = "string[] name\ngeometry_msgs/Pose[] pose\ngeometry_msgs/Twist[] twist"
_DONE = "bool success\nstring status_message"

ModelState = message("gazebo_msgs/ModelState", f"string model_name\n{_STATE}")
ModelStates = message("gazebo_msgs/ModelStates", _STATES)
LinkState = message("gazebo_msgs/LinkState", f"string link_name\n{_STATE}")
LinkStates = message("gazebo_msgs/LinkStates", _STATES)

GetModelState, GetModelStateRequest, GetModelStateResponse = service(
    "gazebo_msgs/GetModelState",
    "string model_name\nstring relative_entity_name\n---\n"
    f"Header header\ngeometry_msgs/Pose pose\ngeometry_msgs/Twist twist\n{_DONE}",
)
SetModelState, SetModelStateRequest, SetModelStateResponse = service(
    "gazebo_msgs/SetModelState", f"ModelState model_state\n---\n{_DONE}"
)
GetLinkState, GetLinkStateRequest, GetLinkStateResponse = service(
    "gazebo_msgs/GetLinkState",
    f"string link_name\nstring reference_frame\n---\nLinkState link_state\n{_DONE}",
)
SpawnModel, SpawnModelRequest, SpawnModelResponse = service(
    "gazebo_msgs/SpawnModel",
    "string model_name\nstring model_xml\nstring robot_namespace\ngeometry_msgs/Pose initial_pose\n"
    f"string reference_frame\n---\n{_DONE}",
)
DeleteModel, DeleteModelRequest, DeleteModelResponse = service(
    "gazebo_msgs/DeleteModel", f"string model_name\n---\n{_DONE}"
)
