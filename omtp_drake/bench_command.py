"""``omtp-drake bench``'s link to the benchmarks: ``bench/`` owns them (the speed
table's measurements are ``bench/speed.py``), and this module loads that file from
the source checkout the package is installed from."""

from __future__ import annotations

import importlib.util
import sys
from collections.abc import Callable
from pathlib import Path
from types import ModuleType
from typing import Any, Optional

from omtp_drake.errors import BenchmarkError

#: The benchmarks' directory of the checkout this package lives in.
BENCH_DIR = Path(__file__).resolve().parent.parent / "bench"
#: The name ``bench/speed.py`` is imported under.
_MODULE = "omtp_bench_speed"


def speed_module() -> ModuleType:
    """``bench/speed.py``, imported once; BenchmarkError when the package has no
    ``bench/`` beside it (an install without the source checkout)."""
    return _import(BENCH_DIR / "speed.py", _MODULE)


def bench_module(stem: str) -> ModuleType:
    """``bench/<stem>.py``, imported once under its own name ``stem``; the bench modules
    it imports by name at its top (``peer_job``...) load from ``bench/`` too."""
    return _import(BENCH_DIR / f"{stem}.py", stem, siblings=True)


def _import(path: Path, name: str, siblings: bool = False) -> ModuleType:
    if name in sys.modules:
        return sys.modules[name]
    spec = importlib.util.spec_from_file_location(name, path)
    if not path.is_file() or spec is None or spec.loader is None:
        raise BenchmarkError(
            f"omtp-drake bench measures with {path}, which is not there: run it from a source checkout"
        )
    module = importlib.util.module_from_spec(spec)
    sys.modules[name] = module  # (its dataclasses look their module up by name)
    if siblings:
        sys.path.insert(0, str(BENCH_DIR))
    try:
        spec.loader.exec_module(module)
    except BaseException:
        del sys.modules[name]
        raise
    finally:
        if siblings:
            sys.path.remove(str(BENCH_DIR))
    return module


def measure(
    repeats: int = 2, bare_seconds: float = 10.0, progress: Optional[Callable[[str], None]] = None
) -> Any:
    """``bench/speed.py``'s ``measure``: the speed table's report."""
    return speed_module().measure(repeats, bare_seconds, progress)
