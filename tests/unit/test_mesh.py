"""Tests of radscene.geometry.mesh and radscene.geometry.primitives."""

import numpy as np
import pytest
import trimesh

from radscene.errors import ConfigError
from radscene.geometry import (
    GLTF_TO_ENU,
    Mesh,
    box,
    concatenate,
    cylinder,
    load_mesh,
    plate,
    rotation_matrix,
)

EXACT = 1e-12  # [m] or [-], rounding of a few double operations


def _triangle():
    return Mesh([[0.0, 0.0, 0.0], [3.0, 0.0, 0.0], [0.0, 4.0, 0.0]], [[0, 1, 2]], name="tri")


def _volume(mesh):
    """Signed volume by the divergence theorem (positive for outward winding) [m3]."""
    v0, v1, v2 = (mesh.vertices[mesh.faces[:, k]] for k in range(3))
    return float(np.einsum("ij,ij->i", v0, np.cross(v1, v2)).sum() / 6.0)


def _closed_and_consistent(mesh):
    """Every directed edge appears once and its reverse once (closed, consistently wound)."""
    f = mesh.faces
    edges = np.concatenate([f[:, [0, 1]], f[:, [1, 2]], f[:, [2, 0]]])
    directed = {tuple(e) for e in edges}
    return len(directed) == len(edges) and all((b, a) in directed for a, b in directed)


# -- rotation convention ---------------------------------------------------------------------


def test_yaw_90_turns_north_into_east():
    north = np.array([0.0, 1.0, 0.0])
    assert rotation_matrix(90.0) @ north == pytest.approx([1.0, 0.0, 0.0], abs=EXACT)
    assert rotation_matrix(180.0) @ north == pytest.approx([0.0, -1.0, 0.0], abs=EXACT)
    assert rotation_matrix(-90.0) @ north == pytest.approx([-1.0, 0.0, 0.0], abs=EXACT)


def test_pitch_raises_forward_axis_and_roll_lowers_right_side():
    s, c = np.sin(np.radians(30.0)), np.cos(np.radians(30.0))
    assert rotation_matrix(0.0, 30.0) @ [0, 1, 0] == pytest.approx([0, c, s], abs=EXACT)
    assert rotation_matrix(0.0, 0.0, 30.0) @ [1, 0, 0] == pytest.approx([c, 0, -s], abs=EXACT)
    # Roll does not move the forward axis.
    assert rotation_matrix(0.0, 0.0, 30.0) @ [0, 1, 0] == pytest.approx([0, 1, 0], abs=EXACT)


def test_rotation_order_is_yaw_then_pitch_then_roll():
    # yaw 90 then pitch 45: forward points east and 45 deg up.
    h = np.sqrt(0.5)
    assert rotation_matrix(90.0, 45.0) @ [0, 1, 0] == pytest.approx([h, 0, h], abs=EXACT)
    # pitch 90 (forward up, body up south), then roll 90: the right axis turns to north.
    assert rotation_matrix(0.0, 90.0, 90.0) @ [1, 0, 0] == pytest.approx([0, 1, 0], abs=EXACT)


def test_rotation_matrix_is_proper_and_broadcasts():
    rng = np.random.default_rng(1)
    angles = rng.uniform(-180, 180, (3, 4, 5))
    r = rotation_matrix(angles[0], angles[1], angles[2])
    assert r.shape == (4, 5, 3, 3)
    assert r @ np.swapaxes(r, -1, -2) == pytest.approx(np.broadcast_to(np.eye(3), r.shape),
                                                       abs=EXACT)
    assert np.linalg.det(r) == pytest.approx(np.ones((4, 5)), abs=EXACT)


# -- Mesh ------------------------------------------------------------------------------------


def test_transformed_scales_then_rotates_then_translates():
    m = Mesh([[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]], [[0, 1, 2]], name="m")
    out = m.transformed(translation=(10.0, 0.0, 5.0), rotation=(90.0, 0.0, 0.0), scale=2.0)
    # east rotated clockwise by 90 deg is south
    assert out.vertices == pytest.approx(np.array([[10, -2, 5], [12, 0, 5], [10, 0, 7]]), abs=EXACT)
    assert out.name == "m"
    assert np.array_equal(out.faces, m.faces)
    assert m.vertices[0] == pytest.approx([1, 0, 0], abs=0.0)  # original untouched


def test_transformed_per_axis_scale_keeps_outward_normals():
    b = box((1.0, 1.0, 1.0)).transformed(scale=(2.0, 3.0, 4.0), rotation=(30.0, 10.0, 5.0))
    assert _volume(b) == pytest.approx(24.0, rel=1e-12)


@pytest.mark.parametrize(
    ("kwargs", "key"),
    [({"scale": 0.0}, "scale"), ({"scale": (1.0, -1.0, 1.0)}, "scale"),
     ({"rotation": (1.0, 2.0)}, "rotation"), ({"translation": (0.0, np.nan, 0.0)}, "translation")],
)
def test_transformed_rejects_bad_arguments(kwargs, key):
    with pytest.raises(ConfigError, match=key):
        _triangle().transformed(**kwargs)


def test_bounds_normals_and_area_of_a_triangle():
    m = _triangle()
    lo, hi = m.bounds
    assert lo == pytest.approx([0, 0, 0], abs=0.0)
    assert hi == pytest.approx([3, 4, 0], abs=0.0)
    assert m.face_normals == pytest.approx(np.array([[0, 0, 1]]), abs=EXACT)
    assert m.area == pytest.approx([6.0], rel=EXACT)


def test_degenerate_face_has_zero_normal():
    m = Mesh([[0, 0, 0], [1, 0, 0], [2, 0, 0]], [[0, 1, 2]])
    assert m.face_normals == pytest.approx(np.array([[0, 0, 0]]), abs=0.0)
    assert m.area == pytest.approx([0.0], abs=0.0)


def test_concatenate_offsets_faces():
    a, b = _triangle(), _triangle().transformed(translation=(0, 0, 1))
    c = concatenate([a, b], name="both")
    assert len(c.vertices) == 6 and c.name == "both"
    assert np.array_equal(c.faces, [[0, 1, 2], [3, 4, 5]])
    assert c.area == pytest.approx([6.0, 6.0], rel=EXACT)
    assert len(concatenate([]).faces) == 0


@pytest.mark.parametrize(
    ("vertices", "faces", "match"),
    [([[0, 0], [1, 1]], [[0, 1, 1]], r"vertices must have shape \(N, 3\)"),
     ([[0, 0, np.nan], [1, 0, 0], [0, 1, 0]], [[0, 1, 2]], "1 vertices are not finite"),
     ([[0, 0, 0], [1, 0, 0], [0, 1, 0]], [[0, 1, 3]], r"face indices must lie in \[0, 2\]"),
     ([[0, 0, 0], [1, 0, 0], [0, 1, 0]], [[0.0, 1.0, 2.0]], "must be integer")],
)
def test_mesh_rejects_bad_arrays(vertices, faces, match):
    with pytest.raises(ConfigError, match=match):
        Mesh(vertices, faces)


# -- primitives ------------------------------------------------------------------------------


def test_box_faces_point_away_from_its_centre():
    b = box((2.0, 4.0, 6.0))
    centroid = b.vertices.mean(axis=0)
    face_centres = b.vertices[b.faces].mean(axis=1)
    outward = np.einsum("ij,ij->i", b.face_normals, face_centres - centroid)
    assert (outward > 0).all()
    assert centroid == pytest.approx([0, 0, 3], abs=EXACT)
    assert b.bounds[0] == pytest.approx([-1, -2, 0], abs=0.0)
    assert _volume(b) == pytest.approx(48.0, rel=EXACT)
    assert b.area.sum() == pytest.approx(2 * (8 + 12 + 24), rel=EXACT)
    assert _closed_and_consistent(b)


def test_box_side_order_is_documented_order():
    n = box((1.0, 1.0, 1.0)).face_normals[::2]
    expected = [[0, 0, -1], [0, 0, 1], [0, -1, 0], [0, 1, 0], [-1, 0, 0], [1, 0, 0]]
    assert n == pytest.approx(np.array(expected), abs=EXACT)


def test_cylinder_volume_area_and_winding():
    r, h, n = 2.0, 5.0, 24
    c = cylinder(r, h, sections=n)
    polygon_area = 0.5 * n * r**2 * np.sin(2 * np.pi / n)  # regular n-gon in the circle
    assert _volume(c) == pytest.approx(polygon_area * h, rel=1e-12)
    side = 2 * n * r * np.sin(np.pi / n) * h
    assert c.area.sum() == pytest.approx(side + 2 * polygon_area, rel=1e-12)
    assert _closed_and_consistent(c)
    centres = c.vertices[c.faces].mean(axis=1)
    axis_to_face = centres - np.array([0, 0, h / 2])
    assert (np.einsum("ij,ij->i", c.face_normals, axis_to_face) > 0).all()


def test_plate_is_flat_facing_up():
    p = plate(3.0, 2.0)
    assert p.face_normals == pytest.approx(np.array([[0, 0, 1], [0, 0, 1]]), abs=EXACT)
    assert p.area.sum() == pytest.approx(6.0, rel=EXACT)
    assert p.bounds[1] == pytest.approx([1.5, 1.0, 0.0], abs=0.0)


@pytest.mark.parametrize(
    ("make", "match"),
    [(lambda: box((1.0, 0.0, 1.0)), r"size\[1\]"), (lambda: box((1.0, 2.0)), "size"),
     (lambda: cylinder(-1.0, 1.0), "radius"), (lambda: cylinder(1.0, np.inf), "height"),
     (lambda: cylinder(1.0, 1.0, sections=2), "sections"),
     (lambda: plate(0.0, 1.0), "width"), (lambda: plate(1.0, -2.0), "length")],
)
def test_primitives_reject_non_positive_sizes(make, match):
    with pytest.raises(ConfigError, match=match):
        make()


# -- loading ---------------------------------------------------------------------------------


@pytest.mark.parametrize("suffix", ["obj", "ply", "stl"])
def test_load_mesh_z_up_formats_keep_coordinates(tmp_path, suffix):
    source = box((2.0, 3.0, 4.0)).transformed(translation=(5.0, 6.0, 7.0))
    path = tmp_path / f"thing.{suffix}"
    trimesh.Trimesh(source.vertices, source.faces).export(path)
    m = load_mesh(path)
    assert m.name == "thing"
    assert m.bounds[0] == pytest.approx([4.0, 4.5, 7.0], abs=1e-6)
    assert m.bounds[1] == pytest.approx([6.0, 7.5, 11.0], abs=1e-6)
    assert _volume(m) == pytest.approx(24.0, rel=1e-6)


def test_load_gltf_converts_y_up_to_z_up(tmp_path):
    # In glTF coordinates: a triangle whose tip points +Y (up), offset to +Z (front).
    gl = trimesh.Trimesh([[0, 0, 5], [1, 0, 5], [0, 2, 5]], [[0, 1, 2]], process=False)
    path = tmp_path / "tip.glb"
    gl.export(path)
    m = load_mesh(path, name="tip")
    assert m.name == "tip"
    expected = np.array([[0, 0, 5], [1, 0, 5], [0, 2, 5]], dtype=float) @ GLTF_TO_ENU.T
    assert m.vertices == pytest.approx(expected, abs=1e-6)
    assert expected[2] == pytest.approx([0, 5, 2], abs=0.0)  # up is +z, front is north


def test_load_gltf_scene_applies_node_transforms(tmp_path):
    scene = trimesh.Scene()
    part = trimesh.creation.box(extents=(1.0, 1.0, 1.0))
    for offset in ((10.0, 0.0, 0.0), (0.0, 0.0, 20.0)):  # glTF +X and glTF +Z (front)
        transform = np.eye(4)
        transform[:3, 3] = offset
        scene.add_geometry(part, transform=transform)
    path = tmp_path / "two.glb"
    scene.export(path)
    m = load_mesh(path)
    assert len(m.faces) == 24
    # glTF +X is west (-x), glTF +Z is north (+y).
    assert m.bounds[0] == pytest.approx([-10.5, -0.5, -0.5], abs=1e-6)
    assert m.bounds[1] == pytest.approx([0.5, 20.5, 0.5], abs=1e-6)


def test_load_mesh_errors(tmp_path):
    with pytest.raises(ConfigError, match="not found.*nowhere.obj"):
        load_mesh(tmp_path / "nowhere.obj")
    empty = tmp_path / "empty.obj"
    empty.write_text("# nothing here\n")
    with pytest.raises(ConfigError, match="no triangles"):
        load_mesh(empty)
    odd = tmp_path / "thing.xyz123"
    odd.write_text("1 2 3\n")
    with pytest.raises(ConfigError, match="unknown mesh format.*accepted: .glb"):
        load_mesh(odd)
