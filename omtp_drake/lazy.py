"""A package's public names, imported from their modules on first use (PEP 562).

A package ``__init__`` that re-exports its modules' names eagerly makes importing any one
of its modules (``omtp_drake.scenario.robot_world``) import all of them, and with them
Drake: a command line that only declares its options paid for the whole cell. Such a
package says where each name lives instead::

    __getattr__, __dir__ = lazy_names(__name__, {"Scenario": ".schema", ...})

``from omtp_drake.scenario import Scenario`` then imports ``omtp_drake.scenario.schema``
then (a module named as ``importlib.import_module`` takes it: relative to the package, or
absolute, as the top-level facade ``omtp_drake`` names its modules), and the name is kept
on the package (the next lookup is a plain attribute). Type checkers read the package's
``if TYPE_CHECKING:`` imports of the same names (tests/test_layering.py holds the two
lists equal).
"""

from __future__ import annotations

import importlib
import sys
from collections.abc import Callable, Mapping
from typing import Any


def lazy_names(
    package: str, modules: Mapping[str, str]
) -> tuple[Callable[[str], Any], Callable[[], list[str]]]:
    """The module ``__getattr__`` and ``__dir__`` of ``package`` whose public names are
    ``modules``' keys, each defined in the module its value names (``.sub``: relative to
    ``package``)."""

    def __getattr__(name: str) -> Any:
        module = modules.get(name)
        if module is None:
            raise AttributeError(f"module {package!r} has no attribute {name!r}")
        value = getattr(importlib.import_module(module, package), name)
        setattr(sys.modules[package], name, value)
        return value

    def __dir__() -> list[str]:
        return sorted({*vars(sys.modules[package]), *modules})

    return __getattr__, __dir__
