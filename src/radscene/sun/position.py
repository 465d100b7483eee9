"""Sun position (NREL SPA via pvlib) and Earth-Sun distance.

Angles follow radscene's conventions: zenith from the local vertical, azimuth clockwise
from north (east = 90°), in degrees.

References
----------
I. Reda and A. Andreas, "Solar position algorithm for solar radiation applications",
Solar Energy 76, 577-589 (2004), https://doi.org/10.1016/j.solener.2003.12.003
(NREL/TP-560-34302). Implementation: ``pvlib.solarposition.spa_python``.
"""

from __future__ import annotations

import datetime as _dt
import math
from dataclasses import dataclass

import numpy as np
import pandas as pd

from radscene.errors import ConfigError

__all__ = ["SunPosition", "sun_position", "earth_sun_distance"]


@dataclass(frozen=True)
class SunPosition:
    """Position of the Sun seen from a place, at one or more times.

    Every field is a float64 numpy array of the shape of the input times (0-d for one time).

    Attributes
    ----------
    zenith : numpy.ndarray
        True topocentric zenith angle, without refraction [deg].
    apparent_zenith : numpy.ndarray
        Zenith angle with atmospheric refraction [deg].
    azimuth : numpy.ndarray
        Azimuth, clockwise from north [deg], in [0, 360).
    elevation : numpy.ndarray
        True elevation, 90 - zenith [deg].
    distance : numpy.ndarray
        Earth-Sun distance [AU].
    """

    zenith: np.ndarray
    apparent_zenith: np.ndarray
    azimuth: np.ndarray
    elevation: np.ndarray
    distance: np.ndarray


def _naive(where):
    return ConfigError(
        f"times must be timezone-aware (e.g. datetime(..., tzinfo=timezone.utc) or "
        f"pandas.Timestamp('...', tz='UTC')); got a naive {where}",
        key="time",
    )


def _utc_index(time):
    """Return (DatetimeIndex in UTC, shape of the input)."""
    if isinstance(time, pd.Series):
        time = pd.DatetimeIndex(time)
    if isinstance(time, pd.DatetimeIndex):
        if time.tz is None:
            raise _naive("DatetimeIndex")
        return time.tz_convert("UTC"), (len(time),)
    if isinstance(time, (np.datetime64, str)) or (
        isinstance(time, np.ndarray) and np.issubdtype(time.dtype, np.datetime64)
    ):
        if isinstance(time, str):
            raise ConfigError(
                f"expected a timezone-aware datetime or Timestamp; got the string {time!r}",
                key="time",
            )
        raise _naive("numpy datetime64 (which has no timezone)")
    if isinstance(time, _dt.datetime):
        values, shape = [time], ()
    else:
        array = np.asarray(time, dtype=object)
        values, shape = list(array.ravel()), array.shape
    stamps = []
    for value in values:
        if not isinstance(value, _dt.datetime):
            raise ConfigError(
                f"expected timezone-aware datetimes or Timestamps; got {value!r}", key="time"
            )
        if value.tzinfo is None or value.utcoffset() is None:
            raise _naive(f"datetime {value!r}")
        stamps.append(pd.Timestamp(value).tz_convert("UTC"))
    return pd.DatetimeIndex(stamps, tz="UTC"), shape


def _scalar(value, key, low, high, high_inclusive=True):
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise ConfigError(f"must be a number [deg]; got {value!r}", key=key) from None
    ok = low <= v <= high if high_inclusive else low <= v < high
    if not ok:
        bracket = "]" if high_inclusive else ")"
        raise ConfigError(f"must lie in [{low:g}, {high:g}{bracket} deg; got {value!r}", key=key)
    return v


def _finite(value, key, unit):
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise ConfigError(f"must be a number [{unit}]; got {value!r}", key=key) from None
    if not math.isfinite(v):
        raise ConfigError(f"must be finite [{unit}]; got {value!r}", key=key)
    return v


def earth_sun_distance(time, delta_t: float = 67.0) -> np.ndarray:
    """Earth-Sun distance at the given times (NREL SPA).

    Parameters
    ----------
    time : datetime, pandas.Timestamp, DatetimeIndex or array_like of them
        Timezone-aware times.
    delta_t : float
        TT - UT1 [s].

    Returns
    -------
    numpy.ndarray
        Distance [AU], float64 of the shape of `time` (0-d for one time).

    Examples
    --------
    >>> import datetime as dt
    >>> t = dt.datetime(2003, 10, 17, 19, 30, 30, tzinfo=dt.timezone.utc)
    >>> round(float(earth_sun_distance(t)), 6)
    0.996542
    """
    from pvlib.solarposition import nrel_earthsun_distance

    index, shape = _utc_index(time)
    delta_t = _finite(delta_t, "delta_t", "s")
    if len(index) == 0:
        return np.empty(shape)
    distance = nrel_earthsun_distance(index, how="numpy", delta_t=delta_t)
    return np.asarray(distance, dtype=float).reshape(shape)


def sun_position(
    time,
    latitude,
    longitude,
    altitude=0.0,
    pressure=None,
    temperature=12.0,
    delta_t=67.0,
) -> SunPosition:
    """Topocentric position of the Sun and the Earth-Sun distance (NREL SPA).

    Parameters
    ----------
    time : datetime, pandas.Timestamp, DatetimeIndex or array_like of them
        Timezone-aware times (naive times are refused).
    latitude : float
        Geodetic latitude [deg], in [-90, 90], north positive.
    longitude : float
        Longitude [deg], in [-180, 360), east positive.
    altitude : float
        Height above mean sea level [m].
    pressure : float, optional
        Surface air pressure [Pa] for refraction; default the standard atmosphere's at
        `altitude` (``pvlib.atmosphere.alt2pres``).
    temperature : float
        Surface air temperature [degC] for refraction (pvlib's convention), > -273.15.
    delta_t : float
        TT - UT1 [s].

    Returns
    -------
    SunPosition
        Arrays of the shape of `time` (0-d for one time).

    Notes
    -----
    Refraction at the horizon is pvlib's default 0.5667 deg. The SPA is accurate to
    ±0.0003 deg from year -2000 to 6000 (Reda & Andreas 2004).

    Examples
    --------
    >>> import datetime as dt
    >>> t = dt.datetime(2003, 10, 17, 12, 30, 30, tzinfo=dt.timezone(dt.timedelta(hours=-7)))
    >>> sun = sun_position(t, 39.742476, -105.1786, 1830.14, 82000.0, 11.0)
    >>> round(float(sun.zenith), 5), round(float(sun.azimuth), 5)
    (50.12795, 194.34024)
    """
    from pvlib.atmosphere import alt2pres
    from pvlib.solarposition import nrel_earthsun_distance, spa_python

    index, shape = _utc_index(time)
    lat = _scalar(latitude, "latitude", -90.0, 90.0)
    lon = _scalar(longitude, "longitude", -180.0, 360.0, high_inclusive=False)
    if lon >= 180.0:
        lon -= 360.0
    alt = _finite(altitude, "altitude", "m")
    if pressure is None:
        p = float(alt2pres(alt))
    else:
        p = _finite(pressure, "pressure", "Pa")
        if p <= 0:
            raise ConfigError(f"must be > 0 Pa; got {pressure!r}", key="pressure")
    t_air = _finite(temperature, "temperature", "degC")
    if t_air <= -273.15:
        raise ConfigError(f"must be > -273.15 degC; got {temperature!r}", key="temperature")
    delta_t = _finite(delta_t, "delta_t", "s")
    if len(index) == 0:
        empty = np.empty(shape)
        return SunPosition(empty, empty.copy(), empty.copy(), empty.copy(), empty.copy())
    frame = spa_python(
        index,
        lat,
        lon,
        altitude=alt,
        pressure=p,
        temperature=t_air,
        delta_t=delta_t,
        how="numpy",
    )
    distance = nrel_earthsun_distance(index, how="numpy", delta_t=delta_t)

    def column(values):
        return np.asarray(values, dtype=float).reshape(shape)

    return SunPosition(
        zenith=column(frame["zenith"]),
        apparent_zenith=column(frame["apparent_zenith"]),
        azimuth=column(frame["azimuth"]),
        elevation=column(frame["elevation"]),
        distance=column(distance),
    )
