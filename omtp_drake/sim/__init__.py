"""Running the cell: what changes while it runs, between and across advances.

Modules (one job each):

- ``runtime``: a scenario's cell, ready to run, with the course's services on it
- ``driver``: the Simulator's owner: advances the cell and applies world edits between advances
- ``deletion_wall``: the course's deletion wall (object disposal), a world edit at 5 Hz
- ``heap``: the process's heap thresholds, tuned for the plant's step (no page faults per step)
- ``gripper_events``: the world edit that runs a gripper's rule when something happens, and its weld
- ``part_sleep``: the world edit that puts resting parts to sleep and wakes touched ones
- ``joint_pose_trajectory``: gazebo_ros's joint pose trajectory plugin: a world edit setting joints
- ``ros_control``: ros_control / ros2_control controllers' rules on a running cell, transport-neutral
- ``trajectory_request``: a JointTrajectory as every plugin and controller reads it, from either transport
- ``trajectory_goals``: a trajectory controller's follow_joint_trajectory goal, judged as ros_controllers does
- ``pool``: the part pool: which parts are parked, spawning and disposal
- ``parts``: the course's part services on a running cell (spawn, knock, remove, read)
- ``ledger``: where every part that entered the world is, now
- ``faults``: a scenario's ``faults:`` applied while the cell runs, and what each did
- ``tf``: tf2's buffer over a running station: frame poses and camera images with history
- ``tf_poses``: the plant's named frames in the buffer's snapshots, and their poses at a time
- ``tf_broadcast``: tf as ROS broadcasts it: which frames go on /tf_static and /tf, pose and stamp

May import: ``omtp_drake.cell`` and everything below it (scenario, errors, assets).
"""
