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

#: anna's behaviour: a state of her own workspace's (the example's states package) stops the belt.
#: (The example's whole conveyor pick, end to end, is test_flexbe_run's: graded here it cost
#: 9 of this module's 17 CPU s.)
STOP_BELT = """
    from flexbe_core import Behavior, Autonomy, OperatableStateMachine
    from omtp_pick_flexbe_states.conveyor_power_state import ConveyorPowerState


    class StopBeltSM(Behavior):
        def __init__(self):
            super(StopBeltSM, self).__init__()
            self.name = 'Stop Belt'

        def create(self):
            _state_machine = OperatableStateMachine(outcomes=['finished', 'failed'])
            _state_machine.userdata.speed = 0.0
            with _state_machine:
                OperatableStateMachine.add('stop belt', ConveyorPowerState(stop=True),
                                           transitions={'succeeded': 'finished', 'failed': 'failed'},
                                           autonomy={'succeeded': Autonomy.Off, 'failed': Autonomy.Off})
            return _state_machine
"""

#: The FlexBE cell with a part dropped into bin 2: a row's parts in bins come from the run's
#: ledger, whatever the behaviour did.
PART_IN_BIN = f"""
base: {SCENARIO}
description: "lecture 7 (FlexBE) with a part dropped into bin 2"
parts:
  - {{name: object_1, xyz: [-0.1, 2.5, 0.5], size: 0.1, mass: 0.2}}
"""


@pytest.fixture
def flexbe_class(tmp_path):
    """anna: a behaviour that uses her workspace's own states; ben: a behaviour whose state
    divides by zero."""
    folder = tmp_path / "class"
    shutil.copytree(EXAMPLE / "omtp_pick_flexbe_states", folder / "anna" / "omtp_pick_flexbe_states")
    _behavior_package(folder / "anna", "anna_behaviors", "Stop Belt", "stop_belt_sm", "StopBeltSM", STOP_BELT)
    _behavior_package(folder / "ben", "boom_behaviors", "Boom", "boom_sm", "BoomSM", BOOM)
    return folder


def test_each_students_behaviour_is_graded_on_its_own(flexbe_class, tmp_path, capsys):
    out = tmp_path / "out"
    scenario = tmp_path / "part_in_bin.yaml"
    scenario.write_text(PART_IN_BIN)
    argv = ["grade", str(flexbe_class), "--flexbe", "--scenario", str(scenario), "--workers", "2"]
    code = main(argv + ["--timeout", "40", "--sandbox", "none", "--out", str(out)])
    assert code == 1  # ben's behaviour failed
    rows = {r["script"]: r for r in csv.DictReader(open(out / "grades.csv"))}
    assert rows["anna"]["status"] == "ok" and rows["anna"]["message"].startswith("outcome finished")
    assert rows["anna"]["in_bins"] == "1"  # the part dropped into bin 2
    assert rows["ben"]["status"] == "exception"
    assert rows["ben"]["message"] == "ZeroDivisionError: division by zero (at boom_sm.py:11 in execute)"
    assert "2 scripts: 1 ran cleanly" in capsys.readouterr().out


def test_a_workspace_needs_exactly_one_behaviour_and_flexbe_takes_its_own_options(flexbe_class):
    _behavior_package(flexbe_class / "ben", "more_behaviors", "Other", "other_sm", "OtherSM", BOOM)
    with pytest.raises(ConfigError, match="workspace 'ben' must hold one .*'Boom', 'Other'; choose one with"):
        grade_folder(flexbe_class, SCENARIO, flexbe=FlexbeGrading())
    with pytest.raises(ConfigError, match="'anna' must hold one .*Stop Belt' \\(none is 'Other'"):
        grade_folder(flexbe_class, SCENARIO, flexbe=FlexbeGrading(behavior="Other"))
    shutil.rmtree(flexbe_class / "ben")
    with pytest.raises(ConfigError, match="'moveit' is a ros-run option; flexbe-run takes srdf, moveit_co"):
        grade_folder(flexbe_class, SCENARIO, flexbe=FlexbeGrading(), options={"moveit": "melodic"})
    with pytest.raises(SystemExit):
        main(["grade", str(flexbe_class), "--scenario", SCENARIO, "--python2", "--workspace"])
    assert main(["grade", str(flexbe_class), "--scenario", SCENARIO, "--python2"]) == 2
