"""move_base_msgs: the navigation stack's ``move_base`` action types.

The course's factory states include a ``MoveBaseState`` (the turtlebot of the
HRWROS factory). The course's OMTP cell has no mobile base and no ``/move_base``
server, and neither has this one: the types exist so such a state loads, and its
action client is reported unavailable, as FlexBE reports it in the course's cell.
"""

from __future__ import annotations

from typing import ClassVar

from omtp_drake.ros.comm.messages import Message, PoseStamped


class MoveBaseGoal(Message):
    __slots__ = ("target_pose",)
    _type = "move_base_msgs/MoveBaseGoal"
    _defaults = (PoseStamped,)


class MoveBaseResult(Message):
    __slots__ = ()
    _type = "move_base_msgs/MoveBaseResult"
    _defaults = ()


class MoveBaseFeedback(Message):
    __slots__ = ("base_position",)
    _type = "move_base_msgs/MoveBaseFeedback"
    _defaults = (PoseStamped,)


class MoveBaseAction(Message):
    """The action type: ``SimpleActionClient('move_base', MoveBaseAction)``."""

    __slots__ = ()
    _type = "move_base_msgs/MoveBaseAction"
    _goal_class: ClassVar[type[Message]] = MoveBaseGoal
    _result_class: ClassVar[type[Message]] = MoveBaseResult
    _feedback_class: ClassVar[type[Message]] = MoveBaseFeedback
