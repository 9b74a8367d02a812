"""omtp_drake: the OMTP factory cell of the object-detection-and-grasping course in Drake.

The usual entry points::

    from omtp_drake import Cell, tool_down          # script the cell yourself
    from omtp_drake import FactoryRuntime           # the cell and its services
    from omtp_drake import run_task, load_scenario  # a scenario's pick-and-place task
"""

from omtp_drake.planning import tool_down
from omtp_drake.runtime import FactoryRuntime
from omtp_drake.scenario import load_scenario
from omtp_drake.script import Cell
from omtp_drake.tasks import run_task

__all__ = ["Cell", "FactoryRuntime", "load_scenario", "run_task", "tool_down"]
