"""What a batch adds up to per setting: success rate with its Wilson interval, cycle times, failures."""

from __future__ import annotations

import collections
import json
import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from omtp_drake.batch.run_records import FINISHED, RunRecord
from omtp_drake.batch.sweep import settings_label

#: z of the two-sided 95 % interval.
_Z95 = 1.959963984540054


def wilson_interval(successes: int, n: int, z: float = _Z95) -> tuple[float, float]:
    """The Wilson score interval of a success rate (95 % by default); (0, 1) for n = 0."""
    if n == 0:
        return 0.0, 1.0
    p = successes / n
    denom = 1 + z * z / n
    centre = (p + z * z / (2 * n)) / denom
    half = z * math.sqrt(p * (1 - p) / n + z * z / (4 * n * n)) / denom
    lo = 0.0 if successes == 0 else max(0.0, min(p, centre - half))
    hi = 1.0 if successes == n else min(1.0, max(p, centre + half))
    return lo, hi


@dataclass
class SettingSummary:
    """What the runs of one setting add up to."""

    settings: dict[str, Any]
    runs: int
    successes: int
    #: Runs by status (finished, error, timeout, crashed).
    statuses: dict[str, int]
    #: 95 % Wilson interval of the success rate.
    interval: tuple[float, float]
    #: Cycle times (simulated s) of the successful picks.
    cycle_times: list[float]
    #: Failed runs by reason (status, or the last failed pick's reason, or ``incomplete``).
    failure_reasons: dict[str, int]
    #: Failed picks (recovered or not) by reason.
    failed_picks: dict[str, int]
    #: Seeds of finished runs with parts unaccounted for (ledger unbalanced or parts loose).
    ledger_anomalies: list[int]
    #: Mean real-time factor of the finished runs.
    real_time_factor: float
    #: Runs started again (after a failed attempt or a lost worker), and workers lost.
    retries: int = 0
    lost_workers: int = 0
    #: Runs taken from an earlier call's results folder (a resume) instead of run.
    resumed: int = 0

    @property
    def label(self) -> str:
        return settings_label(self.settings)

    @property
    def success_rate(self) -> float:
        return self.successes / self.runs if self.runs else math.nan

    @property
    def cycle_mean(self) -> float:
        return float(np.mean(self.cycle_times)) if self.cycle_times else math.nan

    @property
    def cycle_p95(self) -> float:
        return float(np.percentile(self.cycle_times, 95)) if self.cycle_times else math.nan

    @property
    def cycle_worst(self) -> float:
        return max(self.cycle_times) if self.cycle_times else math.nan

    def to_dict(self) -> dict[str, Any]:
        return {
            "settings": dict(self.settings),
            "runs": self.runs,
            "successes": self.successes,
            "success_rate": self.success_rate,
            "success_rate_95ci": list(self.interval),
            "statuses": dict(self.statuses),
            "cycle_time_mean_s": self.cycle_mean,
            "cycle_time_p95_s": self.cycle_p95,
            "cycle_time_worst_s": self.cycle_worst,
            "failure_reasons": dict(self.failure_reasons),
            "failed_picks": dict(self.failed_picks),
            "ledger_anomalies": list(self.ledger_anomalies),
            "real_time_factor": self.real_time_factor,
            "retries": self.retries,
            "lost_workers": self.lost_workers,
            "resumed": self.resumed,
        }


def summarize(records: Sequence[RunRecord]) -> list[SettingSummary]:
    """One summary per setting, in the order the settings first appear."""
    groups: dict[str, list[RunRecord]] = {}
    for r in records:
        groups.setdefault(json.dumps(r.settings, sort_keys=False), []).append(r)
    out = []
    for group in groups.values():
        successes = sum(r.success for r in group)
        finished = [r.result for r in group if r.status == FINISHED and r.result is not None]
        rtfs = [x for x in (res.summary["real_time_factor"] for res in finished) if math.isfinite(x)]
        out.append(
            SettingSummary(
                settings=dict(group[0].settings),
                runs=len(group),
                successes=successes,
                statuses=dict(collections.Counter(r.status for r in group)),
                interval=wilson_interval(successes, len(group)),
                cycle_times=[p.cycle_time for res in finished for p in res.picks if p.success and p.part],
                failure_reasons=dict(collections.Counter(r.failure_reason for r in group if not r.success)),
                failed_picks=dict(
                    collections.Counter(p.reason.value for res in finished for p in res.picks if p.reason)
                ),
                ledger_anomalies=[r.seed for r in group if r.ledger_anomaly],
                real_time_factor=float(np.mean(rtfs)) if rtfs else math.nan,
                retries=sum(r.retries for r in group),
                lost_workers=sum(r.lost_workers for r in group),
                resumed=sum(r.resumed for r in group),
            )
        )
    return out


def format_summary(summaries: Sequence[SettingSummary]) -> str:
    """The summary as text, a block per setting."""
    lines = []
    for s in summaries:
        lo, hi = s.interval
        lines.append(f"{s.label}:")
        lines.append(
            f"  runs {s.runs}: success {s.successes}/{s.runs} = {100 * s.success_rate:.1f} % "
            f"(95 % CI {100 * lo:.1f}-{100 * hi:.1f} %)"
            + (
                "; " + ", ".join(f"{k} {v}" for k, v in s.statuses.items() if k != FINISHED)
                if set(s.statuses) - {FINISHED}
                else ""
            )
        )
        lines.append(
            f"  cycle time (s, {len(s.cycle_times)} picks): mean {s.cycle_mean:.2f}, "
            f"p95 {s.cycle_p95:.2f}, worst {s.cycle_worst:.2f}; real-time factor {s.real_time_factor:.1f}"
        )
        if s.failure_reasons:
            reasons = ", ".join(
                f"{k} {v}" for k, v in sorted(s.failure_reasons.items(), key=lambda kv: -kv[1])
            )
            lines.append(f"  failed runs by reason: {reasons}")
        if s.failed_picks:
            picks = ", ".join(f"{k} {v}" for k, v in sorted(s.failed_picks.items(), key=lambda kv: -kv[1]))
            lines.append(f"  failed picks by reason: {picks}")
        anomalies = ", ".join(map(str, s.ledger_anomalies)) if s.ledger_anomalies else "none"
        lines.append(
            f"  ledger anomalies (parts unaccounted for): {len(s.ledger_anomalies)} (seeds: {anomalies})"
        )
        lines.append(
            f"  retries {s.retries} (workers lost {s.lost_workers}); "
            f"resumed from the results folder: {s.resumed} of {s.runs} runs"
        )
    return "\n".join(lines)
