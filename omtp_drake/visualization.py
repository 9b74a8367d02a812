"""Meshcat: live views and standalone HTML replays of a simulation."""

from __future__ import annotations

import logging
from pathlib import Path
from typing import Sequence

from pydrake.geometry import Meshcat, MeshcatVisualizer

_log = logging.getLogger(__name__)

#: Default eye and target of the Meshcat camera (world): the whole cell, from
#: beside the conveyor, looking toward robot 2 and bin 1.
DEFAULT_VIEW = ((4.0, 5.5, 4.5), (-3.0, -0.5, 0.5))


def start_meshcat(view: tuple[Sequence[float], Sequence[float]] = DEFAULT_VIEW) -> Meshcat:
    """Starts Drake's Meshcat server (localhost) and aims its camera at ``view``."""
    meshcat = Meshcat()
    eye, target = view
    meshcat.SetCameraPose(list(eye), list(target))
    _log.info("Meshcat is at %s", meshcat.web_url())
    return meshcat


def start_recording(visualizer: MeshcatVisualizer) -> None:
    """Records every published frame for a replay (no live updates meanwhile)."""
    visualizer.StartRecording(set_transforms_while_recording=False)


def save_recording(visualizer: MeshcatVisualizer, meshcat: Meshcat, path: str | Path) -> Path:
    """Ends the recording and writes a standalone HTML replay to ``path``."""
    visualizer.StopRecording()
    visualizer.PublishRecording()
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(meshcat.StaticHtml())
    _log.info("replay written to %s (%.1f MB)", path, path.stat().st_size / 1e6)
    return path
