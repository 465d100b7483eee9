"""Fans kept between frames (radscene.render.kept_fans): the ray–sphere test against its
closed form, and kept fans against fans traced afresh, before and after a box moves."""

from __future__ import annotations

import numpy as np
import pytest

from radscene.geometry import RayTracer, box, plate
from radscene.geometry.frames import normalize
from radscene.render import illumination
from radscene.render.kept_fans import bounding_sphere, kept_fans, meets_spheres

GRID = (np.array([0.0, 45.0, 90.0]), np.array([0.0, 90.0, 180.0, 270.0]))
N_SAMPLES = 16


def _meets_reference(origin, direction, sphere):
    """The ray's closest approach to the sphere's centre (t ≥ 0) within its radius."""
    d = np.asarray(direction, float)
    w = sphere[:3] - origin
    t = max(0.0, float(w @ d) / float(d @ d))
    return float(np.linalg.norm(origin + t * d - sphere[:3])) <= sphere[3]


def test_meets_spheres_matches_the_closest_approach():
    rng = np.random.default_rng(0)
    origins = rng.uniform(-20, 20, (2000, 3))
    directions = rng.normal(size=(2000, 3)) * rng.uniform(0.5, 2.0, (2000, 1))  # not unit
    spheres = np.array([[0.0, 0.0, 0.0, 5.0], [10.0, -4.0, 2.0, 1.5]])
    got = meets_spheres(origins, directions, spheres)
    want = [any(_meets_reference(o, d, s) for s in spheres) for o, d in zip(origins, directions, strict=True)]
    np.testing.assert_array_equal(got, want)
    assert 0 < got.sum() < len(got)
    assert not meets_spheres(origins, directions, np.zeros((0, 4))).any()


def test_bounding_sphere_holds_every_vertex():
    vertices = box((4.0, 2.0, 6.0)).transformed(translation=(3, -1, 2)).vertices
    sphere = bounding_sphere(vertices)
    assert np.linalg.norm(vertices - sphere[:3], axis=1).max() == pytest.approx(sphere[3], rel=1e-12)
    assert sphere[:3] == pytest.approx([3.0, -1.0, 2.0 + 3.0], abs=1e-12)


def _scene(x):
    return RayTracer([plate(200.0, 200.0), box((10.0, 10.0, 10.0)).transformed(translation=(x, 0, 0))])


def _points(n, seed=0):
    rng = np.random.default_rng(seed)
    xy = rng.uniform(-30, 30, size=(n, 2))
    xy = xy[(np.abs(xy[:, 0]) > 12) | (np.abs(xy[:, 1]) > 6)]  # off both of the box's footprints
    origins = np.column_stack([xy, np.full(len(xy), 1e-3)])
    return origins, np.tile([0.0, 0.0, 1.0], (len(xy), 1)), rng.random((len(xy), 2))


@pytest.mark.parametrize("lobe", [False, True])
def test_kept_fans_equal_fans_traced_afresh_after_a_box_moved(lobe):
    origins, normals, shift = _points(400)
    axes = normalize(np.tile([0.6, 0.0, 0.8], (len(origins), 1)))
    exponents = np.full(len(origins), 20.0)
    extra = {"lobe": (axes, exponents)} if lobe else {}

    def afresh(tracer):
        if lobe:
            return illumination.lobe_sky_fractions(tracer, origins, normals, axes, exponents, N_SAMPLES,
                                                   GRID, None, shift=shift)
        return illumination.sky_fractions(tracer, origins, normals, N_SAMPLES, GRID, None, shift=shift)

    before, after = _scene(-4.0), _scene(4.0)
    bits = np.zeros(len(origins), np.uint64)
    everything = np.ones(len(origins), dtype=bool)
    first, traced = kept_fans(before, origins, normals, N_SAMPLES, GRID, shift, bits, everything,
                              np.zeros((0, 4)), **extra)
    np.testing.assert_array_equal(first, afresh(before))  # the same numbers, bit for bit
    assert traced > 0
    # nothing moved: every fan kept, nothing traced
    again, traced = kept_fans(before, origins, normals, N_SAMPLES, GRID, shift, bits.copy(),
                              ~everything, np.zeros((0, 4)), **extra)
    np.testing.assert_array_equal(again, first)
    assert traced == 0
    # the box moved 8 m east: the fans through its old or new sphere traced again
    spheres = [bounding_sphere(m.vertices) for m in (before.meshes[1], after.meshes[1])]
    moved, traced = kept_fans(after, origins, normals, N_SAMPLES, GRID, shift, bits, ~everything,
                              np.array(spheres), **extra)
    np.testing.assert_array_equal(moved, afresh(after))
    assert 0 < traced < len(origins) * N_SAMPLES
    assert not np.array_equal(moved, first)  # the box's move changed some fans


def test_kept_sky_sums_equal_the_sums_traced_afresh():
    origins, normals, shift = _points(300, seed=2)
    tracer = _scene(0.0)
    n = len(origins)
    rng = np.random.default_rng(3)
    table = rng.random((2, 3, 4, GRID[0].size * GRID[1].size))  # material, path node, band, sky node
    index = rng.integers(0, 3, (n, 2))
    weight = rng.random((n, 2))
    material = rng.integers(0, 2, n)
    rank = np.arange(n)
    want = illumination.sky_sums(tracer, origins, normals, N_SAMPLES, GRID, None, rank=rank,
                                 material=material, index=index, weight=weight, table=table, shift=shift)
    bits = np.zeros(n, np.uint64)
    for retrace in (True, False):  # traced, then kept
        got, _ = kept_fans(tracer, origins, normals, N_SAMPLES, GRID, shift, bits, np.full(n, retrace),
                           np.zeros((0, 4)), sky=(rank, material, index, weight, table))
        for a, b in zip(got, want, strict=True):
            np.testing.assert_array_equal(a, b)
