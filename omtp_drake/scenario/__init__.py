"""The scenario: the typed schema of ``diagrams/*.yaml`` and the one loader.

Lives here: :class:`Scenario` and every ``*Config`` of the schema (``configs``,
``camera``, ``suction``), the loader (``loader``: YAML, ``base:`` merges, checks),
and :func:`as_scenario`, the one door from a name or path to a ``Scenario``.

May import: ``omtp_drake.errors`` and ``omtp_drake.assets`` only (the bottom layer).
"""

from omtp_drake.scenario.camera import LogicalCameraConfig
from omtp_drake.scenario.configs import (
    BinConfig,
    BinGeometry,
    ConveyorConfig,
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
