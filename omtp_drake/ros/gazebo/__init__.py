"""The course's Gazebo world: Gazebo's own ROS API, the cell's sensor topics, joint
states and services, and the part spawner, as the course's launch files wire them.

Modules, one concept each:

- ``sensor_topics``: the logical cameras' topics
- ``plugin_topics``: the Gazebo plugin layer on ROS 1: its topics (joint states, cameras, break beam,
  gripper state, set_joint_trajectory) and services (gripper and conveyor control)
- ``ros_control_topics``: gazebo_ros_control's controller topics (joint_states, command, state), ROS 1 names
- ``ros_control_action``: a trajectory controller's follow_joint_trajectory action, actionlib's client
- ``cell_services``: a service of the ROS 1 graph (name, type, handler) and a handler's failure
- ``ros_api``: Gazebo's own ROS API under ``/gazebo`` (states, model services), over the plugin layer
- ``interfaces``: gazebo_msgs: the messages and services of Gazebo's ROS API
- ``spawner``: the course's part spawner's services and ``/spawned_part``, over the plugin layer
- ``world_plugins``: the world's ROS plugins (Gazebo's API, the spawner) attached to a run
- ``graph``: what those plugins use of a run's ROS graph (the Session as a protocol)
"""
