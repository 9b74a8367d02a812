"""The scenario: the typed schema of ``diagrams/*.yaml`` and the one loader.

Modules (one job each):

- ``schema``: ``Scenario``: which world to build, the root of the schema
- ``configs``: the scenario's pieces: robots, bins, parts, the belt, the spawner, the task
- ``camera``: a logical camera's settings
- ``suction``: a vacuum gripper's settings
- ``latency``: the simulated time a ROS script's calls take
- ``faults``: faults as data: what goes wrong in a run, when, and for how long
- ``loader``: YAML, ``base:`` merges and Drake's typed load: the one place a file becomes a ``Scenario``
- ``refusals``: a refused document said in one line (the key path, the valid keys, the closest name)

:func:`as_scenario` is the one door from a name or path to a ``Scenario``.

May import: ``omtp_drake.errors`` and ``omtp_drake.assets`` only (the bottom layer).
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
from omtp_drake.scenario.refusals import closest_name, is_record, schema_fields, unwrap_optional
from omtp_drake.scenario.schema import Scenario
from omtp_drake.scenario.suction import SuctionConfig

__all__ = [
    "BinConfig",
    "BinGeometry",
    "ConveyorConfig",
    "FaultConfig",
    "FrameConfig",
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
    "require_scenario",
    "scenario_document",
    "scenario_from_dict",
    "scenario_names",
    "scenario_text",
    "schema_fields",
    "unwrap_optional",
]
