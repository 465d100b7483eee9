"""The compiled sky and lobe fans against their numpy reference implementations."""

from __future__ import annotations

import numpy as np
import pytest

from radscene.geometry import RayTracer, box, plate
from radscene.geometry.frames import normalize
from radscene.render import illumination


@pytest.fixture(scope="module")
def tracer():
    return RayTracer([plate(200.0, 200.0), box((10.0, 10.0, 10.0)).transformed(translation=(8, 0, 0))])


def _points(n, seed=0):
    rng = np.random.default_rng(seed)
    xy = rng.uniform(-30, 30, size=(n, 2))
    xy = xy[(np.abs(xy[:, 0] - 8) > 6) | (np.abs(xy[:, 1]) > 6)]  # off the box footprint
    origins = np.column_stack([xy, np.full(len(xy), 1e-3)])
    normals = np.tile([0.0, 0.0, 1.0], (len(xy), 1))
    return origins, normals


@pytest.mark.parametrize("nodes", [[0.0], [0.0, 45.0, 90.0]])
def test_compiled_sky_fan_matches_reference(tracer, nodes):
    origins, normals = _points(400)
    fast = illumination.sky_fractions(tracer, origins, normals, 64, np.array(nodes),
                                      np.random.default_rng(5))
    slow = illumination.sky_fractions_reference(tracer, origins, normals, 64, np.array(nodes),
                                                np.random.default_rng(5))
    assert fast.shape == (len(origins), len(nodes))
    # same random numbers; float32 rays may flip a grazing sample at the box edges
    assert np.abs(fast - slow).max() <= 1.0 / 64 + 1e-12
    assert fast.sum(axis=1).mean() == pytest.approx(slow.sum(axis=1).mean(), abs=1e-3)
    # the box hides part of the sky from points near it
    assert fast.sum(axis=1).min() < 0.95
    assert fast.sum(axis=1).max() <= 1.0 + 1e-12


def test_compiled_lobe_fan_matches_reference(tracer):
    origins, normals = _points(300, seed=1)
    axes = normalize(np.tile([0.6, 0.0, 0.8], (len(origins), 1)))
    expo = np.full(len(origins), 20.0)
    nodes = np.array([0.0, 60.0, 90.0])
    fast = illumination.lobe_sky_fractions(tracer, origins, normals, axes, expo, 64, nodes,
                                           np.random.default_rng(2))
    slow = illumination.lobe_sky_fractions_reference(tracer, origins, normals, axes, expo, 64,
                                                     nodes, np.random.default_rng(2))
    assert np.abs(fast - slow).max() <= 1.0 / 64 + 1e-12
    assert fast.sum(axis=1).mean() == pytest.approx(slow.sum(axis=1).mean(), abs=1e-3)


def test_open_plane_sky_view_is_exactly_one():
    rt = RayTracer([plate(100.0, 100.0)])
    origins = np.array([[0.0, 0.0, 1e-3], [10.0, -5.0, 1e-3]])
    normals = np.tile([0.0, 0.0, 1.0], (2, 1))
    f = illumination.sky_fractions(rt, origins, normals, 16, np.array([0.0]),
                                   np.random.default_rng(0))
    assert f == pytest.approx(np.ones((2, 1)), abs=0)


def test_stratified_pattern_covers_every_cell_once():
    p = illumination.stratified_pattern(16)
    cells = (np.floor(p[:, 0] * 4) * 4 + np.floor(p[:, 1] * 4)).astype(int)
    assert sorted(cells) == list(range(16))
    q = illumination.stratified_pattern(10)
    assert sorted(np.floor(q[:, 0] * 10).astype(int)) == list(range(10))


def test_compiled_fan_with_azimuth_nodes_matches_reference(tracer):
    origins, normals = _points(300, seed=4)
    grid = (np.array([0.0, 45.0, 90.0]), np.array([0.0, 90.0, 180.0, 270.0]))
    fast = illumination.sky_fractions(tracer, origins, normals, 64, grid, np.random.default_rng(9))
    slow = illumination.sky_fractions_reference(tracer, origins, normals, 64, grid,
                                                np.random.default_rng(9))
    assert fast.shape == (len(origins), 12)
    assert fast == pytest.approx(slow, abs=1e-6)
    # from points west of the box, only the eastern sky is hidden
    west = origins[:, 0] < 0.0
    open_sky = illumination.sky_fractions(RayTracer([plate(200.0, 200.0)]), origins[west],
                                          normals[west], 64, grid, np.random.default_rng(9))
    hidden = illumination.sky_fractions(tracer, origins[west], normals[west], 64, grid,
                                        np.random.default_rng(9))
    lost = (open_sky - hidden).reshape(-1, 3, 4).sum(axis=(0, 1))
    assert lost[1] > 0.5 and lost[3] == pytest.approx(0.0, abs=1e-9)


def test_azimuth_weights_wrap_around_north():
    from radscene.atmosphere import azimuth_hat_weights

    w = azimuth_hat_weights(np.array([350.0, 10.0, 180.0]), [0.0, 90.0, 180.0, 270.0])
    assert w[0] == pytest.approx([80 / 90, 0, 0, 10 / 90])
    assert w[1] == pytest.approx([80 / 90, 10 / 90, 0, 0])
    assert w[2] == pytest.approx([0, 0, 1, 0])


@pytest.mark.parametrize("n_samples", [10, 12])
def test_compiled_fans_with_a_non_square_pattern_match_reference(tracer, n_samples):
    origins, normals = _points(200, seed=6)
    nodes = np.array([0.0, 45.0, 90.0])
    fast = illumination.sky_fractions(tracer, origins, normals, n_samples, nodes,
                                      np.random.default_rng(3))
    slow = illumination.sky_fractions_reference(tracer, origins, normals, n_samples, nodes,
                                                np.random.default_rng(3))
    assert np.abs(fast - slow).max() <= 1.0 / n_samples + 1e-12
    axes = normalize(np.tile([0.5, 0.1, 0.8], (len(origins), 1)))
    expo = np.full(len(origins), 8.0)
    fast = illumination.lobe_sky_fractions(tracer, origins, normals, axes, expo, n_samples,
                                           nodes, np.random.default_rng(4))
    slow = illumination.lobe_sky_fractions_reference(tracer, origins, normals, axes, expo,
                                                     n_samples, nodes, np.random.default_rng(4))
    assert np.abs(fast - slow).max() <= 1.0 / n_samples + 1e-12


def test_pre_drawn_shifts_and_kept_buffers_give_the_same_fractions(tracer):
    origins, normals = _points(300, seed=7)
    nodes = np.array([0.0, 60.0, 90.0])
    drawn = illumination.sky_fractions(tracer, origins, normals, 16, nodes,
                                       np.random.default_rng(11))
    scratch = {}
    shift = np.random.default_rng(11).random((len(origins), 2))
    again = illumination.sky_fractions(tracer, origins, normals, 16, nodes, None, shift=shift,
                                       scratch=scratch)
    assert np.array_equal(drawn, again)
    # a smaller call reuses the kept buffers, a larger one grows them
    part = illumination.sky_fractions(tracer, origins[:50], normals[:50], 16, nodes, None,
                                      shift=shift[:50], scratch=scratch)
    assert np.array_equal(part, drawn[:50])
    more = illumination.sky_fractions(tracer, origins, normals, 25, nodes, None, shift=shift,
                                      scratch=scratch)
    assert np.array_equal(more, illumination.sky_fractions(tracer, origins, normals, 25, nodes,
                                                           None, shift=shift))
    with pytest.raises(ValueError, match="shift"):
        illumination.sky_fractions(tracer, origins, normals, 16, nodes, None, shift=shift[:5])


def test_cast_shadow_fast_path_equals_the_checked_query(tracer):
    origins, _ = _points(300, seed=8)
    # some points in the box's shadow, and some far above the scene (outside the tracer's box)
    origins = np.vstack([origins, [[20.0, 0.0, 1e-3], [-3.0, 2.0, 500.0]]])
    sun = np.array([-1.0, 0.2, 0.5])  # not unit: normalised as the checked query does
    lit = illumination.cast_shadow(tracer, origins, sun)
    expected = 1.0 - tracer.occluded(origins, np.broadcast_to(sun, origins.shape)).astype(float)
    assert np.array_equal(lit, expected)
    assert 0.0 < lit.mean() < 1.0
    assert tracer.to_local(origins) is None  # the last point took the checked path
    assert np.array_equal(illumination.cast_shadow(tracer, origins[:-1], sun), expected[:-1])


@pytest.mark.parametrize("grid", [np.array([0.0, 30.0, 60.0, 90.0]),
                                  (np.array([0.0, 45.0, 90.0]), np.array([0.0, 90.0, 180.0, 270.0]))],
                         ids=["zenith", "zenith-azimuth"])
def test_folded_sky_sums_equal_fractions_times_tables(tracer, grid):
    """illumination.sky_sums against sky_fractions followed by node_mixing.mix_sky, with the
    same rotations: several materials, path nodes with two weights per point, three bands."""
    from radscene.render.node_mixing import mix_sky

    origins, normals = _points(500, seed=6)
    n = len(origins)
    rng = np.random.default_rng(2)
    n_k = len(grid) if not isinstance(grid, tuple) else grid[0].size * grid[1].size
    table = rng.random((3, 5, 3, n_k))  # (materials, path nodes, bands, sky nodes)
    rank = rng.permutation(n)  # hits' rows of index/weight in another order
    index = rng.integers(0, 5, (n, 2))
    weight = rng.random((n, 2))
    weight[::7, 1] = 0.0
    material = rng.integers(0, 3, n)
    shift = rng.random((n, 2))
    f = illumination.sky_fractions(tracer, origins, normals, 16, grid, None, shift=shift)
    sums, view = illumination.sky_sums(tracer, origins, normals, 16, grid, None, rank=rank,
                                       material=material, index=index, weight=weight,
                                       table=table, shift=shift)
    want = np.empty((n, 3))
    for m in range(3):
        sel = material == m
        want[sel] = mix_sky(table[m][None], np.zeros(sel.sum(), int), index[rank[sel]],
                            weight[rank[sel]], f[sel])
    assert sums == pytest.approx(want, rel=1e-12, abs=1e-15)
    assert view == pytest.approx(f.sum(axis=1), rel=1e-12, abs=1e-15)
    assert view.min() < 0.95  # the box hides part of the sky from some points
    with pytest.raises(ValueError, match="table must be"):
        illumination.sky_sums(tracer, origins, normals, 16, grid, None, rank=rank,
                              material=material, index=index, weight=weight,
                              table=table[..., :-1], shift=shift)


@pytest.mark.parametrize("grid", [np.array([0.0, 30.0, 60.0, 90.0]),
                                  (np.array([0.0, 45.0, 90.0]), np.array([0.0, 90.0, 180.0, 270.0]))],
                         ids=["zenith", "zenith-azimuth"])
def test_packet_kernels_equal_the_single_ray_path(tracer, grid):
    """Fans traced as Embree packets inside the kernels give the same fractions and sky sums
    as the fans written out and traced ray by ray through embreex, for the same rotations."""
    if tracer.packets is None:
        pytest.skip("Embree's packet queries are not available here")
    single = RayTracer(tracer.meshes, packets=False)
    assert single.packets is None
    origins, normals = _points(600, seed=9)
    normals[::5] = normalize(normals[::5] + [0.3, -0.2, 0.0])  # some tilted surfaces
    n = len(origins)
    rng = np.random.default_rng(4)
    shift, lobe_shift = rng.random((n, 2)), rng.random((n, 2))
    for n_samples in (16, 10):  # the regular grid, and the golden-ratio pattern
        f_packets = illumination.sky_fractions(tracer, origins, normals, n_samples, grid, None,
                                               shift=shift)
        f_single = illumination.sky_fractions(single, origins, normals, n_samples, grid, None,
                                              shift=shift)
        np.testing.assert_array_equal(f_packets, f_single)
    assert f_packets.sum(axis=1).min() < 0.95  # the box hides sky: occlusion is exercised
    axes = normalize(np.tile([0.6, 0.0, 0.8], (n, 1)))
    expo = np.linspace(1.0, 50.0, n)
    g = [illumination.lobe_sky_fractions(t, origins, normals, axes, expo, 12, grid, None,
                                         shift=lobe_shift) for t in (tracer, single)]
    np.testing.assert_array_equal(g[0], g[1])
    n_k = g[0].shape[1]
    table = rng.random((2, 3, 4, n_k))
    kw = dict(rank=np.arange(n), material=rng.integers(0, 2, n), index=rng.integers(0, 3, (n, 2)),
              weight=rng.random((n, 2)), table=table, shift=shift)
    sums = [illumination.sky_sums(t, origins, normals, 16, grid, None, **kw)
            for t in (tracer, single)]
    np.testing.assert_array_equal(sums[0][0], sums[1][0])
    np.testing.assert_array_equal(sums[0][1], sums[1][1])


def test_fold_zenith_angles_equal_the_arc_cosine_to_float32_precision():
    """The folds' zenith angle (Abramowitz & Stegun 4.4.46) against numpy's arc cosine over
    the whole upper hemisphere: within 2e-8 rad (1.2e-6 deg), exact at the zenith."""
    from radscene.render.kernels import _zenith_degrees

    z = np.concatenate([np.linspace(0.0, 1.0, 20_001), [1.0 - 1e-12, 1.0 + 1e-12]])
    got = np.array([_zenith_degrees(x) for x in z])
    want = np.degrees(np.arccos(np.minimum(z, 1.0)))
    assert np.abs(got - want).max() <= np.degrees(2.2e-8)
    assert _zenith_degrees(1.0) == 0.0 and _zenith_degrees(1.0 + 1e-12) == 0.0


def test_surface_state_turns_normals_to_the_viewer_and_offsets_the_origins():
    from radscene.render import kernels

    rng = np.random.default_rng(4)
    n = 500
    normal = normalize(rng.normal(size=(n, 3)))
    direction = normalize(rng.normal(size=(n, 3)))
    position = rng.uniform(-50.0, 50.0, (n, 3))
    sun = normalize(np.array([0.3, -0.2, 0.9]))
    index = np.sort(rng.choice(n, 300, replace=False))
    nrm, wo, cos_v, cos_i, origin = kernels.surface_state(normal, direction, position, index,
                                                          0.01, sun)
    flip = np.einsum("nc,nc->n", normal[index], direction[index]) > 0.0
    expected = np.where(flip[:, None], -normal[index], normal[index])
    assert np.array_equal(nrm, expected) and np.array_equal(wo, -direction[index])
    assert cos_v == pytest.approx(np.einsum("nc,nc->n", expected, -direction[index]), abs=1e-15)
    assert np.all(cos_v >= 0.0)  # facing the viewer
    assert cos_i == pytest.approx(expected @ sun, abs=1e-15)
    assert origin == pytest.approx(position[index] + 0.01 * expected, abs=1e-12)


@pytest.mark.parametrize("n_samples", [16, 64, 10])
def test_compiled_fans_point_where_the_reference_samples_do(n_samples):
    # the compiled fans take the sines and cosines of a square pattern's later azimuth
    # columns from its first quarter, turned by a quarter turn: same directions
    from radscene.materials.brdf import lambertian, phong
    from radscene.render import kernels

    rng = np.random.default_rng(8)
    n = 50
    position = rng.uniform(-5.0, 5.0, (n, 3))
    normal = normalize(rng.normal(size=(n, 3)))
    axis = normalize(normal + 0.3 * rng.normal(size=(n, 3)))
    exponent = rng.uniform(5.0, 200.0, n)
    shift = np.random.default_rng(9).random((n, 2))
    base = illumination.stratified_pattern(n_samples)
    side = int(np.sqrt(n_samples)) if int(np.sqrt(n_samples)) ** 2 == n_samples else 0
    u1, u2 = illumination.stratified_square(n, n_samples, np.random.default_rng(9))
    origins = np.empty((n * n_samples, 3), np.float32)
    directions = np.empty((n * n_samples, 3), np.float32)
    kernels.cosine_fan(position, normal, np.zeros(3), 0.0, shift, base, side, origins,
                       directions)
    expected, _ = lambertian.sample(np.repeat(normal[:, None, :], n_samples, axis=1), u1, u2)
    assert np.abs(directions - expected.reshape(-1, 3)).max() < 1e-6  # float32 rays
    kernels.lobe_fan(position, normal, axis, exponent, np.zeros(3), 0.0, shift, base, side,
                     origins, directions)
    expected, _ = phong.sample(np.repeat(axis[:, None, :], n_samples, axis=1),
                               np.repeat(exponent[:, None], n_samples, axis=1), u1, u2)
    assert np.abs(directions - expected.reshape(-1, 3)).max() < 1e-6
