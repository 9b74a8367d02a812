"""A mesh as convex pieces that keep it open (omtp_drake.convex_pieces): a bin made as one
closed solid, as open surfaces either way round, finely meshed; and the pieces' cache."""

from __future__ import annotations

import numpy as np
import pytest

from omtp_drake.convex_pieces import PIECE_DEPTH, axis_box, convex_pieces, ray_distance

#: A cup (one closed solid): 0.6 x 0.4 outside, 2 cm walls, a 5 cm floor, 0.4 high.
OUTER, INNER, FLOOR, RIM = (0.3, 0.2), (0.28, 0.18), 0.05, 0.4


def _rect(h, z):
    return [[-h[0], -h[1], z], [h[0], -h[1], z], [h[0], h[1], z], [-h[0], h[1], z]]


def cup() -> tuple[np.ndarray, np.ndarray]:
    """Its bottom, outer sides, rim, inner sides and the floor's top, outward normals."""
    vertices = _rect(OUTER, 0) + _rect(OUTER, RIM) + _rect(INNER, RIM) + _rect(INNER, FLOOR)
    faces = [[0, 3, 2], [0, 2, 1], [12, 13, 14], [12, 14, 15]]
    for i in range(4):
        j = (i + 1) % 4
        for a, b in ((0, 4), (4, 8), (8, 12)):
            faces += [[a + i, a + j, b + j], [a + i, b + j, b + i]]
    return np.array(vertices, float), np.array(faces)


def _containing(pieces, p) -> list[int]:
    """The pieces whose convex hull holds the point ``p`` (each hull's faces computed once)."""
    from scipy.spatial import ConvexHull  # (here: scipy and trimesh cost each xdist worker ~1.8 s
    #  CPU at collection; only the worker that runs these tests needs them)

    if _HULLS.get("pieces") is not pieces:  # (held here, so a new list is never taken for it)
        _HULLS.update(pieces=pieces, faces=[ConvexHull(points).equations for points in pieces])
    return [k for k, faces in enumerate(_HULLS["faces"]) if np.all(faces[:, :3] @ p + faces[:, 3] <= 1e-9)]


_HULLS: dict = {}


@pytest.mark.parametrize("winding", ["outward", "inward", "mixed"])
def test_a_closed_cup_is_its_skin_its_inside_stays_open(winding):
    vertices, faces = cup()
    if winding == "inward":
        faces = faces[:, ::-1]
    elif winding == "mixed":  # (as some exporters leave them: no consistent side)
        faces = faces.copy()
        faces[::3] = faces[::3, ::-1]
    pieces = convex_pieces(vertices, faces, max_depth=PIECE_DEPTH)
    for p in ([0, 0, 0.2], [0.27, 0, 0.3], [0, 0.17, 0.06], [0, 0, 0.39]):
        assert not _containing(pieces, p), p  # the cavity: no piece
    for p in ([0, 0, 0.03], [0.29, 0, 0.2], [0, -0.19, 0.35], [0.29, 0.19, 0.399], [0.29, 0.19, 0.01]):
        assert _containing(pieces, p), p  # the floor, the walls, the rim's corner
    # No piece reaches out of the solid (the cup's outside).
    points = np.vstack(pieces)
    assert np.all(np.abs(points[:, 0]) <= OUTER[0] + 1e-9) and np.all(np.abs(points[:, 1]) <= OUTER[1] + 1e-9)
    assert points[:, 2].min() >= -1e-9 and points[:, 2].max() <= RIM + 1e-9


def test_a_finely_meshed_cup_is_the_same_skin():
    vertices, faces = cup()
    import trimesh

    vertices, faces = trimesh.remesh.subdivide(vertices, faces)
    pieces = convex_pieces(vertices, faces, max_depth=PIECE_DEPTH)
    assert not _containing(pieces, [0, 0, 0.2]) and not _containing(pieces, [-0.27, 0.1, 0.3])
    assert _containing(pieces, [0, 0, 0.03]) and _containing(pieces, [-0.29, 0.1, 0.3])


@pytest.mark.parametrize("flip", [False, True])
def test_open_surfaces_are_thickened_outwards_either_way_round(flip):
    """The inner sides and the floor only (no thickness): slabs ``PIECE_DEPTH`` deep on the
    side away from the mesh's centre, whichever way its triangles face."""
    vertices, faces = cup()
    faces = np.array([f for f in faces if min(f) >= 8])
    pieces = convex_pieces(vertices, faces[:, ::-1] if flip else faces, max_depth=PIECE_DEPTH)
    assert not _containing(pieces, [0, 0, 0.2]) and not _containing(pieces, [0.275, 0, 0.3])
    assert _containing(pieces, [0.28 + PIECE_DEPTH / 2, 0, 0.3]) and _containing(pieces, [0, 0, 0.03])


def test_a_closed_box_is_one_piece_and_an_axis_box():
    import trimesh

    box = trimesh.creation.box(bounds=[[-0.3, -0.2, 0], [0.3, 0.2, 0.05]])
    (piece,) = convex_pieces(box.vertices, box.faces, max_depth=0.01)
    centre, size = axis_box(piece)
    np.testing.assert_allclose(centre, [0, 0, 0.025], atol=1e-12)
    np.testing.assert_allclose(size, [0.6, 0.4, 0.05])
    assert axis_box(np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1.0]])) is None  # a tetrahedron


def test_a_ray_meets_the_nearest_triangle_in_front():
    triangles = np.array([[[-1, -1, 1], [1, -1, 1], [0, 1, 1]], [[-1, -1, 3], [1, -1, 3], [0, 1, 3]]], float)
    assert ray_distance(triangles, [0, 0, 0], [0, 0, 1]) == pytest.approx(1.0)
    assert ray_distance(triangles, [0, 0, 2], [0, 0, 1]) == pytest.approx(1.0)
    assert ray_distance(triangles, [0, 0, 4], [0, 0, 1]) is None
    assert ray_distance(triangles, [5, 0, 0], [0, 0, 1]) is None


def test_the_pieces_are_cut_once_and_cached_by_the_meshs_content(tmp_path, monkeypatch):
    from omtp_drake import assets
    from omtp_drake import convex_pieces as module

    monkeypatch.setenv("OMTP_DRAKE_CACHE", str(tmp_path / "cache"))
    mesh = tmp_path / "cup.obj"
    import trimesh

    mesh.write_text(trimesh.Trimesh(*cup()).export(file_type="obj"))
    first = assets.convex_piece_files(mesh)
    assert len(first) > 5 and all(path.is_file() for path, _ in first)
    assert sum(1 for _, box in first if box) >= 5  # (the floor and walls' slabs are boxes)
    copy = tmp_path / "elsewhere.obj"
    copy.write_bytes(mesh.read_bytes())

    def never(*args):
        raise AssertionError("cut again")

    monkeypatch.setattr(module, "write_pieces", never)
    assert assets.convex_piece_files(copy) == first


def test_open_links_name_links_of_the_model():
    from omtp_drake.errors import UnknownNameError
    from omtp_drake.scenario import ModelConfig

    text = '<robot name="b"><link name="b_base_link"/></robot>'
    ModelConfig(name="b", file="b.urdf", description=text, open_links=["b_base_link"]).validate()
    with pytest.raises(UnknownNameError, match=r"open_links 'b_link'; valid: b_base_link"):
        ModelConfig(name="b", file="b.urdf", description=text, open_links=["b_link"]).validate()
