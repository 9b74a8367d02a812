"""The student's own MoveIt config (lecture 5's ``omtp_moveit_config``): its SRDF's
groups, named states, end effectors and disabled collision pairs, its
``joint_limits.yaml``, and the ``/robot_description*`` parameters."""

import json
import textwrap
import xml.etree.ElementTree as ET

import numpy as np
import pytest

from omtp_drake.cell.arms import NAMED_POSES
from omtp_drake.errors import ConfigError, NotSupportedError
from omtp_drake.grading.cli import main as ros_cli
from omtp_drake.ros import run_script

A4 = "lecture6_assignment4"
JOINTS = ("shoulder_pan_joint", "shoulder_lift_joint", "elbow_joint", "wrist_1_joint", "wrist_2_joint")
JOINTS += ("wrist_3_joint",)

#: The student's poses: "high" is new, R2Home has their own values (not the cell's).
HIGH = (1.8571, -1.4753, 0.9546, -1.0935, -1.5447, 0.2256)
STUDENT_HOME = (1.2, -1.5708, 1.5708, -1.5708, -1.5708, 0.3)


def _state(name, group, values, robot):
    # As the Setup Assistant writes them: joints in alphabetical order.
    joints = sorted(zip((f"{robot}_{j}" for j in JOINTS), values))
    rows = "\n".join(f'        <joint name="{j}" value="{v}" />' for j, v in joints)
    return f'    <group_state name="{name}" group="{group}">\n{rows}\n    </group_state>'


def student_srdf(
    extra="",
    robot2_group='<chain base_link="robot2_base_link" tip_link="vacuum_gripper2_suction_cup" />',
    robot2_name="robot2",
):
    """An SRDF shaped like the course's omtp.srdf (groups as chains, named states,
    virtual joints, disabled pairs, some naming links the cell has no body for)."""
    states = "\n".join(
        [
            _state("R1Home", "robot1", NAMED_POSES["R1Home"], "robot1"),
            _state("R2Home", robot2_name, STUDENT_HOME, "robot2"),
            _state("high", robot2_name, HIGH, "robot2"),
        ]
    )
    return f"""<?xml version="1.0" ?>
<robot name="omtp">
    <group name="robot1">
        <chain base_link="robot1_base_link" tip_link="vacuum_gripper1_suction_cup" />
    </group>
    <group name="{robot2_name}">
        {robot2_group}
    </group>
{states}
    <virtual_joint name="robot1" type="fixed" parent_frame="robot1_base_link" child_link="world" />
    <virtual_joint name="robot2" type="fixed" parent_frame="robot2_base_link" child_link="world" />
    <disable_collisions link1="bin_1_base_link" link2="robot1_base_link" reason="Adjacent" />
    <disable_collisions link1="robot2_base_link" link2="workcell" reason="Adjacent" />
{extra}
</robot>
"""


@pytest.fixture
def srdf_file(tmp_path):
    def write(text, name="omtp.srdf"):
        path = tmp_path / name
        path.write_text(text)
        return path

    return write


def test_student_named_states_replace_the_cells(course_run, srdf_file):
    path = srdf_file(student_srdf())
    report, out = course_run("srdf_named_states.py", scenario=A4, out_arg=True, srdf=path)
    assert report.ok, report.summary()
    assert out["high_ok"] and out["home_ok"]
    np.testing.assert_allclose(out["high_q"], HIGH, atol=1e-3)
    np.testing.assert_allclose(out["home_q"], STUDENT_HOME, atol=1e-3)
    assert out["named"] == ["R2Home", "high"]
    assert out["high_values"] == {f"robot2_{j}": v for j, v in zip(JOINTS, HIGH)}
    assert out["groups"] == ["robot1", "robot2"]
    assert out["eef"] == "vacuum_gripper2_suction_cup"
    assert out["semantic"] == path.read_text()
    assert out["has_description"]
    # The cell's own R2Up is not in the student's SRDF: MoveIt would not know it either.
    assert "'R2Up'" in out["missing"] and "R2Home, high" in out["missing"]


def test_a_joint_the_cell_lacks_is_one_error(srdf_file):
    group = '<joint name="robot2_shoulder_pan_joint" />\n        <joint name="robot3_elbow_joint" />'
    path = srdf_file(student_srdf(robot2_group=group))
    with pytest.raises(ConfigError) as error:
        run_script(_script_path(), ["/dev/null"], scenario=A4, srdf=path)
    text = str(error.value)
    assert "'robot3_elbow_joint'" in text and "SRDF group 'robot2'" in text
    assert "robot2_elbow_joint" in text  # the valid choices


def test_a_group_the_cell_lacks_is_one_error(srdf_file):
    extra = _state("Up", "robot3", NAMED_POSES["R2Up"], "robot2")
    with pytest.raises(ConfigError) as error:
        run_script(_script_path(), ["/dev/null"], scenario=A4, srdf=srdf_file(student_srdf(extra)))
    assert "'robot3'" in str(error.value) and "valid: robot1, robot2" in str(error.value)


def test_a_group_on_part_of_an_arm_is_not_supported(srdf_file):
    group = '<chain base_link="robot2_base_link" tip_link="robot2_forearm_link" />'
    with pytest.raises(
        NotSupportedError, match="robot2_shoulder_pan_joint, robot2_shoulder_lift_joint, robot2_elbow_joint"
    ):
        run_script(
            _script_path(), ["/dev/null"], scenario=A4, srdf=srdf_file(student_srdf(robot2_group=group))
        )


def _script_path():
    from pathlib import Path

    return Path(__file__).parent / "scripts" / "srdf_named_states.py"


# ----------------------------------------------------------------------------- --moveit-config


def _package(tmp_path, limits_text):
    config = tmp_path / "omtp_moveit_config" / "config"
    config.mkdir(parents=True)
    (config / "omtp.srdf").write_text(student_srdf())
    (config / "joint_limits.yaml").write_text(textwrap.dedent(limits_text))
    return config.parent


def _limits(velocity):
    rows = []
    for robot, vmax in (("robot1", (2.16, 2.16, 3.15, 3.2, 3.2, 3.2)), ("robot2", velocity)):
        for joint, v in zip(JOINTS, vmax):
            rows.append(
                f"  {robot}_{joint}:\n    has_velocity_limits: true\n    max_velocity: {v}\n"
                "    has_acceleration_limits: false\n    max_acceleration: 0\n"
            )
    return "joint_limits:\n" + "".join(rows)


#: The longest joint travel of robot2 from its initial pose (R2Home) to "high" (the elbow).
ELBOW_TRAVEL = abs(NAMED_POSES["R2Home"][2] - HIGH[2])


#: srdf_named_states.py's first move alone (to the student's "high"), timed: what the
#: joint-limit tests read (the whole script runs in test_student_named_states_replace_the_cells).
HIGH_TIME_SCRIPT = """\
import json
import sys

import moveit_commander
import rospy

rospy.init_node("high_time")
group = moveit_commander.MoveGroupCommander("robot2")
start = rospy.get_time()
group.set_named_target("high")
ok = group.go(wait=True)
group.stop()
result = {"high_ok": ok, "high_time": rospy.get_time() - start, "high_q": group.get_current_joint_values()}
with open(sys.argv[1], "w") as f:
    json.dump(result, f)
"""


@pytest.fixture(scope="module")
def high_time(tmp_path_factory):
    """``high_time(limits_text)`` -> (report, what the script wrote) of HIGH_TIME_SCRIPT with a
    config of those limits; run once per module for each (the course's limits serve two tests)."""
    runs: dict = {}

    def run(limits_text):
        if limits_text not in runs:
            tmp = tmp_path_factory.mktemp("limits")
            script, out = tmp / "high_time.py", tmp / "out.json"
            script.write_text(HIGH_TIME_SCRIPT)
            report = run_script(script, [str(out)], scenario=A4, moveit_config=_package(tmp, limits_text))
            runs[limits_text] = report, json.loads(out.read_text())
        return runs[limits_text]

    return run


@pytest.mark.parametrize(
    "limits, slowest",
    [
        (_limits((3.15, 3.15, 0.3, 3.2, 3.2, 3.2)), 0.3),
        (_limits((3.15, 3.15, 3.15, 3.2, 3.2, 3.2)) + "default_velocity_scaling_factor: 0.1\n", 0.315),
    ],
    ids=["max_velocity", "default_velocity_scaling_factor"],
)
def test_moveit_config_joint_limits_time_the_plans(high_time, limits, slowest):
    fast, fast_out = high_time(_limits((3.15, 3.15, 3.15, 3.2, 3.2, 3.2)))
    slow, slow_out = high_time(limits)
    assert fast.ok and slow.ok, (fast.summary(), slow.summary())
    assert fast_out["high_ok"] and slow_out["high_ok"]
    np.testing.assert_allclose(slow_out["high_q"], HIGH, atol=1e-3)
    # The elbow cannot cover its travel faster than its limit allows; with the course's limits it does.
    assert slow_out["high_time"] >= ELBOW_TRAVEL / slowest
    assert fast_out["high_time"] < 0.6 * ELBOW_TRAVEL / slowest


def test_moveit_config_params_and_bad_joint(course_run, tmp_path):
    package = _package(tmp_path, _limits((3.15, 3.15, 0.5, 3.2, 3.2, 3.2)))
    script = "srdf_joint_limits_param.py"
    report, out = course_run(script, scenario=A4, out_arg=True, moveit_config=package)
    assert report.ok and out == {"elbow": 0.5}
    (package / "config" / "joint_limits.yaml").write_text(
        "joint_limits:\n  robot2_elbo_joint:\n    max_velocity: 1\n"
    )
    with pytest.raises(ConfigError, match="'robot2_elbo_joint'; closest: robot2_elbow_joint"):
        course_run(script, scenario=A4, moveit_config=package)
    (package / "config" / "joint_limits.yaml").write_text(
        "joint_limits:\n  robot2_elbow_joint:\n    has_velocity_limits: true\n    max_velocity: -1\n"
    )
    with pytest.raises(ConfigError, match=r"elbow_joint.max_velocity must be a finite number > 0, got -1"):
        course_run(script, scenario=A4, moveit_config=package)


def test_cli_flags_reach_the_run(tmp_path, capsys):
    (tmp_path / "empty" / "config").mkdir(parents=True)
    code = ros_cli(
        ["ros-run", str(_script_path()), "--scenario", A4, "--moveit-config", str(tmp_path / "empty")]
    )
    assert code == 2 and "config/ must hold one .srdf file, found: none" in capsys.readouterr().err


# ----------------------------------------------------------------------------- end effectors, collisions

EEF = """
    <group name="gripper2">
        <link name="vacuum_gripper2_base_link" />
        <link name="vacuum_gripper2_tip" />
    </group>
    <end_effector name="suction2" parent_link="vacuum_gripper2_tip" group="gripper2" parent_group="robot2" />
"""


@pytest.mark.parametrize(
    "parent_link, eef",
    [
        ("vacuum_gripper2_tip", "vacuum_gripper2_tip"),
        # A link that is no tool frame of the cell: a warning, and the suction cup.
        ("robot2_wrist_3_link", "vacuum_gripper2_suction_cup"),
    ],
)
def test_end_effector_of_the_srdf(course_run, srdf_file, caplog, parent_link, eef):
    text = student_srdf(EEF.replace('parent_link="vacuum_gripper2_tip"', f'parent_link="{parent_link}"'))
    report, out = course_run("srdf_end_effector.py", scenario=A4, out_arg=True, srdf=srdf_file(text))
    assert report.ok, report.summary()
    assert out == {"eef": eef, "groups": ["robot1", "robot2", "gripper2"]}
    warned = f"end-effector link {parent_link} is no tool frame of the cell" in caplog.text
    assert warned is (parent_link != eef)


#: The pairs in collision at the script's goal (robot2's gripper against its own pedestal).
DISABLED = """
    <disable_collisions link1="robot2_pedestal_link" link2="vacuum_gripper2_base_link" reason="Never" />
    <disable_collisions link1="robot2_pedestal_link" link2="vacuum_gripper2_cup" reason="Never" />
"""


@pytest.mark.parametrize("extra, planned", [("", False), (DISABLED, True)], ids=["checked", "disabled"])
def test_disabled_collision_pairs_are_not_checked(course_run, srdf_file, extra, planned):
    script = "srdf_plan_into_pedestal.py"
    report, out = course_run(script, scenario=A4, out_arg=True, srdf=srdf_file(student_srdf(extra)))
    assert report.ok, report.summary()
    assert out["success"] is planned
    assert out["code"] == (1 if planned else -12)  # SUCCESS, GOAL_IN_COLLISION


# ----------------------------------------------------------------------------- the cell's own


def test_the_cells_own_description_parameters(course_run):
    """Without --srdf the cell's SRDF (its named poses) and URDF are on the parameter
    server, as a FlexBE state reads them."""
    script = "srdf_description_params.py"
    report, out = course_run(script, scenario=A4, out_arg=True)
    assert report.ok, report.summary()
    srdf = ET.fromstring(out["srdf"])
    states = {
        s.get("name"): [float(j.get("value")) for j in s.iter("joint")] for s in srdf.iter("group_state")
    }
    assert states["R2Place"] == list(NAMED_POSES["R2Place"])
    urdf = ET.fromstring(out["urdf"])
    joints = {j.get("name"): j for j in urdf.findall("joint")}
    elbow = joints["robot2_elbow_joint"]
    assert elbow.get("type") == "revolute" and elbow.find("parent").get("link") == "robot2_upper_arm_link"
    assert float(elbow.find("limit").get("upper")) == pytest.approx(np.pi)
    links = {link.get("name") for link in urdf.findall("link")}
    assert {"world", "robot2_pedestal_link", "vacuum_gripper2_suction_cup", "bin_1_base_link"} <= links
    # Every link hangs from the world, once.
    children = [j.find("child").get("link") for j in joints.values()]
    assert sorted(children) == sorted(links - {"world"})


def test_moveit_config_joint_limits_time_cartesian_paths(course_run, tmp_path):
    course = _package(tmp_path / "course", _limits((3.15, 3.15, 3.15, 3.2, 3.2, 3.2)))
    slow = _package(tmp_path / "slow", _limits((0.1,) * 6))  # (the R2Home move first: ~4 s simulated)
    _, fast_out = course_run("srdf_cartesian_descent.py", scenario=A4, out_arg=True, moveit_config=course)
    report, slow_out = course_run("srdf_cartesian_descent.py", scenario=A4, out_arg=True, moveit_config=slow)
    assert report.ok, report.summary()
    assert fast_out["fraction"] == slow_out["fraction"] == 1.0
    travel = max(abs(a - b) for a, b in zip(slow_out["first"], slow_out["last"]))
    assert slow_out["duration"] >= travel / 0.1
    assert fast_out["duration"] < 0.5 * travel / 0.1


def test_a_group_of_the_students_own_name(course_run, srdf_file):
    """A group may have any name: ``manipulator`` moves robot2, whose six joints it has
    (a list of joints here, with the virtual joint as the Setup Assistant may add it)."""
    joints = '<joint name="robot2" />\n' + "\n".join(f'<joint name="robot2_{j}" />' for j in JOINTS)
    path = srdf_file(student_srdf(robot2_group=joints, robot2_name="manipulator"))
    report, out = course_run("srdf_own_group_name.py", scenario=A4, out_arg=True, srdf=path)
    assert report.ok, report.summary()
    assert out["ok"] and out["groups"] == ["robot1", "manipulator"]
    np.testing.assert_allclose(out["q"], HIGH, atol=1e-3)
    assert "'robot2' was not found; groups: robot1, manipulator" in out["robot2"]
