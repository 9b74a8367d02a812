"""The pick-and-place controller's ``DidNothing`` (issue 46, item 2), measured in one process.

    python bench/paired_did_nothing.py [scenario] [--chunk 1.0] [--until 60]

An update of the controller that decides nothing says ``DidNothing``, and Drake then leaves
its state as it was: nothing that depends on it (the pose table, the suction command, the
control and history ports the run reads at its ticks) is computed again. This builds the
scenario's task run twice: ``didnothing`` as it is, and ``applied`` whose updates always say
``Succeeded`` (the same values written back, every dependent invalidated: as before). The
two give the same run bit for bit (checked here: the plant's positions after every chunk).
It advances each by ``--chunk`` simulated seconds in turn (which first alternating), timing
each chunk's thread CPU, and prints the medians, the totals per simulated second and the
paired ratio (as ``paired_chunks.py``).
"""

from __future__ import annotations

import os
import statistics

from paired_chunks import advance_in_pairs, pair_arguments
from pydrake.systems.framework import EventStatus

from omtp_drake.tasks.run import TaskRun, prepare


def _always_applied(run: TaskRun) -> None:
    """The controller of ``run`` reports every update as ``Succeeded``."""
    controller = run.controller
    record = controller._record

    def applied(*args):
        record(*args)
        return EventStatus.Succeeded()

    controller._record = applied  # the instance's attribute: the update looks it up on self


def main() -> None:
    args = pair_arguments(__doc__)
    runs = {"applied": TaskRun(prepare(args.scenario)), "didnothing": TaskRun(prepare(args.scenario))}
    _always_applied(runs["applied"])
    cpu, t = advance_in_pairs(runs, args.chunk, args.until)
    ratios = [new / old for new, old in zip(cpu["didnothing"], cpu["applied"])]
    for name, chunks in cpu.items():
        print(
            f"{name}: median {1e3 * statistics.median(chunks) / args.chunk:.1f}, "
            f"total {1e3 * sum(chunks) / t:.1f} CPU ms per simulated s"
        )
    print(f"paired didnothing/applied: median {statistics.median(ratios):.3f} ({len(ratios)} pairs)")
    print(f"load average {os.getloadavg()[0]:.2f}")


if __name__ == "__main__":
    main()
