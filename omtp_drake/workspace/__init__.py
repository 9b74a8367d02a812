"""A student's own ROS workspace: packages and Gazebo models by name, as ROS and Gazebo find them.

In the course, students build the cell in their own catkin workspace: a URDF/xacro
factory that says ``$(find omtp_support)``, meshes by ``package://ur_description/...``,
a Gazebo world that includes ``model://logical_camera1``. :class:`Workspace` finds
those names the way ``rospack`` and Gazebo do (``package.xml`` folders under each
workspace folder and ``ROS_PACKAGE_PATH``; ``model.config`` folders under
``GAZEBO_MODEL_PATH`` and the packages' exported ``gazebo_model_path``), and hands
them to Drake's ``PackageMap`` for the parser.

Modules (one job each):

- ``packages``: ``Workspace``: packages and Gazebo models by name, URIs resolved to files
- ``xacro_files``: xacro expanded with ``$(find PKG)`` resolved in a workspace

May import: ``omtp_drake.errors``.
"""

from omtp_drake.workspace.packages import Workspace
from omtp_drake.workspace.xacro_files import expand_xacro_in, xacro_finds_in

__all__ = ["Workspace", "expand_xacro_in", "xacro_finds_in"]
