"""Melodic scripts are Python 2.7: ros-run runs their 2to3 translation, at their own lines."""

import numpy as np
import pytest

from omtp_drake.cell.arms import named_pose

A3 = "lecture6_assignment3"


def test_a_python2_melodic_script_runs_and_moves_the_arm(course_run):
    report, data = course_run("melodic_python2_place.py", scenario=A3, out_arg=True, moveit="melodic")
    assert report.exception is None, report.exception
    assert report.python2
    assert "2to3" in report.summary()
    np.testing.assert_allclose(data["joints"], named_pose("R2Place"), atol=0.02)


def test_a_python2_script_error_points_at_the_students_line(course_run):
    report, _ = course_run(
        """\
        import rospy
        rospy.init_node("py2")
        print "starting"
        rospy.sleep(0.1)
        missing_name
        """,
        scenario=A3,
    )
    assert report.python2
    assert report.exception.startswith("NameError: name 'missing_name' is not defined")
    assert "(at script.py:5 in <module>)" in report.exception


def test_a_script_that_is_neither_python_3_nor_2_reports_its_own_syntax_error(course_run):
    report, _ = course_run("import rospy\nx = = 1\n", scenario=A3)
    assert not report.python2
    assert report.exception.startswith("SyntaxError: invalid syntax")
    assert "line 2" in report.exception


@pytest.mark.parametrize("source", ["import rospy\nprint('python 3')\n"])
def test_a_python3_script_is_not_translated(course_run, source):
    report, _ = course_run(source, scenario=A3)
    assert report.exception is None and not report.python2
