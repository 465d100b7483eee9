"""Band quadrature with breakpoints, and the emission table's spline path."""

from __future__ import annotations

import numpy as np
import pytest

from radscene.radiometry import (
    GaussianResponse,
    RectangularResponse,
    TabulatedResponse,
    band_radiance,
    spectral_radiance,
)
from radscene.render.spectral import band_quadrature, emission_coefficients


def test_quadrature_is_exact_for_kinked_tables_when_given_their_breakpoints():
    wl = np.array([0.5, 0.513, 0.537, 0.55, 0.581, 0.6])
    f = np.array([1.0, 3.0, 0.5, 2.0, 1.0, 4.0])
    g = np.array([0.2, 0.9, 0.1, 0.7, 0.3, 0.5])
    nodes, weights = band_quadrature(RectangularResponse(0.5, 0.6), breakpoints=wl)
    got = np.sum(weights * np.interp(nodes, wl, f) * np.interp(nodes, wl, g))
    # exact: product of two linear pieces integrated piece by piece (Simpson is exact for it)
    exact = 0.0
    for i in range(len(wl) - 1):
        h = wl[i + 1] - wl[i]
        fm, gm = 0.5 * (f[i] + f[i + 1]), 0.5 * (g[i] + g[i + 1])
        exact += h / 6 * (f[i] * g[i] + 4 * fm * gm + f[i + 1] * g[i + 1])
    assert got == pytest.approx(exact, rel=1e-13)
    nodes, weights = band_quadrature(RectangularResponse(0.5, 0.6))
    coarse = np.sum(weights * np.interp(nodes, wl, f) * np.interp(nodes, wl, g))
    assert abs(coarse - exact) > 1e-6 * exact  # the breakpoints matter


@pytest.mark.parametrize("response", [RectangularResponse(8.0, 12.0),
                                      GaussianResponse(10.0, 2.0),
                                      TabulatedResponse([3.0, 3.5, 4.5, 5.0], [0.0, 1.0, 0.8, 0.0])])
def test_quadrature_integrates_planck_with_the_response(response):
    nodes, weights = band_quadrature(response)
    got = np.sum(weights * spectral_radiance(nodes, 300.0))
    assert got == pytest.approx(response.integrate_function(lambda w: spectral_radiance(w, 300.0)),
                                rel=1e-9)
    if isinstance(response, RectangularResponse):
        assert got == pytest.approx(float(band_radiance(8.0, 12.0, 300.0)), rel=1e-9)


def test_emission_spline_path_matches_exact_pairs():
    nodes, weights = band_quadrature(RectangularResponse(3.0, 5.0))
    eps_tau = np.stack([np.full((1, nodes.size), 0.9), np.full((1, nodes.size), 0.5)])
    rng = np.random.default_rng(0)
    temperature = rng.uniform(250.0, 350.0, 3000)
    material = rng.integers(0, 2, 3000)
    spline = emission_coefficients(eps_tau, nodes, weights, material, temperature)
    exact = emission_coefficients(eps_tau, nodes, weights, material, temperature,
                                  exact_limit=10**6)
    assert spline.shape == (3000, 1)
    assert spline == pytest.approx(exact, rel=1e-9)
    expected = np.where(material == 0, 0.9, 0.5) * band_radiance(3.0, 5.0, temperature)
    assert exact[:, 0] == pytest.approx(expected, rel=1e-9)


def test_emission_pairs_match_each_hit_grouped_alone_and_a_second_frame_alike():
    """The pairs found by integer temperature steps and their kept splines give each hit the
    emission of its (material, temperature) grouped to the step, frame after frame."""
    from types import SimpleNamespace

    from radscene.render.band_setup import emission_pairs

    rng = np.random.default_rng(3)
    nodes, weights = band_quadrature(RectangularResponse(8.0, 12.0))
    bset = SimpleNamespace(emissivity_tau=[rng.uniform(0.5, 1.0, (4, 3, nodes.size))],
                           quadrature=[(nodes, weights)])
    material = rng.integers(0, 4, 5000)
    temperature = 290.0 + 20.0 * rng.random(5000)
    step = 1e-3
    grouped = np.round(temperature / step) * step
    want = emission_coefficients(bset.emissivity_tau[0], nodes, weights, material, grouped)
    for _ in range(2):  # the second call takes the kept splines
        pair, tables = emission_pairs(bset, material, temperature, step)
        np.testing.assert_array_equal(tables[0][pair], want)


def test_pixel_sums_add_each_pixels_samples_in_any_order():
    from radscene.render.tiles import pixel_sums

    rng = np.random.default_rng(4)
    pixel = np.sort(rng.integers(0, 300, 2000))
    weight, rows = rng.random(2000), rng.random((5, 2000))
    want = np.array([[np.sum(rows[r, pixel == p] * weight[pixel == p]) for p in np.unique(pixel)]
                     for r in range(5)])
    for order in (np.arange(2000), rng.permutation(2000)):
        got_pixel, got = pixel_sums(pixel[order], weight[order], rows[:, order])
        np.testing.assert_array_equal(got_pixel, np.unique(pixel))
        np.testing.assert_allclose(got, want, rtol=1e-13)
