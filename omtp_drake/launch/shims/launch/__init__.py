"""omtp_drake's own ``launch`` (ROS 2's launch API, the part course and tutorial files use).

Put on ``sys.path`` by :mod:`omtp_drake.launch.launch_py` only while a ``.launch.py`` runs:
the file's ``generate_launch_description()`` builds these entities, and the reader visits
them as ``ros2 launch`` would (arguments, substitutions, conditions, includes, timers, event
handlers), recording what would start instead of starting it.
"""

from launch.launch_context import LaunchContext, LaunchDescriptionEntity, Substitution
from launch.launch_description import LaunchDescription

__all__ = ["LaunchContext", "LaunchDescription", "LaunchDescriptionEntity", "Substitution"]
