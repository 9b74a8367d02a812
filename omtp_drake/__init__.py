"""omtp_drake: the OMTP factory cell of the object-detection-and-grasping course in Drake.

The usual entry points::

    from omtp_drake import Cell, tool_down          # script the cell yourself
    from omtp_drake import FactoryRuntime           # the cell and its services
    from omtp_drake import run_task, load_scenario  # a scenario's pick-and-place task

``import omtp_drake`` loads nothing heavy: each name is imported on first use.

The packages, bottom to top (a package imports only from those below it):
``errors`` -> ``assets`` -> ``scenario`` -> ``cell`` -> ``sim``, ``control`` -> ``viz``
-> ``tasks``, ``script`` -> ``batch`` -> ``ros``, ``demos``, ``benchmark`` -> ``cli``
(tests/test_layering.py holds the order and checks it).
"""

from __future__ import annotations

import importlib
from typing import TYPE_CHECKING, Any

_LAZY = {
    "Cell": "omtp_drake.script",
    "FactoryRuntime": "omtp_drake.sim.runtime",
    "load_scenario": "omtp_drake.scenario",
    "run_task": "omtp_drake.tasks",
    "tool_down": "omtp_drake.control.tool_paths",
}

__all__ = ["Cell", "FactoryRuntime", "load_scenario", "run_task", "tool_down"]

if TYPE_CHECKING:
    from omtp_drake.control.tool_paths import tool_down
    from omtp_drake.scenario import load_scenario
    from omtp_drake.script import Cell
    from omtp_drake.sim.runtime import FactoryRuntime
    from omtp_drake.tasks import run_task


def __getattr__(name: str) -> Any:
    if name not in _LAZY:
        raise AttributeError(f"module 'omtp_drake' has no attribute {name!r}")
    value = getattr(importlib.import_module(_LAZY[name]), name)
    globals()[name] = value
    return value
