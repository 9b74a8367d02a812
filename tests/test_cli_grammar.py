"""The command line's grammar (issue 45 item 3, issue 43 item 7): every command's usage line,
as ``--help`` prints it, is accepted in every order it allows: each option before, between
and after the positionals, all options first, all last, reversed. The lines and their orders
are generated from the parser itself (its subparsers and their actions), so a new command or
option is covered when it is added. Parse-only (no cell is built): milliseconds a command.
"""

from __future__ import annotations

import argparse
import contextlib
import io

import pytest

from omtp_drake.cli import _values_that_look_like_options, build_parser

PARSER = build_parser()
COMMANDS: dict[str, argparse.ArgumentParser] = next(
    a for a in PARSER._actions if isinstance(a, argparse._SubParsersAction)
).choices
#: The cell options every command that builds a cell takes (issue 43 item 7).
CELL_OPTIONS = ("--scenario", "--launch", "--world", "--robot", "--workspace", "--arg")
#: The commands that build a cell; `bench` measures its fixed scenarios, `demo` is fill_bin,
#: `screenshot` reads a replay, `scenarios` lists names.
CELL_COMMANDS = (
    "run",
    "camera",
    "tf-echo",
    "frames",
    "view",
    "ros-run",
    "flexbe-run",
    "grade",
    "batch",
    "ros2",
)


def _sample(action: argparse.Action, i: int) -> list[str]:
    """Values for ``action`` that it parses (one, or none for a flag)."""
    if action.nargs == 0:
        return []
    if action.choices:
        return [str(list(action.choices)[-1])]
    if action.type is int:
        return [str(3 + i)]
    if action.type is float:
        return [f"{1.5 + i}"]
    return [f"v{i}"]


def _optionals(p: argparse.ArgumentParser) -> list[argparse.Action]:
    """The options of ``p``'s usage (help left out; of a mutually exclusive group the first)."""
    left_out = {id(a) for g in p._mutually_exclusive_groups for a in g._group_actions[1:]}
    return [
        a
        for a in p._actions
        if a.option_strings and not isinstance(a, argparse._HelpAction) and id(a) not in left_out
    ]


def _words(p: argparse.ArgumentParser) -> tuple[list[list[str]], list[list[str]]]:
    """(positionals, options) of a full usage line of ``p``: each as its words."""
    positionals = [
        _sample(a, i) if a.nargs not in ("*", "+") else [f"p{i}a", f"p{i}b"]
        for i, a in enumerate(p._get_positional_actions())
    ]
    options = [[a.option_strings[-1], *_sample(a, 20 + i)] for i, a in enumerate(_optionals(p))]
    return positionals, options


def _orders(positionals: list[list[str]], options: list[list[str]]) -> list[list[str]]:
    """The orders a line allows: every option at every gap of the positionals (the others
    after them), all options first, all last, and reversed."""
    flat = [w for words in positionals for w in words]
    rest = [w for words in options for w in words]
    out = [flat + rest, rest + flat, [w for words in reversed(options) for w in words] + flat]
    gaps = [sum(len(words) for words in positionals[:k]) for k in range(len(positionals) + 1)]
    for i, words in enumerate(options):
        others = [w for j, ws in enumerate(options) if j != i for w in ws]
        for gap in gaps:
            out.append(flat[:gap] + words + flat[gap:] + others)
    return out


def _parse(command: str, words: list[str]) -> dict:
    with contextlib.redirect_stderr(io.StringIO()) as err:
        try:
            args = PARSER.parse_args(_values_that_look_like_options([command, *words]))
        except SystemExit:
            raise AssertionError(f"omtp-drake {command} {' '.join(words)}: {err.getvalue()}") from None
    return {k: v for k, v in vars(args).items() if k != "func"}


def test_every_command_is_covered():
    assert set(COMMANDS) >= set(CELL_COMMANDS) | {"demo", "scenarios", "screenshot", "bench"}
    for command in CELL_COMMANDS:
        flags = {s for a in COMMANDS[command]._actions for s in a.option_strings}
        missing = [
            o for o in CELL_OPTIONS if o not in flags and not (command == "view" and o == "--scenario")
        ]
        assert not missing, f"{command} lacks {missing}"


@pytest.mark.parametrize("command", sorted(COMMANDS))
def test_the_usage_line_parses_in_every_order(command):
    p = COMMANDS[command]
    positionals, options = _words(p)
    orders = _orders(positionals, options)
    expected = _parse(command, orders[0])
    for words in orders[1:]:
        assert _parse(command, words) == expected, f"omtp-drake {command} {' '.join(words)}"
    # what the usage line names is what was parsed: every option's value reached its dest
    for action in _optionals(p):
        if action.nargs != 0 and action.dest in expected and action.default is not argparse.SUPPRESS:
            assert expected[action.dest] not in (None, []), f"{command} {action.option_strings[-1]}"


@pytest.mark.parametrize("command", sorted(COMMANDS))
def test_help_prints_the_usage_of_every_option(command):
    p = COMMANDS[command]
    with contextlib.redirect_stdout(io.StringIO()) as out, pytest.raises(SystemExit) as exit_:
        PARSER.parse_args([command, "--help"])
    assert exit_.value.code == 0
    for action in _optionals(p):
        assert action.option_strings[-1] in out.getvalue()


def test_tf_echo_as_its_usage_reads():
    """Issue 45: the optional SCENARIO before two required positionals, --time between."""
    args = PARSER.parse_args(["tf-echo", "lecture6_assignment3", "--time", "1.5", "world", "robot1_tool0"])
    assert (args.scenario, args.time, args.source, args.target) == (
        "lecture6_assignment3",
        1.5,
        "world",
        "robot1_tool0",
    )
    args = PARSER.parse_args(["tf-echo", "--scenario", "omtp_factory", "world", "--json", "robot1_tool0"])
    assert (args.scenario, args.scenario_option, args.source, args.target, args.json) == (
        None,
        "omtp_factory",
        "world",
        "robot1_tool0",
        True,
    )


def test_ros_run_script_arguments_stay_the_scripts():
    args = PARSER.parse_args(["ros-run", "s.py", "2", "--scenario", "x", "3", "--", "--not-ours"])
    assert (args.script, args.script_args, args.scenario_option) == ("s.py", ["2", "3", "--not-ours"], "x")
