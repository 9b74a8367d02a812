"""One clear error for every ROS name this project does not provide."""

from __future__ import annotations

from collections.abc import Callable
from typing import Any, NoReturn

from omtp_drake.errors import NotSupportedError

__all__ = ["NotSupportedError", "module_getattr", "not_supported"]


def not_supported(what: str, hint: str = "") -> NoReturn:
    raise NotSupportedError(f"{what} is not supported by omtp-drake ros-run" + (f"; {hint}" if hint else ""))


def module_getattr(module: str, names: list[str]) -> Callable[[str], Any]:
    """A module ``__getattr__`` that names the missing attribute and what the module has."""

    def __getattr__(name: str) -> Any:
        if name.startswith("_"):
            raise AttributeError(name)
        not_supported(f"{module}.{name}", f"{module} here has: {', '.join(sorted(names))}")

    return __getattr__
