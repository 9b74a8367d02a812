"""omtp_drake's stand-in for gazebo_ros's ``gzclient.launch.py`` (ROS 2): Gazebo's window
(omtp_drake shows the cell in Meshcat instead)."""

from launch import LaunchDescription
from launch.actions import DeclareLaunchArgument, ExecuteProcess


def generate_launch_description():
    names = ("version", "verbose", "help", "gdb", "valgrind", "gui_required")
    args = [DeclareLaunchArgument(name, default_value="") for name in names]
    return LaunchDescription([*args, ExecuteProcess(cmd=["gzclient"])])
