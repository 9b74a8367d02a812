"""Run the course's ROS 1 scripts unchanged: rospy, MoveIt commander, tf2 and the cell's
services, in simulated time, in one process, with no ROS installed.

    omtp-drake ros-run my_pick.py --scenario lecture6_assignment4 --json result.json

or from Python::

    from omtp_drake.ros import run_script
    report = run_script("my_pick.py", scenario="lecture6_assignment4")
    text = report.summary()          # what ros-run prints

The ROS names a script imports (``rospy``, ``moveit_commander``, ``moveit_msgs``,
``actionlib``, ``tf2_ros``, ``tf2_geometry_msgs``, ``tf.transformations``,
``geometry_msgs``, ``std_msgs``, ``std_srvs``, ``sensor_msgs``,
``trajectory_msgs``, ``omtp_gazebo``) live in ``omtp_drake/ros/shims``, which
only :func:`run_script` puts on ``sys.path``, for the script's run: importing
omtp_drake never shadows a real ROS installation. What is not provided raises
:class:`~omtp_drake.errors.NotSupportedError` naming it.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from omtp_drake.ros.report import RosReport
    from omtp_drake.ros.runner import run_script

__all__ = ["RosReport", "run_script"]


def __getattr__(name: str) -> Any:
    # Lazy: ``import omtp_drake.ros`` (the CLI) stays cheap.
    if name == "run_script":
        from omtp_drake.ros.runner import run_script

        return run_script
    if name == "RosReport":
        from omtp_drake.ros.report import RosReport

        return RosReport
    raise AttributeError(name)
