"""The command line of lecture 6: ``camera``, ``frames`` and ``tf-echo`` with camera frames.

Commands run in-process through ``main`` (exit code 2 and one line on stderr for
errors; test_cli.py checks the same through a subprocess).
"""

import json

import numpy as np
import pytest

from omtp_drake.cli import main


def test_camera_json_has_the_part_on_the_belt(capsys):
    assert main(["camera", "lecture6_assignment1", "--camera", "logical_camera_1", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert {"time", "camera_pose", "models"} <= set(out)
    assert out["time"] == pytest.approx(0.5)  # the sample due at --time is taken
    np.testing.assert_allclose(out["camera_pose"]["translation"], [1.2, 1.8, 2.0], atol=1e-9)
    # What /omtp/logical_camera_1 carries: the course plugin lists every model in view
    # (the belt, with its nested models unnamed, and the hall), the part among them.
    listed = [(m["name"], m["type"]) for m in out["models"]]
    assert listed == [("conveyor_belt", "conveyor_belt"), ("", "conveyor_belt_fixed"),
                      ("", "conveyor_belt_moving"), ("workcell_", "workcell"), ("object_1", "object")]
    model = out["models"][-1]
    # Straight below the camera (+Cx looks down): 2.0 - 1.021 = 0.979 m away.
    np.testing.assert_allclose(model["pose"]["translation"], [0.979, 0.0, 0.0], atol=2e-3)


def test_camera_text_is_like_rostopic_echo(capsys):
    assert main(["camera", "lecture6_assignment3", "--camera", "logical_camera_2",
                 "--time", "1.5"]) == 0
    out = capsys.readouterr().out
    assert 'camera_name: "logical_camera_2"' in out
    assert 'name: "object_1"' in out and 'type: "object"' in out
    assert out.rstrip().endswith("---")


@pytest.mark.parametrize("args, message", [
    (["camera", "lecture6_assignment1", "--camera", "logical_camera_3"],
     "unknown camera 'logical_camera_3'; valid: logical_camera_1, logical_camera_2"),
    (["camera", "lecture6_assignment1", "--camera", "logical_camera_1", "--time", "-1"],
     "--time -1.0 is invalid; valid: a finite time >= 0 s"),
    (["tf-echo", "lecture6_assignment3", "world", "logical_camera_2_object_2_frame"],
     "frame 'logical_camera_2_object_2_frame' does not exist: logical_camera_2 has not seen 'object_2'"),
])
def test_errors_are_one_line(capsys, args, message):
    assert main(args) == 2
    err = capsys.readouterr().err
    assert message in err
    assert err.count("\n") == 1 and "Traceback" not in err


def test_tf_echo_of_the_detected_part_in_the_suction_cup(capsys):
    """Assignment 3 from the command line: the part on the floor seen from robot 2's
    suction cup at R2Home (-8.287, -1.609, 1.122), tool pointing down."""
    assert main(["tf-echo", "lecture6_assignment3", "vacuum_gripper2_suction_cup",
                 "logical_camera_2_object_1_frame", "--time", "1.5", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["time"] == pytest.approx(1.5)
    p = np.array(out["translation"])
    # In world, the part is at (-8.3, -1.23, 0.101): 1.021 below the cup along its z axis.
    assert p[2] == pytest.approx(1.122 - 0.101, abs=3e-3)
    assert np.linalg.norm(p) == pytest.approx(np.linalg.norm([-0.013, 0.379, -1.021]), abs=3e-3)


def test_tf_echo_text_prints_the_time(capsys):
    assert main(["tf-echo", "lecture6_assignment1", "world", "logical_camera_1_object_1_frame"]) == 0
    out = capsys.readouterr().out
    assert out.startswith("At time 0.500\n")
    assert "- Translation: [1.200, 1.800, 1.021]" in out


def test_frames_writes_pdf_and_png(capsys, tmp_path):
    assert main(["frames", "lecture6_assignment3", "-o", str(tmp_path / "tree"), "--time", "0.2"]) == 0
    printed = capsys.readouterr().out.split()
    assert printed == [str(tmp_path / "tree.pdf"), str(tmp_path / "tree.png")]
    assert (tmp_path / "tree.png").stat().st_size > 20_000
    assert (tmp_path / "tree.pdf").stat().st_size > 5_000
