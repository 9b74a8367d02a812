"""Where the test suite's time goes: a pytest plugin that appends each test's CPU seconds (the
xdist worker's own, and its children's that it has waited for: grade's runs, notebook kernels,
chromium, ROS 2 cells) and wall seconds as JSON lines, and a summary by file.

    PYTHONPATH=bench .venv/bin/python -m pytest -q -n 2 -p suite_cpu     # writes suite_cpu.jsonl
    .venv/bin/python bench/suite_cpu.py suite_cpu.jsonl                  # the files, costliest first

CPU seconds, not wall: they hold on a busy machine (wall seconds there grow with the load).
Children still running when a test ends (a module's Dask cluster) count for the test that
reaps them, or not at all.
"""

from __future__ import annotations

import collections
import json
import os
import resource
import sys
import time

import pytest

OUT = os.environ.get("SUITE_CPU_OUT", "suite_cpu.jsonl")


def _cpu() -> tuple[float, float]:
    me, children = (resource.getrusage(who) for who in (resource.RUSAGE_SELF, resource.RUSAGE_CHILDREN))
    return me.ru_utime + me.ru_stime, children.ru_utime + children.ru_stime


@pytest.hookimpl(hookwrapper=True)
def pytest_runtest_protocol(item, nextitem):
    (me0, ch0), wall0 = _cpu(), time.monotonic()
    yield
    (me1, ch1), wall = _cpu(), time.monotonic() - wall0
    row = {"id": item.nodeid, "self": me1 - me0, "children": ch1 - ch0, "wall": wall}
    with open(OUT, "a") as f:
        f.write(json.dumps(row) + "\n")


def summary(path: str, top: int = 40) -> str:
    by_file: dict[str, list[float]] = collections.defaultdict(lambda: [0.0, 0.0, 0.0, 0])
    for line in open(path):
        row = json.loads(line)
        totals = by_file[row["id"].split("::")[0]]
        totals[0] += row["self"]
        totals[1] += row["children"]
        totals[2] += row["wall"]
        totals[3] += 1
    cpu = sum(t[0] + t[1] for t in by_file.values())
    lines = [f"{sum(int(t[3]) for t in by_file.values())} tests, {cpu:.0f} CPU s"]
    lines.append(f"{'CPU s':>7} {'self':>6} {'children':>8} {'wall s':>7} {'tests':>5}  file")
    for name, (me, children, wall, n) in sorted(by_file.items(), key=lambda kv: -(kv[1][0] + kv[1][1]))[:top]:
        lines.append(f"{me + children:7.1f} {me:6.1f} {children:8.1f} {wall:7.1f} {int(n):5d}  {name}")
    return "\n".join(lines)


if __name__ == "__main__":
    print(summary(sys.argv[1] if len(sys.argv) > 1 else OUT))
