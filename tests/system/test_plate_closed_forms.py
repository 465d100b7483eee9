"""System tests (a) and (b): a flat plate's terms against their closed forms.

The oracle integrates each term's spectral formula on a dense uniform grid with the trapezoid
rule (1e-5 um steps), independently of the renderer's breakpoint-aware Gauss–Legendre rule.
"""

from __future__ import annotations

import numpy as np
import pytest

from radscene import load_scene, render
from radscene.radiometry import band_radiance, spectral_radiance
from radscene.sun import toa_solar_irradiance

REL = 1e-6

RHO_WL = [0.4, 0.55, 0.7, 1.0, 2.5, 5.0, 9.0, 11.0, 14.0]
RHO = [0.05, 0.08, 0.30, 0.45, 0.25, 0.10, 0.04, 0.06, 0.05]
TAU_WL = [0.4, 0.6, 0.9, 3.0, 8.0, 10.0, 13.0]
TAU = [0.70, 0.80, 0.90, 0.75, 0.80, 0.88, 0.70]
PATH_WL = [0.4, 1.0, 5.0, 14.0]
PATH = [30.0, 5.0, 0.5, 2.0]
SKY = 3.5


def _dense(lo, hi, step=1e-5):
    n = int(round((hi - lo) / step)) + 1
    return np.linspace(lo, hi, n)


def _trapz(y, x):
    return float(np.sum(0.5 * (y[1:] + y[:-1]) * np.diff(x)))


@pytest.mark.parametrize("sun_zenith", [0.0, 30.0, 60.0])
def test_lambertian_plate_terms_equal_closed_forms(make_plate_scene, sun_zenith):
    bands = [{"name": "vis", "min": 0.5, "max": 0.6},
             {"name": "lwir", "min": 8.0, "max": 12.0},
             {"name": "nir_g", "type": "gaussian", "center": 0.85, "fwhm": 0.04}]
    atmosphere = {"type": "uniform",
                  "transmittance": {"wavelength": TAU_WL, "values": TAU},
                  "sun_transmittance": 0.9,
                  "path_radiance": {"wavelength": PATH_WL, "values": PATH},
                  "sky_radiance": SKY}
    scene = load_scene(make_plate_scene(
        {"reflectance": {"wavelength": RHO_WL, "values": RHO}}, atmosphere, bands,
        sun_zenith=sun_zenith, temperature="310 K"))
    ds = render(scene)
    cos_sun = np.cos(np.radians(sun_zenith))
    for band in scene.bands:
        lo, hi = band.response.support
        wl = _dense(lo, hi)
        s = band.response(wl)
        rho = np.interp(wl, RHO_WL, RHO)
        tau = np.interp(wl, TAU_WL, TAU)
        expected = {
            "sun_diffuse": _trapz(s * toa_solar_irradiance(wl) * 0.9 * rho / np.pi * cos_sun * tau, wl),
            "sky_reflected": _trapz(s * rho * SKY * tau, wl),
            "thermal_emission": _trapz(s * (1 - rho) * spectral_radiance(wl, 310.0) * tau, wl),
            "path_radiance": _trapz(s * np.interp(wl, PATH_WL, PATH), wl),
            "sun_specular": 0.0,
        }
        for term, value in expected.items():
            got = ds[term].sel(band=band.name).values
            assert got == pytest.approx(np.full(got.shape, value), rel=REL, abs=1e-12), term
        total = sum(expected.values())
        assert ds["radiance"].sel(band=band.name).values == pytest.approx(
            np.full((8, 8), total), rel=REL)
        assert ds["path_transmittance"].sel(band=band.name).values == pytest.approx(
            np.full((8, 8), _trapz(s * tau, wl) / _trapz(s, wl)), rel=REL)
    assert ds["sky_view_fraction"].values == pytest.approx(np.ones((8, 8)), abs=1e-12)
    assert ds["cos_incidence"].values == pytest.approx(np.full((8, 8), cos_sun), rel=1e-9)
    assert ds["shadow_fraction"].values == pytest.approx(np.zeros((8, 8)), abs=0)


@pytest.mark.parametrize("temperature", [273.15, 300.0, 1000.0])
def test_blackbody_plate_in_vacuum_gives_planck_band_integral(make_plate_scene, temperature):
    bands = [{"name": "lwir", "min": 8.0, "max": 12.0}, {"name": "mwir", "min": 3.0, "max": 5.0},
             {"name": "wide", "min": 8.0, "max": 14.0}]
    scene = load_scene(make_plate_scene({"emissivity": 1.0}, {"type": "none"}, bands,
                                        sun_zenith=120.0, temperature=temperature))
    ds = render(scene)
    for band, (lo, hi) in zip(["lwir", "mwir", "wide"], [(8, 12), (3, 5), (8, 14)], strict=True):
        expected = float(band_radiance(lo, hi, temperature))
        assert ds["radiance"].sel(band=band).values == pytest.approx(
            np.full((8, 8), expected), rel=REL)
        assert ds["brightness_temperature"].sel(band=band).values == pytest.approx(
            np.full((8, 8), temperature), abs=1e-4)


def test_specular_plate_peaks_in_the_mirror_direction(make_plate_scene):
    """OSSIM eq. 4 lobe: at the mirror geometry L_spec = E_sun τ ρ_s (n+1)/(2π)."""
    bands = [{"name": "vis", "min": 0.5, "max": 0.6}]
    scene_dict = make_plate_scene(
        {"reflectance": 0.3, "specular_reflectance": 0.1, "specular_exponent": 50},
        {"type": "none"}, bands, sun_zenith=0.0)
    scene = load_scene(scene_dict)
    ds = render(scene)
    wl = _dense(0.5, 0.6)
    expected = _trapz(toa_solar_irradiance(wl) * 0.1 * 51 / (2 * np.pi), wl)
    assert ds["sun_specular"].sel(band="vis").values == pytest.approx(
        np.full((8, 8), expected), rel=REL)


def test_texture_multipliers_scale_reflected_and_emitted_terms(make_plate_scene, tmp_path):
    """Δρ scales the reflected terms and Δε the emitted term, pixel by pixel."""
    texture = np.full((4, 4), 0.5)
    np.save(tmp_path / "half.npy", texture)
    np.save(tmp_path / "double.npy", np.full((4, 4), 1.5))
    bands = [{"name": "vis", "min": 0.5, "max": 0.6}, {"name": "lwir", "min": 8.0, "max": 12.0}]
    atmosphere = {"type": "uniform", "sky_radiance": 2.0}
    plain = make_plate_scene({"reflectance": 0.4}, atmosphere, bands)
    textured = make_plate_scene({"reflectance": 0.4}, atmosphere, bands)
    textured["objects"][0]["textures"] = {
        "reflectance": {"file": str(tmp_path / "half.npy"), "size": [50, 50]},
        "emissivity": {"file": str(tmp_path / "double.npy"), "size": [50, 50]},
    }
    a = render(load_scene(plain))
    b = render(load_scene(textured))
    for term, factor in (("sun_diffuse", 0.5), ("sky_reflected", 0.5), ("thermal_emission", 1.5)):
        assert b[term].values == pytest.approx(factor * a[term].values, rel=1e-12), term
    assert b["path_radiance"].values == pytest.approx(a["path_radiance"].values, rel=1e-12)


def test_a_lambertian_brdf_model_renders_like_the_lambertian_material(make_plate_scene):
    """The BRDF path (band-centre kernel, ρ_dh for the sky, directional ε) against the
    spectral Lambertian path, for a spectrally flat reflectance where both are exact."""
    bands = [{"name": "vis", "min": 0.5, "max": 0.6}, {"name": "lwir", "min": 8.0, "max": 12.0}]
    atmosphere = {"type": "uniform", "transmittance": 0.8, "sky_radiance": 3.0,
                  "path_radiance": 1.0}
    plain = make_plate_scene({"reflectance": 0.3}, atmosphere, bands, sun_zenith=35.0)
    model = make_plate_scene({"reflectance": 0.3, "brdf": {"type": "lambertian",
                                                           "reflectance": 0.3}},
                             atmosphere, bands, sun_zenith=35.0)
    a = render(load_scene(plain))
    b = render(load_scene(model))
    for term in ("sun_diffuse", "sky_reflected", "thermal_emission", "path_radiance", "radiance"):
        assert b[term].values == pytest.approx(a[term].values, rel=1e-9), term


def test_water_brdf_emissivity_falls_towards_grazing(make_plate_scene):
    """Cox–Munk water: the LWIR emission seen at 80° is below that seen from nadir."""
    bands = [{"name": "lwir", "min": 8.0, "max": 12.0}]
    scene = make_plate_scene({"emissivity": 0.98, "brdf": {"type": "coxmunk", "wind_speed": 3.0}},
                             {"type": "none"}, bands, sun_zenith=120.0, temperature="300 K")
    scene["observers"] = [
        {"name": "nadir", "type": "orthographic", "center": [0, 0], "gsd": 1.0, "shape": [4, 4]},
        {"name": "grazing", "type": "orthographic", "center": [0, 0], "gsd": 1.0,
         "shape": [4, 4], "zenith": 80.0, "azimuth": 0.0},
    ]
    loaded = load_scene(scene)
    nadir = render(loaded, "nadir")["thermal_emission"].values.mean()
    grazing = render(loaded, "grazing")["thermal_emission"].values.mean()
    planck = float(band_radiance(8.0, 12.0, 300.0))
    assert 0.97 < nadir / planck < 1.0
    assert grazing / planck < nadir / planck - 0.1
