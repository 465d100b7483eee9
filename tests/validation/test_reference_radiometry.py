"""Validation of radscene.radiometry and radscene.sun against published reference figures.

Figures are typed in from a collection of published reference cases; each test names its case id and the
case's source.
"""

import datetime as dt

import pandas as pd
import pytest

from radscene.radiometry import (
    C1,
    C1L,
    C2,
    SIGMA,
    WIEN_B,
    RectangularResponse,
    band_radiance,
    exitance,
    peak_wavelength,
    radiance_temperature_derivative,
    spectral_radiance,
)
from radscene.sun import earth_sun_distance, solar_constant, sun_position

# --- codata2018_radiation_constants: CODATA 2018 (NIST) via scipy.constants, rel 1e-9 ---
CODATA_REL = 1e-9


@pytest.mark.parametrize(
    ("value", "expected"),
    [
        (SIGMA, 5.670374419e-08),  # W m-2 K-4
        (C1, 3.741771852e-16),  # W m2
        (C1L, 1.191042972e-16),  # W m2 sr-1
        (C2, 0.01438776877),  # m K
        (WIEN_B, 0.002897771955),  # m K
    ],
    ids=["sigma", "c1", "c1L", "c2", "wien_b"],
)
def test_codata2018_radiation_constants(value, expected):
    assert value == pytest.approx(expected, rel=CODATA_REL)


# --- planck_band_radiance_table: adaptive quadrature of Planck with CODATA 2018 (rel 1e-12),
# cross-checked against pyradi ryplanck; tolerance rel 1e-6 ---
PLANCK_REL = 1e-6
BAND_TABLE = [
    (8.0, 12.0, 300.0, 38.500424),
    (8.0, 12.0, 288.15, 31.478024),
    (8.0, 12.0, 273.15, 23.821891),
    (8.0, 12.0, 1000.0, 1602.829863),
    (3.0, 5.0, 300.0, 1.865956),
    (3.0, 5.0, 288.15, 1.194033),
    (3.0, 5.0, 273.15, 0.644266),
    (3.0, 5.0, 1000.0, 6506.733979),
    (8.0, 14.0, 300.0, 54.933461),
    (8.0, 14.0, 288.15, 45.538287),
    (3.4, 4.8, 300.0, 1.346072),
    (3.4, 4.8, 288.15, 0.852112),
]  # W m-2 sr-1


@pytest.mark.parametrize(("lo", "hi", "temperature", "expected"), BAND_TABLE)
def test_planck_band_radiance_table_exact(lo, hi, temperature, expected):
    assert band_radiance(lo, hi, temperature) == pytest.approx(expected, rel=PLANCK_REL)


@pytest.mark.parametrize(("lo", "hi", "temperature", "expected"), BAND_TABLE)
def test_planck_band_radiance_table_rectangular_response(lo, hi, temperature, expected):
    band = RectangularResponse(lo, hi)
    got = band.integrate_function(lambda wl: spectral_radiance(wl, temperature))
    assert got == pytest.approx(expected, rel=PLANCK_REL)


@pytest.mark.parametrize(
    ("wavelength", "temperature", "expected"),
    [
        (10.0, 300.0, 9.924033),
        (4.0, 300.0, 0.721976),
        (2.0, 1000.0, 2797.947166),
        (0.5, 5778.0, 26375670.0),
    ],
)
def test_planck_band_radiance_table_spectral(wavelength, temperature, expected):
    # W m-2 sr-1 um-1
    assert spectral_radiance(wavelength, temperature) == pytest.approx(expected, rel=PLANCK_REL)


def test_planck_band_radiance_table_derivative_peak_exitance():
    # printed to 6 decimals only: 0.159972 carries ±5e-7 (3e-6 relative) of rounding
    assert radiance_temperature_derivative(10.0, 300.0) == pytest.approx(0.159972, abs=5e-7)
    assert peak_wavelength([300.0, 5778.0]) == pytest.approx([9.65924, 0.501518], rel=PLANCK_REL)
    assert exitance([300.0, 288.15]) == pytest.approx([459.30033, 390.91851], rel=PLANCK_REL)


# --- solar_constant_tsi: Kopp & Lean (2011) GRL 38 L01706, TSI 1360.8 W m-2; IAU 2015 B3
# nominal 1361 W m-2; rel 0.005 ---
TSI_REL = 0.005


def test_solar_constant_tsi():
    assert solar_constant() == pytest.approx(1360.8, rel=TSI_REL)
    assert solar_constant() == pytest.approx(1361.0, rel=TSI_REL)


# --- pvlib_nrel_spa_golden: pvlib tests/test_spa.py, the worked example of Reda & Andreas,
# NREL/TP-560-34302; abs 1e-5 deg (decimal 5), R decimal 6 ---
SPA_ABS = 1e-5  # deg
SPA_TIME = dt.datetime(2003, 10, 17, 12, 30, 30, tzinfo=dt.timezone(dt.timedelta(hours=-7)))


def test_pvlib_nrel_spa_golden():
    sun = sun_position(
        SPA_TIME,
        latitude=39.742476,
        longitude=-105.1786,
        altitude=1830.14,
        pressure=82000.0,  # 820 mbar
        temperature=11.0,  # degC
        delta_t=67.0,
    )  # atmos_refract 0.5667 deg is pvlib's default
    assert float(sun.apparent_zenith) == pytest.approx(50.11162, abs=SPA_ABS)
    assert float(sun.zenith) == pytest.approx(50.127954, abs=SPA_ABS)
    assert float(sun.azimuth) == pytest.approx(194.340241, abs=SPA_ABS)
    assert float(sun.distance) == pytest.approx(0.9965422974, abs=1e-6)
    assert float(earth_sun_distance(pd.Timestamp(SPA_TIME))) == pytest.approx(
        0.9965422974, abs=1e-6
    )


# --- pvlib_extraterrestrial_irradiance: pvlib tests/test_irradiance.py::test_get_extra_radiation,
# 2016-10-26, solar constant 1366.1 -> 1383.636203 W m-2, abs 10 ---
def test_pvlib_extraterrestrial_irradiance():
    distance = earth_sun_distance(pd.Timestamp("2016-10-26", tz="UTC"))
    assert 1366.1 / float(distance) ** 2 == pytest.approx(1383.636203, abs=10.0)
