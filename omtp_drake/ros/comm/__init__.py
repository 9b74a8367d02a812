"""ros_comm's rospy on the cell: the node, names, parameters, simulated time, topics,
services and messages, and the session a run's ROS calls act on.

Modules, one concept each:

- ``client``: the node, its names, shutdown, ``spin``, the parameter server and logging
- ``names``: ROS graph names as rospy resolves them (canonical, relative, ``~private``, remaps)
- ``params``: the parameter server's tree over the session's store of resolved names
- ``rostime``: time, ``sleep`` and ``Rate`` on the cell's simulated clock
- ``topics``: Publisher, Subscriber and ``wait_for_message``
- ``service``: ServiceProxy and ``wait_for_service``
- ``exceptions``: rospy's exceptions (ROSException, ROSInterruptException...)
- ``messages``: ROS time; messages and services made from their ``.msg``/``.srv`` text (one factory)
- ``image_messages``: sensor_msgs' images, camera info and point clouds, and ``read_points``
- ``interfaces``: the course cell's own interfaces: omtp_gazebo, std_srvs, moveit_msgs types
- ``nav_interfaces``: move_base_msgs' action types (no ``/move_base``, as in the course's cell)
- ``control_interfaces``: control_msgs' trajectory controller state and follow_joint_trajectory action
- ``graph``: the master's view of the session's graph (who publishes, subscribes to, serves what)
- ``master``: rosgraph's ``Master`` and rospy's ``get_published_topics`` over that graph
- ``session``: one ROS-style run on a cell: simulated time, topics, callbacks, shutdown
- ``threads``: a script's threads on the session's clock, taking turns (one runs at a time)
- ``current``: the run a ROS call acts on (a stack of the session or FlexBE run in progress)
- ``latency``: the simulated time a call takes (planning, a trajectory's start, a service)
- ``unsupported``: one clear error for every ROS name this project does not provide
- ``_core``: the one place the ROS layer imports the core from (checked)
"""
