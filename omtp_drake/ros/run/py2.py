"""Course code written for ROS Melodic, which ran Python 2.7.

Melodic scripts and FlexBE states often have Python 2 syntax (``print "..."``,
``except rospy.ServiceException, e:``, tabs mixed with spaces) or meaning
(``map(...)[0]``). :func:`translate` turns such code into Python 3 with 2to3
(``fissix``, the maintained fork of the standard library's deprecated
``lib2to3``), after reading its indentation as Python 2 reads it (a tab advances
to the next multiple of 8 columns). Lines stay where they were, so a traceback
still points at the student's line. What 2to3 does not change stays Python 3:
``/`` on two integers is true division.

- ``ros-run``: :func:`script_code` compiles a script as it is and, only when that is
  a ``SyntaxError``, its translation (then the modules of the script's folder load
  translated too, :func:`python2_imports`).
- ``flexbe-run``: a workspace with a module that compiles only as its translation
  (:func:`python2_roots`) loads every module translated (:func:`python2_imports`),
  since a Python 2 state may compile as Python 3 and fail only when it runs;
  ``--python2`` does so for every workspace.
"""

from __future__ import annotations

import contextlib
import functools
import importlib.abc
import importlib.machinery
import importlib.util
import io
import logging
import sys
import threading
import tokenize
import types
from collections.abc import Iterator, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Optional

_log = logging.getLogger(__name__)

#: Python 2's tab stops.
TAB_STOP = 8
#: The 2to3 fixer for Python 2's implicit relative imports (``import helper`` in a
#: package -> ``from . import helper``): right in a package, wrong in a script.
_RELATIVE_IMPORTS = "fissix.fixes.fix_import"


@dataclass(frozen=True)
class ScriptCode:
    """A script compiled for ``exec``; ``python2``: it is its 2to3 translation."""

    code: types.CodeType
    python2: bool


def script_code(path: Path) -> ScriptCode:
    """``path`` compiled as Python 3 or, when that fails, as its 2to3 translation.

    A script that is neither raises the ``SyntaxError`` of the script as written.
    """
    source = path.read_text(encoding="utf-8", errors="surrogateescape")
    try:
        return ScriptCode(compile(source, str(path), "exec", dont_inherit=True), python2=False)
    except SyntaxError as error:
        translated = translate(source, path, in_package=False)
        if translated is None:
            raise error from None
        try:
            code = compile(translated, str(path), "exec", dont_inherit=True)
        except SyntaxError:
            raise error from None
    _log.warning("%s is Python 2 (ROS Melodic): running its 2to3 translation", path.name)
    return ScriptCode(code, python2=True)


def _is_python2(path: Path) -> bool:
    """``path`` does not compile as Python 3 and its 2to3 translation does."""
    source = path.read_text(encoding="utf-8", errors="surrogateescape")
    try:
        compile(source, str(path), "exec", dont_inherit=True)
        return False
    except (SyntaxError, ValueError):
        pass
    translated = translate(source, path, in_package=True)
    if translated is None:
        return False
    try:
        compile(translated, str(path), "exec", dont_inherit=True)
    except (SyntaxError, ValueError):
        return False
    return True


def python2_roots(roots: Sequence[Path]) -> list[Path]:
    """The folders of ``roots`` (catkin workspaces) that hold a Python 2 module: one that
    does not compile as Python 3 while its 2to3 translation does."""
    found = []
    for root in roots:
        modules = sorted(p for p in Path(root).rglob("*.py") if p.is_file())
        python2 = next((m for m in modules if _is_python2(m)), None)
        if python2 is not None:
            _log.warning(
                "%s is Python 2 (ROS Melodic): the modules of %s load as their 2to3 translation",
                python2.name,
                root,
            )
            found.append(Path(root))
    return found


def _string_continuation_lines(source: str) -> set[int]:
    """Line numbers (1-based) that continue a multi-line string token."""
    inside: set[int] = set()
    try:
        for token in tokenize.generate_tokens(io.StringIO(source).readline):
            if token.type == tokenize.STRING and token.end[0] > token.start[0]:
                inside.update(range(token.start[0] + 1, token.end[0] + 1))
    except (tokenize.TokenError, SyntaxError):
        pass  # compile() reports what is wrong with the file
    return inside


def python2_indentation(source: str) -> str:
    """``source`` with tabs in indentation replaced as Python 2 reads them."""
    inside = _string_continuation_lines(source)
    out = []
    for number, line in enumerate(source.splitlines(keepends=True), start=1):
        body = line.lstrip(" \t")
        indent = line[: len(line) - len(body)]
        if number in inside or "\t" not in indent:
            out.append(line)
            continue
        column = 0
        for char in indent:
            column = (column // TAB_STOP + 1) * TAB_STOP if char == "\t" else column + 1
        out.append(" " * column + body)
    return "".join(out)


#: One 2to3 run at a time per process: a tool's fixers keep the tree they work on.
_TOOL_LOCK = threading.Lock()


@functools.lru_cache(maxsize=2)
def _refactoring_tool(in_package: bool) -> Any:
    """2to3's tool with every fixer (but the relative imports' outside a package), made once
    per process: making one (its fixers' patterns compiled) costs ~0.1 CPU s, a script's
    translation with it ~2 ms, and 2to3 itself runs one tool over many files (each fixer
    starts afresh on each file's tree)."""
    from fissix.refactor import RefactoringTool, get_fixers_from_package

    fixers = [f for f in get_fixers_from_package("fissix.fixes") if in_package or f != _RELATIVE_IMPORTS]
    return RefactoringTool(fixers)


def translate(source: str, path: str | Path, *, in_package: bool) -> Optional[str]:
    """``source`` (Python 2) as Python 3; None when 2to3 cannot parse it.
    ``in_package``: a package's module (implicit relative imports are relative)."""
    from fissix.pgen2.parse import ParseError

    source = python2_indentation(source if source.endswith("\n") else source + "\n")
    with _TOOL_LOCK:
        try:
            return str(_refactoring_tool(in_package).refactor_string(source, str(path)))
        except ParseError:
            return None


def run_as_main(script: ScriptCode, path: Path) -> None:
    """Runs the code as the ``__main__`` module of ``path`` (as ``python path`` would,
    and as ``runpy.run_path`` does); the previous ``__main__`` is restored after."""
    module = types.ModuleType("__main__")
    module.__file__ = str(path)
    module.__builtins__ = __builtins__  # type: ignore[attr-defined]
    saved = sys.modules.get("__main__")
    sys.modules["__main__"] = module
    try:
        exec(script.code, module.__dict__)
    finally:
        if saved is not None:
            sys.modules["__main__"] = saved
        else:
            del sys.modules["__main__"]


class _Python2Loader(importlib.machinery.SourceFileLoader):
    """Loads a module from its 2to3 translation (nothing is cached on disk)."""

    def get_code(self, fullname: str) -> Any:
        path = self.get_filename(fullname)
        source = importlib.util.decode_source(self.get_data(path))
        translated = translate(source, path, in_package="." in fullname)
        return compile(source if translated is None else translated, path, "exec", dont_inherit=True)


class _Python2Finder(importlib.abc.MetaPathFinder):
    def __init__(self, roots: Sequence[Path]):
        self._roots = tuple(str(r) for r in roots)

    def find_spec(self, fullname: str, path: Any, target: Any = None) -> Optional[Any]:
        spec = importlib.machinery.PathFinder.find_spec(fullname, path)
        if spec is None or not spec.origin or not spec.origin.endswith(".py"):
            return None
        if not spec.origin.startswith(self._roots):
            return None
        spec.loader = _Python2Loader(fullname, spec.origin)
        return spec


@contextlib.contextmanager
def python2_imports(roots: Sequence[Path], enabled: bool) -> Iterator[None]:
    """While active (and ``enabled``), modules under ``roots`` load converted from Python 2."""
    if not enabled:
        yield
        return
    finder = _Python2Finder(roots)
    sys.meta_path.insert(0, finder)
    try:
        yield
    finally:
        sys.meta_path.remove(finder)
