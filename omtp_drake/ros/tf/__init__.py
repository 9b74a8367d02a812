"""tf (geometry2's tf2 and the classic ``tf`` helpers) on the cell's tf buffer.

Modules, one concept each:

- ``tf2``: tf2_ros and tf2_geometry_msgs on the cell's tf buffer
- ``listener``: ROS 1 tf's TransformListener on the cell's tf buffer
- ``transformations``: the helpers of ``tf.transformations`` that course scripts use
- ``convert``: ROS geometry messages to and from Drake's RigidTransform
"""
