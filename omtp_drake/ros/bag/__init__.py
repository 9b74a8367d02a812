"""rosbag2's bags: a run's topics as a ROS 2 bag (``--bag run.mcap``: ``ros2 bag play``,
Foxglove), from the ROS 1 shim's session (``ros-run``, ``flexbe-run``) or the ROS 2 node
(``omtp-drake ros2``, :mod:`omtp_drake.ros2.bag`).

Modules, one concept each:

- ``writer``: the MCAP file: channels, schemas, messages as CDR bytes or values, simulated times
- ``definitions``: ROS 2 message definitions as a bag's schema carries them (the ``.msg`` texts)
- ``ros1``: the shim's ROS 1 messages as their ROS 2 equivalents (types, fields, times)
- ``session``: a ROS 1 session recorded: every topic, ``/clock`` and ``/tf``
"""
