"""The course's bin meshes as Collada, in its layout (``visual/bin.dae``,
``collision/bin_bottom.dae`` + ``bin_sides.dae``), written here (never the course's files):
a floor plate and an open ring of walls around it, of the sizes asked for.

``python tests/bin_meshes.py`` rewrites the meshes of the course-layout fixtures
(``tests/fixtures/{catkin_ws,group_ws}/src/omtp_support/meshes/bin``): the catalogue's bin
(``models/bin.urdf.xacro``: 0.40 m outside, 1 cm walls, its floor's top at 0.12 m, 0.475 m
high) before the course xacro's scale of 0.6.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

#: The course xacro's ``scale`` of its bin meshes.
COURSE_SCALE = 0.6


def _ring(outer: np.ndarray, inner: np.ndarray, z0: float, z1: float):
    """A closed solid: the rectangle of half lengths ``outer`` less ``inner``, from z0 to z1."""
    import trimesh

    def rect(h, z):
        return [[-h[0], -h[1], z], [h[0], -h[1], z], [h[0], h[1], z], [-h[0], h[1], z]]

    vertices = rect(outer, z0) + rect(outer, z1) + rect(inner, z1) + rect(inner, z0)
    faces = []
    for i in range(4):
        j = (i + 1) % 4
        for a, b in ((0, 4), (4, 8), (8, 12), (12, 0)):  # outer side, rim, inner side, under the rim
            faces += [[a + i, a + j, b + j], [a + i, b + j, b + i]]
    mesh = trimesh.Trimesh(vertices, faces)
    mesh.fix_normals()
    return mesh


def write_bin_meshes(
    folder: Path, outer=(0.5, 0.4), wall: float = 1 / 30, floor: float = 1 / 12, height: float = 2 / 3
) -> None:
    """The three meshes in ``folder``: ``outer`` half lengths, ``wall`` thick walls on a
    ``floor`` thick plate, ``height`` high (in the mesh's units, before any scale)."""
    import trimesh

    outer = np.asarray(outer, dtype=float)
    bottom = trimesh.creation.box(bounds=[[-outer[0], -outer[1], 0.0], [outer[0], outer[1], floor]])
    sides = _ring(outer, outer - wall, floor, height)
    for name, mesh in (
        ("collision/bin_bottom", bottom),
        ("collision/bin_sides", sides),
        ("visual/bin", bottom + sides),
    ):
        (folder / name).parent.mkdir(parents=True, exist_ok=True)
        (folder / f"{name}.dae").write_bytes(trimesh.exchange.dae.export_collada(mesh))


def write_catalogue_sized(folder: Path) -> None:
    """The catalogue bin's sizes, divided by the course's scale."""
    s = COURSE_SCALE
    write_bin_meshes(folder, outer=(0.2 / s, 0.2 / s), wall=0.01 / s, floor=0.12 / s, height=0.475 / s)


if __name__ == "__main__":
    fixtures = Path(__file__).resolve().parent / "fixtures"
    for ws in ("catkin_ws", "group_ws"):
        write_catalogue_sized(fixtures / ws / "src" / "omtp_support" / "meshes" / "bin")
