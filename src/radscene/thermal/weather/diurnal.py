"""A diurnal default weather from the place, the date and a few numbers stated in the scene:
air temperature by the model of Parton & Logan (1981), the humidity at a constant dew point,
constant wind, cloud cover and pressure.

Air temperature (Parton & Logan 1981): a sine from the minimum, c hours after sunrise, to the
maximum, a hours after solar noon, on to sunset; then an exponential decay through the night
to the next minimum:

.. math::
    T_{day}(m) = T_n + (T_x - T_n)\\,\\sin\\frac{\\pi m}{Y + 2a},
    \\qquad m = t - t_{sunrise} - c

    T_{night}(n) = T_n + (T_{sn} - T_n)\\,\\frac{e^{-b n/Z} - e^{-b}}{1 - e^{-b}},
    \\qquad n = t - t_{sunset}

with Y the day length, Z the time from sunset to the next minimum, T_sn the day curve's value
at sunset, all times in hours. Parton & Logan's night curve is T_n + (T_sn − T_n) e^(−bn/Z),
which ends e^(−b) (11 % for b = 2.2) of the way above T_n; radscene rescales it as above so
that the night ends at T_n and the day starts there without a jump. The coefficients fitted for
air at 150 cm are a = 1.86 h, b = 2.20, c = −0.17 h (Parton & Logan 1981): the
maximum comes 1.69 h after the midpoint of sunrise and sunset (about 13:40 local solar time)
when the day is longer than 2(a + c) = 3.4 h, and the minimum 10 minutes before sunrise.
Sunrise and sunset come from NREL's SPA (``pvlib.solarposition.sun_rise_set_transit_spa``),
on the local mean-solar calendar date (UTC offset = longitude / 15°).

Relative humidity: the stated value holds at the mean of the minimum and maximum temperature;
the dew point it gives is kept all day, so the humidity rises at night and falls by day.

References
----------
Parton, W. J. and Logan, J. A. (1981). A model for diurnal variation in soil and air
temperature. *Agric. Meteorol.* 23, 205–216. doi:10.1016/0002-1571(81)90105-9
Reda, I. and Andreas, A. (2004). Solar position algorithm for solar radiation applications.
*Solar Energy* 76, 577–589. doi:10.1016/j.solener.2003.12.003
"""

from __future__ import annotations

import datetime as _dt
from typing import NamedTuple

import numpy as np
import pandas as pd

from radscene.errors import ConfigError
from radscene.radiometry.units import parse_quantity
from radscene.thermal.weather.humidity import (
    dew_point_to_relative_humidity,
    relative_humidity_to_dew_point,
)
from radscene.thermal.weather.series import WeatherSeries

__all__ = ["DiurnalCoefficients", "PARTON_LOGAN_AIR_150CM", "diurnal_air_temperature", "diurnal_weather"]

_HOUR_NS = 3.6e12


class DiurnalCoefficients(NamedTuple):
    """Coefficients of the Parton & Logan (1981) diurnal temperature model.

    Attributes
    ----------
    a : float
        Lag of the maximum after solar noon [h].
    b : float
        Night-time decay coefficient [-].
    c : float
        Lag of the minimum after sunrise [h].
    """

    a: float
    b: float
    c: float


#: Parton & Logan (1981): the fit for air temperature at 150 cm.
PARTON_LOGAN_AIR_150CM = DiurnalCoefficients(a=1.86, b=2.20, c=-0.17)


def _local_date(date):
    if isinstance(date, _dt.datetime):
        return date.date()
    if isinstance(date, _dt.date):
        return date
    try:
        return _dt.date.fromisoformat(str(date))
    except ValueError:
        raise ConfigError(f"expected a calendar date 'YYYY-MM-DD'; got {date!r}", key="date") from None


def sun_events(latitude, longitude, dates):
    """Sunrise and sunset [datetime64[ns], UTC] of each local mean-solar calendar date.

    Parameters
    ----------
    latitude, longitude : float
        [deg], north and east positive.
    dates : list of datetime.date
        Local dates.

    Returns
    -------
    tuple of numpy.ndarray
        (sunrise, sunset), each ``datetime64[ns]`` [UTC] of the length of ``dates``.

    Raises
    ------
    ConfigError
        A date without sunrise or sunset at that latitude (polar day or night).
    """
    from pvlib.solarposition import sun_rise_set_transit_spa

    zone = _dt.timezone(_dt.timedelta(minutes=round(float(longitude) * 4.0)))
    index = pd.DatetimeIndex([pd.Timestamp(d).tz_localize(zone) + pd.Timedelta(hours=12) for d in dates])
    events = sun_rise_set_transit_spa(index, float(latitude), float(longitude))
    missing = events["sunrise"].isna() | events["sunset"].isna()
    if missing.any():
        day = dates[int(np.flatnonzero(missing.to_numpy())[0])]
        raise ConfigError(
            f"no sunrise or sunset at latitude {float(latitude):g} deg on {day} (polar day or night); "
            "the diurnal model needs both: give a weather file",
            key="date",
        )
    utc = [pd.DatetimeIndex(events[k]).tz_convert("UTC").tz_localize(None).to_numpy("datetime64[ns]") for k in ("sunrise", "sunset")]
    return utc[0], utc[1]


def diurnal_air_temperature(time, sunrise, sunset, t_min, t_max, coefficients=PARTON_LOGAN_AIR_150CM):
    """Air temperature of the Parton & Logan (1981) model at the given times [K].

    Parameters
    ----------
    time : numpy.ndarray
        ``datetime64[ns]`` [UTC], between the minimum of the first day and that of the last.
    sunrise, sunset : numpy.ndarray
        ``datetime64[ns]`` [UTC] of consecutive days, the first day's sunset before the first
        time and the last day's minimum (sunrise + c) at or after the last time.
    t_min, t_max : float
        Daily minimum and maximum [K], the same every day.
    coefficients : DiurnalCoefficients, optional
        a [h], b [-], c [h].

    Returns
    -------
    numpy.ndarray
        T_air [K], of the shape of ``time``.
    """
    a, b, c = coefficients
    t = np.asarray(time, "datetime64[ns]").astype(np.int64) / _HOUR_NS
    rise = np.asarray(sunrise, "datetime64[ns]").astype(np.int64) / _HOUR_NS
    set_ = np.asarray(sunset, "datetime64[ns]").astype(np.int64) / _HOUR_NS
    low = rise + c
    out = np.full(t.shape, np.nan)
    amplitude = t_max - t_min
    for k in range(len(rise)):
        length = set_[k] - rise[k]
        day = (t >= low[k]) & (t <= set_[k])
        out[day] = t_min + amplitude * np.sin(np.pi * (t[day] - low[k]) / (length + 2 * a))
        if k + 1 < len(rise):
            at_sunset = t_min + amplitude * np.sin(np.pi * (set_[k] - low[k]) / (length + 2 * a))
            night_length = low[k + 1] - set_[k]
            night = (t > set_[k]) & (t < low[k + 1])
            shape = (np.exp(-b * (t[night] - set_[k]) / night_length) - np.exp(-b)) / (1 - np.exp(-b))
            out[night] = t_min + (at_sunset - t_min) * shape
    if np.any(np.isnan(out)):
        raise ConfigError("times outside the days whose sunrise and sunset were given", key="time")
    return out


def diurnal_weather(
    latitude,
    longitude,
    date,
    *,
    t_min,
    t_max,
    relative_humidity,
    wind_speed,
    cloud_cover=0.0,
    pressure=101325.0,
    days=1,
    step=900.0,
    coefficients=PARTON_LOGAN_AIR_150CM,
):
    """A default weather for days without a weather file, from the place and the date.

    Parameters
    ----------
    latitude, longitude : float
        Place [deg], north and east positive.
    date : datetime.date or str
        First local (mean-solar) calendar date, ``'YYYY-MM-DD'``.
    t_min, t_max : float or str
        Daily minimum and maximum air temperature [K] (or strings such as ``"12 degC"``).
    relative_humidity : float
        Relative humidity at the mean of t_min and t_max [0-1]; the dew point it gives is kept.
    wind_speed : float
        [m s-1], constant.
    cloud_cover : float, optional
        [0-1], constant.
    pressure : float, optional
        [Pa], constant.
    days : int, optional
        Number of days, from local mean-solar midnight of ``date``.
    step : float or str, optional
        Time between samples [s] (or a string such as ``"10 min"``); the last sample falls on
        the end of the span.
    coefficients : DiurnalCoefficients, optional
        Parton & Logan's a [h], b [-], c [h]; by default those of air at 150 cm.

    Returns
    -------
    WeatherSeries
        With the place, and ``source`` naming the model and its inputs.

    Raises
    ------
    ConfigError
        t_min ≥ t_max, a humidity whose dew point lies above t_min, a step longer than the span,
        days < 1, a polar day or night, or a value out of range (each names its key).

    Examples
    --------
    >>> w = diurnal_weather(43.16, -77.61, "2024-06-21", t_min=288.15, t_max=301.15,
    ...                     relative_humidity=0.6, wind_speed=2.0)
    >>> bool(abs(w.air_temperature.max() - 301.15) < 0.01), bool(abs(w.air_temperature.min() - 288.15) < 0.2)
    (True, True)
    """
    day0 = _local_date(date)
    t_lo = parse_quantity(t_min, "temperature", key="t_min")
    t_hi = parse_quantity(t_max, "temperature", key="t_max")
    if not t_lo < t_hi:
        raise ConfigError(f"must be above t_min = {t_lo:g} K; got {t_hi:g} K", key="t_max")
    if int(days) != days or days < 1:
        raise ConfigError(f"must be a whole number >= 1; got {days!r}", key="days")
    days = int(days)
    dt = parse_quantity(step, "time", key="step")
    span = days * 86400.0
    if not dt > 0:
        raise ConfigError(f"must be > 0 s; got {step!r}", key="step")
    if dt > span:
        raise ConfigError(f"{dt:g} s is longer than the span of {days} day(s) ({span:g} s)", key="step")
    rh = float(relative_humidity)
    if not 0 < rh <= 1:
        raise ConfigError(f"must lie in (0, 1] (a fraction); got {relative_humidity!r}", key="relative_humidity")
    if not -90 <= float(latitude) <= 90 or not -180 <= float(longitude) <= 180:
        raise ConfigError(f"place ({latitude!r}, {longitude!r}) outside [-90, 90] x [-180, 180] deg", key="latitude")
    dew = float(relative_humidity_to_dew_point(0.5 * (t_lo + t_hi), rh))
    if dew > t_lo:
        raise ConfigError(
            f"{rh:g} at the mean temperature {0.5 * (t_lo + t_hi):.2f} K gives a dew point of {dew:.2f} K, "
            f"above t_min = {t_lo:g} K: the night would be supersaturated; give a lower relative_humidity",
            key="relative_humidity",
        )
    offset = np.timedelta64(round(float(longitude) * 240.0 * 1e9), "ns")  # 240 s of time per degree
    midnight = np.datetime64(day0.isoformat(), "ns") - offset
    seconds = np.append(np.arange(0.0, span, dt), span)
    time = midnight + np.round(seconds * 1e9).astype("timedelta64[ns]")
    dates = [day0 + _dt.timedelta(days=k) for k in range(-1, days + 1)]
    sunrise, sunset = sun_events(latitude, longitude, dates)
    air = diurnal_air_temperature(time, sunrise, sunset, t_lo, t_hi, coefficients)
    source = (
        f"diurnal weather (Parton & Logan 1981; a={coefficients.a:g} h, b={coefficients.b:g}, c={coefficients.c:g} h): "
        f"t_min {t_lo:g} K, t_max {t_hi:g} K, RH {rh:g} at the mean, at ({float(latitude):g}, {float(longitude):g}) deg "
        f"from {day0.isoformat()} for {days} day(s)"
    )
    return WeatherSeries(
        time=time,
        air_temperature=air,
        relative_humidity=dew_point_to_relative_humidity(air, np.full(air.shape, dew)),
        wind_speed=wind_speed,
        cloud_cover=cloud_cover,
        pressure=pressure,
        latitude=float(latitude),
        longitude=float(longitude),
        source=source,
    )
