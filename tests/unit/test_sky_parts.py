"""Every engine's sky split into scattered sunlight and emission (``Atmosphere.sky_parts``):
the parts sum to ``sky``; a part the engine does not compute is zero. LOWTRAN's split is
tested with its stand-in executable in test_lowtran_engine.py."""

from __future__ import annotations

import numpy as np
import pytest

from radscene.atmosphere import (
    SKY_CROSSOVER_WAVELENGTH,
    DatabaseAtmosphere,
    SkyGeometry,
    UniformAtmosphere,
)
from radscene.atmosphere import sixs_runner as sr
from radscene.atmosphere.sixs import SixSAtmosphere
from radscene.errors import ConfigError

ZENITH, AZIMUTH = np.array([0.0, 40.0, 80.0]), np.array([0.0, 90.0, 200.0])
SUM = 1e-15  # parts summed against the whole: rounding only


def test_uniform_parts_given_apart():
    atm = UniformAtmosphere(sky_solar_radiance=1.5,
                            sky_thermal_radiance={"wavelength": [0.3, 20.0], "values": [0.0, 4.0]},
                            sky_zenith=[0.0, 90.0], sky_profile=[1.0, 2.0])
    wl = np.array([0.55, 4.0, 10.0])
    parts = atm.sky_parts(ZENITH, AZIMUTH, wl, SkyGeometry())
    factor = 1.0 + ZENITH / 90.0
    assert parts.solar == pytest.approx(1.5 * factor[:, None] * np.ones(3), rel=1e-12)
    assert parts.thermal == pytest.approx(
        factor[:, None] * np.interp(wl, [0.3, 20.0], [0.0, 4.0]), rel=1e-12)
    assert parts.solar + parts.thermal == pytest.approx(
        atm.sky(ZENITH, AZIMUTH, wl, SkyGeometry()), rel=SUM)


def test_uniform_sky_radiance_split_at_the_crossover():
    atm = UniformAtmosphere(sky_radiance=2.0)
    wl = np.array([0.55, SKY_CROSSOVER_WAVELENGTH - 1e-6, SKY_CROSSOVER_WAVELENGTH, 10.0])
    parts = atm.sky_parts(0.0, 0.0, wl, SkyGeometry())
    assert parts.solar.tolist() == [2.0, 2.0, 0.0, 0.0]
    assert parts.thermal.tolist() == [0.0, 0.0, 2.0, 2.0]


def test_uniform_refuses_the_sky_and_its_parts_together():
    with pytest.raises(ConfigError, match="sky_radiance or its parts"):
        UniformAtmosphere(sky_radiance=1.0, sky_thermal_radiance=1.0)


@pytest.fixture(scope="module")
def db():
    return DatabaseAtmosphere(profile="midlatitude_summer", aerosol="rural", visibility="23 km",
                              sun_zenith=30.0, sun_azimuth=180.0)


@pytest.mark.parametrize("wavelength", [[0.45, 0.55, 0.9], [3.5, 3.7, 3.9], [8.5, 10.0, 12.0]])
def test_database_parts(db, wavelength):
    geometry = SkyGeometry(0.0, 30.0, 180.0)
    parts = db.sky_parts(ZENITH, AZIMUTH, wavelength, geometry)
    assert parts.solar + parts.thermal == pytest.approx(
        db.sky(ZENITH, AZIMUTH, wavelength, geometry), rel=SUM)
    if wavelength[-1] < 1.0:  # visible: the air emits nothing the tables hold
        assert np.all(parts.thermal == 0.0) and np.all(parts.solar > 0.0)
    else:
        assert np.all(parts.thermal > 0.0)
    if wavelength[0] > 3.0 and wavelength[-1] < 5.0:  # MWIR: both
        assert np.all(parts.solar > 0.0)


def test_database_night_sky_is_emission(db):
    parts = db.sky_parts(ZENITH, AZIMUTH, [3.9, 10.0], SkyGeometry(0.0, 100.0, 180.0))
    assert np.all(parts.solar == 0.0) and np.all(parts.thermal > 0.0)


@pytest.mark.skipif(not sr.sixs_available()[0], reason="6S cannot run here")
def test_sixs_sky_is_scattered_sunlight():
    atm = SixSAtmosphere(sun_zenith=30.0)
    geometry = SkyGeometry(0.0, 30.0, 0.0)
    parts = atm.sky_parts(ZENITH, AZIMUTH, [0.55, 0.85], geometry)
    assert np.all(parts.thermal == 0.0)
    assert parts.solar == pytest.approx(atm.sky(ZENITH, AZIMUTH, [0.55, 0.85], geometry),
                                        rel=SUM)
