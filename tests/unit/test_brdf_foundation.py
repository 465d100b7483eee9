"""Tests of radscene.materials.brdf.lambertian and .phong (Willers et al. 2011, eq. 4."""

import numpy as np
import pytest
from scipy import integrate, stats

from radscene.errors import ConfigError
from radscene.geometry.frames import direction_from_angles, normalize
from radscene.materials import brdf
from radscene.materials.brdf import lambertian, phong

CHI2_QUANTILE = 0.999  # reject a correct sampler 1 time in 1000 (fixed seeds: deterministic)


def _random_unit(rng, n):
    return normalize(rng.normal(size=(n, 3)))


# ---------------------------------------------------------------------------- Lambertian
def test_lambertian_brdf_value_and_broadcast():
    assert lambertian.brdf(0.5) == pytest.approx(0.5 / np.pi, rel=1e-15)
    rho = np.linspace(0.0, 1.0, 12).reshape(3, 4)
    assert lambertian.brdf(rho).shape == (3, 4)


def test_lambertian_cosine_sampling_mean_cos_is_two_thirds():
    rng = np.random.default_rng(1)
    n = 200_000
    normal = normalize(np.array([0.3, -0.2, 0.9]))
    d, pdf = lambertian.sample(normal, rng.random(n), rng.random(n))
    cos = d @ normal
    # E[cos] = 2/3, sd of cos = sqrt(1/2 - 4/9); 6 standard errors
    assert cos.mean() == pytest.approx(2.0 / 3.0, abs=6 * np.sqrt(1 / 18) / np.sqrt(n))
    assert np.all(cos >= 0.0)
    np.testing.assert_allclose(np.linalg.norm(d, axis=-1), 1.0, rtol=0, atol=1e-12)
    np.testing.assert_allclose(pdf, cos / np.pi, rtol=0, atol=1e-12)
    np.testing.assert_allclose(lambertian.pdf(d, normal), pdf, rtol=0, atol=1e-12)


def test_lambertian_sampling_chi2_of_cos_theta():
    rng = np.random.default_rng(2)
    n, bins = 100_000, 20
    d, _ = lambertian.sample([0.0, 0.0, 1.0], rng.random(n), rng.random(n))
    edges = np.linspace(0.0, 1.0, bins + 1)
    counts, _ = np.histogram(d[:, 2], edges)
    expected = n * np.diff(edges**2)  # P(cos <= c) = c^2 for density cos/pi
    chi2 = np.sum((counts - expected) ** 2 / expected)
    assert chi2 < stats.chi2.ppf(CHI2_QUANTILE, bins - 1)


def test_lambertian_sample_broadcasting_and_bad_u():
    normals = normalize(np.ones((4, 1, 3)))
    d, pdf = lambertian.sample(normals, np.full(5, 0.3), 0.7)
    assert d.shape == (4, 5, 3) and pdf.shape == (4, 5)
    with pytest.raises(ConfigError, match=r"\[0, 1\]"):
        lambertian.sample([0, 0, 1], 1.5, 0.2)


# ---------------------------------------------------------------------------- Phong
def test_mirror_reference_and_properties():
    assert phong.mirror([1.0, 0.0, 1.0], [0.0, 0.0, 1.0]) == pytest.approx([-1.0, 0.0, 1.0])
    rng = np.random.default_rng(3)
    d, n = _random_unit(rng, 100), _random_unit(rng, 100)
    r = phong.mirror(d, n)
    assert np.linalg.norm(r, axis=-1) == pytest.approx(np.ones(100), abs=1e-12)
    assert np.sum(r * n, axis=-1) == pytest.approx(np.sum(d * n, axis=-1), abs=1e-12)
    # sun at zenith 30 deg, azimuth 90 (east): the reflected ray leaves towards the west
    sun = direction_from_angles(30.0, 90.0)
    assert phong.mirror(sun, [0, 0, 1]) == pytest.approx(
        direction_from_angles(30.0, 270.0), abs=1e-12
    )


@pytest.mark.parametrize("exponent", [0.0, 1.0, 5.0, 50.0, 200.0, 1000.0])
def test_lobe_integrates_to_one_over_hemisphere(exponent):
    # integral over the hemisphere about the axis: 2 pi * int_0^{pi/2} lobe(cos a) sin a da
    value, _ = integrate.quad(
        lambda a: 2 * np.pi * phong.lobe(np.cos(a), exponent) * np.sin(a),
        0.0,
        np.pi / 2,
        epsabs=1e-12,
        epsrel=1e-12,
        limit=200,
    )
    assert value == pytest.approx(1.0, abs=1e-6)


def test_lobe_values():
    assert phong.lobe(1.0, 10.0) == pytest.approx(11.0 / (2 * np.pi), rel=1e-15)
    assert phong.lobe(0.5, 2.0) == pytest.approx(3.0 / (2 * np.pi) * 0.25, rel=1e-15)
    assert phong.lobe([-0.1, -1.0], 3.0) == pytest.approx([0.0, 0.0], abs=0.0)
    assert phong.lobe(0.0, 0.0) == pytest.approx(1 / (2 * np.pi), rel=1e-15)
    assert phong.lobe(np.zeros((2, 3)), np.ones((3,))).shape == (2, 3)
    with pytest.raises(ConfigError, match="exponent must be finite and >= 0"):
        phong.lobe(0.5, -1.0)


def test_phong_sampling_chi2_of_cos_alpha():
    rng = np.random.default_rng(4)
    n, bins, exponent = 100_000, 20, 20.0
    axis = normalize(np.array([0.2, 0.5, 0.8]))
    d, pdf = phong.sample(axis, exponent, rng.random(n), rng.random(n))
    cos = d @ axis
    # equal-probability bins of P(cos a <= c) = c^(n+1)
    edges = np.linspace(0.0, 1.0, bins + 1) ** (1.0 / (exponent + 1.0))
    counts, _ = np.histogram(cos, edges)
    expected = np.full(bins, n / bins)
    chi2 = np.sum((counts - expected) ** 2 / expected)
    assert chi2 < stats.chi2.ppf(CHI2_QUANTILE, bins - 1)
    np.testing.assert_allclose(pdf, phong.lobe(cos, exponent), rtol=1e-10, atol=0)
    np.testing.assert_allclose(phong.pdf(d, axis, exponent), pdf, rtol=1e-10, atol=0)
    # azimuth about the axis is uniform: mean of the perpendicular component is ~0
    perp = d - cos[:, None] * axis
    assert np.abs(perp.mean(axis=0)) == pytest.approx(np.zeros(3), abs=5e-3)


def test_phong_sample_broadcasting():
    axes = normalize(np.ones((3, 1, 3)))
    d, pdf = phong.sample(axes, np.array([1.0, 10.0]), 0.5, 0.25)
    assert d.shape == (3, 2, 3) and pdf.shape == (3, 2)
    with pytest.raises(ConfigError, match=r"\[0, 1\]"):
        phong.sample([0, 0, 1], 5.0, 0.5, -0.1)


def test_phong_brdf_reciprocity():
    rng = np.random.default_rng(5)
    m = 2000
    normal = np.array([0.0, 0.0, 1.0])
    wi = _random_unit(rng, m)
    wo = _random_unit(rng, m)
    wi[:, 2] = np.abs(wi[:, 2])
    wo[:, 2] = np.abs(wo[:, 2])
    for exponent in (0.0, 3.0, 40.0):
        f1 = phong.brdf(wi, wo, normal, 0.3, exponent)
        f2 = phong.brdf(wo, wi, normal, 0.3, exponent)
        np.testing.assert_allclose(f1, f2, rtol=1e-12, atol=0)
        assert np.any(f1 > 0.0)


def test_phong_brdf_matches_ossim_term_at_mirror_direction():
    # OSSIM eq. 4: L = E_sun rho_s lobe(cos theta_r); as a BRDF L / (E_sun cos theta_i)
    normal = np.array([0.0, 0.0, 1.0])
    sun = direction_from_angles(40.0, 135.0)
    view = normalize(phong.mirror(sun, normal) + np.array([0.0, 0.02, 0.0]))
    cos_i = sun @ normal
    assert view @ normal <= cos_i  # in this geometry the plain OSSIM form applies
    e_sun, rho_s, n = 1000.0, 0.04, 100.0
    radiance = e_sun * cos_i * phong.brdf(sun, view, normal, rho_s, n)
    cos_r = view @ phong.mirror(sun, normal)
    assert radiance == pytest.approx(e_sun * rho_s * phong.lobe(cos_r, n), rel=1e-12)


def test_phong_brdf_zero_below_horizon():
    normal = np.array([0.0, 0.0, 1.0])
    up = np.array([0.0, 0.0, 1.0])
    below = normalize(np.array([0.3, 0.0, -0.2]))
    assert phong.brdf(below, up, normal, 0.5, 1.0) == 0.0
    assert phong.brdf(up, below, normal, 0.5, 1.0) == 0.0


@pytest.mark.parametrize(("zenith", "exponent"), [(0.0, 500.0), (80.0, 1.0), (85.0, 0.0)])
def test_phong_brdf_energy_conservation(zenith, exponent):
    # directional-hemispherical reflectance by Monte Carlo (cosine-weighted outgoing samples)
    rng = np.random.default_rng(6)
    m = 400_000
    normal = np.array([0.0, 0.0, 1.0])
    wi = direction_from_angles(zenith, 0.0)
    wo, pdf = lambertian.sample(normal, rng.random(m), rng.random(m))
    est = phong.brdf(wi, wo, normal, 1.0, exponent) * (wo @ normal) / pdf
    albedo, err = est.mean(), est.std() / np.sqrt(m)
    assert albedo <= 1.0 + 5 * err
    if zenith == 0.0:  # narrow lobe about the normal: nearly all of rho_s is reflected
        assert albedo == pytest.approx(1.0, abs=5 * err + 5e-3)


def test_registry():
    assert brdf.get_model("Phong") is phong
    assert brdf.get_model("LAMBERTIAN") is lambertian
    with pytest.raises(ConfigError, match="unknown BRDF model 'rpv'; known: lambertian, phong"):
        brdf.get_model("rpv")
