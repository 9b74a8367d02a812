"""A batch's results folder: what batch it holds, a JSON per run (resume), the table, summary and plots.

Outputs in ``out``: ``batch.json`` (the batch's scenario and options),
``runs/<run id>.json`` per run (resuming with the same ``out`` skips runs whose
JSON exists), ``runs.csv``, ``summary.json``, ``success_rate.png`` and
``cycle_times.png``.
"""

from __future__ import annotations

import json
import logging
import os
from collections.abc import Sequence
from pathlib import Path
from typing import Any

from omtp_drake.batch.plots import plot_cycle_time_histograms, plot_success_rates
from omtp_drake.batch.run_records import RunRecord, write_table
from omtp_drake.batch.summary import summarize
from omtp_drake.batch.sweep import BatchPlan
from omtp_drake.errors import ConfigError

_log = logging.getLogger(__name__)


class ResultStore:
    """The results folder: ``batch.json`` (what batch it holds), ``runs/*.json``,
    ``runs.csv``, ``summary.json`` and the plots."""

    def __init__(self, out: Path, plan: BatchPlan):
        self.out = out
        self.plan = plan
        self.runs_dir = out / "runs"
        self.manifest = out / "batch.json"

    def _manifest_data(self) -> dict[str, Any]:
        return {
            "scenario": self.plan.scenario,
            "parts": self.plan.parts,
            "duration": self.plan.duration,
            "fingerprint": self.plan.fingerprint,
        }

    def check(self) -> None:
        """ConfigError if ``out`` holds something other than this batch's results."""
        if self.out.exists() and not self.out.is_dir():
            raise ConfigError(f"--out {str(self.out)!r} is a file; give a folder")
        if not self.manifest.is_file():
            return
        try:
            held = json.loads(self.manifest.read_text())
        except (OSError, ValueError) as e:
            raise ConfigError(f"--out {str(self.out)!r}: unreadable {self.manifest.name} ({e})") from None
        if held.get("fingerprint") != self.plan.fingerprint:
            raise ConfigError(
                f"--out {str(self.out)!r} holds a batch of another scenario or options "
                f"({held.get('scenario')}, parts {held.get('parts')}, duration {held.get('duration')}); "
                "give another --out to start a new batch"
            )

    def load_done(self) -> dict[str, RunRecord]:
        """Records of the plan's runs whose JSON exists (unreadable ones are run again)."""
        done = {}
        for spec in self.plan.runs:
            path = self.runs_dir / f"{spec.run_id}.json"
            if not path.is_file():
                continue
            try:
                record = RunRecord.from_dict(json.loads(path.read_text()))
            except (OSError, ValueError, KeyError, TypeError) as e:
                _log.warning("%s is unreadable (%s); running it again", path, e)
                continue
            if record.seed == spec.seed and record.settings == spec.settings:
                record.resumed = True
                done[spec.run_id] = record
        return done

    def start(self) -> None:
        self.runs_dir.mkdir(parents=True, exist_ok=True)
        _write_json(self.manifest, self._manifest_data())

    def write(self, record: RunRecord) -> None:
        _write_json(self.runs_dir / f"{record.run_id}.json", record.to_dict())

    def finish(self, records: Sequence[RunRecord]) -> None:
        write_table(records, self.out / "runs.csv")
        summaries = summarize(records)
        _write_json(self.out / "summary.json", [s.to_dict() for s in summaries])
        plot_success_rates(summaries).savefig(self.out / "success_rate.png", dpi=100)
        plot_cycle_time_histograms(records).savefig(self.out / "cycle_times.png", dpi=100)


def _write_json(path: Path, data: Any) -> None:
    """Written whole or not at all (a killed batch leaves no half file)."""
    tmp = path.with_name(f".{path.name}.{os.getpid()}.tmp")
    tmp.write_text(json.dumps(data, indent=2))
    os.replace(tmp, path)
