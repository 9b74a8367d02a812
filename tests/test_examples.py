"""The course's scripts in examples/, written on the scripting layer, run to their outcomes
(shortened with --parts where they loop)."""

import runpy
from pathlib import Path

import numpy as np
import pytest

EXAMPLES = Path(__file__).resolve().parent.parent / "examples"


def run_example(name, *args):
    main = runpy.run_path(str(EXAMPLES / f"{name}.py"))["main"]
    return main(list(args))


def test_every_example_is_tested():
    assert sorted(p.stem for p in EXAMPLES.glob("*.py")) == sorted(
        [
            "transform_object_pose",
            "lecture6_assignment3",
            "lecture6_assignment4",
            "lecture7_pick",
            "fill_a_bin",
        ]
    )


def test_transform_object_pose_puts_the_part_where_it_is(capsys):
    out = run_example("transform_object_pose")
    np.testing.assert_allclose(out["p_W"], out["truth"], atol=2e-3)
    np.testing.assert_allclose(out["p_W"], [1.2, 1.8, 1.021], atol=2e-3)  # the course's value
    assert "in world: (1.200, 1.800, 1.021)" in capsys.readouterr().out


def test_assignment3_part_in_the_suction_cup_frame():
    out = run_example("lecture6_assignment3")
    np.testing.assert_allclose(out["X_SP"].translation(), out["truth"].translation(), atol=2e-3)
    angle = out["X_SP"].rotation().InvertAndCompose(out["truth"].rotation()).ToAngleAxis().angle()
    assert angle < 0.01


@pytest.mark.parametrize(
    "name, args, bin_name, parts",
    [
        ("lecture6_assignment4", ["--parts", "1"], "bin_1", 1),
        ("lecture7_pick", ["--parts", "1"], "bin_2", 1),
        ("fill_a_bin", ["--parts", "2"], "bin_1", 2),
    ],
)
def test_pick_scripts_put_the_parts_in_the_bin(name, args, bin_name, parts):
    ledger = run_example(name, *args)["ledger"]
    assert ledger.in_bin[bin_name] == parts and ledger.balanced
    assert sum(ledger.held.values()) == 0 and ledger.disposed == 0
