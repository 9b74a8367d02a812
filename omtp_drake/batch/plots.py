"""A batch's figures: success rate per setting and cycle-time histograms (matplotlib, imported when drawn)."""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import TYPE_CHECKING

import numpy as np

from omtp_drake.batch.summary import SettingSummary, summarize
from omtp_drake.errors import ConfigError

if TYPE_CHECKING:
    from matplotlib.figure import Figure

    from omtp_drake.batch.run_records import RunRecord


def plot_success_rates(summaries: Sequence[SettingSummary]) -> Figure:
    """Success rate per setting with its 95 % Wilson interval."""
    from matplotlib.figure import Figure

    if not summaries:
        raise ConfigError("plot_success_rates needs at least one setting's summary")
    fig = Figure(figsize=(max(5.0, 1.2 * len(summaries) + 2), 4.5), layout="constrained")
    ax = fig.subplots()
    x = np.arange(len(summaries))
    rates = np.array([s.success_rate for s in summaries])
    lo = np.array([s.interval[0] for s in summaries])
    hi = np.array([s.interval[1] for s in summaries])
    ax.bar(x, 100 * rates, width=0.6, color="tab:green", alpha=0.7)
    ax.errorbar(
        x,
        100 * rates,
        yerr=100 * np.clip(np.vstack([rates - lo, hi - rates]), 0, None),
        fmt="none",
        ecolor="k",
        capsize=6,
    )
    for xi, s in zip(x, summaries):
        ax.annotate(f"{s.successes}/{s.runs}", (xi, 2), ha="center", fontsize=8)
    ax.set_xticks(x, [s.label.replace(" ", "\n") for s in summaries], fontsize=8)
    ax.set_ylim(0, 105)
    ax.set_ylabel("success rate [%] (95 % Wilson interval)")
    ax.set_title("Success rate per setting")
    return fig


def plot_cycle_time_histograms(records: Sequence[RunRecord]) -> Figure:
    """Histograms of the successful picks' cycle times, one panel per setting."""
    from matplotlib.figure import Figure

    summaries = summarize(records)
    if not summaries:
        raise ConfigError("plot_cycle_time_histograms needs at least one record")
    n = len(summaries)
    cols = min(n, 3)
    rows = math.ceil(n / cols)
    fig = Figure(figsize=(4.0 * cols, 3.0 * rows), layout="constrained")
    axes = np.atleast_1d(fig.subplots(rows, cols, sharex=True, squeeze=False)).ravel()
    every = [c for s in summaries for c in s.cycle_times]
    bins = np.histogram_bin_edges(every, bins=20) if every else np.linspace(0, 1, 21)
    for ax, s in zip(axes, summaries):
        if s.cycle_times:
            ax.hist(s.cycle_times, bins=bins, color="tab:blue", alpha=0.8)
        else:
            ax.text(0.5, 0.5, "no successful picks", ha="center", va="center", transform=ax.transAxes)
        ax.set_title(s.label, fontsize=8)
        ax.set_xlabel("cycle time [s]")
        ax.set_ylabel("picks")
    for ax in axes[n:]:
        ax.set_visible(False)
    return fig
