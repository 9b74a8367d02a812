"""The cell as ROS 2 nodes over real DDS: what a student's rclpy code, ``ros2`` tools and
rviz2 talk to (``omtp-drake ros2``; needs the ``ros2`` extra: rclpy and Fast DDS from PyPI).

In simulated time: ``/clock``, ``/joint_states``, ``/robot_description`` (latched, as
robot_state_publisher publishes it), the RGB-D cameras' ``image_raw``, ``camera_info``,
``depth/image_raw`` and ``points``, the logical cameras and the parts as poses and rviz2
markers; ``/set_joint_trajectory`` as Gazebo's joint pose trajectory plugin; the grippers
and the belt as ``std_srvs/SetBool`` services. No ``/tf``: no ``tf2_msgs`` wheel is on
PyPI, the wheels there ship no C headers to build one against, and rclpy has no runtime
type support in Python; a peer's robot_state_publisher makes tf from ``/joint_states``
and ``/robot_description``.

Modules (one job each):

- ``network``: the run's DDS domain and discovery range, and rclpy or one error naming the extra
- ``messages``: the cell's state as ROS 2 messages (clock, joints, images, clouds, markers)
- ``joint_pose_trajectory``: ``/set_joint_trajectory``'s rules, as Gazebo's plugin plays a trajectory
- ``topics``: the topics the cell publishes, and when
- ``commands``: the trajectory topic and the services a peer calls, run between steps
- ``ros2_control``: gazebo_ros2_control's controller topics (joint_trajectory, commands, joint_states)
- ``bridge``: ``Ros2Cell``: the cell as one ROS 2 node, stepped in simulated time
- ``run``: ``omtp-drake ros2``: a scenario's cell on ROS 2 until its timeout or Ctrl-C

May import: ``omtp_drake.ros`` (the cell's URDF, the course's names) and below.
Nothing here is imported by the layers below; rclpy is imported only when a node starts.
"""
