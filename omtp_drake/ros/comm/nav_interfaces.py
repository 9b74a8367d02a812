"""move_base_msgs: the navigation stack's ``move_base`` action types.

The course's factory states include a ``MoveBaseState`` (the turtlebot of the
HRWROS factory). The course's OMTP cell has no mobile base and no ``/move_base``
server, and neither has this one: the types exist so such a state loads, and its
action client is reported unavailable, as FlexBE reports it in the course's cell.
"""

from __future__ import annotations

from omtp_drake.ros.comm.messages import action

MoveBaseAction, MoveBaseGoal, MoveBaseResult, MoveBaseFeedback = action(
    "move_base_msgs/MoveBase",
    "geometry_msgs/PoseStamped target_pose\n---\n---\ngeometry_msgs/PoseStamped base_position",
    "The action type: ``SimpleActionClient('move_base', MoveBaseAction)``.",
)
