"""Gazebo's ROS plugins, each defined once and transport-neutral: what a model's
``<gazebo>`` plugins (and the cell's own equivalents) publish, when, in which frame and
encoding, and what a request to them gets. The ROS 1 shim (:mod:`omtp_drake.ros.gazebo`)
and the ROS 2 node (:mod:`omtp_drake.ros2`) are thin transports over this layer: they
give each publication a topic type and QoS of their middleware and convert these
messages field for field, nothing else.

The rules were read in gazebo_ros_pkgs' plugins (ROS 1 ``noetic-devel`` and ``ros2``);
where the two branches differ, the module says which one is followed and why.

Modules, one plugin each:

- ``messages``: the neutral messages (joint states, images, camera info, clouds; a trajectory
  request is :mod:`omtp_drake.sim.trajectory_request`'s); a plugin of the course's own types
  declares its messages in its module
- ``schedule``: the one periodic scheduler and a publication (topic, message type, poll)
- ``joint_states``: ``gazebo_ros_joint_state_publisher`` and the arms' joint states (50 Hz)
- ``camera``: ``gazebo_ros_camera`` (camera and depth), and the logical cameras' RGB-D views
- ``joint_pose_trajectory``: ``gazebo_ros_joint_pose_trajectory``: what a trajectory request gets
- ``logical_camera``: the course's logical camera plugin: ``/omtp/<camera>``, every model in view
- ``parts``: the parts in the world as ground truth (ROS 2's ``/omtp/parts``)
- ``services``: what a plugin serves: a service's name, neutral request and reply
- ``vacuum_gripper``: the course's vacuum gripper plugin: ``/gripperN/state`` and ``/gripperN/control``
  (or the names its ``<plugin>`` sets; the scenario's ``plugin_names``)
- ``conveyor``: the course's conveyor belt plugin: ``/omtp/conveyor/control`` (belt power)
  (or its ``<plugin>``'s name)
- ``proximity_ray``: the course's break beam: ``/break_beam_sensor`` and ``/break_beam_sensor_change``
  (or its ``<plugin>``'s names)
- ``world``: the world the plugins share: its Gazebo models and its physics updates
- ``models``: the cell's models and links under Gazebo's names: poses and twists
- ``model_states``: Gazebo's ``/gazebo/model_states`` and ``/gazebo/link_states`` (both branches' rates)
- ``world_services``: Gazebo's model services: get/set model state, get link state, delete model
- ``spawn``: Gazebo's spawn services and reset_world: what a spawn request gets
- ``spawner``: the course's part spawner: its start/stop services and ``/spawned_part``
- ``plugins``: every plugin of a loaded cell: its publications, subscriptions and warnings
"""
