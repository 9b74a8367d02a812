"""Run the course's ROS 1 scripts unchanged: rospy, MoveIt commander, tf2, Gazebo's and the
cell's services, FlexBE behaviours, in simulated time, in one process, with no ROS installed.

    omtp-drake ros-run my_pick.py --scenario lecture6_assignment4 --json result.json

or from Python::

    from omtp_drake.ros import run_script
    report = run_script("my_pick.py", scenario="lecture6_assignment4")
    text = report.summary()          # what ros-run prints

The ROS names a script imports (``rospy``, ``moveit_commander``, ``moveit_msgs``,
``actionlib``, ``tf2_ros``, ``gazebo_msgs``, ``flexbe_core``...) live in
``omtp_drake/ros/shims``, which only a run puts on ``sys.path``: importing
omtp_drake never shadows a real ROS installation. What is not provided raises
:class:`~omtp_drake.errors.NotSupportedError` naming it.

Where simulated time advances: ``comm.session.Session.run_until`` ticks the cell and
delivers messages to callbacks in time order; ``comm.rostime.sleep``/``Rate``,
``comm.client.spin``, ``comm.topics.wait_for_message``, action waits and
``Session.think`` (a call's own time, from ``comm.latency``) call it. A blocking MoveIt
move advances it in the arm's loop (``omtp_drake.script.motion``), the session
delivering between its steps (``Cell.on_move_step``).

Subpackages, one per ROS project this layer mirrors (each maps its modules, one
concept each; ``docs/ros_conformance.md`` has the course's rule for each). No module
lies outside them (``tests/test_layering.py`` checks it). Grading a class's scripts
is an application on top of ``ros-run``: :mod:`omtp_drake.grading`.

- ``comm``: ros_comm's rospy: node, names, parameters, time, topics, services, messages, the session
- ``moveit``: moveit_commander and MoveIt's move_group: commander, targets, scene, services, config
- ``tf``: tf2_ros, tf2_geometry_msgs and ``tf.transformations`` on the cell's tf buffer
- ``gazebo``: the course's Gazebo world: Gazebo's ROS API, the cell's topics, services and spawner
- ``flexbe``: FlexBE behaviours on the cell (``flexbe-run``: engine, states, proxies, run)
- ``run``: ``ros-run``: an unmodified course script on a cell, its report and its command
- ``shims``: the ROS-named packages a run puts on ``sys.path``
- ``bag``: rosbag2's bags: a run's topics as a ROS 2 bag (MCAP), ROS 1 messages as ROS 2's
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from omtp_drake.ros.run.report import RosReport
    from omtp_drake.ros.run.runner import run_script

__all__ = ["RosReport", "run_script"]


def __getattr__(name: str) -> Any:
    # Lazy: ``import omtp_drake.ros`` (the CLI) stays cheap.
    if name == "run_script":
        from omtp_drake.ros.run.runner import run_script

        return run_script
    if name == "RosReport":
        from omtp_drake.ros.run.report import RosReport

        return RosReport
    raise AttributeError(name)
