"""``grade``: every ROS script of a folder (a class's submissions) run on a scenario.

Each script is one ``ros-run`` in a process of its own (a script that crashes,
hangs or calls ``os._exit`` costs only its run), on the workers of the batch
machinery's Dask cluster (:func:`omtp_drake.batch.connect`). The result is one
row per script: its status, the parts it put in bins, the ledger, its times and
its exception; written to ``OUT/runs/<script>.json`` (the run's report),
``OUT/grades.csv`` and ``OUT/grades.png`` (parts in bins and simulated time
per script).
"""

from __future__ import annotations

import csv
import json
import logging
import subprocess
import sys
import tempfile
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any, Optional

from omtp_drake.errors import ConfigError

if TYPE_CHECKING:
    from matplotlib.figure import Figure

_log = logging.getLogger(__name__)

#: Statuses: the script ended cleanly; raised; a move hit something; the run's
#: process exceeded the wall-time limit; the process died.
OK, EXCEPTION, COLLISION, TIMEOUT, CRASHED = "ok", "exception", "collision", "timeout", "crashed"


@dataclass
class Grade:
    """One script's row."""

    script: str
    status: str
    in_bins: int
    report: Optional[dict[str, Any]]
    message: str = ""

    def row(self) -> dict[str, Any]:
        r = self.report or {}
        ledger = r.get("ledger", {})
        return {
            "script": self.script,
            "status": self.status,
            "in_bins": self.in_bins,
            "spawned": ledger.get("spawned", ""),
            "on_floor": ledger.get("on_floor", ""),
            "held": sum(ledger.get("held", {}).values()) if ledger else "",
            "collisions": len(r.get("collisions", [])),
            "sim_time_s": r.get("sim_time_s", ""),
            "wall_time_s": r.get("wall_time_s", ""),
            "message": self.message,
        }


def grade_one(script: str, scenario: str, seed: Optional[int], timeout: float, wall_timeout: float) -> Grade:
    """One script's ros-run in a child process (a Dask task)."""
    with tempfile.TemporaryDirectory() as tmp:
        out = Path(tmp) / "report.json"
        command = [
            sys.executable,
            "-m",
            "omtp_drake.ros.cli",
            "ros-run",
            script,
            "--scenario",
            scenario,
            "--timeout",
            str(timeout),
            "--json",
            str(out),
        ]
        if seed is not None:
            command += ["--seed", str(seed)]
        try:
            done = subprocess.run(
                command, capture_output=True, text=True, timeout=wall_timeout, cwd=str(Path(script).parent)
            )
        except subprocess.TimeoutExpired:
            return Grade(Path(script).name, TIMEOUT, 0, None, f"over {wall_timeout:g} s wall time (killed)")
        if not out.is_file():
            tail = " | ".join((done.stderr or done.stdout).strip().splitlines()[-3:])
            return Grade(Path(script).name, CRASHED, 0, None, f"exit code {done.returncode}: {tail}")
        report = json.loads(out.read_text())
    in_bins = sum(report["ledger"]["in_bin"].values())
    if report["exception"] or report["callback_errors"]:
        status = EXCEPTION
        message = report["exception"] or f"bad callback: {report['callback_errors'][0]}"
    elif report["collisions"]:
        status, message = COLLISION, report["collisions"][0]
    else:
        status, message = OK, report.get("shutdown") or ""
    return Grade(Path(script).name, status, in_bins, report, message)


def find_scripts(folder: str | Path) -> list[Path]:
    path = Path(folder)
    if not path.is_dir():
        raise ConfigError(f"grade needs a folder of scripts, got {str(folder)!r}")
    scripts = sorted(p for p in path.glob("*.py") if not p.name.startswith("_"))
    if not scripts:
        raise ConfigError(f"{str(folder)!r} has no .py scripts")
    return scripts


def grade_folder(
    folder: str | Path,
    scenario: str,
    *,
    workers: Optional[int] = None,
    seed: Optional[int] = None,
    timeout: float = 600.0,
    wall_timeout: float = 900.0,
    out: Optional[str | Path] = None,
) -> list[Grade]:
    """Every script of ``folder`` on ``scenario``, on ``workers`` local Dask workers;
    the grades in script order (also written to ``out``, see the module doc)."""
    from omtp_drake.ros._core import batch_connect, load_scenario

    scripts = find_scripts(folder)
    load_scenario(scenario)  # a bad name fails before any worker starts
    if workers is not None and (isinstance(workers, bool) or not isinstance(workers, int) or workers < 1):
        raise ConfigError(f"--workers must be an integer >= 1, got {workers!r}")
    with batch_connect(workers) as client:
        futures = [
            client.submit(grade_one, str(s.resolve()), str(scenario), seed, timeout, wall_timeout, pure=False)
            for s in scripts
        ]
        grades = client.gather(futures)
    if out is not None:
        write_grades(grades, Path(out))
    return grades


def write_grades(grades: list[Grade], out: Path) -> None:
    runs = out / "runs"
    runs.mkdir(parents=True, exist_ok=True)
    for g in grades:
        data = {"status": g.status, "message": g.message, "report": g.report}
        (runs / f"{Path(g.script).stem}.json").write_text(json.dumps(data, indent=2))
    rows = [g.row() for g in grades]
    with open(out / "grades.csv", "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=list(rows[0]))
        writer.writeheader()
        writer.writerows(rows)
    plot_grades(grades).savefig(out / "grades.png", dpi=100)


def format_grades(grades: list[Grade]) -> str:
    width = max(10, *(len(g.script) for g in grades))
    lines = [f"{'script':<{width}} {'status':<9} {'in bins':>7} {'sim s':>7} {'wall s':>7}  message"]
    for g in grades:
        r = g.row()
        sim = f"{r['sim_time_s']:.1f}" if r["sim_time_s"] != "" else "-"
        wall = f"{r['wall_time_s']:.1f}" if r["wall_time_s"] != "" else "-"
        lines.append(
            f"{g.script:<{width}} {g.status:<9} {g.in_bins:>7} {sim:>7} {wall:>7}  {g.message[:100]}"
        )
    ok = sum(g.status == OK for g in grades)
    lines.append(
        f"{len(grades)} scripts: {ok} ran cleanly; {sum(g.in_bins for g in grades)} parts in bins in all"
    )
    return "\n".join(lines)


def plot_grades(grades: list[Grade]) -> Figure:
    """Parts in bins (bars coloured by status) and simulated time per script."""
    from matplotlib.figure import Figure

    colours = {
        OK: "tab:green",
        EXCEPTION: "tab:red",
        COLLISION: "tab:orange",
        TIMEOUT: "tab:gray",
        CRASHED: "k",
    }
    fig = Figure(figsize=(max(6.0, 0.5 * len(grades) + 2), 6), layout="constrained")
    top, bottom = fig.subplots(2, 1, sharex=True)
    x = range(len(grades))
    top.bar(x, [g.in_bins for g in grades], color=[colours[g.status] for g in grades])
    for xi, g in zip(x, grades):  # the status on every bar (a failed script may have none)
        top.annotate(g.status, (xi, g.in_bins), ha="center", va="bottom", fontsize=8, color=colours[g.status])
    top.set_ylim(0, max(g.in_bins for g in grades) + 1)
    top.yaxis.get_major_locator().set_params(integer=True)
    top.set_ylabel("parts in bins")
    top.set_title("Parts in bins per script")
    bottom.bar(x, [(g.report or {}).get("sim_time_s", 0.0) for g in grades], color="tab:blue")
    bottom.set_ylabel("simulated time [s]")
    bottom.set_xticks(list(x), [g.script for g in grades], rotation=60, ha="right", fontsize=8)
    return fig
