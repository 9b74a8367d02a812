"""The Cell API's side of issue 19: MoveIt's planning-scene semantics, a start in collision
that moves out, joint limits, bins with a free drop point, and the docs' examples run."""

import re
import textwrap
from pathlib import Path

import numpy as np
import pytest
from pydrake.math import RigidTransform

import omtp_drake.script.bins
import omtp_drake.script.cell
import omtp_drake.script.scene
from omtp_drake import Cell, tool_down
from omtp_drake.errors import PlanningError, SimulationError, UnknownNameError

README = Path(__file__).resolve().parent.parent / "README.md"
SPOT = [-8.3, -1.23, 0.3]  # under logical camera 2


@pytest.fixture(scope="module")
def cell():
    return Cell("lecture6_assignment4", auto_spawn=False)


def rest(cell, part):
    cell.wait(1.0)
    return cell.part_pose(part).translation()


def test_the_cup_pressed_onto_a_loose_part_plans_and_suction_attaches(cell):
    """The course's goal (suction_cup frame 0.16 above a 0.2 m part's centre: the cup
    face 7.5 mm into the top face) plans and runs; physics presses, suction attaches."""
    arm, vacuum = cell.arm("robot2"), cell.gripper("robot2")
    arm.go("Home")
    part = cell.spawn_part(xyz=SPOT, yaw=0.0)
    try:
        p = rest(cell, part)
        vacuum.on()
        arm.go(tool_down(p + [0, 0, 0.16]), frame="suction_cup")
        assert vacuum.wait_for_attach(0.5) == part
        arm.go("Home")
        assert cell.ledger().parts[part] == "held:robot2"
    finally:
        vacuum.off()
        cell.wait(0.5)
        cell.remove_part(part)


def test_a_held_part_pressed_into_the_floor_can_move_out(cell):
    """A guarded descent at the default speed presses the held part into the floor; the
    next plans start in collision and still move out of it (MoveIt's start-state fix)."""
    arm, vacuum = cell.arm("robot2"), cell.gripper("robot2")
    arm.go("Home")
    part = cell.spawn_part(xyz=SPOT, yaw=0.0)
    try:
        p = rest(cell, part)
        arm.move_to(tool_down(p + [0, 0, 0.2]))
        vacuum.on()
        arm.move_linear(tool_down(p + [0, 0, 0.06]), until=lambda: vacuum.attached)
        arm.move_linear(tool_down(p + [0, 0, 0.07]))  # pressed on: the held part into the floor
        assert vacuum.attached
        plan, fraction = arm.compute_cartesian_path(tool_down(p + [0, 0, 0.4]))
        assert fraction == 1.0
        arm.go("Home")
        assert cell.ledger().parts[part] == "held:robot2"
    finally:
        vacuum.off()
        cell.wait(0.5)
        cell.remove_part(part)


def test_parts_in_the_planning_scene_are_obstacles_named_by_their_names(cell):
    arm = cell.arm("robot2")
    arm.go("Home")
    part = cell.spawn_part(xyz=SPOT, yaw=0.0)
    try:
        p = rest(cell, part)
        cell.planning_scene.add_part(part)
        assert cell.planning_scene.names() == [part]
        with pytest.raises(PlanningError, match=rf"in collision; .*vacuum_gripper2_cup / {part}"):
            arm.plan(tool_down(p + [0, 0, 0.16]), frame="suction_cup")
        cell.planning_scene.add_box("fence", RigidTransform([-8.0, -1.9, 0.6]), [0.6, 0.05, 1.2])
        with pytest.raises(UnknownNameError, match="unknown planning-scene object 'gate'; valid: fence, "):
            cell.planning_scene.remove("gate")
    finally:
        cell.planning_scene.remove()
        cell.remove_part(part)
    assert cell.planning_scene.names() == []


def test_joint_targets_outside_the_limits_raise_planning_error(cell):
    with pytest.raises(
        PlanningError,
        match=r"robot2: the goal is outside the joint limits: joint "
        r"wrist_3_joint of robot2 at 4\.0000 rad is outside",
    ):
        cell.arm("robot2").go([1.5708, -1.5708, 1.5708, -1.5708, -1.5708, 4.0])


def test_a_bin_tells_its_inner_size_and_where_a_part_still_fits(cell):
    bin_1 = cell.bin("bin_1")
    np.testing.assert_allclose(bin_1.inner_size, [0.38, 0.38, 0.355], atol=0.01)
    first = bin_1.drop_point()
    np.testing.assert_allclose(first, [-8.0, -2.2, 0.475 + 0.1 + 0.05], atol=0.01)  # centre, above the rim
    parts = []
    try:
        for _ in range(2):  # a 0.2 m part on the bin's floor, a second one on top of it
            parts.append(cell.spawn_part(xyz=bin_1.drop_point(), yaw=0.0))
            cell.wait(1.5)
        assert bin_1.parts() == sorted(parts)
        with pytest.raises(SimulationError, match="bin_1 is full for a 0.2 m part"):
            bin_1.drop_point()
    finally:
        for part in parts:
            cell.remove_part(part)
    with pytest.raises(UnknownNameError, match="unknown bin 'bin_7'; valid: bin_1"):
        cell.bin("bin_7")


def _docstring_example(module) -> str:
    text = module.__doc__.split("::\n", 1)[1]
    block = re.match(r"((?:\n| {4}.*\n)+)", text + "\n").group(1)
    return textwrap.dedent(block)


def test_the_docstring_examples_run():
    exec(compile(_docstring_example(omtp_drake.script.cell), "script/cell.py docstring", "exec"), {})
    with Cell("lecture6_assignment4", auto_spawn=False) as cell:
        cell.spawn_part(xyz=SPOT, yaw=0.0)
        cell.wait(0.5)
        scope = {"cell": cell, "RigidTransform": RigidTransform}
        exec(compile(_docstring_example(omtp_drake.script.scene), "script/scene.py docstring", "exec"), scope)
        assert cell.planning_scene.names() == ["object_1"]
        cell.remove_part("object_1")  # one part at a time in this scenario
        exec(compile(_docstring_example(omtp_drake.script.bins), "script/bins.py docstring", "exec"), scope)
        assert scope["part"] == "object_2" and cell.ledger().parts["object_2"] == "in_bin:bin_1"


def test_the_readme_pick_loop_puts_its_parts_in_the_bin(monkeypatch):
    """The README's own-pick-script example, run as printed (two parts into bin 1)."""
    text = README.read_text().split("## Write your own pick script", 1)[1]
    code = text.split("```python\n", 1)[1].split("```", 1)[0]
    captured = {}
    original = Cell.__exit__

    def keep(self, *exc):
        captured["ledger"] = self.ledger()
        return original(self, *exc)

    monkeypatch.setattr(Cell, "__exit__", keep)
    exec(compile(code, "README.md", "exec"), {})
    ledger = captured["ledger"]
    assert ledger.in_bin["bin_1"] == 2 and ledger.on_floor == 0 and sum(ledger.held.values()) == 0


def test_a_part_in_the_scene_can_still_be_picked(cell):
    """A part added to the scene is an obstacle for moves, but the held part never is."""
    arm, vacuum = cell.arm("robot2"), cell.gripper("robot2")
    arm.go("Home")
    part = cell.spawn_part(xyz=SPOT, yaw=0.0)
    try:
        p = rest(cell, part)
        cell.planning_scene.add_part(part)
        arm.move_to(tool_down(p + [0, 0, 0.2]))
        vacuum.on()
        cell.planning_scene.remove(part)  # the grasp touches it
        arm.move_linear(tool_down(p + [0, 0, 0.08]), speed=0.05, until=lambda: vacuum.attached)
        cell.planning_scene.add_part(part)  # held now: carried, not avoided
        arm.go("Home")
        assert cell.ledger().parts[part] == "held:robot2" and arm.contacts() == []
    finally:
        vacuum.off()
        cell.wait(0.5)
        cell.planning_scene.remove()
        cell.remove_part(part)
