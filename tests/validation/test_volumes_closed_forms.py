"""Participating volumes (:mod:`radscene.render.volumes`) against closed forms.

Each test renders a scene dict through ``radscene.render``: a grey slab (a box volume, wide
enough that the rays tested cross its top and bottom faces only) of vertical optical depth τ
above a black plate of known temperature, no atmosphere.

* Beer–Lambert: radiance from behind a slab seen at view zenith θ leaves it times
  t = e^{−τ/cos θ} (Bohren & Clothiaux, *Fundamentals of Atmospheric Radiation*, Wiley-VCH
  2006, §2.9).
* An isothermal, purely absorbing slab emits (1 − e^{−τ/cos θ}) B(T) (Kirchhoff's law for the
  slab, the formal solution of the transfer equation with a constant source function;
  Bohren & Clothiaux §2.9; Petty, *A First Course in Atmospheric Radiation*, 2nd ed., Sundog
  2006, eq. 8.10); with single-scattering albedo ω the absorbed share (1 − ω) of it.
* A slab between the sun and the plate lets e^{−τ/μ_0} of the direct sun through, μ_0 the
  cosine of the sun's zenith: the shadow it casts is partial.

The band integrals of B are computed here with scipy's adaptive quadrature, not radscene's.
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.integrate import quad

from radscene import render
from radscene.radiometry import spectral_radiance

LWIR = {"name": "lwir", "min": 8.0, "max": 12.0}
VIS = {"name": "vis", "min": 0.5, "max": 0.6}
PLATE_T, SLAB_T = 300.0, 350.0
#: Band radiance of a blackbody from radscene's quadrature against scipy's: both converge
#: to better than this.
BAND_REL = 1e-7
#: Ratios of radiances in which the same band integral cancels.
EXACT_REL = 1e-10


def _band_planck(temperature, band=LWIR):
    value, _ = quad(lambda wl: float(spectral_radiance(wl, temperature)), band["min"],
                    band["max"], epsabs=0.0, epsrel=1e-11, limit=200)
    return value


def _scene(tau=None, view_zenith=0.0, sun_zenith=120.0, albedo=0.0, extinction=None,
           reflectance=0.0, size=(60.0, 60.0, 2.0)):
    scene = {
        "name": "slab",
        "environment": {"sun": {"zenith": sun_zenith, "azimuth": 180.0},
                        "atmosphere": {"type": "none"}},
        "materials": {"plate": {"reflectance": reflectance}},
        "objects": [{"name": "plate", "shape": {"type": "plate", "width": 400, "length": 400},
                     "material": "plate", "temperature": PLATE_T}],
        "bands": [VIS, LWIR],
        "observers": [{"name": "cam", "type": "orthographic", "center": [0, 0], "gsd": 1.0,
                       "shape": [9, 9], "altitude": 1000, "zenith": view_zenith,
                       "azimuth": 90.0}],
        "render": {"background_bounces": 0},
    }
    if tau is not None or extinction is not None:
        medium = {"optical_depth": tau} if extinction is None else {"extinction": extinction}
        scene["volumes"] = [{"name": "slab", "shape": {"type": "box", "size": list(size)},
                             "position": [0, 0, 20], "temperature": SLAB_T,
                             "single_scattering_albedo": albedo, **medium}]
    return scene


@pytest.mark.parametrize("view_zenith", [0.0, 40.0])
@pytest.mark.parametrize("tau", [0.05, 0.7, 3.0])
def test_beer_lambert_transmittance(tau, view_zenith):
    clear = render(_scene(view_zenith=view_zenith))
    ds = render(_scene(tau, view_zenith=view_zenith))
    expected = np.exp(-tau / np.cos(np.radians(view_zenith)))
    for band in ("vis", "lwir"):
        behind = clear["radiance"].sel(band=band).values
        assert ds["volume_transmittance"].sel(band=band).values == pytest.approx(
            np.full((9, 9), expected), rel=EXACT_REL)
        assert ds["transmitted"].sel(band=band).values == pytest.approx(
            expected * behind, rel=EXACT_REL)
    # the plate is black and 300 K: what is left of its emission
    assert ds["transmitted"].sel(band="lwir").values == pytest.approx(
        np.full((9, 9), expected * _band_planck(PLATE_T)), rel=BAND_REL)


def test_extinction_coefficient_equals_its_optical_depth():
    """k = 0.35 m-1 over a 2 m slab is τ = 0.7."""
    a = render(_scene(0.7))
    b = render(_scene(extinction=0.35))
    assert b["radiance"].values == pytest.approx(a["radiance"].values, rel=EXACT_REL)


@pytest.mark.parametrize("view_zenith", [0.0, 40.0])
@pytest.mark.parametrize("tau", [0.05, 0.7, 3.0])
def test_isothermal_absorbing_slab_emission(tau, view_zenith):
    ds = render(_scene(tau, view_zenith=view_zenith))
    t = np.exp(-tau / np.cos(np.radians(view_zenith)))
    emission = (1.0 - t) * _band_planck(SLAB_T)
    assert ds["volume_emission"].sel(band="lwir").values == pytest.approx(
        np.full((9, 9), emission), rel=BAND_REL)
    total = t * _band_planck(PLATE_T) + emission
    assert ds["radiance"].sel(band="lwir").values == pytest.approx(np.full((9, 9), total),
                                                                   rel=BAND_REL)
    # the slab's brightness temperature lies between the plate's and its own
    bt = ds["brightness_temperature"].sel(band="lwir").values
    assert np.all((bt > PLATE_T) & (bt < SLAB_T))


def test_scattering_slab_emits_its_absorbed_share():
    dark = render(_scene(0.7))
    bright = render(_scene(0.7, albedo=0.4))
    assert bright["volume_emission"].values == pytest.approx(
        0.6 * dark["volume_emission"].values, rel=EXACT_REL)


def test_optically_thick_slab_is_a_blackbody():
    ds = render(_scene(60.0))
    assert ds["radiance"].sel(band="lwir").values == pytest.approx(
        np.full((9, 9), _band_planck(SLAB_T)), rel=BAND_REL)


@pytest.mark.parametrize("sun_zenith", [0.0, 30.0, 55.0])
@pytest.mark.parametrize("tau", [0.2, 1.5])
def test_partial_shadow_fraction(tau, sun_zenith):
    """A grey plate beside the slab's footprint, under its shadow: seen from nadir where the
    line of sight misses the slab and the sun ray crosses it top to bottom."""
    # ground points north of the slab (|y| <= 10 m, z 19-21 m) whose sun rays cross it
    # through its bottom and top faces
    slope = np.tan(np.radians(sun_zenith))
    shift = (10.0 + 19.0 * slope + max(10.0, 21.0 * slope - 10.0)) / 2.0
    scene = _scene(tau, sun_zenith=sun_zenith, reflectance=0.4, size=(60.0, 20.0, 2.0))
    scene["observers"][0]["center"] = [0.0, shift]
    lit_scene = _scene(sun_zenith=sun_zenith, reflectance=0.4)
    lit_scene["observers"][0]["center"] = scene["observers"][0]["center"]
    if sun_zenith == 0.0:  # the slab over the camera's footprint: straight through it
        scene["observers"][0]["center"] = [0.0, 0.0]
        lit_scene["observers"][0]["center"] = [0.0, 0.0]
    ds, lit = render(scene), render(lit_scene)
    mu0 = np.cos(np.radians(sun_zenith))
    expected = np.exp(-tau / mu0)
    ratio = ds["sun_diffuse"].sel(band="vis").values / lit["sun_diffuse"].sel(band="vis").values
    if sun_zenith == 0.0:  # seen through the slab too: the transmitted layer holds it
        ratio = (ds["transmitted"].sel(band="vis").values
                 / lit["radiance"].sel(band="vis").values)
        expected = expected * np.exp(-tau)
    assert ratio == pytest.approx(np.full((9, 9), expected), rel=EXACT_REL)
    assert ds["shadow_fraction"].values == pytest.approx(
        np.full((9, 9), 1.0 - np.exp(-tau / mu0)), rel=EXACT_REL)


@pytest.mark.parametrize("asymmetry", [0.0, 0.5])
@pytest.mark.parametrize(("tau", "albedo", "sun_zenith"), [(0.7, 0.9, 30.0), (0.1, 0.5, 60.0),
                                                           (3.0, 1.0, 30.0)])
def test_single_scattering_of_a_slab(tau, albedo, sun_zenith, asymmetry):
    """Sunlight scattered once by a uniform slab towards nadir:
    ω E P(Θ)/(4π) · μ_0/(μ_0 + μ) · (1 − e^{−τ(1/μ_0 + 1/μ)}), the integral over depth t of
    (ω E P/4π) e^{−t/μ_0} e^{−t/μ} dt/μ (the single-scattering approximation of a
    plane-parallel layer, e.g. Hansen & Travis 1974, Space Sci. Rev. 16, 527,
    doi:10.1007/BF00168069; Henyey–Greenstein P); ∫ S E_sun dλ from a white plate's sun term
    in the same render without the slab, π L / μ_0."""
    scene = _scene(tau, sun_zenith=sun_zenith, albedo=albedo)
    scene["volumes"][0]["asymmetry"] = asymmetry
    ds = render(scene)
    white = _scene(sun_zenith=sun_zenith, reflectance=1.0)
    mu0, mu = np.cos(np.radians(sun_zenith)), 1.0
    e_sun = np.pi * render(white)["sun_diffuse"].sel(band="vis").values / mu0
    g, cos_theta = asymmetry, -mu0  # sun above, line of sight down
    phase = (1 - g * g) / (1 + g * g - 2 * g * cos_theta) ** 1.5
    depth = tau * (1 / mu0 + 1 / mu)
    expected = albedo * e_sun * phase / (4 * np.pi) * mu0 / (mu0 + mu) * -np.expm1(-depth)
    # the midpoint rule over MARCH_STEPS steps of e^{-c s}: relative error (c Δ)² / 24
    from radscene.render.volumes import MARCH_STEPS

    rel = (depth / MARCH_STEPS) ** 2 / 24.0 * 1.5
    assert ds["volume_scattered"].sel(band="vis").values == pytest.approx(expected, rel=rel)
    assert not ds["volume_scattered"].sel(band="vis").values == pytest.approx(
        expected, rel=rel / 100.0)  # a marched answer, within its stated error
    # the emission is the absorbed share's; no sun in the LWIR scattered beyond it matters
    assert ds["volume_emission"].sel(band="lwir").values == pytest.approx(
        np.full((9, 9), (1.0 - albedo) * -np.expm1(-tau) * _band_planck(SLAB_T)),
        rel=BAND_REL, abs=1e-12)
