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

from __future__ import annotations

from typing import TYPE_CHECKING

from omtp_drake.lazy import lazy_names

if TYPE_CHECKING:  # the names for type checkers (``X as X``: re-exported)
    from omtp_drake.scenario.camera import LogicalCameraConfig as LogicalCameraConfig
    from omtp_drake.scenario.configs import BinConfig as BinConfig
    from omtp_drake.scenario.configs import BinGeometry as BinGeometry
    from omtp_drake.scenario.configs import ConveyorConfig as ConveyorConfig
    from omtp_drake.scenario.configs import FrameConfig as FrameConfig
    from omtp_drake.scenario.configs import PartConfig as PartConfig
    from omtp_drake.scenario.configs import RobotConfig as RobotConfig
    from omtp_drake.scenario.configs import SleepConfig as SleepConfig
    from omtp_drake.scenario.configs import SpawnerConfig as SpawnerConfig
    from omtp_drake.scenario.configs import TaskConfig as TaskConfig
    from omtp_drake.scenario.configs import check_in_cell as check_in_cell
    from omtp_drake.scenario.faults import FaultConfig as FaultConfig
    from omtp_drake.scenario.gazebo_tags import GazeboExtensions as GazeboExtensions
    from omtp_drake.scenario.gazebo_tags import SensorConfig as SensorConfig
    from omtp_drake.scenario.latency import RosLatencyConfig as RosLatencyConfig
    from omtp_drake.scenario.loader import as_scenario as as_scenario
    from omtp_drake.scenario.loader import load_scenario as load_scenario
    from omtp_drake.scenario.loader import require_scenario as require_scenario
    from omtp_drake.scenario.loader import scenario_document as scenario_document
    from omtp_drake.scenario.loader import scenario_from_dict as scenario_from_dict
    from omtp_drake.scenario.loader import scenario_names as scenario_names
    from omtp_drake.scenario.loader import scenario_text as scenario_text
    from omtp_drake.scenario.models import ModelConfig as ModelConfig
    from omtp_drake.scenario.models import model_from_file as model_from_file
    from omtp_drake.scenario.models import model_from_text as model_from_text
    from omtp_drake.scenario.refusals import closest_name as closest_name
    from omtp_drake.scenario.refusals import is_record as is_record
    from omtp_drake.scenario.refusals import schema_fields as schema_fields
    from omtp_drake.scenario.refusals import unwrap_optional as unwrap_optional
    from omtp_drake.scenario.robot_world import EMPTY_WORLD as EMPTY_WORLD
    from omtp_drake.scenario.robot_world import with_robot as with_robot
    from omtp_drake.scenario.schema import Scenario as Scenario
    from omtp_drake.scenario.suction import SuctionConfig as SuctionConfig

#: The public names, by the module that defines them: each is imported on first use
#: (:mod:`omtp_drake.lazy`), so that importing one module of this package imports only it.
_MODULES = {
    "as_scenario": ".loader",
    "BinConfig": ".configs",
    "BinGeometry": ".configs",
    "check_in_cell": ".configs",
    "closest_name": ".refusals",
    "ConveyorConfig": ".configs",
    "EMPTY_WORLD": ".robot_world",
    "FaultConfig": ".faults",
    "FrameConfig": ".configs",
    "GazeboExtensions": ".gazebo_tags",
    "is_record": ".refusals",
    "load_scenario": ".loader",
    "LogicalCameraConfig": ".camera",
    "model_from_file": ".models",
    "model_from_text": ".models",
    "ModelConfig": ".models",
    "PartConfig": ".configs",
    "require_scenario": ".loader",
    "RobotConfig": ".configs",
    "RosLatencyConfig": ".latency",
    "Scenario": ".schema",
    "scenario_document": ".loader",
    "scenario_from_dict": ".loader",
    "scenario_names": ".loader",
    "scenario_text": ".loader",
    "schema_fields": ".refusals",
    "SensorConfig": ".gazebo_tags",
    "SleepConfig": ".configs",
    "SpawnerConfig": ".configs",
    "SuctionConfig": ".suction",
    "TaskConfig": ".configs",
    "unwrap_optional": ".refusals",
    "with_robot": ".robot_world",
}
__getattr__, __dir__ = lazy_names(__name__, _MODULES)

__all__ = sorted(_MODULES)
