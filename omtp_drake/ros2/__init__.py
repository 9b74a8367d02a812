"""The cell as ROS 2 nodes over real DDS: what a student's rclpy code, ``ros2`` tools and
rviz2 talk to (``omtp-drake ros2``; needs the ``ros2`` extra: rclpy and Fast DDS from PyPI).

In simulated time: ``/clock``, ``/joint_states``, ``/robot_description`` (latched, as
robot_state_publisher publishes it), the RGB-D cameras' ``image_raw``, ``camera_info``,
``depth/image_raw`` and ``points``, the logical cameras and the parts as poses and rviz2
markers; ``/set_joint_trajectory`` as Gazebo's joint pose trajectory plugin; the grippers
and the belt as ``std_srvs/SetBool`` services. ``/tf`` and ``/tf_static`` as
robot_state_publisher publishes them, and ``/gazebo/model_states``: no ``tf2_msgs`` (nor
``gazebo_msgs``) wheel is on PyPI, the wheels there ship no C headers to build one against,
and rclpy has no runtime type support in Python, so Cyclone DDS writes them beside rclpy
(``dds_types``).

Modules (one job each):

- ``network``: the run's DDS domain and discovery range, and rclpy or one error naming the extra
- ``messages``: the cell's state as ROS 2 messages (clock, joints, images, clouds, markers)
- ``joint_pose_trajectory``: ``/set_joint_trajectory``'s rules, as Gazebo's plugin plays a trajectory
- ``topics``: the topics the cell publishes, and when
- ``commands``: the trajectory topic and the services a peer calls, run between steps
- ``dds_types``: the types rclpy lacks (tf2_msgs, gazebo_msgs) as Cyclone DDS mirrors, and Cyclone's config
- ``cdr``: ``/tf`` and ``/gazebo/model_states`` packed as the mirrors' XCDR1 bytes, in one ``struct`` call
- ``tf_publisher``: ``/tf``, ``/tf_static`` and ``/gazebo/model_states``, written by Cyclone DDS
- ``bag``: ``--bag``: what the node publishes, into a ROS 2 bag
- ``bridge``: ``Ros2Cell``: the cell as one ROS 2 node, stepped in simulated time
- ``launch_api``: the ``launch`` / ``launch_ros`` API a ``*.launch.py`` uses, in house (not on PyPI)
- ``launch_py``: ``--launch 'PKG FILE.launch.py'``: a launch file evaluated, its nodes mapped to the cell
- ``run``: ``omtp-drake ros2``: a scenario's cell on ROS 2 until its timeout or Ctrl-C

May import: ``omtp_drake.ros`` (the cell's URDF, the course's names) and below.
Nothing here is imported by the layers below; rclpy is imported only when a node starts.
"""
