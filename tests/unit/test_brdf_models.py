"""Reference values of the individual BRDF models and of the Fresnel equations.

Oracles: textbook Fresnel values and an independent (real-angle / Born & Wolf a, b) form of the
equations; normalisation identities of microfacet distributions (Walter et al. 2007; Heitz
2014); Cox & Munk's slope variance; the RPV formula written from the paper in angles; MODIS
kernel integrals (Lucht et al. 2000); Chandrasekhar's H function solved by iteration; the
compiled fast paths against their numpy references.
"""

import numpy as np
import pytest
from scipy import integrate, optimize

from radscene.errors import ConfigError
from radscene.geometry.frames import direction_from_angles
from radscene.materials.brdf import make_brdf
from radscene.materials.brdf.base import cos_phase_from_angles
from radscene.materials.brdf.coxmunk import mean_square_slope
from radscene.materials.brdf.fresnel import fresnel_amplitudes, fresnel_reflectance
from radscene.materials.brdf.hapke import h_function
from radscene.materials.brdf.microfacet import (
    beckmann_distribution,
    beckmann_lambda,
    ggx_distribution,
    ggx_lambda,
)
from radscene.materials.brdf.rossli import li_sparse, ross_thick

FRESNEL_ABS = 1e-12  # two closed forms of the same equations
QUAD_ABS = 1e-6  # scipy.integrate results


# ---------------------------------------------------------------------------- Fresnel
def _fresnel_snell(theta_deg, n):
    """Real dielectric: Fresnel's sine and tangent laws with Snell's refraction angle."""
    ti = np.radians(theta_deg)
    tt = np.arcsin(np.sin(ti) / n)
    if ti == 0.0:
        return ((n - 1.0) / (n + 1.0)) ** 2
    rs = -np.sin(ti - tt) / np.sin(ti + tt)
    rp = np.tan(ti - tt) / np.tan(ti + tt)
    return 0.5 * (rs * rs + rp * rp)


def _fresnel_absorbing(theta_deg, n, k):
    """Absorbing medium: Born & Wolf's real a, b form (independent of the complex one)."""
    t = np.radians(theta_deg)
    s2 = np.sin(t) ** 2
    c = np.cos(t)
    root = np.sqrt((n * n - k * k - s2) ** 2 + 4 * n * n * k * k)
    a = np.sqrt(0.5 * (root + n * n - k * k - s2))
    ab2 = root  # a^2 + b^2
    rs = (ab2 - 2 * a * c + c * c) / (ab2 + 2 * a * c + c * c)
    st = np.sin(t) * np.tan(t)
    rp = rs * (ab2 - 2 * a * st + st * st) / (ab2 + 2 * a * st + st * st)
    return 0.5 * (rs + rp)


def test_fresnel_glass_textbook_values():
    assert float(fresnel_reflectance(1.0, 1.5)) == pytest.approx(0.04, abs=FRESNEL_ABS)
    # n = 1.5 at 45 deg: R_s = 0.0920, R_p = 0.0085 (e.g. Hecht, Optics, fig. 4.43)
    assert float(fresnel_reflectance(np.cos(np.radians(45.0)), 1.5)) == pytest.approx(
        0.5 * (0.0920 + 0.0085), abs=1e-4)
    assert float(fresnel_reflectance(0.0, 1.5)) == pytest.approx(1.0, abs=FRESNEL_ABS)


@pytest.mark.parametrize("theta", [0.0, 10.0, 30.0, 45.0, 60.0, 75.0, 85.0, 89.0])
def test_fresnel_dielectric_matches_snell_form(theta):
    got = float(fresnel_reflectance(np.cos(np.radians(theta)), 1.333))
    assert got == pytest.approx(_fresnel_snell(theta, 1.333), abs=FRESNEL_ABS)


def test_fresnel_brewster_angle():
    n = 1.5
    brewster = np.arctan(n)
    _, r_p = fresnel_amplitudes(np.cos(brewster), n)
    assert abs(complex(r_p)) == pytest.approx(0.0, abs=1e-12)


@pytest.mark.parametrize("theta", [0.0, 20.0, 45.0, 70.0, 85.0])
@pytest.mark.parametrize(("n", "k"), [(0.96, 6.69), (1.218, 0.0508), (0.2, 3.4)],
                         ids=["aluminium_0.55um", "water_10um", "gold_0.65um"])
def test_fresnel_absorbing_media_match_born_wolf_form(theta, n, k):
    got = float(fresnel_reflectance(np.cos(np.radians(theta)), n, k))
    assert got == pytest.approx(_fresnel_absorbing(theta, n, k), abs=FRESNEL_ABS)


def test_fresnel_conductor_normal_incidence():
    # aluminium at 0.55 um (n 0.96, k 6.69; Rakic 1995): R = ((n-1)^2+k^2)/((n+1)^2+k^2) = 0.9210
    assert float(fresnel_reflectance(1.0, 0.96, 6.69)) == pytest.approx(0.9210, abs=1e-4)


def test_fresnel_broadcasts():
    r = fresnel_reflectance(np.linspace(0, 1, 5)[:, None], np.array([1.3, 1.5, 2.0]), 0.1)
    assert r.shape == (5, 3) and np.all((r >= 0) & (r <= 1))


# ---------------------------------------------------------------------------- microfacets
@pytest.mark.parametrize("alpha", [0.05, 0.3, 0.8])
@pytest.mark.parametrize("dist", [ggx_distribution, beckmann_distribution],
                         ids=["ggx", "beckmann"])
def test_distribution_projected_area_is_one(dist, alpha):
    # int D(h) cos(theta_h) d omega_h = 1 (Walter et al. 2007)
    value, _ = integrate.quad(lambda t: 2 * np.pi * dist(np.cos(t), alpha) * np.cos(t)
                              * np.sin(t), 0.0, np.pi / 2, limit=400, epsabs=1e-12)
    assert value == pytest.approx(1.0, abs=QUAD_ABS)


@pytest.mark.parametrize("view_zenith", [0.0, 45.0, 80.0])
@pytest.mark.parametrize(("dist", "lam"), [(ggx_distribution, ggx_lambda),
                                           (beckmann_distribution, beckmann_lambda)],
                         ids=["ggx", "beckmann"])
def test_smith_masking_weak_white_furnace(dist, lam, view_zenith):
    # int G1(wo) D(h) max(0, wo.h) d omega_h = cos(theta_o), G1 = 1/(1 + Lambda) (Heitz 2014),
    # by Gauss-Legendre in theta_h and, in phi_h, Gauss-Legendre on the arc where wo.h > 0
    alpha = 0.4
    mu_o = np.cos(np.radians(view_zenith))
    s_o = np.sqrt(1 - mu_o * mu_o)
    t, wt = np.polynomial.legendre.leggauss(400)
    t, wt = 0.25 * np.pi * (t + 1.0), 0.25 * np.pi * wt
    x, wx = np.polynomial.legendre.leggauss(400)
    total = 0.0
    for theta, w_theta in zip(t, wt, strict=True):
        # wo.h = mu_o cos t + s_o sin t cos phi > 0  <=>  cos phi > -mu_o cos t / (s_o sin t)
        c = -mu_o * np.cos(theta) / max(s_o * np.sin(theta), 1e-300)
        half = np.pi if c <= -1.0 else (0.0 if c >= 1.0 else np.arccos(c))
        phi, w_phi = half * x, half * wx  # symmetric arc [-half, half]
        dot = mu_o * np.cos(theta) + s_o * np.sin(theta) * np.cos(phi)
        total += w_theta * np.sin(theta) * float(dist(np.cos(theta), alpha)) * np.sum(
            w_phi * dot)
    g1 = 1.0 / (1.0 + float(lam(mu_o, alpha))) if view_zenith else 1.0
    assert g1 * total == pytest.approx(mu_o, abs=1e-6)


def test_smooth_microfacet_albedo_tends_to_fresnel():
    glass = make_brdf({"type": "ggx", "roughness": 0.01, "refractive_index": 1.5})
    metal = make_brdf({"type": "beckmann", "roughness": 0.01, "refractive_index": 0.96,
                       "extinction_coefficient": 6.69})
    for theta in (0.0, 30.0, 60.0):
        w = direction_from_angles(theta, 0.0)
        c = np.cos(np.radians(theta))
        assert float(glass.albedo(w)) == pytest.approx(float(fresnel_reflectance(c, 1.5)),
                                                       rel=1e-2)
        assert float(metal.albedo(w)) == pytest.approx(
            float(fresnel_reflectance(c, 0.96, 6.69)), rel=1e-2)


def test_microfacet_value_at_the_mirror_direction():
    # sun and view at the same zenith, opposite azimuths: h = n, f = F(theta) D(1) G2 / (4 mu^2)
    alpha, n = 0.2, 1.5
    m = make_brdf({"type": "ggx", "roughness": alpha, "refractive_index": n})
    theta = 40.0
    mu = np.cos(np.radians(theta))
    g2 = 1.0 / (1.0 + 2.0 * float(ggx_lambda(mu, alpha)))
    expected = float(fresnel_reflectance(mu, n)) / (np.pi * alpha**2) * g2 / (4 * mu * mu)
    assert float(m.f_angles(theta, theta, 180.0)) == pytest.approx(expected, rel=1e-12)


# ---------------------------------------------------------------------------- Cox-Munk
def test_cox_munk_slope_variance():
    # Cox & Munk (1954), clean surface: sigma^2 = 0.003 + 5.12e-3 W
    assert mean_square_slope([0.0, 5.0, 10.0]) == pytest.approx([0.003, 0.0286, 0.0542],
                                                                abs=1e-12)


def test_cox_munk_nadir_glint_value():
    # sun and view at nadir: tan(theta_h) = 0, p = 1/(pi sigma^2), G2 = 1:
    # f = F(0) / (4 pi sigma^2)
    sea = make_brdf({"type": "coxmunk", "wind_speed": 7.0, "refractive_index": 1.34})
    r0 = ((1.34 - 1) / (1.34 + 1)) ** 2
    expected = r0 / (4 * np.pi * (0.003 + 5.12e-3 * 7.0))
    assert float(sea.f([0, 0, 1.0], [0, 0, 1.0])) == pytest.approx(expected, rel=1e-12)


def test_cox_munk_glint_lies_in_the_specular_direction():
    # at a low wind the peak of f sits within a degree of the mirror direction (the 1/mu_o
    # factor and the rising Fresnel term push it slightly outward)
    sea = make_brdf({"type": "coxmunk", "wind_speed": 0.5, "refractive_index": 1.34})
    sun = direction_from_angles(35.0, 90.0)
    zen, azi = np.meshgrid(np.arange(0.0, 89.0, 0.25), np.arange(0.0, 360.0, 1.0),
                           indexing="ij")
    f = sea.f(sun, direction_from_angles(zen, azi))
    i, j = np.unravel_index(np.argmax(f), f.shape)
    assert zen[i, j] == pytest.approx(35.0, abs=1.0)
    assert azi[i, j] == pytest.approx(270.0, abs=1.0)


@pytest.mark.parametrize("wavelength", [8.0, 10.0, 12.0])
def test_water_emissivity_about_0_98_to_0_99_at_nadir_falling_toward_grazing(wavelength):
    sea = make_brdf({"type": "coxmunk", "wind_speed": 2.0})  # Hale & Querry water
    zen = np.array([0.0, 20.0, 40.0, 55.0, 65.0, 75.0, 85.0])
    eps = sea.emissivity(direction_from_angles(zen, 0.0), wavelength)
    assert 0.98 <= eps[0] <= 0.995
    assert np.all(np.diff(eps) < 0.0)  # falls toward grazing
    assert eps[-1] < 0.85


def test_water_emissivity_follows_fresnel_at_low_wind():
    # a nearly flat sea: epsilon(theta) = 1 - R(theta) of the flat surface (Kirchhoff)
    n, k = 1.218, 0.0508  # water at 10 um (Hale & Querry 1973)
    sea = make_brdf({"type": "coxmunk", "wind_speed": 0.0, "refractive_index": n,
                     "extinction_coefficient": k})
    zen = np.array([0.0, 30.0, 50.0, 60.0, 70.0])
    eps = sea.emissivity(direction_from_angles(zen, 0.0))
    flat = 1.0 - fresnel_reflectance(np.cos(np.radians(zen)), n, k)
    assert eps == pytest.approx(flat, abs=3e-3)


def test_cox_munk_refuses_k_without_n():
    with pytest.raises(ConfigError, match="extinction_coefficient needs refractive_index"):
        make_brdf({"type": "coxmunk", "wind_speed": 1.0, "extinction_coefficient": 0.1})
    with pytest.raises(ConfigError, match="needs a wavelength"):
        make_brdf({"type": "coxmunk", "wind_speed": 1.0}).f([0, 0, 1.0], [0, 0, 1.0])


# ---------------------------------------------------------------------------- RPV
def _rpv_from_angles(ti, to, dphi, rho0, k, theta, rho_c):
    """Rahman et al. (1993) written with angles; dphi = 0 backscatter."""
    ti, to, dphi = np.radians(ti), np.radians(to), np.radians(dphi)
    cos_g = np.cos(ti) * np.cos(to) + np.sin(ti) * np.sin(to) * np.cos(dphi)
    m = (np.cos(ti) * np.cos(to) * (np.cos(ti) + np.cos(to))) ** (k - 1)
    f = (1 - theta**2) / (1 + 2 * theta * cos_g + theta**2) ** 1.5
    big_g = np.sqrt(np.tan(ti) ** 2 + np.tan(to) ** 2
                    - 2 * np.tan(ti) * np.tan(to) * np.cos(dphi))
    return rho0 * m * f * (1 + (1 - rho_c) / (1 + big_g))


def test_rpv_matches_the_formula_in_angles():
    rng = np.random.default_rng(3)
    ti, to, dphi = rng.uniform(0, 85, 500), rng.uniform(0, 85, 500), rng.uniform(0, 360, 500)
    m = make_brdf({"type": "rpv", "rho0": 0.1, "k": 0.8, "theta": 0.15, "rho_c": 0.3})
    expected = _rpv_from_angles(ti, to, dphi, 0.1, 0.8, 0.15, 0.3) / np.pi
    assert m.f_angles(ti, to, dphi) == pytest.approx(expected, rel=1e-10)


def test_rpv_hot_spot_is_in_the_backscatter_direction():
    m = make_brdf({"type": "rpv", "rho0": 0.076, "k": 0.648, "theta": -0.29})
    to = np.arange(0.0, 80.0, 0.25)
    back = m.f_angles(40.0, to, 0.0)
    assert to[np.argmax(back)] == pytest.approx(40.0, abs=0.25)
    assert back.max() > m.f_angles(40.0, to, 180.0).max()


def test_rpv_spectral_parameters():
    m = make_brdf({"type": "rpv", "rho0": {"wavelength": [0.4, 1.0], "values": [0.05, 0.25]},
                   "k": 0.7, "theta": -0.1})
    f = m.f_angles(30.0, 20.0, 60.0, np.array([0.4, 0.7, 1.0]))
    # rho_c defaults to rho0, so the hot-spot factor varies with rho0 too
    expected = [_rpv_from_angles(30.0, 20.0, 60.0, r, 0.7, -0.1, r) / np.pi
                for r in (0.05, 0.15, 0.25)]
    assert f == pytest.approx(expected, rel=1e-12)
    with pytest.raises(ConfigError, match="rho0 of BRDF 'rpv' varies with wavelength"):
        m.f_angles(30.0, 20.0, 60.0)


# ---------------------------------------------------------------------------- Ross-Li
def _kernel_albedo(kernel, theta_deg, n=160):
    """Black-sky albedo of a kernel, (1/pi) int K mu d omega, by Gauss-Legendre x midpoints."""
    x, w = np.polynomial.legendre.leggauss(n)
    mu, w = 0.5 * (x + 1.0), 0.5 * w
    phi = (np.arange(2 * n) + 0.5) * np.pi / (2 * n)
    mi = np.cos(np.radians(theta_deg))
    mm, pp = np.meshgrid(mu, phi, indexing="ij")
    cg = mi * mm + np.sqrt(1 - mi * mi) * np.sqrt(1 - mm * mm) * np.cos(pp)
    return float(np.sum(kernel(mi, mm, cg) * mm * w[:, None]) * (np.pi / (2 * n)) * 2 / np.pi)


# Lucht, Schaaf & Strahler (2000), Table 1: black-sky albedo of the kernels as
# g0 + g1 theta^2 + g2 theta^3 (theta in rad) and white-sky albedo
MODIS_BLACK_SKY = {"vol": (-0.007574, -0.070987, 0.307588), "geo": (-1.284909, -0.166314,
                                                                    0.041840)}
MODIS_WHITE_SKY = {"vol": 0.189184, "geo": -1.377622}
#: The published cubic is a fit to the integrals; it departs from them by up to 0.018 (K_vol)
#: and 0.006 (K_geo) between 0 and 70 deg. The white-sky values are exact integrals.
MODIS_POLY_ABS = 0.02
MODIS_WHITE_ABS = 1e-4


@pytest.mark.parametrize("name", ["vol", "geo"])
def test_modis_kernel_integrals(name):
    kernel = ross_thick if name == "vol" else li_sparse
    for theta in (0.0, 20.0, 40.0, 60.0, 70.0):
        g0, g1, g2 = MODIS_BLACK_SKY[name]
        t = np.radians(theta)
        assert _kernel_albedo(kernel, theta) == pytest.approx(g0 + g1 * t**2 + g2 * t**3,
                                                              abs=MODIS_POLY_ABS)
    x, w = np.polynomial.legendre.leggauss(40)
    mu, w = 0.5 * (x + 1.0), 0.5 * w
    white = sum(2 * m * wk * _kernel_albedo(kernel, np.degrees(np.arccos(m)), 120)
                for m, wk in zip(mu, w, strict=True))
    assert white == pytest.approx(MODIS_WHITE_SKY[name], abs=MODIS_WHITE_ABS)


def test_rossli_albedo_is_the_kernel_combination():
    # f_iso + f_vol K_vol + f_geo K_geo > 0 everywhere here, so no flooring; the base
    # quadrature must reproduce the independent kernel integrals
    m = make_brdf({"type": "rossli", "f_iso": 0.4, "f_vol": 0.2, "f_geo": 0.01})
    for theta in (0.0, 30.0, 60.0, 80.0):
        expected = (0.4 + 0.2 * _kernel_albedo(ross_thick, theta)
                    + 0.01 * _kernel_albedo(li_sparse, theta))
        assert float(m.albedo(direction_from_angles(theta, 0.0))) == pytest.approx(
            expected, abs=1e-4)  # the kink of the Li overlap term limits the built-in rule


def test_rossli_kernels_vanish_at_nadir_and_hot_spot_doubles_volume_term():
    assert float(ross_thick(1.0, 1.0, 1.0)) == pytest.approx(0.0, abs=1e-15)
    assert float(li_sparse(1.0, 1.0, 1.0)) == pytest.approx(0.0, abs=1e-15)
    mu = np.cos(np.radians(40.0))
    plain = float(ross_thick(mu, mu, 1.0, None, "maignan")) + 1 / 3
    hot = float(ross_thick(mu, mu, 1.0, 1.5, "maignan")) + 1 / 3
    assert hot == pytest.approx(2 * plain, rel=1e-12)  # xi = 0: factor 1 + 1/(1 + 0) = 2


def test_rossli_floors_negative_brf_at_zero():
    m = make_brdf({"type": "rossli", "f_iso": 0.01, "f_vol": 0.0, "f_geo": 0.2})
    f = m.f_angles(80.0, 85.0, 180.0)
    assert float(f) == 0.0
    assert float(m.kernel_reference(*cos_phase_from_angles(80.0, 85.0, 180.0))) == 0.0


def test_li_sparse_original_is_not_reciprocal():
    m = make_brdf({"type": "rossli", "f_iso": 0.3, "f_vol": 0.1, "f_geo": 0.1,
                   "geometric": "sparse"})
    assert m.reciprocal is False
    assert float(m.f_angles(20.0, 60.0, 30.0)) != pytest.approx(
        float(m.f_angles(60.0, 20.0, 30.0)), rel=1e-3)


@pytest.mark.parametrize(("spec"), [
    {"type": "rpv", "rho0": {"wavelength": [0.4, 2.0], "values": [0.05, 0.3]}, "k": 0.7,
     "theta": -0.2, "rho_c": 0.1},
    {"type": "rossli", "f_iso": {"wavelength": [0.4, 2.0], "values": [0.1, 0.4]},
     "f_vol": 0.1, "f_geo": 0.05, "hotspot": True},
    {"type": "rossli", "f_iso": 0.3, "f_vol": 0.1, "f_geo": 0.05, "geometric": "sparse",
     "crown_height": 1.5, "crown_shape": 2.0, "normalization": "maignan"},
], ids=["rpv", "rossli_hotspot", "rossli_sparse"])
def test_compiled_kernels_match_numpy_reference(spec):
    m = make_brdf(spec)
    rng = np.random.default_rng(9)
    n = 5000
    mu_i = rng.uniform(-0.2, 1.0, n)
    mu_o = rng.uniform(-0.2, 1.0, n)
    dphi = rng.uniform(0.0, np.pi, n)
    cg = mu_i * mu_o + np.sqrt(1 - mu_i**2) * np.sqrt(1 - mu_o**2) * np.cos(dphi)
    wl = rng.uniform(0.4, 2.0, n)
    fast = m.kernel(mu_i, mu_o, cg, wl)
    ref = m.kernel_reference(mu_i, mu_o, cg, wl)
    np.testing.assert_allclose(fast, ref, rtol=1e-11, atol=1e-15)
    assert np.all(fast[(mu_i <= 0) | (mu_o <= 0)] == 0.0)


# ---------------------------------------------------------------------------- Hapke
def _chandrasekhar_h(w, mu, n=96):
    """Exact isotropic H function: Chandrasekhar's (1960) H = 1 + (w/2) mu H int H(x)/(mu + x) dx
    on Gauss-Legendre nodes, solved by Newton's method (scipy.optimize.fsolve)."""
    x, wx = np.polynomial.legendre.leggauss(n)
    x, wx = 0.5 * (x + 1.0), 0.5 * wx
    kernel = wx / (x[:, None] + x[None, :])

    def residual(h):
        return h - 1.0 - 0.5 * w * x * h * (kernel @ h)

    def jacobian(h):
        return (np.eye(n) * (1.0 - 0.5 * w * x * (kernel @ h))
                - 0.5 * w * (x * h)[:, None] * kernel)

    # full_output: at w = 1 (a bifurcation point) Newton converges only linearly, which fsolve
    # would report as a warning; the residual is checked instead
    h = optimize.fsolve(residual, np.full(n, 1.5), fprime=jacobian, xtol=1e-13,
                        full_output=True)[0]
    assert np.abs(residual(h)).max() < 1e-9
    mu = np.atleast_1d(mu)
    return 1.0 / (1.0 - 0.5 * w * mu * np.sum(wx * h / (mu[:, None] + x[None, :]), axis=1))


def test_chandrasekhar_oracle_against_his_table():
    # Chandrasekhar (1960), Table XI, conservative isotropic scattering: H(1) = 2.9078
    assert float(_chandrasekhar_h(1.0, 1.0)[0]) == pytest.approx(2.9078, abs=5e-4)


@pytest.mark.parametrize("w", [0.3, 0.8, 0.99])
def test_hapke_h_function_within_one_percent_of_exact(w):
    mu = np.linspace(0.0, 1.0, 21)
    assert h_function(mu, w) == pytest.approx(_chandrasekhar_h(w, mu), rel=1e-2)


#: Hapke's approximate H (error < 1 %) enters ρ_dh through H(μ_i) H(μ_o): ≤ 1.5e-2 off for w
#: up to 0.99, much less for darker surfaces.
HAPKE_ALBEDO_ABS = {0.3: 1e-3, 0.8: 5e-3, 0.99: 1.5e-2}


@pytest.mark.parametrize("w", [0.3, 0.8, 0.99])
def test_hapke_albedo_of_isotropic_scatterers(w):
    # exact H: rho_dh(mu) = 1 - sqrt(1 - w) H(mu) (Chandrasekhar 1960)
    m = make_brdf({"type": "hapke", "single_scattering_albedo": w})
    zen = np.array([0.0, 30.0, 60.0, 80.0])
    mu = np.cos(np.radians(zen))
    exact = 1.0 - np.sqrt(1.0 - w) * _chandrasekhar_h(w, mu)
    assert m.albedo(direction_from_angles(zen, 0.0)) == pytest.approx(
        exact, abs=HAPKE_ALBEDO_ABS[w])


def test_hapke_single_scattering_limit_is_lommel_seeliger():
    # w -> 0: H -> 1 and f -> w p(g) / (4 pi (mu_i + mu_o))
    w, b = 1e-4, -0.3
    m = make_brdf({"type": "hapke", "single_scattering_albedo": w, "asymmetry": b})
    mi, mo, cg = cos_phase_from_angles(30.0, 50.0, 70.0)
    p = (1 - b * b) / (1 + 2 * b * cg + b * b) ** 1.5
    assert float(m.kernel(mi, mo, cg)) == pytest.approx(w * p / (4 * np.pi * (mi + mo)),
                                                        rel=1e-3)


def test_hapke_opposition_surge_at_zero_phase():
    base = {"type": "hapke", "single_scattering_albedo": 0.5, "opposition_width": 0.05}
    plain = make_brdf(base)
    surge = make_brdf({**base, "opposition_amplitude": 1.0})
    # at g = 0 the single-scattering term doubles (B = B0 = 1); far from it B -> 0
    mi, mo, cg = cos_phase_from_angles(30.0, 30.0, 0.0)
    w = 0.5
    single = w / (4 * np.pi) * 1.0 / (mi + mo)  # isotropic p = 1
    assert float(surge.kernel(mi, mo, cg) - plain.kernel(mi, mo, cg)) == pytest.approx(
        single, rel=1e-9)
    far = cos_phase_from_angles(30.0, 60.0, 180.0)
    assert float(surge.kernel(*far) / plain.kernel(*far)) == pytest.approx(1.0, abs=0.05)


# ---------------------------------------------------------------------------- Lambert, Phong
def test_lambertian_and_transmission_closed_forms():
    lam = make_brdf({"type": "lambertian", "reflectance": 0.25})
    assert float(lam.f_angles(10.0, 70.0, 33.0)) == pytest.approx(0.25 / np.pi, rel=1e-15)
    assert float(lam.albedo([0, 0, 1.0])) == 0.25
    leaf = make_brdf({"type": "lambertian_transmission", "reflectance": 0.4,
                      "transmittance": 0.5})
    up, down = np.array([0, 0, 1.0]), np.array([0.6, 0, -0.8])
    assert float(leaf.f(up, down)) == pytest.approx(0.5 / np.pi, rel=1e-15)
    assert float(leaf.f(down, down)) == pytest.approx(0.4 / np.pi, rel=1e-15)
    assert float(leaf.transmittance(down)) == pytest.approx(0.5, rel=1e-15)
    assert float(leaf.emissivity(up)) == pytest.approx(0.1, abs=1e-15)


def test_phong_model_is_lambert_plus_ossim_lobe():
    from radscene.materials.brdf import lambertian, phong

    m = make_brdf({"type": "phong", "diffuse_reflectance": 0.2, "specular_reflectance": 0.05,
                   "specular_exponent": 80.0})
    rng = np.random.default_rng(5)
    wi = rng.normal(size=(300, 3))
    wo = rng.normal(size=(300, 3))
    wi /= np.linalg.norm(wi, axis=1, keepdims=True)
    wo /= np.linalg.norm(wo, axis=1, keepdims=True)
    normal = np.array([0.0, 0.0, 1.0])
    above = (wi[:, 2] > 0) & (wo[:, 2] > 0)
    expected = phong.brdf(wi, wo, normal, 0.05, 80.0) + np.where(above,
                                                                 lambertian.brdf(0.2), 0.0)
    np.testing.assert_allclose(m.f(wi, wo), expected, rtol=1e-12, atol=1e-15)
    # emissivity at normal incidence: the narrow lobe is reflected whole
    assert float(m.emissivity([0, 0, 1.0])) == pytest.approx(0.75, abs=2e-3)


# ---------------------------------------------------------------------------- hemispherical
def test_white_sky_reflectance_of_rossli_is_the_modis_combination():
    # white-sky albedo = f_iso + f_vol 0.189184 + f_geo (-1.377622) (Lucht et al. 2000)
    m = make_brdf({"type": "rossli", "f_iso": 0.4, "f_vol": 0.2, "f_geo": 0.01})
    expected = 0.4 + 0.2 * MODIS_WHITE_SKY["vol"] + 0.01 * MODIS_WHITE_SKY["geo"]
    assert float(m.bihemispherical_reflectance()) == pytest.approx(expected, abs=1e-4)
    assert float(m.hemispherical_emissivity()) == pytest.approx(1.0 - expected, abs=1e-4)


def test_hemispherical_emissivity_closed_forms_and_shape():
    lam = make_brdf({"type": "lambertian",
                     "reflectance": {"wavelength": [0.4, 2.0], "values": [0.1, 0.5]}})
    assert lam.bihemispherical_reflectance([0.4, 1.2]) == pytest.approx([0.1, 0.3], abs=1e-12)
    assert lam.hemispherical_emissivity(np.array([[0.4], [2.0]])).shape == (2, 1)
    leaf = make_brdf({"type": "lambertian_transmission", "reflectance": 0.4,
                      "transmittance": 0.5})
    assert float(leaf.hemispherical_emissivity()) == pytest.approx(0.1, abs=1e-12)
    # water: the hemispherical emissivity lies below the nadir one (Fresnel at grazing angles)
    sea = make_brdf({"type": "coxmunk", "wind_speed": 5.0})
    eps_h = sea.hemispherical_emissivity([8.0, 10.0, 12.0])
    eps_0 = sea.emissivity([0.0, 0.0, 1.0], [8.0, 10.0, 12.0])
    assert np.all(eps_h < eps_0) and np.all(eps_h > 0.93)
