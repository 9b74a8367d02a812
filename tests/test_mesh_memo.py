"""The mesh facts' memo (cell/body_geometry.per_mesh_file): computed once per mesh file
and scale, kept on disk for the next process, computed again when the file changes."""

from __future__ import annotations

import os

import numpy as np
import pytest
from pydrake.geometry import GeometryFrame, GeometryInstance, Mesh, SceneGraph
from pydrake.math import RigidTransform

from omtp_drake.cell import body_geometry

#: A tetrahedron, 0.1 m along each axis.
TETRAHEDRON = """v 0 0 0
v 0.1 0 0
v 0 0.1 0
v 0 0 0.1
f 1 3 2
f 1 2 4
f 1 4 3
f 2 3 4
"""


@pytest.fixture
def mesh_geometry(tmp_path, monkeypatch):
    """An inspector, and the id of a Mesh geometry from a file in ``tmp_path``; the
    cache folder in ``tmp_path`` and the process memo empty."""
    monkeypatch.setenv("OMTP_DRAKE_CACHE", str(tmp_path / "cache"))
    monkeypatch.setattr(body_geometry, "_MESH_MEMO", {})
    path = tmp_path / "part.obj"
    path.write_text(TETRAHEDRON)
    scene_graph = SceneGraph()
    source = scene_graph.RegisterSource("test")
    frame = scene_graph.RegisterFrame(source, GeometryFrame("part"))
    geometry = scene_graph.RegisterGeometry(
        source, frame, GeometryInstance(RigidTransform(), Mesh(str(path)), "part")
    )
    return scene_graph.model_inspector(), geometry, path


def test_mesh_facts_are_computed_once_then_read_from_disk(mesh_geometry, monkeypatch):
    inspector, geometry, _ = mesh_geometry
    calls = []

    def compute():
        calls.append(1)
        return np.array([1.0, 2.0, 3.0])

    first = body_geometry.per_mesh_file("test", inspector, geometry, compute)
    again = body_geometry.per_mesh_file("test", inspector, geometry, compute)
    assert len(calls) == 1 and again is first
    monkeypatch.setattr(body_geometry, "_MESH_MEMO", {})  # as a new process
    from_disk = body_geometry.per_mesh_file("test", inspector, geometry, compute)
    assert len(calls) == 1
    np.testing.assert_array_equal(from_disk, [1.0, 2.0, 3.0])


def test_a_changed_mesh_is_computed_again(mesh_geometry, monkeypatch):
    inspector, geometry, path = mesh_geometry
    body_geometry.per_mesh_file("test", inspector, geometry, lambda: "old")
    path.write_text(TETRAHEDRON + "v 0.2 0.2 0.2\n")
    os.utime(path, ns=(path.stat().st_atime_ns, path.stat().st_mtime_ns + 10**9))
    monkeypatch.setattr(body_geometry, "_MESH_MEMO", {})
    assert body_geometry.per_mesh_file("test", inspector, geometry, lambda: "new") == "new"


def test_the_obb_from_disk_equals_drakes(mesh_geometry, monkeypatch):
    inspector, geometry, _ = mesh_geometry
    computed = body_geometry.oriented_bounding_box(inspector, geometry)
    monkeypatch.setattr(body_geometry, "_MESH_MEMO", {})
    from_disk = body_geometry.oriented_bounding_box(inspector, geometry)
    assert from_disk is not computed
    np.testing.assert_allclose(from_disk.half_width(), inspector.GetObbInGeometryFrame(geometry).half_width())
    assert from_disk.pose().IsExactlyEqualTo(computed.pose())


def test_a_corrupt_entry_is_computed_again(mesh_geometry, monkeypatch, tmp_path):
    inspector, geometry, _ = mesh_geometry
    body_geometry.per_mesh_file("test", inspector, geometry, lambda: "value")
    (entry,) = (tmp_path / "cache").glob("models-*/mesh_facts/test-*.pickle")
    entry.write_bytes(b"not a pickle")
    monkeypatch.setattr(body_geometry, "_MESH_MEMO", {})
    assert body_geometry.per_mesh_file("test", inspector, geometry, lambda: "again") == "again"
