"""Water (and ice/snow): Fresnel from a complex refractive index, absorption, emissivity."""

import math

import numpy as np
import pytest
from scipy import integrate

from radscene.errors import ConfigError
from radscene.materials import get_material
from radscene.materials.snow import ice_refractive_index, snow_reflectance, snow_spherical_albedo
from radscene.materials.water import (
    deep_water_diffuse_reflectance,
    fresnel_reflectance,
    fresnel_reflectance_polarised,
    hemispherical_fresnel_reflectance,
    pure_seawater_backscattering,
    water_absorption_coefficient,
    water_emissivity,
    water_hemispherical_emissivity,
    water_material,
    water_refractive_index,
    water_transmittance,
)

TIGHT = 1e-12


def born_wolf(n, k, theta_deg):
    """Independent oracle: Fresnel reflectances of an absorbing medium in real arithmetic
    (Born & Wolf; Siegel & Howell, Thermal Radiation Heat Transfer, eqs. for a and b)."""
    t = math.radians(theta_deg)
    s2 = math.sin(t) ** 2
    c = n * n - k * k - s2
    root = math.sqrt(c * c + 4 * n * n * k * k)
    a = math.sqrt((root + c) / 2)
    b = math.sqrt((root - c) / 2)
    cos_t = math.cos(t)
    rs = ((a - cos_t) ** 2 + b * b) / ((a + cos_t) ** 2 + b * b)
    st = math.sin(t) * math.tan(t)
    rp = rs * ((a - st) ** 2 + b * b) / ((a + st) ** 2 + b * b)
    return rs, rp


def test_glass_at_45_degrees_textbook():
    # n = 1.5 at 45 deg: R_s = 0.0920, R_p = 0.0085 (Hecht, Optics, Fig. 4.49 values)
    rs, rp = fresnel_reflectance_polarised(1.5, 0.0, 45.0)
    assert float(rs) == pytest.approx(0.09202, abs=5e-5)
    assert float(rp) == pytest.approx(0.008468, abs=5e-6)
    # normal incidence closed form and Brewster's angle (R_p = 0 at tan(theta) = n)
    assert float(fresnel_reflectance(1.5, 0.0)) == pytest.approx(0.04, rel=TIGHT)
    _, rp_b = fresnel_reflectance_polarised(1.5, 0.0, math.degrees(math.atan(1.5)))
    assert float(rp_b) == pytest.approx(0.0, abs=1e-15)
    assert float(fresnel_reflectance(1.33, 0.0, 90.0)) == pytest.approx(1.0, rel=TIGHT)


@pytest.mark.parametrize("n, k", [(1.218, 0.0508), (1.111, 0.199), (26.2, 88.2), (0.95, 0.25)])
@pytest.mark.parametrize("theta", [0.0, 20.0, 45.0, 70.0, 85.0])
def test_absorbing_media_match_born_wolf(n, k, theta):
    rs, rp = fresnel_reflectance_polarised(n, k, theta)
    ref_s, ref_p = born_wolf(n, k, theta)
    assert float(rs) == pytest.approx(ref_s, rel=1e-10)
    assert float(rp) == pytest.approx(ref_p, rel=1e-10)


def test_fresnel_broadcasts_and_refuses_bad_input():
    r = fresnel_reflectance(np.array([1.2, 1.3, 1.4])[:, None], 0.01, np.array([0.0, 30.0, 60.0, 89.0]))
    assert r.shape == (3, 4)
    assert np.all(np.diff(r, axis=1) > 0)  # more reflective towards grazing
    assert np.isnan(fresnel_reflectance(1.3, 0.0, np.nan))
    with pytest.raises(ConfigError, match=r"incidence_angle: must be in \[0, 90\] degrees; got 95"):
        fresnel_reflectance(1.3, 0.0, 95.0)
    with pytest.raises(ConfigError, match="n > 0 and k >= 0"):
        fresnel_reflectance(1.3, -0.1)


def test_hemispherical_reflectance_against_adaptive_quadrature():
    for n, k in [(1.218, 0.0508), (1.5, 0.0), (3.0, 2.0)]:
        ref, _ = integrate.quad(
            lambda mu, n=n, k=k: 2 * mu * 0.5 * sum(born_wolf(n, k, math.degrees(math.acos(mu)))),
            0.0, 1.0, epsabs=1e-13, limit=200,
        )
        assert float(hemispherical_fresnel_reflectance(n, k)) == pytest.approx(ref, rel=1e-6)
    # Stern (1964)-style check: n = 1.5 dielectric, diffuse reflectance 0.0918 (= 1 - 0.9082)
    assert float(hemispherical_fresnel_reflectance(1.5, 0.0)) == pytest.approx(0.0918, abs=2e-4)


def test_hale_querry_values_typed_from_table_1():
    # Hale & Querry (1973) Table 1: 10.0 um n 1.218 k 0.0508; 0.55 um n 1.333
    n, k = water_refractive_index([10.0, 0.55])
    assert n.tolist() == pytest.approx([1.218, 1.333], abs=1e-12)
    assert float(k[0]) == pytest.approx(0.0508, abs=1e-12)
    with pytest.raises(ConfigError, match="outside the Hale & Querry table"):
        water_refractive_index(25.0)


def test_nadir_emissivity_8_to_12_um_and_fall_towards_grazing():
    wl = np.linspace(8.0, 12.0, 41)
    eps0 = water_emissivity(wl, 0.0)
    assert np.all((eps0 >= 0.98) & (eps0 <= 0.995))  # issue 4, item 6
    angles = np.array([0.0, 30.0, 50.0, 60.0, 70.0, 80.0, 89.0])
    eps = water_emissivity(10.0, angles)
    assert np.all(np.diff(eps) < 0)
    assert float(eps[0] - eps[1]) < 2e-3  # nearly flat to 30 deg
    assert float(eps[4]) < 0.95 and float(eps[-1]) < 0.2
    # independent: 1 - Born & Wolf reflectance with the tabulated index at 10 um
    assert float(eps[3]) == pytest.approx(1 - 0.5 * sum(born_wolf(1.218, 0.0508, 60.0)), rel=1e-12)
    assert float(water_hemispherical_emissivity(10.0)) < float(eps[0])
    # the library's water material holds the normal-incidence values
    assert float(get_material("water").emissivity(10.0)) == pytest.approx(float(eps[0]), abs=1e-6)


def test_absorption_coefficient_and_transmittance():
    # a = 4 pi k / lambda; at 10 um, k = 0.0508 -> 6.384e4 m-1
    assert float(water_absorption_coefficient(10.0)) == pytest.approx(4 * math.pi * 0.0508 / 10e-6, rel=TIGHT)
    a = water_absorption_coefficient(0.55)
    t = water_transmittance(0.55, [0.0, 1.0, 10.0])
    np.testing.assert_allclose(t, np.exp(-a * np.array([0.0, 1.0, 10.0])), rtol=TIGHT)
    # deep water: visible light penetrates metres, 1.0 um only centimetres
    assert float(water_transmittance(0.5, 5.0)) > 0.8
    assert float(water_transmittance(1.0, 0.1)) < 0.05
    with pytest.raises(ConfigError, match="path_length must be >= 0"):
        water_transmittance(0.5, -1.0)


def test_deep_water_reflectance_model():
    wl = np.array([0.45, 0.55, 0.7])
    a = water_absorption_coefficient(wl)
    bb = pure_seawater_backscattering(wl)
    assert float(bb[0]) == pytest.approx(0.5 * 0.00288 * 0.9**-4.32, rel=TIGHT)  # Morel 1974
    r_below = 0.33 * bb / (a + bb)
    rrs = 0.52 * (r_below / math.pi) / (1 - 1.7 * r_below / math.pi)
    np.testing.assert_allclose(deep_water_diffuse_reflectance(wl), math.pi * rrs, rtol=TIGHT)
    # blue water: the diffuse reflectance falls with wavelength
    assert np.all(np.diff(deep_water_diffuse_reflectance(wl)) < 0)
    turbid = deep_water_diffuse_reflectance(0.55, backscattering=0.01)
    assert float(turbid) > float(deep_water_diffuse_reflectance(0.55))
    with pytest.raises(ConfigError, match="must be >= 0"):
        deep_water_diffuse_reflectance(0.55, absorption=-1.0)


def test_water_material_kirchhoff():
    m = water_material(diffuse_reflectance=0.01, specular_exponent=500.0)
    wl = np.linspace(0.4, 20.0, 500)
    c = m.components(wl)
    np.testing.assert_allclose(sum(c.values()), 1.0, rtol=TIGHT)
    assert m.specular_exponent == 500.0
    assert float(m.specular_reflectance(10.0)) == pytest.approx(1 - float(water_emissivity(10.0)), rel=1e-12)


# --------------------------------------------------------------------- ice and snow
def test_ice_index_typed_from_warren_brandt():
    # Warren & Brandt (2008): 1.03 um n 1.3010 k 2.33e-6; 10.0 um n 1.1926 k 5.008e-2
    n, k = ice_refractive_index([1.03, 10.0])
    assert n.tolist() == pytest.approx([1.3010, 1.1926], abs=1e-12)
    assert k.tolist() == pytest.approx([2.33e-6, 5.008e-2], rel=1e-12)


def test_snow_art_formula_and_max_rule():
    d = 0.25e-3
    ell = 16 * 1.6 * d / (9 * 0.25)
    alpha = 4 * math.pi * 2.33e-6 / 1.03e-6
    assert float(snow_spherical_albedo(1.03, d)) == pytest.approx(math.exp(-math.sqrt(alpha * ell)), rel=1e-12)
    r = snow_reflectance([0.5, 1.03, 1.3, 2.0, 10.0], d)
    assert float(r[0]) > 0.98  # visible: almost white
    assert 0.65 < float(r[1]) < 0.85 and 0.45 < float(r[2]) < 0.65
    fresnel_ice = fresnel_reflectance(*ice_refractive_index([2.0, 10.0]))
    np.testing.assert_allclose(r[3:], fresnel_ice, rtol=1e-12)  # strong absorption: surface only
    # coarser grains are darker in the near infrared
    assert float(snow_reflectance(1.3, 1e-3)) < float(snow_reflectance(1.3, 1e-4))
    with pytest.raises(ConfigError, match="grain_diameter"):
        snow_reflectance(1.0, -1.0)
    snow = get_material("snow")
    assert float(snow.emissivity(10.0)) == pytest.approx(1 - float(fresnel_ice[1]), abs=1e-6)
