"""``omtp-drake batch`` (registered with :func:`add_batch_command`) and the progress-bar
options the task commands share (``-q``, ``--progress``)."""

from __future__ import annotations

import argparse
import sys

from omtp_drake.launch.options import add_cell_options


def _say(text: str) -> None:
    """A line of the command's output (stdout)."""
    sys.stdout.write(text + "\n")


def show_progress(args: argparse.Namespace) -> bool:
    """A progress bar only on a terminal (a log gets no carriage-return lines):
    ``--progress`` asks for one anyway, ``-q`` for none."""
    if getattr(args, "quiet", False):
        return False
    return bool(getattr(args, "progress", False)) or sys.stderr.isatty()


def add_progress_options(p: argparse.ArgumentParser) -> None:
    """``-q/--quiet`` and ``--progress`` (read by :func:`show_progress`)."""
    p.add_argument("-q", "--quiet", action="store_true", help="no progress bar")
    p.add_argument(
        "--progress", action="store_true", help="a progress bar even when stderr is not a terminal"
    )


def cmd_batch(args: argparse.Namespace) -> int:
    """``omtp-drake batch``: exit 0 when every run succeeded, 1 otherwise."""
    from omtp_drake.batch import format_summary, parse_seeds, parse_sets, run_batch, summarize

    seeds = parse_seeds(args.seeds)
    sweep = parse_sets(args.set)
    out = args.out
    if out is None:
        out = f"batch_{args.scenario.name or 'cell'}"  # (a Scenario: the cell options resolved)
    records = run_batch(
        args.scenario,
        seeds,
        settings=sweep,
        parts=args.parts,
        duration=args.duration,
        workers=args.workers,
        scheduler=args.scheduler,
        timeout=args.timeout,
        out=out,
        progress=show_progress(args),
    )
    resumed = sum(r.resumed for r in records)
    if resumed:
        _say(f"resumed: {resumed} of {len(records)} runs were done already in {out}/ and were skipped")
    _say(format_summary(summarize(records)))
    _say(f"results: {out}/ (runs/*.json, runs.csv, summary.json, success_rate.png, cycle_times.png)")
    return 0 if all(r.success for r in records) else 1


def add_batch_command(sub: argparse._SubParsersAction) -> None:
    """Registers ``omtp-drake batch``: a scenario's task over seeds and settings on Dask."""
    p = sub.add_parser(
        "batch",
        help="run a scenario's task over seeds and settings on Dask: success rates, cycle times",
        description="Every (seed, setting) is one run on a Dask cluster (local processes by default). "
        "Re-running with the same --out resumes.",
    )
    add_cell_options(p, positional=True)
    p.add_argument("--seeds", required=True, metavar="A:B", help="seeds A..B-1 (e.g. 0:100), or 3,7,9")
    p.add_argument("--parts", type=int, default=None, help="parts to place per run")
    p.add_argument("--duration", type=float, default=None, help="simulated seconds at most per run")
    p.add_argument(
        "--set",
        action="append",
        default=[],
        metavar="KEY=V1,V2",
        help="sweep a scenario field, e.g. task.max_tool_speed=0.6,0.8 or "
        "cameras.logical_camera_2.position_noise_sigma=0,0.001 (repeatable; the grid is every combination)",
    )
    where = p.add_mutually_exclusive_group()
    where.add_argument(
        "--workers", type=int, default=None, metavar="N", help="local worker processes (default: core count)"
    )
    where.add_argument("--scheduler", metavar="ADDRESS", help="an existing Dask scheduler, tcp://host:8786")
    p.add_argument(
        "--timeout", type=float, default=None, metavar="S", help="wall seconds per run (default: none)"
    )
    p.add_argument("--out", default=None, metavar="DIR", help="results folder (default: batch_<scenario>)")
    add_progress_options(p)
    p.set_defaults(func=cmd_batch)
