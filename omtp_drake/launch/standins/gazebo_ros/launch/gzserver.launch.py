"""omtp_drake's stand-in for gazebo_ros's ``gzserver.launch.py`` (ROS 2): ``world`` ('' for
Gazebo's empty world) and the other arguments of the original; the world is the cell's."""

from launch import LaunchDescription
from launch.actions import DeclareLaunchArgument, ExecuteProcess
from launch.substitutions import LaunchConfiguration

#: The original's arguments the cell has no use for (declared, so a launch may give them).
UNUSED = (
    "version verbose lockstep help pause physics play record record_encoding record_path record_period "
    "record_filter seed iters minimal_comms profile extra_gazebo_args gdb valgrind init factory force_system "
    "params_file"
).split()


def generate_launch_description():
    args = [DeclareLaunchArgument("world", default_value="", description="the world file ('': empty)")]
    args += [DeclareLaunchArgument(name, default_value="") for name in UNUSED]
    gzserver = ExecuteProcess(
        cmd=[
            "gzserver",
            "-s",
            "libgazebo_ros_init.so",
            "-s",
            "libgazebo_ros_factory.so",
            LaunchConfiguration("world"),
        ]
    )
    return LaunchDescription([*args, gzserver])
