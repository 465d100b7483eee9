"""Embree's packet queries on the library the embreex wheel ships."""

from __future__ import annotations

import numpy as np
import pytest

from radscene.geometry import RayTracer, box, embree, plate

pytestmark = pytest.mark.skipif(not embree.packets_available(),
                                reason="Embree's packet queries are not available here")


@pytest.fixture(scope="module")
def tracer():
    return RayTracer([plate(100.0, 100.0), box((10.0, 10.0, 10.0)),
                      box((4.0, 4.0, 30.0)).transformed(translation=(20.0, 5.0, 0.0))])


def test_packets_answer_as_embreex_does(tracer):
    rng = np.random.default_rng(3)
    n = 5001  # not a multiple of the packet width
    origins = np.column_stack([rng.uniform(-40, 40, (n, 2)), rng.uniform(0.01, 20.0, n)])
    directions = rng.normal(size=(n, 3))
    directions /= np.linalg.norm(directions, axis=1, keepdims=True)
    local = tracer.to_local(origins)
    d32 = directions.astype(np.float32)
    single = RayTracer(tracer.meshes, packets=False).occluded_local(local, d32)  # embreex
    packets = tracer.occluded_local(local, d32)
    np.testing.assert_array_equal(packets, single)
    assert 0.2 < single.mean() < 0.8  # both answers are common


def test_the_packet_scene_is_built_once_and_released(tracer):
    first = tracer.packets
    assert tracer.packets is first and first.handle
    scene = embree.PacketScene([np.zeros((3, 3), np.float32) + [[0, 0, 0], [1, 0, 0], [0, 1, 0]]],
                               [np.array([[0, 1, 2]])])
    hit = scene.occluded(np.array([[0.2, 0.2, 1.0]]), np.array([[0.0, 0.0, -1.0]]))
    assert hit.tolist() == [True]
    scene.close()
    scene.close()  # a second release does nothing


def test_packets_can_be_switched_off(monkeypatch):
    monkeypatch.setenv("RADSCENE_EMBREE_PACKETS", "0")
    embree._library.cache_clear()
    try:
        assert not embree.packets_available()
        assert RayTracer([plate(10.0, 10.0)]).packets is None
    finally:
        monkeypatch.delenv("RADSCENE_EMBREE_PACKETS")
        embree._library.cache_clear()
    assert embree.packets_available()


def test_packet_intersections_equal_embreex_ones(tracer):
    """First hits from packets of eight: the same faces, distances, barycentrics and misses as
    embreex's single rays, through RayTracer.intersect (clipping and hit forming included)."""
    rng = np.random.default_rng(8)
    n = 3003
    origins = np.column_stack([rng.uniform(-60, 60, (n, 2)), rng.uniform(0.5, 40.0, n)])
    directions = rng.normal(size=(n, 3))
    directions[::3, 2] = -np.abs(directions[::3, 2]) - 0.5  # many towards the ground
    origins[::11] += [0.0, 0.0, 500.0]  # some start outside the scene's box
    directions[7::13] = [1.0, 0.0, 0.0]  # some parallel to the plate
    single = RayTracer(tracer.meshes, packets=False).intersect(origins, directions)
    packed = tracer.intersect(origins, directions)
    assert 0.2 < single.hit.mean() < 0.9
    for name in ("object", "primitive", "hit"):
        np.testing.assert_array_equal(getattr(packed, name), getattr(single, name))
    for name in ("distance", "u", "v", "normal", "position"):
        np.testing.assert_array_equal(getattr(packed, name), getattr(single, name))


def test_render_shadows_from_packets_equal_the_checked_queries(tracer):
    """The renderer's shadow pass (render.surface.shadows): packets of eight neighbouring hits,
    against the same hits through embreex — normals turned to face the viewer, faces turned
    from the sun unlit, hits whose offset origin leaves the scene's box (here: above it) sent
    to the checked query; and with shadows off, only the faces' orientation."""
    from types import SimpleNamespace

    from radscene.render.surface import shadows

    rng = np.random.default_rng(12)
    n = 4001
    down = np.tile([0.0, 0.0, -1.0], (n, 1)) + rng.normal(scale=0.2, size=(n, 3))
    down /= np.linalg.norm(down, axis=1, keepdims=True)
    origins = np.column_stack([rng.uniform(-45, 45, (n, 2)), np.full(n, 60.0)])
    hits = tracer.intersect(origins, down)
    assert hits.hit.mean() > 0.8  # some rays leave the 100 m plate
    hits.position[:50] += [0.0, 0.0, 100.0]  # offset origins above the box
    sun = np.array([0.5, -0.3, 0.81])
    sun /= np.linalg.norm(sun)
    single = RayTracer(tracer.meshes, packets=False)
    for trace in (True, False):
        got = [shadows(SimpleNamespace(shadow_tracer=t, sun=SimpleNamespace(zenith=36.0),
                                        epsilon=1e-3),
                        hits, hits.hit, down, sun, trace) for t in (tracer, single)]
        np.testing.assert_array_equal(got[0], got[1])
        assert set(np.unique(got[0])) == {0.0, 1.0}
        if trace:  # the boxes cast shadows on the plate
            shaded = 1.0 - got[0].mean()
    assert 0.02 < shaded < 0.9 and shaded > 1.0 - got[0].mean()


def test_render_shadows_with_a_sun_per_hit(tracer):
    """A scanner's hits each see the sun of their own time: the packet pass and the checked
    query agree hit by hit, and one sun given per hit equals that sun given once."""
    from types import SimpleNamespace

    from radscene.render.surface import shadows

    rng = np.random.default_rng(5)
    n = 3001
    down = np.tile([0.0, 0.0, -1.0], (n, 1)) + rng.normal(scale=0.2, size=(n, 3))
    down /= np.linalg.norm(down, axis=1, keepdims=True)
    origins = np.column_stack([rng.uniform(-45, 45, (n, 2)), np.full(n, 60.0)])
    hits = tracer.intersect(origins, down)
    hits.position[:40] += [0.0, 0.0, 100.0]  # some to the checked query
    n_hit = int(hits.hit.sum())
    sun = np.array([0.5, -0.3, 0.81]) + rng.normal(scale=0.15, size=(n_hit, 3))
    sun /= np.linalg.norm(sun, axis=1, keepdims=True)
    single = RayTracer(tracer.meshes, packets=False)
    tables = [SimpleNamespace(shadow_tracer=t, epsilon=1e-3) for t in (tracer, single)]
    got = [shadows(tb, hits, hits.hit, down, sun, True) for tb in tables]
    np.testing.assert_array_equal(got[0], got[1])
    assert 0.0 < got[0].mean() < 1.0
    one = np.repeat(sun[:1], n_hit, axis=0)
    np.testing.assert_array_equal(shadows(tables[0], hits, hits.hit, down, one, True),
                                  shadows(tables[0], hits, hits.hit, down, sun[0], True))
