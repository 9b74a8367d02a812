"""omtp_drake's stand-in for gazebo_ros's ``gazebo.launch.py`` (ROS 2): the same arguments;
its gzserver process is the cell's world (omtp_drake reads ``world``; '' is the empty world)."""

from launch import LaunchDescription
from launch.actions import DeclareLaunchArgument, IncludeLaunchDescription
from launch.conditions import IfCondition
from launch.launch_description_sources import PythonLaunchDescriptionSource
from launch.substitutions import LaunchConfiguration, ThisLaunchFileDir


def generate_launch_description():
    here = ThisLaunchFileDir()
    return LaunchDescription(
        [
            DeclareLaunchArgument("gui", default_value="true", description="start gzclient"),
            DeclareLaunchArgument("server", default_value="true", description="start gzserver"),
            IncludeLaunchDescription(
                PythonLaunchDescriptionSource([here, "/gzserver.launch.py"]),
                condition=IfCondition(LaunchConfiguration("server")),
            ),
            IncludeLaunchDescription(
                PythonLaunchDescriptionSource([here, "/gzclient.launch.py"]),
                condition=IfCondition(LaunchConfiguration("gui")),
            ),
        ]
    )
