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

Where each concept lives (every module is one concept; ``docs/ros_conformance.md``
has the course's rule for each):

================================  ==========================================================
concept                           module
================================  ==========================================================
**rospy**
a node, its names, shutdown,      ``client`` (init_node, resolve_name, myargv, spin,
params, logging                   signal_shutdown, get/set_param, loginfo...)
name rules (canonical, relative,  ``names``; the parameter tree: ``params``
``~private``, ``from:=to``)
time, sleep, Rate                 ``rostime`` (Time.now, sleep, Rate; ``_blocking``)
Publisher, Subscriber,            ``topics``
wait_for_message
ServiceProxy, wait_for_service    ``service``
exceptions                        ``exceptions`` (ROSException, ROSInterruptException...)
messages and their types          ``messages`` (std/geometry/sensor), ``interfaces``
                                  (omtp_gazebo, moveit_msgs), ``gazebo_interfaces``,
                                  ``moveit_interfaces``
**where simulated time advances** ``session.Session.run_until``: ticks the cell and
                                  delivers messages to callbacks in time order; called by
                                  ``rostime.sleep``/``Rate``, ``client.spin``,
                                  ``topics.wait_for_message``, action waits and
                                  ``Session.think`` (a call's own time). A blocking MoveIt
                                  move advances it in the arm's loop
                                  (``omtp_drake.script.arm``), the session delivering
                                  between its steps (``Cell.on_move_step``)
time a call takes (planning,      ``latency`` (the scenario's ``ros_latency``,
execution start, a service)       ``--latency``)
**moveit_commander**
MoveGroupCommander                ``moveit``
RobotCommander, roscpp_initialize ``robot``
PlanningSceneInterface            ``planning_scene``
the execute_trajectory action     ``actions`` (with GoalStatus)
the move_group action,            ``move_group``, ``ik_service``
/compute_ik
SRDF, joint_limits.yaml, a        ``srdf``, ``joint_limits``, ``moveit_config``;
student's MoveIt config           ``/robot_description``: ``description``
plans <-> RobotTrajectory         ``trajectories``
**tf**
tf2_ros Buffer, transforms        ``tf``; ``tf.transformations``: ``transformations``;
                                  geometry conversions: ``convert``
**the course's Gazebo world**
sensor topics (cameras, break     ``sensor_topics``; joint states: ``joint_state_topics``
beam, gripper state)
gripper and conveyor services     ``cell_services``
Gazebo's ROS API (/gazebo/...)    ``gazebo`` (models: ``gazebo_models``; spawning:
                                  ``gazebo_spawn``)
the part spawner as launched      ``spawner``; attached to a run by ``world_plugins``
what those plugins see of a run   ``graph`` (the Session as a protocol)
**running scripts**
ros-run                           ``runner`` (the run), ``report``, ``cli``
the slides' set-up steps          ``setup_steps`` (``--call``, ``--settle``)
Melodic's Python 2                ``py2``
grade                             ``grade``, ``grade_options`` (``grade.yaml``),
                                  ``isolation`` (sandbox, limits), ``guard``, ``verdicts``
FlexBE (flexbe-run)               ``flexbe`` (engine, states, proxies, run)
what is not provided              ``unsupported``
================================  ==========================================================
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
