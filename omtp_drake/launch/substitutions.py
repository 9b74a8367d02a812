"""roslaunch's substitution args: ``$(arg)``, ``$(find)``, ``$(env)``, ``$(optenv)``,
``$(dirname)``, ``$(anon)`` and ``$(eval)``, by roslaunch's rules.

As roslaunch does: ``$(eval EXPR)`` is only recognised as a whole attribute value, and
evaluates EXPR as Python with the launch file's args as names (and ``arg()``, ``find()``,
``env()``, ``optenv()``, ``dirname()``, ``anon()``, the ``math`` module's names, ``true``,
``false``), with no builtins but a few conversions and no double underscores. Every other
value has its ``$(env)``, ``$(optenv)``, ``$(dirname)``, ``$(anon)`` and ``$(arg)``
resolved first, then ``$(find)``. A value of the wrong form, an unknown command, an arg
without a value, a package no workspace has: one :class:`~omtp_drake.errors.WorkspaceError`
naming the file and line.
"""

from __future__ import annotations

import math
import os
import re
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from omtp_drake.errors import WorkspaceError
from omtp_drake.workspace import Workspace

#: The substitution commands roslaunch knows.
COMMANDS = ("find", "env", "optenv", "dirname", "anon", "arg", "eval")
_SUBST = re.compile(r"\$\(([^()$]*)\)")


@dataclass
class Context:
    """What a substitution sees: the file (and line) it is in, its args, the workspace."""

    file: Path
    args: Mapping[str, str | None]
    workspace: Workspace
    environ: Mapping[str, str] = field(default_factory=lambda: dict(os.environ))
    line: int | None = None

    def where(self) -> str:
        return f"{self.file}:{self.line}" if self.line else str(self.file)

    def fail(self, message: str) -> WorkspaceError:
        return WorkspaceError(f"{self.where()}: {message}")


def auto_value(text: str) -> Any:
    """A parameter's value from its text as roslaunch's ``auto`` type reads it: a
    float if it has a dot, an int, a bool for true/false, else the string."""
    try:
        if "." in text:
            return float(text)
        if "_" not in text:
            return int(text)
    except ValueError:
        pass
    if text.strip().lower() in ("true", "false"):
        return text.strip().lower() == "true"
    return text


def resolve(text: str | None, ctx: Context) -> str:
    """``text`` with its substitution args resolved (see module doc)."""
    if not text:
        return text or ""
    if text.startswith("$(eval ") and text.endswith(")"):
        return _eval(text[len("$(eval ") : -1], ctx)
    first = {"env": _env, "optenv": _optenv, "dirname": _dirname, "anon": _anon, "arg": _arg}
    return _substitute(_substitute(text, ctx, first), ctx, {"find": _find})


def is_true(text: str | None, ctx: Context, what: str) -> bool:
    """An ``if``/``unless`` value: true/1 or false/0 (any case), or the error roslaunch gives."""
    value = resolve(text, ctx).strip().lower()
    if value in ("true", "1"):
        return True
    if value in ("false", "0"):
        return False
    raise ctx.fail(f"{what}={text!r} is {value!r}, not a boolean; valid: true, false, 1, 0")


def _substitute(text: str, ctx: Context, commands: Mapping[str, Callable[[list[str], Context], str]]) -> str:
    def one(match: re.Match) -> str:
        words = match.group(1).split()
        if not words or words[0] not in COMMANDS or words[0] == "eval":
            valid = ", ".join(c for c in COMMANDS if c != "eval")
            raise ctx.fail(
                f"unknown substitution $({match.group(1)}); valid: {valid} (and $(eval ...) as a whole value)"
            )
        command = commands.get(words[0])
        return command(words[1:], ctx) if command else match.group(0)

    return _SUBST.sub(one, text)


def _arg(words: list[str], ctx: Context) -> str:
    if len(words) != 1:
        raise ctx.fail(f"$(arg {' '.join(words)}) must name one arg")
    return _arg_value(words[0], ctx)


def _arg_value(name: str, ctx: Context) -> str:
    if name not in ctx.args:
        known = ", ".join(sorted(ctx.args)) or "none"
        raise ctx.fail(f"$(arg {name}): no arg {name!r} is declared here (declared: {known})")
    value = ctx.args[name]
    if value is None:
        raise ctx.fail(f"$(arg {name}) has no value; give it as {name}:=VALUE")
    return value


def _find(words: list[str], ctx: Context) -> str:
    if len(words) != 1:
        raise ctx.fail(f"$(find {' '.join(words)}) must name one package")
    return str(ctx.workspace.package(words[0], needed_by=ctx.where()))


def _env(words: list[str], ctx: Context) -> str:
    if len(words) != 1:
        raise ctx.fail(f"$(env {' '.join(words)}) must name one variable")
    if words[0] not in ctx.environ:
        raise ctx.fail(f"$(env {words[0]}): environment variable {words[0]} is not set")
    return ctx.environ[words[0]]


def _optenv(words: list[str], ctx: Context) -> str:
    if not words:
        raise ctx.fail("$(optenv) must name a variable")
    return ctx.environ.get(words[0], " ".join(words[1:]))


def _dirname(words: list[str], ctx: Context) -> str:
    return str(ctx.file.resolve().parent)


def _anon(words: list[str], ctx: Context) -> str:
    if len(words) != 1:
        raise ctx.fail(f"$(anon {' '.join(words)}) must give one name")
    return f"{words[0]}_anon"


_EVAL_BUILTINS = {"list": list, "dict": dict, "map": map, "str": str, "float": float, "int": int}


def _eval(expression: str, ctx: Context) -> str:
    if "__" in expression:
        raise ctx.fail(f"$(eval {expression}) may not contain double underscores")
    functions: dict[str, Any] = {name: getattr(math, name) for name in dir(math) if not name.startswith("_")}
    functions.update(
        true=True,
        false=False,
        arg=lambda name: auto_value(_arg_value(name, ctx)),
        find=lambda pkg: _find([pkg], ctx),
        env=lambda name: _env([name], ctx),
        optenv=lambda name, default="": _optenv([name, default], ctx),
        dirname=lambda: _dirname([], ctx),
        anon=lambda name: _anon([name], ctx),
    )

    class Names(dict):
        def __missing__(self, key: str) -> Any:
            return auto_value(_arg_value(key, ctx))

    try:
        return str(eval(expression, {"__builtins__": _EVAL_BUILTINS}, Names(functions)))  # noqa: S307
    except WorkspaceError:
        raise
    except Exception as e:
        raise ctx.fail(f"$(eval {expression}) failed: {type(e).__name__}: {e}") from None
