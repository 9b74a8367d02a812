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

Where simulated time advances: ``session.Session.run_until`` ticks the cell and
delivers messages to callbacks in time order; ``rostime.sleep``/``Rate``,
``client.spin``, ``topics.wait_for_message``, action waits and ``Session.think`` (a
call's own time, from ``latency``) call it. A blocking MoveIt move advances it in the
arm's loop (``omtp_drake.script.motion``), the session delivering between its steps
(``Cell.on_move_step``).

Modules, one concept each (``docs/ros_conformance.md`` has the course's rule for each).

rospy:

- ``client``: the node, its names, shutdown, ``spin``, the parameter server and logging
- ``names``: ROS graph names as rospy resolves them (canonical, relative, ``~private``, remaps)
- ``params``: the parameter server's tree over the session's store of resolved names
- ``rostime``: time, ``sleep`` and ``Rate`` on the cell's simulated clock
- ``topics``: Publisher, Subscriber and ``wait_for_message``
- ``service``: ServiceProxy and ``wait_for_service``
- ``exceptions``: rospy's exceptions (ROSException, ROSInterruptException...)
- ``messages``: ROS 1 messages and services as plain classes (std, geometry, sensor)
- ``interfaces``: the course cell's own interfaces: omtp_gazebo, std_srvs, moveit_msgs types
- ``session``: one ROS-style run on a cell: simulated time, topics, callbacks, shutdown
- ``threads``: a script's threads on the session's clock, taking turns (one runs at a time)
- ``current``: the run a ROS call acts on (a stack of the session or FlexBE run in progress)
- ``latency``: the simulated time a call takes (planning, a trajectory's start, a service)

moveit_commander and MoveIt:

- ``moveit``: MoveGroupCommander on a cell's arm
- ``moveit_targets``: what a MoveGroupCommander's next plan aims for, and how
- ``robot``: RobotCommander and ``roscpp_initialize``
- ``planning_scene``: PlanningSceneInterface
- ``actions``: the ``execute_trajectory`` action client and GoalStatus
- ``move_group``: the ``/move_group`` action on the cell's planner
- ``ik_service``: the ``/compute_ik`` service on the cell's planner
- ``moveit_interfaces``: moveit_msgs types of ``/move_group`` and ``/compute_ik``
- ``srdf``: the semantic robot description (SRDF) on the cell's arms
- ``joint_limits``: a MoveIt config package's ``joint_limits.yaml``
- ``moveit_config``: a student's MoveIt config on a run (``--srdf``, ``--moveit-config``)
- ``description``: ``/robot_description``: the cell's URDF as the course's launch files load it
- ``trajectories``: the cell's timed plans to and from ``moveit_msgs/RobotTrajectory``

tf:

- ``tf``: tf2_ros and tf2_geometry_msgs on the cell's tf buffer
- ``transformations``: the helpers of ``tf.transformations`` that course scripts use
- ``convert``: ROS geometry messages to and from Drake's RigidTransform

the course's Gazebo world:

- ``sensor_topics``: the cell's sensor topics (cameras, break beam, gripper state)
- ``joint_state_topics``: the arms' joint states, by the course's controllers' names
- ``cell_services``: the cell's gripper and conveyor services, by the course's names
- ``gazebo``: Gazebo's own ROS API under ``/gazebo``
- ``gazebo_interfaces``: gazebo_msgs: the messages and services of Gazebo's ROS API
- ``gazebo_models``: the cell's Gazebo models as that API sees them: names, links, poses, twists
- ``gazebo_spawn``: ``/gazebo/spawn_urdf_model``, ``spawn_sdf_model`` and ``reset_world``
- ``spawner``: the course's part spawner, wired as the scenario's launch file wires it
- ``world_plugins``: the world's ROS plugins (Gazebo's API, the spawner) attached to a run
- ``graph``: what those plugins use of a run's ROS graph (the Session as a protocol)

running scripts:

- ``runner``: ``ros-run``: an unmodified course script on a cell, in simulated time
- ``report``: the report of one ``ros-run``: times, ledger, collisions, the script's exception
- ``cli``: the ``ros-run`` and ``grade`` commands
- ``command``: what the ROS commands share: output lines, log levels, passed-on options
- ``setup_steps``: the slides' set-up steps before a script (``--call``, ``--settle``)
- ``settling``: after a run, the cell runs on until its parts rest (``--settle-after``)
- ``py2``: course code written for Melodic's Python 2.7
- ``grade``: ``grade``: every script of a folder run on a scenario, isolated
- ``grade_flexbe``: ``grade --flexbe``: a class's FlexBE behaviours, one workspace each
- ``grade_options``: the ``ros-run`` options ``grade`` passes on (``grade.yaml``)
- ``grade_table``: a grade's results: the printed table, ``grades.csv``, ``grades.png``, JSONs
- ``isolation``: one untrusted ``ros-run`` isolated: its folder copy, limits, sandbox
- ``guard``: the first code of an isolated run: resource limits and its write/network guard
- ``verdicts``: a graded run's verdict, named for what happened
- ``flexbe``: FlexBE behaviours on the cell (``flexbe-run``: engine, states, proxies, run)
- ``shims``: the ROS-named packages a run puts on ``sys.path``
- ``unsupported``: one clear error for every ROS name this project does not provide
- ``_core``: the one place this layer imports the core from
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
