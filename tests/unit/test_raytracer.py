"""Tests of radscene.geometry.raytracer (Embree through embreex)."""

import numpy as np
import pytest

from radscene.errors import ConfigError
from radscene.geometry import Mesh, RayTracer, box, plate, procedural_terrain

# Distances come back as float64 = (box-entry advance, float64) + (Embree tfar, float32 over
# at most the scene's size), so for scenes of <= 1 km they are good to well under a millimetre.
DIST_TOL = 1e-4  # [m] for the small test scenes
FAR_TOL = 0.01  # [m], the 1 cm required for an observer 700 km away


def test_plane_hit_at_the_right_distance_position_and_normal():
    rt = RayTracer([plate(100.0, 100.0)])
    origins = np.array([[1.0, 2.0, 10.0], [0.0, 0.0, 10.0]])
    directions = np.array([[0.0, 0.0, -3.0], [1.0, 0.0, -1.0]])  # not unit on purpose
    hits = rt.intersect(origins, directions)
    assert hits.hit.tolist() == [True, True]
    assert hits.distance == pytest.approx([10.0, 10.0 * np.sqrt(2.0)], abs=DIST_TOL)
    assert hits.position == pytest.approx(np.array([[1.0, 2.0, 0.0], [10.0, 0.0, 0.0]]),
                                          abs=DIST_TOL)
    assert hits.normal == pytest.approx(np.array([[0, 0, 1.0], [0, 0, 1.0]]), abs=1e-12)
    assert hits.object.tolist() == [0, 0] and hits.object.dtype == np.int32
    assert hits.distance.dtype == np.float64 and hits.u.dtype == np.float32


def test_barycentrics_and_primitive_locate_the_hit_point():
    b = box((4.0, 6.0, 2.0)).transformed(translation=(1.0, -2.0, 0.5), rotation=(30, 0, 0))
    rt = RayTracer([b])
    rng = np.random.default_rng(5)
    origins = rng.uniform(-20, 20, (200, 3)) + np.array([0.0, 0.0, 30.0])
    targets = rng.uniform(-1, 1, (200, 3)) + np.array([1.0, -2.0, 1.5])
    hits = rt.intersect(origins, targets - origins)
    assert hits.hit.all()
    v0, v1, v2 = (b.vertices[b.faces[hits.primitive, k]] for k in range(3))
    u, v = hits.u[:, None].astype(float), hits.v[:, None].astype(float)
    on_face = (1 - u - v) * v0 + u * v1 + v * v2
    assert on_face == pytest.approx(hits.position, abs=DIST_TOL)
    assert hits.normal == pytest.approx(b.face_normals[hits.primitive], abs=1e-12)


def test_object_ids_follow_mesh_order_even_with_empty_meshes():
    empty = Mesh(np.zeros((0, 3)), np.zeros((0, 3), dtype=int), name="nothing")
    scene = [plate(10.0, 10.0), empty, box((2.0, 2.0, 2.0)).transformed(translation=(20, 0, 0))]
    rt = RayTracer(scene)
    hits = rt.intersect([[0.0, 0.0, 5.0], [20.0, 0.0, 5.0]], [0.0, 0.0, -1.0])
    assert hits.object.tolist() == [0, 2]
    assert hits.distance == pytest.approx([5.0, 3.0], abs=DIST_TOL)
    assert rt.bounds[0] == pytest.approx([-5, -5, 0], abs=0.0)
    assert rt.bounds[1] == pytest.approx([21, 5, 2], abs=0.0)


def test_misses_are_marked():
    rt = RayTracer([box((2.0, 2.0, 2.0))])
    origins = [[0.0, 0.0, 5.0], [5.0, 5.0, 5.0], [0.0, 0.0, 5.0], [3.0, 0.0, 1.0]]
    directions = [[0.0, 0.0, 1.0], [0.0, 0.0, -1.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]
    hits = rt.intersect(origins, directions)
    assert not hits.hit.any()
    assert np.isinf(hits.distance).all() and (hits.object == -1).all()
    assert (hits.primitive == -1).all()
    assert np.isnan(hits.position).all()
    assert hits.normal == pytest.approx(np.zeros((4, 3)), abs=0.0)


def test_rays_parallel_to_box_faces():
    rt = RayTracer([box((2.0, 2.0, 2.0))])
    # direction with zero y and z: inside the y and z slabs hits, outside misses
    hits = rt.intersect([[-5.0, 0.5, 1.0], [-5.0, 1.5, 1.0], [-5.0, 0.5, 2.5]], [1.0, 0.0, 0.0])
    assert hits.hit.tolist() == [True, False, False]
    assert hits.distance[0] == pytest.approx(4.0, abs=DIST_TOL)
    assert hits.normal[0] == pytest.approx([-1.0, 0.0, 0.0], abs=1e-12)


def test_ray_starting_inside_the_scene_box():
    rt = RayTracer([box((2.0, 2.0, 2.0))])
    hits = rt.intersect([[0.0, 0.0, 1.0]], [[0.0, 0.0, 1.0]])  # from inside the box, up
    assert hits.distance[0] == pytest.approx(1.0, abs=DIST_TOL)
    assert hits.normal[0] == pytest.approx([0.0, 0.0, 1.0], abs=1e-12)  # outward, not flipped


def test_box_occludes_a_segment_through_it():
    rt = RayTracer([box((2.0, 2.0, 2.0))])
    origins = np.array([[-5.0, 0.0, 1.0], [-5.0, 0.0, 1.0], [-5.0, 0.0, 3.0], [-5.0, 0.0, 1.0]])
    directions = np.array([[1.0, 0, 0], [1.0, 0, 0], [1.0, 0, 0], [-1.0, 0, 0]])
    t_max = np.array([10.0, 3.9, 10.0, 10.0])  # the box's west face is 4 m away
    assert rt.occluded(origins, directions, t_max).tolist() == [True, False, False, False]
    assert rt.occluded(origins, directions).tolist() == [True, True, False, False]
    assert rt.occluded(origins, directions, 4.1).tolist() == [True, True, False, False]
    assert rt.occluded(origins, directions, np.inf).dtype == bool


def test_far_observer_hits_with_centimetre_accuracy():
    hf, _ = procedural_terrain((1000.0, 1000.0), spacing=10.0, relief=40.0, seed=3)
    terrain = hf.to_mesh().transformed(translation=(500000.0, 4600000.0, 300.0))
    rt = RayTracer([terrain])
    rng = np.random.default_rng(11)
    n = 2000
    face = rng.integers(0, len(terrain.faces), n)
    w = rng.dirichlet([1.0, 1.0, 1.0], n)
    targets = np.einsum("nk,nkj->nj", w, terrain.vertices[terrain.faces[face]])
    zenith = np.radians(rng.uniform(0.0, 30.0, n))
    azimuth = np.radians(rng.uniform(0.0, 360.0, n))
    to_sky = np.column_stack([np.sin(zenith) * np.sin(azimuth), np.sin(zenith) * np.cos(azimuth),
                              np.cos(zenith)])
    slant = 700e3 / np.cos(zenith)  # observer 700 km above the terrain
    hits = rt.intersect(targets + slant[:, None] * to_sky, -to_sky)
    assert hits.hit.all()
    assert hits.distance == pytest.approx(slant, abs=FAR_TOL)
    assert np.linalg.norm(hits.position - targets, axis=1).max() < FAR_TOL


def test_bad_rays_are_refused():
    rt = RayTracer([plate(1.0, 1.0)])
    with pytest.raises(ConfigError, match="origins: 1 rays are not finite, first is ray 1"):
        rt.intersect([[0, 0, 1.0], [0, np.nan, 1.0]], [[0, 0, -1.0], [0, 0, -1.0]])
    with pytest.raises(ConfigError, match="directions: 1 rays are not finite"):
        rt.occluded([[0, 0, 1.0]], [[0, np.inf, -1.0]])
    with pytest.raises(ConfigError, match="zero length"):
        rt.intersect([[0, 0, 1.0]], [[0.0, 0.0, 0.0]])
    with pytest.raises(ConfigError, match="t_max"):
        rt.occluded([[0, 0, 1.0]], [[0, 0, -1.0]], t_max=-1.0)
    with pytest.raises(ConfigError, match=r"shape \(N, 3\)"):
        rt.intersect([0, 0, 1.0], [0, 0, -1.0])
    with pytest.raises(ConfigError, match=r"meshes\[0\]"):
        RayTracer(["not a mesh"])


def test_thread_chunked_equals_single_chunk():
    hf, _ = procedural_terrain((500.0, 500.0), spacing=10.0, seed=1)
    scene = [hf.to_mesh(), box((50.0, 30.0, 60.0)).transformed(translation=(20, 10, 30))]
    rng = np.random.default_rng(2)
    n = 20000
    origins = rng.uniform(-400, 400, (n, 3)) + np.array([0.0, 0.0, 500.0])
    directions = rng.normal(size=(n, 3)) + np.array([0.0, 0.0, -1.5])
    single = RayTracer(scene, chunk_size=10**9, threads=1)
    chunked = RayTracer(scene, chunk_size=777, threads=4)
    a, b = single.intersect(origins, directions), chunked.intersect(origins, directions)
    assert 0.2 < a.hit.mean() < 0.98  # both hits and misses are exercised
    assert set(np.unique(a.object)) == {-1, 0, 1}
    for name in ("distance", "object", "primitive", "u", "v", "normal", "position", "hit"):
        assert np.array_equal(getattr(a, name), getattr(b, name), equal_nan=name != "hit"), name
    t_max = rng.uniform(0, 800, n)
    assert np.array_equal(single.occluded(origins, directions, t_max),
                          chunked.occluded(origins, directions, t_max))


def test_non_robust_mode_gives_the_same_hits_on_a_plate():
    fast = RayTracer([plate(10.0, 10.0)], robust=False)
    hits = fast.intersect([[1.0, 1.0, 2.0]], [[0.0, 0.0, -1.0]])
    assert hits.distance[0] == pytest.approx(2.0, abs=DIST_TOL)


def test_to_local_gives_float32_points_inside_the_box_only():
    rt = RayTracer([plate(10.0, 10.0).transformed(translation=(100.0, 0.0, 0.0))])
    inside = np.array([[100.0, 0.0, 0.001], [103.0, -4.0, 0.0]])
    local = rt.to_local(inside)
    assert local.dtype == np.float32 and local.shape == (2, 3)
    assert np.array_equal(local, (inside - rt.center).astype(np.float32))
    assert rt.to_local([[100.0, 0.0, 50.0]]) is None  # above the box
    assert rt.to_local([[np.nan, 0.0, 0.0]]) is None
    assert rt.to_local([100.0, 0.0, 0.0]) is None  # not (N, 3)


def test_compiled_clipping_equals_the_numpy_clipping():
    """intersect's one-pass kernel against the checked numpy path occluded uses (_rays,
    _starts): the same unit directions, box entries and float32 starts, to the bit."""
    from radscene.geometry.raytracer import _prepare, _rays

    rt = RayTracer([box((50.0, 30.0, 60.0)).transformed(translation=(20, 10, 30))])
    rng = np.random.default_rng(4)
    n = 5000
    origins = rng.uniform(-200, 200, (n, 3))
    directions = rng.normal(size=(n, 3))
    directions[::2] = rt.center + rng.uniform(-40.0, 40.0, (n // 2, 3)) - origins[::2]  # aimed
    directions[np.arange(300), rng.integers(0, 3, 300)] = 0.0  # parallel to a slab, on it or not
    origins[:100, 0] = rt.center[0] + 25.0 + 1e-3 + 1e-5 * np.linalg.norm([50.0, 30.0, 60.0])
    o, d = _rays(origins, directions)
    traced, t_in, _, start, direction = rt._starts(o, d)
    unit = np.empty((n, 3))
    got = np.empty((n, 3), np.float32), np.empty((n, 3), np.float32), np.empty(n), \
        np.empty(n, dtype=bool)
    assert _prepare(origins, directions, rt._center, rt._half, unit, *got) == 0
    assert np.array_equal(unit, d)
    assert 0.05 < got[3].mean() < 0.95
    assert np.array_equal(np.flatnonzero(got[3]), traced)
    assert np.array_equal(got[2][traced], t_in)
    assert np.array_equal(got[0][traced], start)
    assert np.array_equal(got[1][traced], direction)
    # a bad ray is counted, and intersect then names it
    origins[7, 1] = np.inf
    assert _prepare(origins, directions, rt._center, rt._half, unit, *got) == 1
    with pytest.raises(ConfigError, match="first is ray 7"):
        rt.intersect(origins, directions)
