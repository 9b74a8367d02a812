"""Records what users see of the course-layout fixtures' script runs into
``tests/golden/fixture_reports.json``, the reference of ``tests/fixture_reports.py``
(issue 43: a later change of the loader must not alter the fixtures' ledgers and reports).

A script, not a test: run it from the repository root on the code whose reports are the
reference, e.g. ``.venv/bin/python tests/golden/record_fixture_reports.py``. It runs the
tests that run a fixture's script, each of which records its case instead of comparing.
"""

import os
import subprocess
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
#: The tests that run a course-layout fixture's script (each calls assert_as_recorded).
TESTS = (
    "tests/test_group_workspace.py::test_their_belt_script_puts_parts_in_their_bin_next_to_robot_1",
    "tests/test_arm_links.py::test_their_belt_script_still_picks_with_the_camera_on_the_wrist",
    "tests/test_student_workcell.py::test_their_belt_script_still_puts_parts_in_their_bin",
    "tests/test_plugin_names.py::test_a_rospy_script_on_their_names_picks_a_part_into_their_bin",
    "tests/test_own_cell.py::test_a_course_style_robot_1_script_drops_the_box_into_the_students_bin",
)


def main() -> int:
    out = HERE / "fixture_reports.json"
    out.unlink(missing_ok=True)
    env = {**os.environ, "OMTP_RECORD_FIXTURE_REPORTS": str(out)}
    done = subprocess.run([sys.executable, "-m", "pytest", "-q", "-p", "no:cacheprovider", *TESTS], env=env)
    print(out.read_text() if out.exists() else "nothing recorded")
    return done.returncode


if __name__ == "__main__":
    sys.exit(main())
