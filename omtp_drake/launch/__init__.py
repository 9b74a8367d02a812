"""A student's own cell: their launch files, worlds, URDF/xacro and Gazebo plugins.

In the course, students build the cell in ROS's own files (lecture 1's factory xacro,
lecture 6's world with the cameras they place, assignment 4's bin in a launch file,
lecture 7's spawner config). This package reads them, with what they depend on found
in the student's workspace (:mod:`omtp_drake.workspace`), and turns them into the typed
:class:`~omtp_drake.scenario.Scenario` the station builds.

Modules (one job each):

- ``own_cell``: ``own_cell``: a student's launch or world in their workspace, as a Scenario
- ``options``: the commands' and ``Cell``'s cell options and ``chosen_cell``, the one door to a cell
- ``roslaunch``: roslaunch's XML: args, includes, groups, params, rosparams, remaps, nodes
- ``launch_py``: ROS 2's ``.launch.py`` files, run as ``ros2 launch`` runs them, as roslaunch's result
- ``shims``: the ``launch`` and ``launch_ros`` API a ``.launch.py`` imports (on sys.path only while it runs)
- ``substitutions``: roslaunch's $(arg), $(find), $(env), $(optenv), $(dirname), $(anon), $(eval)
- ``xml_lines``: XML with each element's line, for errors that name file and line
- ``nodes``: a launch's nodes mapped to the cell (spawn_model, gzserver, the spawner, the helpers)
- ``ros2_nodes``: a ROS 2 launch's nodes of the workspace, found as ``ros2 run`` finds them
- ``controller_spawners``: controller_manager's spawners: which controllers start on which robot
- ``urdf_model``: a URDF's links as frames (joint tree, link poses) and its <gazebo> tags
- ``pieces``: the course's pieces in a spawned URDF: arms, grippers, pedestals, bins, the beam
- ``arm_dynamics``: an arm's joint velocity and effort limits and its links' inertia, as written
- ``own_links``: links a student added beside or on those pieces (a shelf, a wrist camera), as written
- ``mesh_bins``: a bin of mesh collisions (the course's own), measured and kept open
- ``parse_verdicts``: Drake's verdict on a world's model folders, kept in the model cache by content
- ``sdf_warnings``: what sdformat warns about and loads without (stray elements), one line each
- ``sdf_world``: a Gazebo world's models (includes by model://, poses, names), checked by Drake's parser
- ``world_pieces``: the course's pieces in a world's models: cameras, the belt, the deletion wall
- ``world_additions``: what a student added to the belt's or the wall's model (a tray), loaded as written
- ``plugins``: the course's Gazebo plugins and their parameters, as the cell's systems take them
- ``description``: the robot description a launch loads (``view --launch``, as rviz shows it)
- ``standins``: the project's stand-ins for the packages the course's files need and no student has

May import: ``omtp_drake.sim``, ``omtp_drake.cell``, ``omtp_drake.scenario``,
``omtp_drake.workspace`` and below.
"""

from omtp_drake.launch.options import add_cell_options, chosen_cell, resolve_cell_options
from omtp_drake.launch.own_cell import OwnCell, own_cell, student_workspace

__all__ = [
    "OwnCell",
    "add_cell_options",
    "chosen_cell",
    "own_cell",
    "resolve_cell_options",
    "student_workspace",
]
