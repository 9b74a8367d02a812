"""The course's logical camera housing as Collada, in its layout
(``omtp_gazebo/models/logical_camera{1,2}/meshes/camera.dae``), written here (never the
course's file): a body and a lens of the course mesh's size, in millimetres as the course's
file is (``<unit meter="0.001">``).

The course's ``camera.dae`` spans 79.4 x 57.9 x 128.1 mm about its origin (x -39.7..39.7,
y -38.1..19.7, z -67.8..60.3, its node's offset applied); its ``model.sdf`` places it at
``0 0.02 0`` turned ``-1.5708`` about z in the camera's link, for its visual and its
collision alike. ``python tests/camera_meshes.py`` rewrites the course-layout fixtures'.
"""

from __future__ import annotations

import re
from pathlib import Path

#: The course mesh's bounds (mm): (x, y, z) lows and highs.
LOW = (-39.7, -38.1, -67.8)
HIGH = (39.7, 19.7, 60.3)
#: The lens: its length along the mesh's +y (the camera's front once turned) and radius (mm).
LENS = (10.0, 20.0)


def camera_mesh():
    """The housing: a box body, the lens a cylinder in front of it along +y (mm)."""
    import numpy as np
    import trimesh

    length, radius = LENS
    body = trimesh.creation.box(bounds=[LOW, [HIGH[0], HIGH[1] - length, HIGH[2]]])
    lens = trimesh.creation.cylinder(radius=radius, height=length, sections=24)
    lens.apply_transform(trimesh.transformations.rotation_matrix(-np.pi / 2, [1, 0, 0]))
    lens.apply_translation([0.0, HIGH[1] - length / 2, 0.0])
    return body + lens


def write_camera_mesh(path: Path) -> None:
    """``camera.dae`` at ``path``, in millimetres, z up."""
    import trimesh

    text = trimesh.exchange.dae.export_collada(camera_mesh()).decode()
    text = re.sub(
        r"<up_axis>\w+</up_axis>",
        '<unit name="millimeter" meter="0.001"/>\n    <up_axis>Z_UP</up_axis>',
        text,
    )
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(text)


def without_cameras(scenario, **changes):
    """``scenario`` (changed by ``changes``) without its logical cameras, and so without the
    housings its world's camera models hang on their frames (model entries whose parent
    is a camera's frame): what a test that needs no camera runs, faster."""
    import dataclasses

    frames = {f"{c.name}_frame" for c in scenario.cameras}
    models = [m for m in scenario.models if m.parent not in frames]
    return dataclasses.replace(scenario, cameras=[], models=models, **changes)


if __name__ == "__main__":
    fixtures = Path(__file__).resolve().parent / "fixtures"
    for ws in ("catkin_ws", "group_ws"):
        for camera in ("logical_camera1", "logical_camera2"):
            write_camera_mesh(
                fixtures / ws / "src" / "omtp_gazebo" / "models" / camera / "meshes" / "camera.dae"
            )
