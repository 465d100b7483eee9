"""Unit tests of radscene.sun (position and top-of-atmosphere spectrum)."""

import datetime as dt
import math

import numpy as np
import pandas as pd
import pytest

from radscene.errors import ConfigError
from radscene.radiometry import brightness_temperature, spectral_radiance
from radscene.sun import (
    SUN_SOLID_ANGLE,
    SunPosition,
    earth_sun_distance,
    solar_constant,
    sun_position,
    sun_radiance,
    toa_solar_irradiance,
    toa_solar_spectrum,
)

UTC = dt.UTC
EQUINOX_NOON = dt.datetime(2021, 3, 20, 12, 7, tzinfo=UTC)  # near solar noon at lon 0


def test_scalar_time_gives_0d_float_arrays():
    sun = sun_position(EQUINOX_NOON, 0.0, 0.0)
    assert isinstance(sun, SunPosition)
    for field in ("zenith", "apparent_zenith", "azimuth", "elevation", "distance"):
        value = getattr(sun, field)
        assert isinstance(value, np.ndarray) and value.shape == () and value.dtype == np.float64
    assert sun.elevation == pytest.approx(90.0 - sun.zenith, abs=1e-12)
    with pytest.raises(AttributeError):
        sun.zenith = 0.0  # frozen


def test_equinox_noon_sun_is_near_zenith_at_the_equator_and_south_at_45n():
    assert float(sun_position(EQUINOX_NOON, 0.0, 0.0).zenith) == pytest.approx(0.0, abs=0.5)
    north = sun_position(EQUINOX_NOON, 45.0, 0.0)
    assert float(north.zenith) == pytest.approx(45.0, abs=0.5)
    assert float(north.azimuth) == pytest.approx(180.0, abs=1.0)
    # refraction lifts the sun: apparent zenith is smaller, by ~1 arcmin at 45°
    assert 0.0 < float(north.zenith - north.apparent_zenith) < 0.05


def test_array_shapes_and_timezones_are_respected():
    berlin = pd.date_range("2020-06-21 04:00", periods=6, freq="4h", tz="Europe/Berlin")
    grid = np.array(berlin.to_pydatetime()).reshape(2, 3)
    sun = sun_position(grid, 48.1, 11.6, altitude=520.0)
    assert sun.zenith.shape == (2, 3) and sun.distance.shape == (2, 3)
    flat = sun_position(berlin.tz_convert("UTC"), 48.1, 11.6, altitude=520.0)
    assert sun.zenith.ravel() == pytest.approx(flat.zenith, abs=1e-9)
    assert flat.zenith.shape == (6,)
    # morning sun in the east, evening sun in the west
    assert 0.0 < flat.azimuth[0] < 90.0 and 180.0 < flat.azimuth[4] < 360.0


def test_longitude_above_180_is_west():
    t = dt.datetime(2022, 7, 1, 18, 0, tzinfo=UTC)
    east = sun_position(t, 30.0, 200.0)
    west = sun_position(t, 30.0, -160.0)
    assert float(east.azimuth) == pytest.approx(float(west.azimuth), abs=1e-9)


@pytest.mark.parametrize(
    "time",
    [
        dt.datetime(2020, 1, 1, 12),
        pd.Timestamp("2020-01-01 12:00"),
        np.datetime64("2020-01-01T12:00"),
        pd.date_range("2020-01-01", periods=2, freq="h"),
        [dt.datetime(2020, 1, 1, 12, tzinfo=UTC), dt.datetime(2020, 1, 1, 13)],
    ],
)
def test_naive_times_raise(time):
    with pytest.raises(ConfigError, match="^time: times must be timezone-aware"):
        sun_position(time, 40.0, -105.0)
    with pytest.raises(ConfigError, match="timezone-aware"):
        earth_sun_distance(time)


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"latitude": 91.0}, r"^latitude: must lie in \[-90, 90\] deg"),
        ({"latitude": "north"}, "^latitude: must be a number"),
        ({"longitude": 360.0}, r"^longitude: must lie in \[-180, 360\) deg"),
        ({"longitude": -181.0}, "^longitude: "),
        ({"pressure": 0.0}, "^pressure: must be > 0 Pa"),
        ({"temperature": -300.0}, "^temperature: must be > -273.15 degC"),
        ({"altitude": float("nan")}, "^altitude: must be finite"),
    ],
)
def test_bad_position_parameters_raise(kwargs, match):
    args = {"time": EQUINOX_NOON, "latitude": 10.0, "longitude": 10.0, **kwargs}
    with pytest.raises(ConfigError, match=match):
        sun_position(**args)


def test_earth_sun_distance_perihelion_aphelion():
    # Perihelion 2023-01-04 ~0.98330 AU, aphelion 2023-07-06 ~1.01668 AU (USNO/JPL almanac)
    d = earth_sun_distance(
        [dt.datetime(2023, 1, 4, 16, tzinfo=UTC), dt.datetime(2023, 7, 6, 20, tzinfo=UTC)]
    )
    assert d == pytest.approx([0.98330, 1.01668], abs=2e-5)


def test_sun_solid_angle_iau_nominal():
    # π (R_sun / AU)², R_sun = 6.957e8 m (IAU 2015 B3), AU = 1.495978707e11 m
    assert SUN_SOLID_ANGLE == pytest.approx(6.794274e-5, rel=1e-6)


def test_toa_irradiance_matches_astm_g173_samples():
    # ASTM G173-03 extraterrestrial column, W m-2 nm-1: 500 nm 1.916, 1000 nm 0.7422 (Gueymard)
    assert toa_solar_irradiance([0.5, 1.0]) == pytest.approx([1916.0, 742.2], rel=1e-3)


def test_toa_irradiance_distance_scaling_and_broadcasting():
    wl = np.array([0.5, 1.0, 10.0])
    d = np.array([[0.983], [1.017]])
    out = toa_solar_irradiance(wl, d)
    assert out.shape == (2, 3)
    assert out == pytest.approx(toa_solar_irradiance(wl) / d**2, rel=1e-14)


def test_blackbody_extensions_join_the_measured_spectrum():
    # the tail beyond 4 um steps by < 2 % at the join and is a 5772 K disk shape
    below, above = toa_solar_irradiance([4.0, 4.0 + 1e-9])
    assert above == pytest.approx(below, rel=0.02)
    ratio = toa_solar_irradiance([5.0, 12.0]) / (
        spectral_radiance([5.0, 12.0], 5772.0) * SUN_SOLID_ANGLE
    )
    assert ratio[0] == pytest.approx(ratio[1], rel=1e-12)
    assert 0.9 < ratio[0] < 1.0
    # below 0.28 um: positive, below the 0.28-0.285 um mean, falling toward short waves
    head = toa_solar_irradiance([0.25, 0.265, 0.2799])
    assert np.all(np.diff(head) > 0) and head[-1] < 600.0


def test_sun_brightness_temperature_is_solar():
    # the disk-mean brightness temperature of the Sun is within ~5 % of Teff = 5772 K from
    # the visible to 4 um (lower in the infrared, where limb darkening and H- opacity act)
    wl = np.array([0.5, 0.8, 1.0, 4.0])
    tb = brightness_temperature(wl, sun_radiance(wl))
    assert tb == pytest.approx(np.full(4, 5772.0), rel=0.05)
    # the H- opacity minimum near 1.6 um shows deeper, hotter layers
    assert float(brightness_temperature(1.6, sun_radiance(1.6))) > tb.max()


def test_sun_radiance_is_independent_of_distance():
    wl = np.array([0.55, 2.2])
    assert sun_radiance(wl, 0.98) == pytest.approx(sun_radiance(wl), rel=1e-14)
    assert sun_radiance(wl) == pytest.approx(toa_solar_irradiance(wl) / SUN_SOLID_ANGLE, rel=1e-14)


def test_native_spectrum_integrates_to_the_solar_constant():
    wl, e = toa_solar_spectrum()
    assert wl[0] == 0.25 and wl[-1] == 20.0 and np.all(np.diff(wl) > 0)
    assert np.trapezoid(e, wl) == pytest.approx(solar_constant(), rel=1e-4)


@pytest.mark.parametrize(
    ("args", "match"),
    [
        ((0.2,), r"^wavelength: must lie in 0.25-20 µm"),
        (([0.5, 25.0],), "^wavelength: "),
        ((float("nan"),), "^wavelength: "),
        ((0.5, 0.0), "^distance: must be > 0 AU"),
        ((0.5, -1.0), "^distance: "),
    ],
)
def test_toa_bad_input_raises(args, match):
    with pytest.raises(ConfigError, match=match):
        toa_solar_irradiance(*args)
    with pytest.raises(ConfigError, match=match):
        sun_radiance(*args)


def test_solar_constant_is_plausible():
    assert math.isfinite(solar_constant())
    assert 1355.0 < solar_constant() < 1370.0
