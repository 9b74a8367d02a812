"""``grade --flexbe``: a class of student workspaces, one FlexBE behaviour each, each run
with flexbe-run on its own copy, isolated; one row per student."""

import csv
import shutil

import pytest
from test_flexbe_run import BOOM, EXAMPLE, SCENARIO, _behavior_package

from omtp_drake.errors import ConfigError
from omtp_drake.grading.cli import main
from omtp_drake.grading.flexbe import FlexbeGrading
from omtp_drake.grading.grade import grade_folder


@pytest.fixture
def flexbe_class(tmp_path):
    """anna: the example's conveyor pick (states in her own workspace); ben: a behaviour
    whose state divides by zero."""
    folder = tmp_path / "class"
    shutil.copytree(EXAMPLE, folder / "anna", ignore=shutil.ignore_patterns("README.md"))
    _behavior_package(folder / "ben", "boom_behaviors", "Boom", "boom_sm", "BoomSM", BOOM)
    return folder


def test_each_students_behaviour_is_graded_on_its_own(flexbe_class, tmp_path, capsys):
    out = tmp_path / "out"
    argv = ["grade", str(flexbe_class), "--flexbe", "--scenario", SCENARIO, "--workers", "2"]
    code = main(argv + ["--timeout", "40", "--sandbox", "none", "--out", str(out)])
    assert code == 1  # ben's behaviour failed
    rows = {r["script"]: r for r in csv.DictReader(open(out / "grades.csv"))}
    assert rows["anna"]["status"] == "ok" and rows["anna"]["message"].startswith("outcome finished")
    assert rows["anna"]["in_bins"] == "1"  # the example's default: one part into bin 2
    assert rows["ben"]["status"] == "exception"
    assert rows["ben"]["message"] == "ZeroDivisionError: division by zero (at boom_sm.py:11 in execute)"
    assert "2 scripts: 1 ran cleanly" in capsys.readouterr().out


def test_a_workspace_needs_exactly_one_behaviour_and_flexbe_takes_its_own_options(flexbe_class):
    _behavior_package(flexbe_class / "ben", "more_behaviors", "Other", "other_sm", "OtherSM", BOOM)
    with pytest.raises(ConfigError, match="workspace 'ben' must hold one .*'Boom', 'Other'; choose one with"):
        grade_folder(flexbe_class, SCENARIO, flexbe=FlexbeGrading())
    with pytest.raises(ConfigError, match="'anna' must hold one .*Conveyor Pick' \\(none is 'Other'"):
        grade_folder(flexbe_class, SCENARIO, flexbe=FlexbeGrading(behavior="Other"))
    shutil.rmtree(flexbe_class / "ben")
    with pytest.raises(ConfigError, match="'moveit' is a ros-run option; flexbe-run takes srdf, moveit_co"):
        grade_folder(flexbe_class, SCENARIO, flexbe=FlexbeGrading(), options={"moveit": "melodic"})
    with pytest.raises(SystemExit):
        main(["grade", str(flexbe_class), "--scenario", SCENARIO, "--python2", "--workspace"])
    assert main(["grade", str(flexbe_class), "--scenario", SCENARIO, "--python2"]) == 2
