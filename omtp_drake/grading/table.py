"""A grade's results: one :class:`Grade` per script, the table ``grade`` prints,
``OUT/grades.csv``, ``OUT/grades.png`` and ``OUT/runs/<script>.json``."""

from __future__ import annotations

import csv
import json
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any, Optional

from omtp_drake.grading.isolation import Limits
from omtp_drake.grading.verdicts import (
    COLLISION,
    CPU_LIMIT,
    EXCEPTION,
    EXITED_EARLY,
    KILLED,
    MEMORY_LIMIT,
    OK,
    OUTPUT_CUT,
    PROCESS_LIMIT,
    SIM_TIMEOUT,
    VERDICTS,
    WALL_TIMEOUT,
    WORKER_DIED,
)

if TYPE_CHECKING:
    from matplotlib.figure import Figure

#: Each verdict's colour in the plot.
_COLOURS = {
    OK: "tab:green",
    OUTPUT_CUT: "tab:olive",
    SIM_TIMEOUT: "tab:cyan",
    EXCEPTION: "tab:red",
    COLLISION: "tab:orange",
    EXITED_EARLY: "tab:pink",
    WALL_TIMEOUT: "tab:gray",
    CPU_LIMIT: "tab:brown",
    MEMORY_LIMIT: "tab:purple",
    PROCESS_LIMIT: "tab:blue",
    KILLED: "k",
    WORKER_DIED: "k",
}


@dataclass
class Grade:
    """One script's row."""

    script: str
    status: str
    in_bins: int
    report: Optional[dict[str, Any]]
    message: str = ""
    #: What the sandbox refused the script (writes, network, signals).
    refused: str = ""
    #: How the isolated run ended: sandbox, limits, wall time, exit, output kept and cut.
    isolation: dict[str, Any] = field(default_factory=dict)

    def row(self) -> dict[str, Any]:
        r = self.report or {}
        ledger = r.get("ledger", {})
        out = self.isolation.get("stdout", {}), self.isolation.get("stderr", {})
        return {
            "script": self.script,
            "status": self.status,
            "in_bins": self.in_bins,
            "spawned": ledger.get("spawned", ""),
            "on_floor": ledger.get("on_floor", ""),
            "held": sum(ledger.get("held", {}).values()) if ledger else "",
            "collisions": len(r.get("collisions", [])),
            "sim_time_s": r.get("sim_time_s", ""),
            "wall_time_s": r.get("wall_time_s", self.isolation.get("wall_s", "")),
            "output_cut_bytes": sum(s.get("cut", 0) for s in out),
            "refused": self.refused,
            "message": self.message,
        }


def write_grades(grades: list[Grade], out: Path) -> None:
    runs = out / "runs"
    runs.mkdir(parents=True, exist_ok=True)
    for g in grades:
        data = run_record(g)
        (runs / f"{Path(g.script).stem}.json").write_text(json.dumps(data, indent=2))
    rows = [g.row() for g in grades]
    with open(out / "grades.csv", "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=list(rows[0]))
        writer.writeheader()
        writer.writerows(rows)
    plot_grades(grades).savefig(out / "grades.png", dpi=100)


def run_record(g: Grade) -> dict[str, Any]:
    return {
        "status": g.status,
        "message": g.message,
        "refused": g.refused,
        "isolation": g.isolation,
        "report": g.report,
    }


def format_grades(grades: list[Grade]) -> str:
    width = max(10, *(len(g.script) for g in grades))
    lines = [f"{'script':<{width}} {'status':<17} {'in bins':>7} {'sim s':>7} {'wall s':>7}  message"]
    for g in grades:
        r = g.row()
        sim = f"{r['sim_time_s']:.1f}" if r["sim_time_s"] != "" else "-"
        wall = f"{r['wall_time_s']:.1f}" if r["wall_time_s"] != "" else "-"
        lines.append(
            f"{g.script:<{width}} {g.status:<17} {g.in_bins:>7} {sim:>7} {wall:>7}  {g.message[:100]}"
        )
        if g.refused:
            lines.append(f"{'':<{width}} refused by the sandbox: {g.refused[:100]}")
    ok = sum(g.status == OK for g in grades)
    lines.append(
        f"{len(grades)} scripts: {ok} ran cleanly; {sum(g.in_bins for g in grades)} parts in bins in all"
    )
    first = grades[0].isolation
    if first:
        limits = Limits(**first["limits"]).describe()
        lines.append(f"each run: sandbox {first['sandbox']}; limits: {limits}")
    return "\n".join(lines)


def plot_grades(grades: list[Grade]) -> Figure:
    """Parts in bins (bars coloured by status, a legend of the statuses) and simulated time
    per script. Each script's status is written once, under its bar with its name, upright
    (one line per bar, so neighbouring labels never overlap, whatever they say)."""
    from matplotlib.figure import Figure
    from matplotlib.patches import Patch

    fig = Figure(figsize=(max(6.0, 0.5 * len(grades) + 2), 7), layout="constrained")
    top, bottom = fig.subplots(2, 1, sharex=True)
    x = range(len(grades))
    top.bar(x, [g.in_bins for g in grades], color=[_COLOURS[g.status] for g in grades])
    shown = [s for s in VERDICTS if any(g.status == s for g in grades)]
    top.legend(handles=[Patch(color=_COLOURS[s], label=s) for s in shown], fontsize=8, loc="upper left")
    top.set_ylim(0, max(g.in_bins for g in grades) + 1)
    top.yaxis.get_major_locator().set_params(integer=True)
    top.set_ylabel("parts in bins")
    top.set_title("Parts in bins per script")
    bottom.bar(x, [(g.report or {}).get("sim_time_s", 0.0) for g in grades], color="tab:blue")
    bottom.set_ylabel("simulated time [s]")
    bottom.set_xticks(list(x), [f"{g.script}: {g.status}" for g in grades], rotation=90, fontsize=8)
    for label, g in zip(bottom.get_xticklabels(), grades):
        label.set_color(_COLOURS[g.status])
    return fig
