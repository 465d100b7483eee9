"""The reflected background's first bounce from the render's sky fan
(radscene.render.background_first): the order in which paths take the fan's samples, the fan's
directions and blocked flags against the sky pass's, and the estimator against independent
paths and against the BRDF's own mixture sampling, in expectation."""

from __future__ import annotations

import numpy as np
import pytest

from radscene.geometry import RayTracer, box, plate
from radscene.materials import Material
from radscene.render import background, background_first, background_kernels, illumination
from radscene.render import kernels as fan_kernels
from radscene.render.spectral import band_quadrature

#: Standard errors within which two unbiased estimates of the same mean must agree.
K_SIGMA = 4.0


class _Band:
    """A rectangular response of peak 1 over [lo, hi] [um]."""

    def __init__(self, lo, hi):
        self.support = (lo, hi)
        self.center = 0.5 * (lo + hi)

    def __call__(self, wl):
        wl = np.asarray(wl, dtype=float)
        return ((wl >= self.support[0]) & (wl <= self.support[1])).astype(float)


def _scene(n, specular=0.0, sun=1500.0, sky=True, seed=4):
    """A 2 m box on a 40 m plate, a visible and a thermal band; ``n`` points on the plate
    around the box and on the box's walls, each with its normal and a view from above."""
    meshes = [plate(40.0, 40.0), box((2.0, 2.0, 2.0))]
    tracer = RayTracer(meshes)
    materials = [Material.create("ground", reflectance=0.3 + specular,
                                 specular_reflectance=specular, specular_exponent=20.0),
                 Material.create("wall", reflectance=0.6)]
    quadrature = [band_quadrature(_Band(0.5, 0.6)), band_quadrature(_Band(8.0, 12.0))]
    faces = [len(m.faces) for m in meshes]
    zen, az = np.array([0.0, 45.0, 90.0]), np.array([0.0, 180.0])
    sky_table = np.array([[20.0, 25.0, 30.0, 32.0, 40.0, 41.0], [2.0, 2.5, 3.0, 3.0, 4.0, 4.0]])
    tables = background.band_tables(
        materials, {}, quadrature, [np.full(q[0].shape, sun) for q in quadrature],
        sky_table * float(sky), (zen, az), [False, True], np.array([0, faces[0]]),
        np.concatenate([np.zeros(faces[0], int), np.ones(faces[1], int)]),
        np.concatenate([np.full(faces[0], 300.0), np.full(faces[1], 340.0)]))
    rng = np.random.default_rng(seed)
    ground = n - n // 4
    azimuth, radius = rng.uniform(0.0, 2.0 * np.pi, ground), rng.uniform(1.2, 3.0, ground)
    xy = radius[:, None] * np.column_stack([np.cos(azimuth), np.sin(azimuth)])
    walls = n - ground  # on the box's +x face, looking at the ground beside it
    origin = np.concatenate([np.column_stack([xy, np.full(ground, 1e-3)]),
                             np.column_stack([np.full(walls, 1.0 + 1e-3),
                                              rng.uniform(-0.9, 0.9, walls),
                                              rng.uniform(0.1, 1.9, walls)])])
    normal = np.concatenate([np.tile([0.0, 0.0, 1.0], (ground, 1)),
                             np.tile([1.0, 0.0, 0.0], (walls, 1))])
    wo = np.tile([0.3, 0.1, 1.0] / np.linalg.norm([0.3, 0.1, 1.0]), (n, 1))
    material = np.concatenate([np.zeros(ground, int), np.ones(walls, int)])
    return tracer, tables, origin, normal, wo, material


def _fan(tracer, origin, normal, sky_samples, seed=5, packets=True):
    shift = np.random.default_rng(seed).random((len(origin), 2))
    blocked = np.empty((len(origin), sky_samples), dtype=bool)
    if not packets:
        tracer = RayTracer(tracer.meshes, packets=False)
    illumination.sky_fractions(tracer, origin, normal, sky_samples, np.array([0.0, 90.0]),
                               None, shift=shift, blocked=blocked)
    return background.Fan(shift, sky_samples, blocked)


def test_sobol_points_are_a_02_sequence():
    """Every 2^k consecutive points from the start fall one in each elementary interval of
    area 2^-k (Sobol' 1967; a (0, 2)-sequence in base 2)."""
    points = background_first.sobol_points(64)
    assert points[:4] == pytest.approx(
        np.array([[0.0, 0.0], [0.5, 0.5], [0.25, 0.75], [0.75, 0.25]]), abs=0.0)
    for k in range(7):
        for a in range(k + 1):  # intervals 2^-a wide, 2^-(k - a) high
            cells = (np.floor(points[:2**k, 0] * 2**a) * 2**(k - a)
                     + np.floor(points[:2**k, 1] * 2**(k - a)))
            assert len(np.unique(cells)) == 2**k


@pytest.mark.parametrize("n_samples", [1, 2, 3, 4, 9, 12, 16, 25, 64, 256])
def test_fan_order_is_a_permutation(n_samples):
    order = background_first.fan_order(n_samples)
    assert sorted(order.tolist()) == list(range(n_samples))


@pytest.mark.parametrize("side", [2, 4, 8, 16])
def test_the_fans_first_samples_spread_over_the_pattern(side):
    """On a square fan of side 2^m the first 2^j samples taken fall in distinct elementary
    cells of the pattern's grid at every scale: one per row and one per column for 2^j ≤ side,
    one per quadrant of four for 4 samples."""
    order = background_first.fan_order(side * side)
    row, column = np.divmod(order, side)
    for count in (2**j for j in range(1, int(np.log2(side)) + 1)):
        assert len(np.unique(row[:count])) == count
        assert len(np.unique(column[:count])) == count
    quadrant = (row[:4] * 2 // side) * 2 + column[:4] * 2 // side
    assert sorted(quadrant.tolist()) == [0, 1, 2, 3]


@pytest.mark.parametrize("sky_samples", [4, 9, 16, 12])
def test_fan_directions_are_the_sky_fans(sky_samples):
    """The first directions taken from the fan are the directions the sky pass traces (float32
    there), sample by sample in :func:`fan_order`'s order."""
    tracer, tables, origin, normal, wo, material = _scene(40)
    shift = np.random.default_rng(2).random((len(origin), 2))
    base = illumination.stratified_pattern(sky_samples)
    side = int(np.sqrt(sky_samples)) if int(np.sqrt(sky_samples)) ** 2 == sky_samples else 0
    o32 = np.empty((len(origin) * sky_samples, 3), np.float32)
    d32 = np.empty_like(o32)
    fan_kernels.cosine_fan(origin, normal, tracer.center, 0.0, shift, base, side, o32, d32)
    count = sky_samples
    path, d = np.empty(len(origin) * count, np.int64), np.empty((len(origin) * count, 3))
    kept = background_kernels.fan_directions(
        np.zeros((0, sky_samples), dtype=bool), shift, base, background_first.fan_order(
            sky_samples), count, 0, len(origin), count, wo, normal, material.astype(np.int64),
        np.ones(2, dtype=bool), path, d)
    assert kept == len(origin) * count  # all above their surfaces, in order
    point, sample = np.divmod(path, count)
    taken = point * sky_samples + background_first.fan_order(sky_samples)[sample]
    assert d == pytest.approx(d32[taken].astype(float), abs=2e-7)


@pytest.mark.parametrize("packets", [True, False])
def test_the_fans_blocked_flags_are_its_directions_that_meet_the_scene(packets):
    """A fan direction is flagged where it points at or below the horizon or meets the scene:
    every direction that meets the scene is flagged (none is lost to the background), every
    other one above the horizon is not. With Embree's packets and without, the same flags."""
    tracer, _tables, origin, normal, _wo, _material = _scene(60)
    m = 16
    fan = _fan(tracer, origin, normal, m, packets=packets)
    point = np.repeat(np.arange(len(origin)), m)
    sample = np.tile(np.arange(m), len(origin))
    u = fan.uniforms(point, sample)
    from radscene.materials.brdf import lambertian

    d, _ = lambertian.sample(normal[point], u[:, 0], u[:, 1])
    hit = tracer.intersect(origin[point], d).hit
    blocked = fan.blocked.ravel()
    assert np.all(blocked[hit])
    assert not np.any(blocked[~hit & (d[:, 2] > 1e-6)])
    assert 0.05 < hit.mean() < 0.95  # the box and the ground are seen
    if not packets:
        assert np.array_equal(fan.blocked, _fan(tracer, origin, normal, m).blocked)


def _paired(a, b):
    """|mean(a − b)| over points and its standard error, per band."""
    diff = a - b
    return np.abs(diff.mean(axis=0)), diff.std(axis=0, ddof=1) / np.sqrt(len(diff))


@pytest.mark.parametrize("samples, sky_samples", [(16, 16), (4, 16), (32, 8)])
@pytest.mark.parametrize("specular", [0.0, 0.3])
def test_the_fan_estimator_equals_independent_paths_in_expectation(samples, sky_samples,
                                                                   specular):
    """Over 600 points, one bounce: the paths whose diffuse directions come from the fan and
    paths that draw them all have the same mean (within K_SIGMA paired standard errors); with
    no more paths than the fan's directions the fan's errors against a 2048-path estimate are
    smaller."""
    tracer, tables, origin, normal, wo, material = _scene(600, specular)
    fan = _fan(tracer, origin, normal, sky_samples)
    args = (tracer, tables, origin, normal, wo, material, [0.5, -0.3, 0.8])
    u = background.draws(11, 0, len(origin), samples, 1)
    with_fan = background.reflected(*args, u, epsilon=1e-3, fan=fan)
    drawn = background.reflected(*args, background.draws(12, 0, len(origin), samples, 1),
                                 epsilon=1e-3)
    difference, error = _paired(with_fan, drawn)
    assert np.all(difference < K_SIGMA * error), (difference, error)
    if samples <= sky_samples:
        truth = background.reflected(*args, background.draws(13, 0, len(origin), 2048, 1),
                                     epsilon=1e-3)
        assert np.all(np.mean((with_fan - truth) ** 2, axis=0)
                      < np.mean((drawn - truth) ** 2, axis=0))


def test_the_lobe_split_equals_the_brdf_mixture_in_expectation():
    """A glossy plain material (ρ_d = 0.3, ρ_s = 0.3, n = 20) whose lobe looks at a warm
    box, emission only (no sun, black sky), one bounce: the split (diffuse part from the fan, the lobe drawn with probability q)
    against the registry's Phong mixture sampling of f cos θ / pdf, path by path, over 600
    points (within K_SIGMA paired standard errors)."""
    tracer, tables, origin, normal, wo, material = _scene(600, 0.3, sun=0.0, sky=False)
    ground = material == 0
    origin, normal, material = origin[ground], normal[ground], material[ground]
    # seen from 25° above the horizon, from the side away from the box: the lobe's mirror
    # direction looks at the box
    away = origin[:, :2] / np.linalg.norm(origin[:, :2], axis=1)[:, None]
    elevation = np.radians(25.0)
    wo = np.column_stack([np.cos(elevation) * away, np.full(len(away), np.sin(elevation))])
    samples = 32
    fan = _fan(tracer, origin, normal, 16)
    u = background.draws(3, 0, len(origin), samples, 1)
    split = background.reflected(tracer, tables, origin, normal, wo, material, [0, 0, 1], u,
                                 epsilon=1e-3, fan=fan)
    # the mixture: ω_i from the material's phong model, weight f cos θ / pdf, the vertex's
    # emission
    n = len(origin)
    point = np.repeat(np.arange(n), samples)
    uniforms = np.random.default_rng(8).random((n * samples, 2))
    wi, weight = background.brdf_weight_reference(tables, material[point], wo[point],
                                                  normal[point], uniforms)
    mixture = np.zeros((n, tables.bands))
    go = np.flatnonzero(np.any(weight > 0.0, axis=1))
    hits = tracer.intersect(origin[point[go]], wi[go])
    go, hits = go[hits.hit], background_first.take(hits, hits.hit)
    vertices = background._vertices(tables, hits, wi[go], 1e-3, None)
    own = background._own(tracer, tables, vertices, np.array([0.0, 0.0, 1.0]), True)[0]
    np.add.at(mixture, point[go], weight[go] * own)
    mixture /= samples
    assert np.mean(split[:, 1] > 0.0) > 0.9  # most points see the warm box
    difference, error = _paired(split, mixture)
    assert np.all(difference < K_SIGMA * error), (difference, error)
