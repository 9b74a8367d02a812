"""The scenario: the typed schema of ``diagrams/*.yaml`` and the one loader.

Modules (one job each):

- ``schema``: ``Scenario``: which world to build, the root of the schema
- ``configs``: the scenario's pieces: robots, bins, parts, the belt, the spawner, the task
- ``arm_dynamics``: an arm's joint velocity/effort limits and links' inertials as its file writes them
- ``conveyor_spawner``: the course's conveyor spawner plugin: its parameters read once, its draws
- ``camera``: a logical camera's settings
- ``suction``: a vacuum gripper's settings
- ``plugin_names``: the ROS names of the course's plugins, as a student's ``<plugin>`` sets them
- ``latency``: the simulated time a ROS script's calls take
- ``models``: a model from a description file (URDF, xacro, SDF): name, pose, Gazebo tags
- ``gazebo_tags``: a description's ``<gazebo>`` tags as typed settings: materials, friction, sensors, plugins
- ``gazebo_parse``: reading those tags from URDF or SDF text
- ``ros_control``: a robot's ros_control / ros2_control set-up: hardware joints, started controllers
- ``ros_control_parse``: reading it from transmissions, ``<ros2_control>`` tags and controllers YAML
- ``robot_world``: a scenario (or Gazebo's empty world) with a student's robot spawned in it
- ``faults``: faults as data: what goes wrong in a run, when, and for how long
- ``loader``: YAML, ``base:`` merges and Drake's typed load: the one place a file becomes a ``Scenario``
- ``refusals``: a refused document said in one line (the key path, the valid keys, the closest name)

:func:`as_scenario` is the one door from a name or path to a ``Scenario``.

May import: ``omtp_drake.errors``, ``omtp_drake.assets`` and ``omtp_drake.workspace`` (the layers below).
"""

from omtp_drake.scenario.camera import LogicalCameraConfig
from omtp_drake.scenario.configs import (
    BinConfig,
    BinGeometry,
    ConveyorConfig,
    FrameConfig,
    PartConfig,
    RobotConfig,
    SleepConfig,
    SpawnerConfig,
    TaskConfig,
    check_in_cell,
)
from omtp_drake.scenario.faults import FaultConfig
from omtp_drake.scenario.gazebo_tags import GazeboExtensions, SensorConfig
from omtp_drake.scenario.latency import RosLatencyConfig
from omtp_drake.scenario.loader import (
    as_scenario,
    load_scenario,
    require_scenario,
    scenario_document,
    scenario_from_dict,
    scenario_names,
    scenario_text,
)
from omtp_drake.scenario.models import ModelConfig, model_from_file, model_from_text
from omtp_drake.scenario.refusals import closest_name, is_record, schema_fields, unwrap_optional
from omtp_drake.scenario.robot_world import EMPTY_WORLD, with_robot
from omtp_drake.scenario.schema import Scenario
from omtp_drake.scenario.suction import SuctionConfig

__all__ = [
    "EMPTY_WORLD",
    "BinConfig",
    "BinGeometry",
    "ConveyorConfig",
    "FaultConfig",
    "FrameConfig",
    "GazeboExtensions",
    "ModelConfig",
    "SensorConfig",
    "LogicalCameraConfig",
    "PartConfig",
    "RosLatencyConfig",
    "RobotConfig",
    "Scenario",
    "SleepConfig",
    "SpawnerConfig",
    "SuctionConfig",
    "TaskConfig",
    "as_scenario",
    "check_in_cell",
    "closest_name",
    "is_record",
    "load_scenario",
    "model_from_file",
    "model_from_text",
    "require_scenario",
    "scenario_document",
    "scenario_from_dict",
    "scenario_names",
    "scenario_text",
    "schema_fields",
    "unwrap_optional",
    "with_robot",
]
