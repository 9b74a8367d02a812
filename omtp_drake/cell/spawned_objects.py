"""The course's conveyor spawner's objects as the cell's parts: the model its plugin
makes of an object (``createObjectURDF``: one link, the object's ``mesh_resource`` as
visual and collision, mass 0.2 kg, inertia 1 kg m^2 about each axis at the link's
origin; :mod:`omtp_drake.scenario.conveyor_spawner`), for Drake's parser.

Drake reads the mesh as ``.obj``: an ``.stl`` (or another format) is converted once into
the model cache, keyed by the file's content. In contact the mesh is its convex hull
(Drake's point contact; Gazebo's ODE collides the triangles themselves); eight 1 mm spheres
at the corners of its bounding box give it the cube parts' four supports on a flat
surface (:mod:`omtp_drake.cell.parts`). An object whose mesh no package has is the
course's box (the cell's 0.2 m cube part): see :mod:`omtp_drake.launch.nodes`.
"""

from __future__ import annotations

import itertools

from omtp_drake.scenario.conveyor_spawner import OBJECT_INERTIA, OBJECT_MASS, SpawnObjectConfig, object_mesh

_CORNER_RADIUS = 0.001


def object_part_urdf(name: str, obj: SpawnObjectConfig) -> str:
    """The URDF of pool part ``name`` built as spawner object ``obj`` (its mesh file set)."""
    mesh, (lo, hi) = object_mesh(obj.mesh_file)
    geometry = f'<geometry><mesh filename="{mesh.resolve().as_uri()}"/></geometry>'
    corners = "".join(
        f'<collision name="corner_{k}"><origin xyz="{x} {y} {z}"/>'
        f'<geometry><sphere radius="{_CORNER_RADIUS}"/></geometry></collision>'
        for k, (x, y, z) in enumerate(itertools.product(*zip(lo, hi)))
    )
    ixx, iyy, izz = OBJECT_INERTIA
    return (
        f'<?xml version="1.0"?><robot name="{name}"><link name="{name}">'
        f'<visual>{geometry}<material name="medium_gray"><color rgba="0.5 0.5 0.5 1.0"/></material></visual>'
        f"<collision>{geometry}</collision>{corners}"
        f'<inertial><mass value="{OBJECT_MASS}"/>'
        f'<inertia ixx="{ixx}" iyy="{iyy}" izz="{izz}" ixy="0" iyz="0" ixz="0"/></inertial>'
        "</link></robot>"
    )
