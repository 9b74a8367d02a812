"""The conformance suite: course-style scripts, written in the course's students' habits,
run through ``ros-run`` on the course's scenarios; each test asserts the run's ledger,
report or what the script wrote.

A script lives in ``scripts/`` (as a student would write it: no test hooks) or inline
in its test; :func:`run_course_script` runs it with ``run_script`` and returns the
report and the JSON the script wrote to the path in its first argument, if any.
"""

import json
import textwrap
from pathlib import Path

import pytest

from omtp_drake.ros import run_script

SCRIPTS = Path(__file__).parent / "scripts"


def run_course_script(tmp_path, script, *, scenario, args=(), out_arg=False, **options):
    """Runs ``script`` (a file name in ``scripts/`` or source text) under ros-run.

    ``out_arg``: pass a JSON path as the script's first argument and read it back.
    Returns ``(report, data)``; ``data`` is None when the script wrote nothing.
    """
    if "\n" not in script and (SCRIPTS / script).is_file():
        path = SCRIPTS / script
    else:
        path = tmp_path / "script.py"
        path.write_text(textwrap.dedent(script))
    out = tmp_path / "out.json"
    argv = [str(out), *args] if out_arg else list(args)
    report = run_script(path, argv, scenario=scenario, **options)
    data = json.loads(out.read_text()) if out_arg and out.is_file() else None
    return report, data


@pytest.fixture
def course_run(tmp_path):
    """``course_run(script, scenario=..., **options)`` -> (report, data)."""

    def run(script, **kwargs):
        return run_course_script(tmp_path, script, **kwargs)

    return run
