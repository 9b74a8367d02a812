"""Records what users see of the built-in pick-and-place scenarios (seed 0) into
``tests/golden/outcomes_before.json``, the reference of ``tests/test_equivalence.py``
(issue 46: the arms' motion changed how it is integrated; outcomes, ledgers, cycle times
and the tool path at the machine's decisions must not).

A script, not a test: run it from the repository root on the code whose outcomes are
the reference, e.g. ``.venv/bin/python tests/golden/record_outcomes.py``.
"""

import json
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent))

from outcome_record import EXTRA_SCENARIOS, SCENARIOS, record  # noqa: E402


def main() -> None:
    out = HERE / "outcomes_before.json"
    names = sys.argv[1:] or [*SCENARIOS, *EXTRA_SCENARIOS]
    recorded = json.loads(out.read_text()) if out.exists() else {}
    for name in names:
        recorded[name] = record(name)
        r = recorded[name]
        print(name, r["success"], r["in_bin"], r["mean_cycle_time_s"], len(r["decisions"]), flush=True)
        out.write_text(json.dumps(recorded, indent=1, sort_keys=True) + "\n")


if __name__ == "__main__":
    main()
