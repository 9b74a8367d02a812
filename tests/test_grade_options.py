"""``grade`` passes ros-run's options on: ``--moveit`` for the class, ``grade.yaml`` per script."""

import csv
import io
import json
import re
import sys

import pytest

from omtp_drake.errors import ConfigError
from omtp_drake.grading.cli import main
from omtp_drake.grading.grade import grade_folder
from omtp_drake.grading.options import check_options, ros_run_flags

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


@pytest.fixture(scope="module")
def graded_class(tmp_path_factory):
    """One grade of a class (a grade's cluster and its runs cost seconds, so the two tests
    below share it), run as ``grade ... --moveit melodic``: MoveIt's Noetic habit (which fails
    under Melodic's), and a Noetic plan to lecture 5's named pose given, in grade.yaml, her own
    MoveIt, her SRDF and the slides' set-up call (lena), or only a settle (tom: the class's
    MoveIt and the cell's SRDF). (Melodic's habit under ``--moveit melodic`` is ros-run's, in
    test_ros_moveit.) (exit code, what it printed, the CSV's rows by script, each run's JSON
    by script stem)."""
    tmp = tmp_path_factory.mktemp("graded_class")
    folder = tmp / "class"
    (folder / "lena").mkdir(parents=True)
    (folder / "noetic_student.py").write_text(NOETIC)
    (folder / "lena" / "omtp.srdf").write_text(STUDENT_SRDF)
    (folder / "lena.py").write_text(HIGH_PLAN)
    (folder / "tom.py").write_text(HIGH_PLAN)
    (folder / "grade.yaml").write_text(
        "lena.py:\n  moveit: noetic\n  srdf: lena/omtp.srdf\n"
        "  call: [/spawn_object_at_robot2]\n  settle: 0.5\n"
        "tom.py:\n  settle: 0.5\n"
    )
    out = tmp / "out"
    argv = ["grade", str(folder), "--scenario", "lecture6_assignment3", "--workers", "2"]
    with pytest.MonkeyPatch.context() as mp:
        printed = io.StringIO()
        mp.setattr(sys, "stdout", printed)
        code = main(argv + ["--moveit", "melodic", "--out", str(out)])
    rows = {r["script"]: r for r in csv.DictReader(open(out / "grades.csv"))}
    runs = {p.stem: json.loads(p.read_text()) for p in (out / "runs").glob("*.json")}
    return code, printed.getvalue(), rows, runs


def test_grade_moveit_melodic_is_passed_to_every_script_and_grade_yaml_overrides_it(graded_class):
    """``--moveit melodic`` for the class reaches every script (Noetic's habit fails under it),
    and grade.yaml gives one script its own MoveIt (lena's Noetic plan works)."""
    code, printed, rows, runs = graded_class
    assert code == 1
    assert re.search(r"^lena\.py +ok ", printed, re.M) and "noetic_student.py exception " in printed
    assert {name: row["status"] for name, row in rows.items()} == {
        "noetic_student.py": "exception", "lena.py": "ok", "tom.py": "exception"}  # tom: the next test
    message = (
        "TypeError: cannot unpack non-iterable RobotTrajectory object (at noetic_student.py:8 in <module>)"
    )
    assert rows["noetic_student.py"]["message"] == message
    options = {name: run["isolation"]["options"] for name, run in runs.items()}
    melodic = {"moveit": "melodic"}
    assert {name: value for name, value in options.items() if name != "lena"} == {
        "noetic_student": melodic, "tom": {**melodic, "settle": 0.5}}  # tom: the class's, under his settle
    assert options["lena"]["moveit"] == "noetic" and options["lena"]["srdf"].endswith("omtp.srdf")


def test_grade_yaml_must_name_scripts_of_the_folder(mixed_class):
    (mixed_class / "grade.yaml").write_text("carol.py:\n  moveit: melodic\n")
    with pytest.raises(ConfigError, match="no script 'carol.py' in the folder; scripts: melodic_student.py"):
        grade_folder(mixed_class, "lecture6_assignment3", workers=1)


def test_options_are_checked_against_ros_runs_flags(tmp_path):
    assert ros_run_flags(check_options({"moveit": "melodic"}, "grade", tmp_path)) == ["--moveit", "melodic"]
    with pytest.raises(ConfigError, match="moveit 'kinetic' is unknown; valid: noetic, melodic"):
        check_options({"moveit": "kinetic"}, "grade.yaml: a.py", tmp_path)
    with pytest.raises(ConfigError, match="unknown option 'gravity'; valid: moveit, srdf, moveit_config"):
        check_options({"gravity": 9.81}, "grade.yaml: a.py", tmp_path)
    with pytest.raises(ConfigError, match="srdf 'mine.srdf': no such file"):
        check_options({"srdf": "mine.srdf"}, "grade.yaml: a.py", tmp_path)
    with pytest.raises(ConfigError, match="latency .*valid"):
        check_options({"latency": "think=1"}, "grade", tmp_path)
    calls = {"call": ["/spawn_object_at_robot2", "/gripper2/control true"], "settle": 1.5}
    calls = check_options(calls, "g", tmp_path)
    assert ros_run_flags(calls) == [
        "--call", "/spawn_object_at_robot2", "--call", "/gripper2/control true", "--settle", "1.5"]


#: A student's own named pose (lecture 5's SRDF), set as the target after the slides' set-up
#: call: an unknown name raises. (Moving there is tests/ros_conformance/test_srdf's: here the
#: move cost each of the two runs that made it about 2 CPU s, TOPP-RA's import and the motion.)
HIGH_POSE = """
import moveit_commander, rospy
rospy.init_node("high_student")
group = moveit_commander.MoveGroupCommander("robot2")
group.set_named_target("high")
print("high:", sorted(group.get_named_target_values("high").items()))
"""

#: HIGH_POSE planned with Noetic's habit: works under Noetic's MoveIt, with an SRDF that has "high".
HIGH_PLAN = HIGH_POSE + """success, plan, planning_time, error_code = group.plan()
print("planned to high:", success)
"""

STUDENT_SRDF = """<?xml version="1.0" ?>
<robot name="omtp">
  <group name="robot2"><chain base_link="robot2_base_link" tip_link="vacuum_gripper2_suction_cup"/></group>
  <group_state name="high" group="robot2">
    <joint name="robot2_shoulder_pan_joint" value="1.2"/>
    <joint name="robot2_shoulder_lift_joint" value="-1.2"/>
    <joint name="robot2_elbow_joint" value="0.9"/>
    <joint name="robot2_wrist_1_joint" value="-1.3"/>
    <joint name="robot2_wrist_2_joint" value="-1.5708"/>
    <joint name="robot2_wrist_3_joint" value="0"/>
  </group_state>
</robot>
"""


def test_grade_yaml_passes_a_students_srdf_and_set_up_calls(graded_class):
    _, _, rows, runs = graded_class
    assert rows["lena.py"]["status"] == "ok", rows["lena.py"]["message"]
    assert runs["lena"]["report"]["sim_time_s"] >= 0.5 - 1e-9  # the settle ran before the script
    assert runs["lena"]["report"]["empty_spawn_calls"]  # object_1 is there: the call spawns nothing
    assert rows["tom.py"]["status"] == "exception"  # no "high" in the cell's own SRDF
    assert "high" in rows["tom.py"]["message"]


def test_ros_run_sandbox_passes_the_course_options_on(tmp_path, capsys):
    """``ros-run --sandbox``: --srdf and --settle reach the isolated run (its SRDF readable
    inside the sandbox wherever it lies: here in a folder of its own, away from the script's,
    so nothing but --srdf brings "high", which the cell's own SRDF lacks: tom's row above)."""
    folder = tmp_path / "student"
    folder.mkdir()
    (tmp_path / "config").mkdir()
    srdf = tmp_path / "config" / "omtp.srdf"
    srdf.write_text(STUDENT_SRDF)
    script = folder / "high.py"
    script.write_text(HIGH_POSE.replace('rospy.init_node("high_student")', 'rospy.init_node("high_student")\n'
                                        'print("start %.2f" % rospy.get_time())'))
    argv = ["ros-run", str(script), "--scenario", "lecture6_assignment3", "--sandbox", "auto", "-q"]
    assert main(argv + ["--srdf", str(srdf), "--settle", "0.5"]) == 0
    out = capsys.readouterr().out
    assert "start 0.50" in out and "verdict: ok" in out
    assert "('robot2_shoulder_pan_joint', 1.2)" in out  # the student's "high"


@pytest.mark.parametrize("bad", [float("inf"), float("nan"), -1.0])
def test_every_duration_of_a_run_refuses_inf_nan_and_negatives(tmp_path, bad):
    """One check of a duration (errors.check_duration): a hand-written ``> 0`` took inf."""
    from omtp_drake.ros import run_script

    settle = rf"settle \(simulated seconds\) must be a finite time >= 0 s, got {bad}"
    with pytest.raises(ConfigError, match=settle):
        check_options({"settle": bad}, "grade.yaml: a.py", tmp_path)
    script = tmp_path / "a.py"
    script.write_text("print('never runs')\n")
    with pytest.raises(ConfigError, match=rf"--wall-timeout must be a finite time > 0 s, got {bad}"):
        grade_folder(tmp_path, "lecture6_assignment3", workers=1, wall_timeout=bad)
    with pytest.raises(ConfigError, match=rf"--timeout must be a finite time > 0 s, got {bad}"):
        run_script(script, scenario="lecture6_assignment3", timeout=bad)
