"""moveit_commander and MoveIt's move_group on the cell's arms and planner.

Modules, one concept each:

- ``commander``: MoveGroupCommander on a cell's arm
- ``targets``: what a MoveGroupCommander's next plan aims for, and how
- ``robot``: RobotCommander and ``roscpp_initialize``
- ``planning_scene``: PlanningSceneInterface
- ``actions``: the ``execute_trajectory`` action client and GoalStatus
- ``node``: the ``move_group`` node on a run: its config and its services
- ``move_group``: the ``/move_group`` action on the cell's planner
- ``bounds``: MoveIt's joint-bounds rules for a plan's start and joint goals
- ``ik_service``: the ``/compute_ik`` service on the cell's planner
- ``fk_service``: the ``/compute_fk`` service on the cell's model
- ``cartesian_service``: the ``/compute_cartesian_path`` service on the cell's planner
- ``interfaces``: moveit_msgs types of ``/move_group`` and its kinematics services
- ``moveit_python``: moveit_python's MoveGroupInterface and PlanningSceneInterface
- ``srdf``: the semantic robot description (SRDF) on the cell's arms
- ``joint_limits``: a MoveIt config package's ``joint_limits.yaml``
- ``config``: a student's MoveIt config on a run (``--srdf``, ``--moveit-config``)
- ``description``: ``/robot_description``: the cell's URDF as the course's launch files load it
- ``trajectories``: the cell's timed plans to and from ``moveit_msgs/RobotTrajectory``
"""
