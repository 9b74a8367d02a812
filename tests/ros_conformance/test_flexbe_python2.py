"""flexbe-run converts a ROS Melodic (Python 2) workspace by itself, as ros-run does a script:
a workspace with a module that compiles only as Python 2 loads as its 2to3 translation, and
the report says so; ``--python2`` still forces it."""

import textwrap
from pathlib import Path

import pytest

from omtp_drake.ros.flexbe import run_behavior
from omtp_drake.ros.run.py2 import python2_roots

ROOT = Path(__file__).resolve().parents[2]
MELODIC = Path(__file__).parent / "scripts" / "flexbe_melodic"
SCENARIO = "lecture7_flexbe"


def test_a_melodic_workspace_runs_without_python2(caplog):
    """Its states have print statements, ``except X, e:``, a line indented by a tab and
    spaces, and ``map(...)[0]`` in a module that compiles as Python 3 too (so every module of
    the workspace loads translated, not only the one that does not compile)."""
    report = run_behavior("Feed One Part", [MELODIC], scenario=SCENARIO, timeout=30.0)
    assert report.outcome == "finished" and report.ok, report.summary()
    assert report.python2 == [str(MELODIC)]
    assert f"python 2: {MELODIC} loaded as its 2to3 translation (Melodic)" in report.summary()
    assert "start_line_state.py is Python 2 (ROS Melodic)" in caplog.text
    # The spawner's first part (3 s after /start_spawn) reaches the beam, which stops the belt.
    assert [t["state"] for t in report.trace] == ["/start line", "/wait for beam"]
    seen = [x for x in report.logs if x["text"].startswith("beam broken at")]
    assert len(seen) == 1 and 3.0 < seen[0]["time"] == pytest.approx(report.sim_time_s)
    forced = run_behavior("Feed One Part", [MELODIC], scenario=SCENARIO, timeout=30.0, python2=True)
    assert forced.to_dict() | {"wall_time_s": 0} == report.to_dict() | {"wall_time_s": 0}


def test_python3_workspaces_are_not_converted():
    assert python2_roots([ROOT / "examples" / "flexbe"]) == []
    assert python2_roots([ROOT / "examples" / "flexbe", MELODIC]) == [MELODIC]


def test_a_module_that_is_neither_python_3_nor_2_names_its_line(tmp_path):
    package = tmp_path / "broken_behaviors"
    (package / "manifest").mkdir(parents=True)
    (package / "src" / "broken_behaviors").mkdir(parents=True)
    (package / "package.xml").write_text(
        "<package format='2'><name>broken_behaviors</name><version>0.0.1</version>"
        "<description>x</description><maintainer email='s@example.org'>s</maintainer>"
        "<license>BSD</license></package>"
    )
    (package / "manifest" / "broken.xml").write_text(
        '<behavior name="Broken"><executable package_path="broken_behaviors.broken_sm" class="BrokenSM" />'
        "</behavior>"
    )
    (package / "src" / "broken_behaviors" / "__init__.py").write_text("")
    (package / "src" / "broken_behaviors" / "broken_sm.py").write_text(
        textwrap.dedent(
            """\
            from flexbe_core import Behavior
            x = = 1
            """
        )
    )
    report = run_behavior("Broken", [tmp_path], scenario=SCENARIO, timeout=1.0)
    assert report.python2 == [] and report.outcome is None
    assert report.exception.startswith("SyntaxError: invalid syntax")
    assert "it compiles neither as Python 3 nor, through 2to3, as Python 2 (ROS Melodic)" in report.exception
    assert "(at broken_sm.py:2" in report.exception
