"""Everything that loaded before the loader was inverted (issue 43) loads the same: every frame of
the built-in scenarios and of the course-layout fixture launches, at t = 0 with the arms at their
initial poses, where it was (1 mm, 1e-3 in each rotation entry).

``tests/golden/frames_before.json`` was recorded from main at 32fbe6a (the last landing before the
loader's inversion) by looking up ``X_WF`` of every frame the tf buffer names; a frame may be added
(a world's own model, say), none may move or vanish.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from omtp_drake.launch.options import chosen_cell
from omtp_drake.sim.runtime import runtime_at
from omtp_drake.sim.tf import TfBuffer

ROOT = Path(__file__).resolve().parents[1]
BEFORE = json.loads((ROOT / "tests/golden/frames_before.json").read_text())
WORKSPACE = ROOT / "tests/fixtures/catkin_ws/src"


def _scenario(case: str):
    kind, _, name = case.partition(":")
    if kind == "launch":
        return chosen_cell(launch=name, workspace=[WORKSPACE]).scenario
    return case


@pytest.mark.parametrize("case", sorted(BEFORE))
def test_frames_where_they_were(case: str) -> None:
    runtime = runtime_at(_scenario(case), 0.0)
    try:
        tf = TfBuffer.from_context(runtime.station, runtime.context)
        names = set(tf.all_frame_names())
        missing = sorted(set(BEFORE[case]) - names)
        assert not missing, f"{case}: frames gone: {missing}"
        for frame, X_before in BEFORE[case].items():
            X_WF = np.asarray(tf.lookup_transform("world", frame).transform.GetAsMatrix4())
            X_before = np.asarray(X_before)
            moved = np.linalg.norm(X_WF[:3, 3] - X_before[:3, 3])
            assert moved < 1e-3, f"{case}: {frame} moved {moved * 1000:.2f} mm"
            assert np.abs(X_WF[:3, :3] - X_before[:3, :3]).max() < 1e-3, f"{case}: {frame} turned"
    finally:
        runtime.close()
