"""The same cell options on every command (issue 43 item 7), through one resolver: SCENARIO or
``--scenario``, ``--launch``, ``--world``, ``--robot [NAME=]FILE[@X,Y,Z[,R,P,Y]]`` (repeatable),
``--workspace``, ``--arg``, each in every position, resolved to a typed Scenario (a file only for
``grade``); ``flexbe-run --call``; ``ros2`` handed the resolved cell."""

from __future__ import annotations

import argparse
import json
import textwrap
from pathlib import Path

import numpy as np
import pytest

from omtp_drake.cli import build_parser, main
from omtp_drake.errors import ConfigError
from omtp_drake.launch.options import resolve_cell_options
from omtp_drake.scenario import Scenario, load_scenario
from omtp_drake.scenario.robot_world import RobotSpawn, parse_robot

ROOT = Path(__file__).resolve().parent
TUTORIAL = ROOT / "fixtures" / "tutorial_ws" / "src"
CATKIN = ROOT / "fixtures" / "catkin_ws" / "src"
ROBOT = TUTORIAL / "slider_arm_description" / "urdf" / "slider_arm.urdf.xacro"
PARSER = build_parser()
COMMANDS = next(a for a in PARSER._actions if isinstance(a, argparse._SubParsersAction)).choices


@pytest.mark.parametrize(
    ("text", "spawn"),
    [
        ("a.urdf", RobotSpawn("a.urdf")),
        ("dir/a.urdf.xacro@1,2,3", RobotSpawn("dir/a.urdf.xacro", "", (1, 2, 3))),
        ("arm2=a.sdf@1,2,3,0,0,1.57", RobotSpawn("a.sdf", "arm2", (1, 2, 3), (0, 0, 1.57))),
        ("./x=y/a.urdf", RobotSpawn("./x=y/a.urdf")),  # a path with '=' is a path
    ],
)
def test_robot_syntax(text, spawn):
    assert parse_robot(text) == spawn


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ("a.urdf@1,2", "the placement '1,2' is not X,Y,Z or X,Y,Z,R,P,Y"),
        ("a.urdf@1,2,x", "the placement '1,2,x'"),
        ("a.urdf@1,2,nan", "(finite numbers"),
        ("@1,2,3", "give [NAME=]FILE[@X,Y,Z[,R,P,Y]]"),
    ],
)
def test_robot_syntax_errors_name_the_value(text, message):
    with pytest.raises(ConfigError, match=None) as e:
        parse_robot(text)
    assert message in str(e.value) and repr(text) in str(e.value)


def _required(command: str) -> list[str]:
    """The words a command needs besides its cell: a value for each required positional and option."""
    p = COMMANDS[command]
    words = []
    for action in p._actions:
        if action.dest == "scenario" or not action.required:
            continue
        value = {"camera": "logical_camera_1", "seeds": "0:1", "workspace": str(TUTORIAL)}.get(
            action.dest, "x"
        )
        words += [*action.option_strings[-1:], value]
    return words


#: The cell commands whose cell the resolver builds in the process (view shows one model, below).
IN_PROCESS = ("run", "camera", "tf-echo", "frames", "ros-run", "flexbe-run", "batch", "ros2")


@pytest.mark.parametrize("command", [*IN_PROCESS, "grade"])
@pytest.mark.parametrize("where", ["first", "last"])
def test_every_command_resolves_the_cell_options_wherever_they_stand(command, where):
    """Two robots, each placed, with the workspace and a xacro arg, before or after the
    command's own words: the same typed scenario (for grade, its file)."""
    cell = [
        "--robot",
        f"left={ROBOT}@1,2,0.5",
        "--workspace",
        str(TUTORIAL),
        "--robot",
        f"right={ROBOT}@-1,0,0,0,0,1.5",
        "--arg",
        "unused:=1",
    ]
    if command in ("flexbe-run", "grade"):
        cell = cell[:2] + cell[4:]  # their --workspace is their own (given with the required words)
    words = [*cell, *_required(command)] if where == "first" else [*_required(command), *cell]
    args = PARSER.parse_args([command, *words])
    resolve_cell_options(args)
    scenario = args.scenario if command != "grade" else load_scenario(args.scenario)
    assert isinstance(scenario, Scenario) and scenario.name == "empty_world"
    assert [(m.name, m.xyz, m.rpy) for m in scenario.models] == [
        ("left", [1.0, 2.0, 0.5], [0.0, 0.0, 0.0]),
        ("right", [-1.0, 0.0, 0.0], [0.0, 0.0, 1.5]),
    ]


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (["run", "fill_bin", "--scenario", "omtp_factory"], "the scenario is given twice"),
        (["run", "--scenario", "fill_bin", "--world", "x.world"], "give one of a scenario"),
        (["run", "fill_bin", "--arg", "a:=1"], "--arg NAME:=VALUE goes with --launch"),
        (["frames", "fill_bin", "--workspace", "/tmp"], "--workspace goes with --launch, --world or a robot"),
        (["tf-echo", "world", "x", "--robot", "a.urdf@1"], "--robot 'a.urdf@1': the placement"),
        (["view", str(ROBOT), "--robot", str(ROBOT)], "view shows one model"),
    ],
)
def test_option_errors_are_one_line(capsys, argv, message):
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert message in err and err.count("\n") == 1


def test_a_robot_file_as_scenario_takes_workspace_and_placement_in_tf_echo(capsys):
    """`tf-echo ROBOT --workspace WS` (refused before), and --robot's placement is spawn_model's."""
    argv = ["tf-echo", "world", "--robot", f"{ROBOT}@1,2,0.25,0,0,1.5707963", "base_link"]
    assert main([*argv, "--workspace", str(TUTORIAL), "--json", "--time", "0.01"]) == 0
    out = json.loads(capsys.readouterr().out)
    np.testing.assert_allclose(out["translation"], [1, 2, 0.25], atol=1e-6)
    np.testing.assert_allclose(out["rotation_xyzw"], [0, 0, np.sqrt(0.5), np.sqrt(0.5)], atol=1e-6)
    assert (
        main(["tf-echo", str(ROBOT), "--workspace", str(TUTORIAL), "world", "base_link", "--time", "0"]) == 0
    )
    assert "- Translation: [0.000, 0.000, 0.000]" in capsys.readouterr().out


def test_ros2_is_handed_the_resolved_cell(monkeypatch, capsys):
    """`ros2` takes the cell options; its node gets the typed Scenario (no DDS here: run_ros2
    is replaced by a recorder; tests/test_ros2.py runs the node)."""
    import omtp_drake.ros2.run as ros2_run

    seen = []
    monkeypatch.setattr(ros2_run, "run_ros2", lambda options, network, say: seen.append(options) or 0.0)
    monkeypatch.setattr(ros2_run, "choose_network", lambda domain_id, subnet: None)
    argv = ["ros2", "--timeout", "1", "--robot", f"arm={ROBOT}@0,0,1", "--workspace", str(TUTORIAL)]
    assert main(argv) == 0
    (options,) = seen
    assert isinstance(options.scenario, Scenario) and options.timeout == 1.0
    assert [(m.name, m.xyz) for m in options.scenario.models] == [("arm", [0.0, 0.0, 1.0])]
    assert options.cell().scenario.models[0].name == "arm"  # what the node runs


#: A FlexBE state that reports the simulated time it started at and the part count.
CLOCK_STATE = """
    import rospy
    from flexbe_core import EventState


    class ClockState(EventState):
        def __init__(self):
            super(ClockState, self).__init__(outcomes=['done'], output_keys=['report'])

        def execute(self, userdata):
            userdata.report = {'t': rospy.get_time()}
            return 'done'
"""
CLOCK_BEHAVIOR = """
    import json
    from flexbe_core import Behavior, Autonomy, OperatableStateMachine
    from flexbe_states.calculation_state import CalculationState
    from clock_states.clock_state import ClockState


    class ClockSM(Behavior):
        def __init__(self):
            super(ClockSM, self).__init__()
            self.name = 'Clock'
            self.add_parameter('out', '')

        def create(self):
            sm = OperatableStateMachine(outcomes=['finished'])
            with sm:
                OperatableStateMachine.add('clock', ClockState(), transitions={'done': 'save'},
                                           autonomy={'done': Autonomy.Off}, remapping={'report': 'report'})
                OperatableStateMachine.add('save', CalculationState(calculation=self._save),
                                           transitions={'done': 'finished'}, autonomy={'done': Autonomy.Off},
                                           remapping={'input_value': 'report', 'output_value': 'saved'})
            return sm

        def _save(self, report):
            with open(self.out, 'w') as f:
                json.dump(report, f)
            return True
"""
PACKAGE_XML = (
    '<?xml version="1.0"?><package format="2"><name>{}</name><version>0.0.1</version>'
    "<description>t</description><maintainer email='s@example.org'>s</maintainer>"
    "<license>BSD</license></package>"
)


def _workspace(src: Path) -> None:
    for name, files in {
        "clock_states": {"src/clock_states/clock_state.py": CLOCK_STATE},
        "clock_behaviors": {
            "src/clock_behaviors/clock_sm.py": CLOCK_BEHAVIOR,
            "manifest/clock_sm.xml": '<?xml version="1.0"?><behavior name="Clock">'
            '<executable package_path="clock_behaviors.clock_sm" class="ClockSM" /></behavior>',
        },
    }.items():
        (src / name / "src" / name).mkdir(parents=True)
        (src / name / "package.xml").write_text(PACKAGE_XML.format(name))
        (src / name / "src" / name / "__init__.py").write_text("")
        for rel, text in files.items():
            (src / name / rel).parent.mkdir(parents=True, exist_ok=True)
            (src / name / rel).write_text(textwrap.dedent(text))


def test_flexbe_run_calls_services_before_the_behaviour(tmp_path, capsys):
    """`flexbe-run --call SERVICE [YAML]` as ros-run's (a group's README calls /start_spawn first),
    then --settle; an unknown service is one error before the behaviour runs."""
    src = tmp_path / "src"
    _workspace(src)
    out = tmp_path / "clock.json"
    argv = ["flexbe-run", "Clock", "--workspace", str(src), "--scenario", "lecture7_flexbe"]
    rest = ["--param", f"out={out}", "--timeout", "5", "--settle-after", "0", "-q"]
    assert main([*argv, "--call", "/start_spawn", "--settle", "0.5", *rest]) == 0
    assert json.loads(out.read_text())["t"] == pytest.approx(0.5, abs=0.11)
    capsys.readouterr()
    assert main([*argv, "--call", "/no_such_service", *rest]) == 2
    assert "/no_such_service" in capsys.readouterr().err


def test_arg_reaches_the_launch_as_roslaunch_takes_it(capsys):
    """`--arg NAME:=VALUE` with --launch is the launch's argument: an undeclared one is refused
    as roslaunch refuses it (so the value reached the launch), naming the declared ones."""
    launch = ["--launch", "omtp_lecture6 lecture6_assignment1.launch", "--workspace", str(CATKIN)]
    assert main(["frames", "--arg", "nosuch:=1", *launch]) == 2
    err = capsys.readouterr().err
    assert "unused args [nosuch]" in err and "declared: debug, extra_gazebo_args, gui" in err
