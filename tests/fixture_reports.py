"""What a user sees of a course-layout fixture's script run (``ros-run SCRIPT --launch ...
--workspace FIXTURE --json REPORT``), compared with a recorded reference, so that a later
change of the loader that alters it fails (issue 43: "everything that loads today loads the
same: ... ledgers and reports as before").

The reference, ``tests/golden/fixture_reports.json``, holds per case (one per test that
runs a fixture's script) what :func:`seen` keeps of the run's report: the script's outcome
(exception, exit code, timed out), where each part ended (the ledger's parts, bins, what
each gripper holds, spawned, disposed) and when the script ended (simulated time; compared
within :data:`SIM_TIME_TOLERANCE_S`, since the ledger is what the run is judged by and the
arms' timing may be tuned). ``tests/golden/record_fixture_reports.py`` records it: the
tests below run with ``OMTP_RECORD_FIXTURE_REPORTS`` naming the file, each writes its case
instead of comparing.
"""

from __future__ import annotations

import json
import os
from pathlib import Path
from typing import Any

GOLDEN = Path(__file__).resolve().parent / "golden" / "fixture_reports.json"
#: How far (simulated s) a script's end may move before it counts as a changed run.
SIM_TIME_TOLERANCE_S = 1.0
_RECORD_ENV = "OMTP_RECORD_FIXTURE_REPORTS"


def seen(report: dict[str, Any]) -> dict[str, Any]:
    """What the reference keeps of a ``ros-run --json`` report."""
    ledger = report["ledger"]
    return {
        "exception": report["exception"],
        "exit_code": report["exit_code"],
        "timed_out": report["timed_out"],
        "parts": ledger["parts"],
        "in_bin": ledger["in_bin"],
        "held": ledger["held"],
        "spawned": ledger["spawned"],
        "disposed": ledger["disposed"],
        "sim_time_s": round(float(report["sim_time_s"]), 2),
    }


def assert_as_recorded(case: str, report: dict[str, Any]) -> None:
    """``report`` (a run's ``--json``) shows what the reference recorded for ``case``
    (in recording mode: records it)."""
    now = seen(report)
    target = os.environ.get(_RECORD_ENV)
    if target:
        path = Path(target)
        recorded = json.loads(path.read_text()) if path.exists() else {}
        recorded[case] = now
        path.write_text(json.dumps(recorded, indent=1, sort_keys=True) + "\n")
        return
    before = json.loads(GOLDEN.read_text())[case]
    time_now, time_before = now.pop("sim_time_s"), before.pop("sim_time_s")
    assert now == before, f"{case}: the run's outcome changed: now {now}, recorded {before}"
    assert abs(time_now - time_before) <= SIM_TIME_TOLERANCE_S, (
        f"{case}: the script ended at {time_now} s simulated, recorded {time_before} s"
    )
