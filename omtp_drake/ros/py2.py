"""Course scripts written for ROS Melodic, which ran Python 2.7.

A Melodic script often has Python 2 syntax (``print "..."``,
``except rospy.ServiceException, e:``) that Python 3 cannot compile, so it would
fail before its first line runs. :func:`script_code` compiles a script as it is
and, only when that is a ``SyntaxError``, compiles its 2to3 translation instead
(``fissix``, the maintained fork of the standard library's deprecated
``lib2to3``); the translation keeps the script's lines where they were, so a
traceback still points at the student's line. What 2to3 does not change stays
Python 3: ``/`` on two integers is true division, as in Python 3.

Only the script itself is translated, not modules it imports from its folder.
"""

from __future__ import annotations

import logging
import sys
import types
from dataclasses import dataclass
from pathlib import Path

_log = logging.getLogger(__name__)

#: 2to3's fixers that would change what a script means when run as ``__main__``:
#: ``fix_import`` turns ``import helper`` into ``from . import helper``.
_SKIPPED_FIXERS = frozenset({"fissix.fixes.fix_import"})


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
        translated = _translate(source, path)
        if translated is None:
            raise error from None
        try:
            code = compile(translated, str(path), "exec", dont_inherit=True)
        except SyntaxError:
            raise error from None
    _log.warning("%s is Python 2 (ROS Melodic): running its 2to3 translation", path.name)
    return ScriptCode(code, python2=True)


def _translate(source: str, path: Path) -> str | None:
    from fissix.pgen2.parse import ParseError
    from fissix.refactor import RefactoringTool, get_fixers_from_package

    fixers = [f for f in get_fixers_from_package("fissix.fixes") if f not in _SKIPPED_FIXERS]
    if not source.endswith("\n"):
        source += "\n"
    try:
        return str(RefactoringTool(fixers).refactor_string(source, str(path)))
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
