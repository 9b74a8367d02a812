"""The cell as ROS 2 nodes over real DDS: what a student's rclpy code, ``ros2`` tools and
rviz2 talk to (``omtp-drake ros2``; needs the ``ros2`` extra: rclpy and Fast DDS from PyPI).

A transport only: the Gazebo plugins of whatever was loaded (a scenario, a robot file)
are :mod:`omtp_drake.gazebo`'s, defined once for this node and the ROS 1 shim; here
they get ROS 2 names, types and QoS (docs/ros2.md's table says where the two differ).

In simulated time: ``/clock``, ``/robot_description`` (latched, as robot_state_publisher
publishes it), the plugins' topics (joint states, cameras' ``image_raw``,
``camera_info``, ``depth/image_raw`` and ``points``) and ``set_joint_trajectory``
subscriptions, the logical cameras and the parts as poses and rviz2 markers; the
grippers and the belt as ``std_srvs/SetBool`` services; the grippers' state and the break
beam in the course's types (Cyclone DDS) and as ``std_msgs/Bool``. ``/tf`` and ``/tf_static`` as
robot_state_publisher publishes them, and ``/gazebo/model_states`` and ``link_states``: no
``tf2_msgs`` (nor ``gazebo_msgs``) wheel is on PyPI, so rclpy publishes them with their type
support built here, or, where it cannot be built, Cyclone DDS writes them beside rclpy
(``packed_topics``). A volatile topic's message is built only while someone would get it
(``audience``). Gazebo's model services (``/spawn_entity``...) need real type support (Cyclone cannot answer a
Fast DDS client), and so does ``follow_joint_trajectory``: ``gazebo_msgs`` and ``control_msgs`` are
built for rclpy once, into the model cache, with the rosidl
generators the rclpy wheels bring, their headers and the system's compiler (``interface_build``).

Modules (one job each):

- ``network``: the run's DDS domain and discovery range, the cell's Fast DDS profile (no type
  lookups: ``fastdds_profile.xml``), and rclpy or one error naming the extra
- ``messages``: the Gazebo plugin layer's messages as ROS 2 messages, and the clock and markers
- ``topics``: the topics the cell publishes (the plugin layer's, by ROS 2 names and QoS)
- ``commands``: the plugins' trajectory topics and the services a peer calls, run between steps
- ``course_types``: the course's ``omtp_gazebo`` messages (gripper state, proximity) as Cyclone DDS mirrors
- ``course_topics``: the plugins' topics of those types (Cyclone) and their ``std_msgs/Bool`` views (rclpy)
- ``ros2_control``: gazebo_ros2_control's controller topics (joint_trajectory, commands, joint_states)
- ``trajectory_action``: the trajectory controllers' ``follow_joint_trajectory`` (``control_msgs``)
- ``dds_types``: the types rclpy lacks (tf2_msgs, gazebo_msgs) as Cyclone DDS mirrors, and Cyclone's config
- ``cdr``: ``/tf`` and Gazebo's states packed as the mirrors' XCDR1 bytes, in one ``struct`` call
- ``packed_topics``: those topics by rclpy with the built types, else by Cyclone DDS (one warning)
- ``audience``: the one rule of when a message is built at all (someone would receive it)
- ``launched_nodes``: the launch's own ROS 2 nodes, run beside the cell as ``ros2 launch`` runs them
- ``tf_publisher``: ``/tf`` and ``/tf_static``
- ``gazebo_world``: Gazebo's model and link states and the spawner's services
- ``gazebo_services``: Gazebo's model services (``gazebo_msgs``, built here) over the plugin layer's rules
- ``interface_build``: rclpy type support for ``gazebo_msgs``, ``control_msgs``, ``tf2_msgs``, built once
- ``interface_generate``: its rosidl generation step, in a process of its own
- ``bag``: ``--bag``: what the node publishes, into a ROS 2 bag
- ``bridge``: ``Ros2Cell``: the cell as one ROS 2 node, stepped in simulated time
- ``run``: ``omtp-drake ros2``: a scenario's cell on ROS 2 until its timeout or Ctrl-C

May import: ``omtp_drake.ros`` (the cell's URDF, the course's names) and below.
Nothing here is imported by the layers below; rclpy is imported only when a node starts.
"""
