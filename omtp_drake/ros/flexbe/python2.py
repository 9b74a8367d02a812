"""``--python2``: the workspaces' modules converted from Python 2 as they load.

The course's lecture-7 packages were written for ROS Melodic, whose Python is 2:
their states mix tabs and spaces in indentation and index ``map(...)`` results.
With ``--python2`` every module of a workspace package is, when imported,
converted with ``lib2to3``'s standard fixers (``map`` -> ``list(map(...))``,
``print`` statements, ``dict.iteritems``, implicit relative imports...) and its
indentation read as Python 2 reads it (a tab advances to the next multiple of 8
columns; lines inside multi-line strings are left as they are). Line numbers
stay those of the file, so errors point at the student's lines. Nothing is
written to the workspace (no bytecode cache of converted code).
"""

from __future__ import annotations

import contextlib
import importlib.abc
import importlib.machinery
import importlib.util
import io
import sys
import tokenize
import warnings
from collections.abc import Iterator, Sequence
from pathlib import Path
from typing import Any, Optional

from omtp_drake.errors import NotSupportedError

#: Python 2's tab stops.
TAB_STOP = 8


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


class Python2Converter:
    """lib2to3's refactoring tool with its standard fixers."""

    def __init__(self) -> None:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            try:
                from lib2to3.refactor import RefactoringTool, get_fixers_from_package
            except ImportError:
                raise NotSupportedError(
                    "--python2 needs the standard library's lib2to3 (Python <= 3.12); this Python has none"
                ) from None
        self._tool = RefactoringTool(get_fixers_from_package("lib2to3.fixes"))

    def convert(self, source: str, path: str) -> str:
        source = python2_indentation(source if source.endswith("\n") else source + "\n")
        return str(self._tool.refactor_string(source, path))


class _Python2Loader(importlib.machinery.SourceFileLoader):
    def __init__(self, fullname: str, path: str, converter: Python2Converter):
        super().__init__(fullname, path)
        self._converter = converter

    def get_code(self, fullname: str) -> Any:
        path = self.get_filename(fullname)
        source = importlib.util.decode_source(self.get_data(path))
        return compile(self._converter.convert(source, path), path, "exec", dont_inherit=True)


class _Python2Finder(importlib.abc.MetaPathFinder):
    def __init__(self, roots: Sequence[Path], converter: Python2Converter):
        self._roots = tuple(str(r) for r in roots)
        self._converter = converter

    def find_spec(self, fullname: str, path: Any, target: Any = None) -> Optional[Any]:
        spec = importlib.machinery.PathFinder.find_spec(fullname, path)
        if spec is None or not spec.origin or not spec.origin.endswith(".py"):
            return None
        if not spec.origin.startswith(self._roots):
            return None
        spec.loader = _Python2Loader(fullname, spec.origin, self._converter)
        return spec


@contextlib.contextmanager
def python2_imports(roots: Sequence[Path], enabled: bool) -> Iterator[None]:
    """While active (and ``enabled``), modules under ``roots`` load converted from Python 2."""
    if not enabled:
        yield
        return
    finder = _Python2Finder(roots, Python2Converter())
    sys.meta_path.insert(0, finder)
    try:
        yield
    finally:
        sys.meta_path.remove(finder)
