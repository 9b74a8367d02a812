"""``grade``: a folder of ROS scripts on the batch machinery's workers, one row per script."""

import csv
import shutil
from pathlib import Path

from omtp_drake.grading.cli import main
from omtp_drake.grading.grade import COLLISION, EXCEPTION, OK, grade_folder

#: A hand-made trajectory (not collision-checked, as in MoveIt) that swings the arm into the floor.
CAROL = """
import moveit_commander, rospy
from moveit_msgs.msg import RobotTrajectory
from trajectory_msgs.msg import JointTrajectoryPoint
rospy.init_node("carol")
group = moveit_commander.MoveGroupCommander("robot2")
plan = RobotTrajectory()
plan.joint_trajectory.joint_names = group.get_active_joints()
start = group.get_current_joint_values()
down = list(start)
down[1], down[2] = 1.5, 0.0
plan.joint_trajectory.points = [
    JointTrajectoryPoint(positions=start, time_from_start=rospy.Duration(0)),
    JointTrajectoryPoint(positions=down, time_from_start=rospy.Duration(3.0)),
]
group.execute(plan, wait=True)
"""

EXAMPLES = Path(__file__).resolve().parent.parent / "examples" / "ros"


def test_grade_runs_every_script_and_writes_one_row_each(tmp_path, capsys):
    folder = tmp_path / "submissions"
    folder.mkdir()
    shutil.copy(EXAMPLES / "lecture6_assignment3.py", folder / "alice.py")
    (folder / "bob.py").write_text("import rospy\nrospy.init_node('bob')\nrospy.sleep(0.2)\n1 / 0\n")
    (folder / "carol.py").write_text(CAROL)
    grades = grade_folder(folder, "lecture6_assignment3", workers=2, out=tmp_path / "out")
    assert [g.script for g in grades] == ["alice.py", "bob.py", "carol.py"]
    assert [g.status for g in grades] == [OK, EXCEPTION, COLLISION]
    assert "robot2 touched something it should not: vacuum_gripper2_base_link - floor" in grades[2].message
    assert grades[1].message == "ZeroDivisionError: division by zero (at bob.py:4 in <module>)"
    rows = list(csv.DictReader(open(tmp_path / "out" / "grades.csv")))
    assert [r["status"] for r in rows] == [g.status for g in grades]
    assert (tmp_path / "out" / "grades.png").stat().st_size > 1000
    assert main(["grade", str(tmp_path / "nothing"), "--scenario", "lecture6_assignment3"]) == 2
    assert "grade needs a folder of scripts" in capsys.readouterr().err


def test_the_grade_plot_never_writes_labels_over_each_other():
    """Neighbouring bars with the same long verdict: every script's status is written once,
    and no two labels of the plot share a pixel."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.text import Text

    from omtp_drake.grading.table import Grade, plot_grades
    from omtp_drake.grading.verdicts import SIM_TIMEOUT

    statuses = [SIM_TIMEOUT] * 6 + [OK, "process limit", "process limit", EXCEPTION]
    # Neighbours with the same status have the same height too (no parts in bins).
    grades = [
        Grade(f"student_{i:02d}.py", s, 0 if s == SIM_TIMEOUT else 1, {"sim_time_s": 5.0})
        for i, s in enumerate(statuses)
    ]
    fig = plot_grades(grades)
    canvas = FigureCanvasAgg(fig)
    canvas.draw()
    renderer = canvas.get_renderer()
    texts = [t for t in fig.findobj(Text) if t.get_visible() and t.get_text()]
    labelled = [t.get_text() for t in texts if t.get_text().startswith("student_")]
    assert labelled == [f"{g.script}: {g.status}" for g in grades]
    boxes = [(t.get_text(), t.get_window_extent(renderer)) for t in texts]
    overlapping = [
        (a, b) for i, (a, box_a) in enumerate(boxes) for b, box_b in boxes[i + 1 :] if box_a.overlaps(box_b)
    ]
    assert not overlapping, overlapping
