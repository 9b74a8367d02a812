"""The cell: what the factory is made of, as Drake systems and models.

Modules (one job each):

- ``station``: ``build_station``: the whole cell as one Drake diagram
- ``cell_models``: the cell's models in a plant, every model of a scenario welded at its pose
- ``described_models``: models from description files (a student's URDF/SDF), placed as Gazebo spawns them
- ``depth_camera``: a Gazebo camera or depth sensor as Drake's RGB-D rendering, with its point cloud
- ``gazebo_models``: the cell's model instances under the names the course's Gazebo world gives them
- ``arms``: the classic UR arms: the course's named poses, loading, position control
- ``arm_servos``: the arms in the station: initial poses, servos, their exported ports
- ``joint_controllers``: any robot's ros_control joints: actuators, PD drives and the controllers' commands
- ``joint_splines``: joint trajectories interpolated as ros_controllers' trajectory controller does
- ``conveyor``: the conveyor belt and the break beam
- ``spawned_objects``: the conveyor spawner's objects as parts: the plugin's model of each, its mesh for Drake
- ``parts``: where parts are put (parking slots, spawn poses) and which are parked or asleep
- ``rest_clock``: ``RestClock``: since when each part has been still (what lets it fall asleep)
- ``frames``: frames by name, like tf: every frame of the factory and the transforms between them
- ``poses``: stamped poses and transforms, as in geometry_msgs and tf2
- ``logical_camera``: the Gazebo-like logical camera system: the models in view and their poses
- ``gazebo_camera``: what the course's logical camera plugin publishes (boxes against the frustum)
- ``camera_image``: what a logical camera reports: the models in view and the image holding them
- ``camera_candidates``: the models a logical camera may report, and which overlap its frustum
- ``frustum``: the view frustum's test against oriented boxes
- ``body_geometry``: which geometries of a body a camera counts, and the boxes that bound them
- ``kdop``: every geometry as a convex polytope of slabs (a 26-DOP) for ray casting
- ``occlusion``: the visible fraction of each model in view
- ``rgbd``: the RGB-D view of a logical camera: colour, depth and label images by VTK
- ``suction``: the vacuum gripper's attach rule: enable, attach on contact, release on disable
- ``suction_touch``: what touches the suction cup: the candidate parts and the touch rule
- ``suction_holds``: the gripper's two ways of holding a part (weld, force) and their wiring
- ``suction_constraints``: the weld hold's six distance constraints between the cup and a part
- ``lifetime``: freeing a built cell: the cycles through our systems that Python's gc cannot collect

May import: ``omtp_drake.scenario``, ``omtp_drake.errors``, ``omtp_drake.assets``.
"""
