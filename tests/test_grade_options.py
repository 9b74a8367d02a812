"""``grade`` passes ros-run's options on: ``--moveit`` for the class, ``grade.yaml`` per script."""

import csv

import pytest

from omtp_drake.errors import ConfigError
from omtp_drake.ros.cli import main
from omtp_drake.ros.grade import grade_folder
from omtp_drake.ros.grade_options import check_options, ros_run_flags

#: Melodic's habit: plan() returns the trajectory, handed straight to execute().
MELODIC = """
import sys
import moveit_commander, rospy
moveit_commander.roscpp_initialize(sys.argv)
rospy.init_node("melodic_student")
group = moveit_commander.MoveGroupCommander("robot2")
group.set_named_target("R2Up")
plan = group.plan()
group.execute(plan, wait=True)
"""

#: Noetic's habit: plan() returns (success, trajectory, planning time, error code).
NOETIC = """
import sys
import moveit_commander, rospy
moveit_commander.roscpp_initialize(sys.argv)
rospy.init_node("noetic_student")
group = moveit_commander.MoveGroupCommander("robot2")
group.set_named_target("R2Up")
success, plan, planning_time, error_code = group.plan()
if success:
    group.execute(plan, wait=True)
"""


@pytest.fixture
def mixed_class(tmp_path):
    folder = tmp_path / "class"
    folder.mkdir()
    (folder / "melodic_student.py").write_text(MELODIC)
    (folder / "noetic_student.py").write_text(NOETIC)
    return folder


def statuses(grades):
    return {g.script: g.status for g in grades}


def test_grade_moveit_melodic_is_passed_to_every_script(mixed_class, tmp_path, capsys):
    argv = ["grade", str(mixed_class), "--scenario", "lecture6_assignment3", "--workers", "1"]
    assert main(argv + ["--moveit", "melodic", "--out", str(tmp_path / "out")]) == 1
    assert "melodic_student.py ok " in capsys.readouterr().out
    rows = {r["script"]: r for r in csv.DictReader(open(tmp_path / "out" / "grades.csv"))}
    assert rows["melodic_student.py"]["status"] == "ok"
    assert rows["noetic_student.py"]["status"] == "exception"
    message = (
        "TypeError: cannot unpack non-iterable RobotTrajectory object (at noetic_student.py:8 in <module>)"
    )
    assert rows["noetic_student.py"]["message"] == message


def test_grade_yaml_gives_a_script_its_own_moveit(mixed_class):
    (mixed_class / "grade.yaml").write_text("melodic_student.py:\n  moveit: melodic\n")
    grades = grade_folder(mixed_class, "lecture6_assignment3", workers=1)
    assert statuses(grades) == {"melodic_student.py": "ok", "noetic_student.py": "ok"}
    assert grades[0].isolation["options"] == {"moveit": "melodic"} and grades[1].isolation["options"] == {}
    (mixed_class / "grade.yaml").write_text("carol.py:\n  moveit: melodic\n")
    with pytest.raises(ConfigError, match="no script 'carol.py' in the folder; scripts: melodic_student.py"):
        grade_folder(mixed_class, "lecture6_assignment3", workers=1)


def test_options_are_checked_against_ros_runs_flags():
    assert ros_run_flags(check_options({"moveit": "melodic"}, "grade")) == ["--moveit", "melodic"]
    with pytest.raises(ConfigError, match="moveit 'kinetic' is unknown; valid: noetic, melodic"):
        check_options({"moveit": "kinetic"}, "grade.yaml: a.py")
    with pytest.raises(ConfigError, match="unknown option 'gravity'; valid: moveit"):
        check_options({"gravity": 9.81}, "grade.yaml: a.py")
