"""A run's outcome: its status and result (:class:`RunRecord`), and the table of runs (``runs.csv``)."""

from __future__ import annotations

import csv
import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any, Optional, Union

from omtp_drake.batch.sweep import RunSpec, format_value

if TYPE_CHECKING:
    from omtp_drake.tasks.run import TaskResult

#: Statuses of a run: it ran to its end (successful or not), it raised, it
#: exceeded its wall-time limit, or its process died.
FINISHED, ERROR, TIMEOUT, CRASHED = "finished", "error", "timeout", "crashed"


@dataclass
class RunRecord:
    """The outcome of one run of a batch (``to_dict`` is its JSON file)."""

    scenario: str
    seed: int
    settings: dict[str, Any]
    #: ``finished`` (ran to its end, successful or not), ``error``, ``timeout`` or ``crashed``.
    status: str
    #: What went wrong (empty when finished).
    message: str = ""
    #: The task's result (None unless finished).
    result: Optional[TaskResult] = None
    #: Attempts made (a failed attempt is retried once, on another worker).
    attempts: int = 1
    #: Address of the worker of the last attempt.
    worker: str = ""
    #: Wall seconds of the last attempt in its process (building included).
    run_wall_time_s: float = math.nan
    #: Earlier attempts that failed: status, message, worker.
    failed_attempts: list[dict[str, Any]] = field(default_factory=list)
    #: Times a worker died while it ran this run and Dask ran it again elsewhere.
    lost_workers: int = 0
    #: Loaded from the results folder of an earlier call (a resume), not run by this one.
    resumed: bool = field(default=False, compare=False)

    @property
    def retries(self) -> int:
        """Times the run was started again: after a failed attempt, or a lost worker."""
        return self.attempts - 1 + self.lost_workers

    @property
    def success(self) -> bool:
        """Finished and judged successful."""
        return self.status == FINISHED and self.result is not None and self.result.success

    @property
    def run_id(self) -> str:
        return RunSpec(self.seed, self.settings, "").run_id

    @property
    def ledger_anomaly(self) -> bool:
        """Finished with parts unaccounted for (``TaskResult.accounted_for``): the ledger
        does not balance, or a part is left loose that the controller did not give up
        on with a record of where it lies."""
        return self.result is not None and not self.result.accounted_for

    @property
    def failure_reason(self) -> str:
        """Why the run did not succeed (empty when it did): its status if it did
        not finish, else its last failed pick's reason, else ``incomplete``."""
        if self.success:
            return ""
        if self.status != FINISHED or self.result is None:
            return self.status
        failed = [p.reason.value for p in self.result.picks if p.reason]
        return failed[-1] if failed else "incomplete"

    def to_dict(self) -> dict[str, Any]:
        out: dict[str, Any] = {"scenario": self.scenario, "seed": self.seed}
        if self.result is not None:
            out.update(self.result.to_dict())
            out["bin"] = self.result.bin
        out.update(
            {
                "settings": dict(self.settings),
                "status": self.status,
                "message": self.message,
                "attempts": self.attempts,
                "worker": self.worker,
                "run_wall_time_s": self.run_wall_time_s,
                "failed_attempts": list(self.failed_attempts),
                "lost_workers": self.lost_workers,
                "retries": self.retries,
            }
        )
        return out

    @classmethod
    def from_dict(cls, data: Mapping[str, Any]) -> RunRecord:
        """The record of ``to_dict`` (a run's JSON file)."""
        from omtp_drake.tasks.run import TaskResult

        result = TaskResult.from_dict(data, data["bin"]) if "summary" in data else None
        return cls(
            scenario=data["scenario"],
            seed=data["seed"],
            settings=dict(data["settings"]),
            status=data["status"],
            message=data.get("message", ""),
            result=result,
            attempts=data.get("attempts", 1),
            worker=data.get("worker", ""),
            run_wall_time_s=data.get("run_wall_time_s", math.nan),
            failed_attempts=list(data.get("failed_attempts", [])),
            lost_workers=data.get("lost_workers", 0),
        )


def write_table(records: Sequence[RunRecord], path: Union[str, Path]) -> Path:
    """One CSV row per run: seed, settings, status, success and the summary numbers."""
    keys: list[str] = []
    for r in records:
        keys += [k for k in r.settings if k not in keys]
    columns = ["scenario", "seed", *keys, "status", "success", "attempts", "in_bin", "parts"]
    columns += ["picks", "failed_picks", "failure_reason", "mean_cycle_time_s", "max_cycle_time_s"]
    columns += ["sim_time_s", "wall_time_s", "real_time_factor", "ledger_balanced", "loose_parts"]
    columns += ["run_wall_time_s", "worker", "message"]
    path = Path(path)
    with open(path, "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=columns)
        writer.writeheader()
        for r in records:
            row: dict[str, Any] = {"scenario": r.scenario, "seed": r.seed, "status": r.status}
            row.update({k: format_value(r.settings[k]) if k in r.settings else "" for k in keys})
            row.update(success=r.success, attempts=r.attempts, failure_reason=r.failure_reason)
            row.update(run_wall_time_s=r.run_wall_time_s, worker=r.worker, message=r.message)
            if r.result is not None:
                s = r.result.summary
                row.update(
                    in_bin=s["in_bin"], parts=s["parts"], picks=s["attempted"], failed_picks=s["failed"]
                )
                row.update({k: s[k] for k in ("mean_cycle_time_s", "max_cycle_time_s", "sim_time_s")})
                row.update(wall_time_s=s["wall_time_s"], real_time_factor=s["real_time_factor"])
                row.update(ledger_balanced=r.result.ledger.balanced, loose_parts=r.result.ledger.loose)
            writer.writerow(row)
    return path
