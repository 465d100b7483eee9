"""A weather time series, interpolated linearly in time: the container every weather source
(file or diurnal default) produces and the heat balance reads.

Times are numpy ``datetime64[ns]`` in UTC. A numpy datetime64 given to radscene is taken to be
UTC; a Python ``datetime``, pandas ``Timestamp`` or ISO 8601 string must carry its time zone
(as in ``radscene.sun``), so that a local time is never read as UTC.
"""

from __future__ import annotations

import datetime as _dt
from dataclasses import dataclass, fields

import numpy as np
import pandas as pd

from radscene.errors import ConfigError
from radscene.thermal.weather.sky import sky_longwave as _sky_longwave

__all__ = ["WeatherSeries", "to_utc_datetime64", "format_time"]

#: Variables every series holds, with their unit and valid range (low, high, low_inclusive).
REQUIRED = {
    "air_temperature": ("K", 0.0, np.inf, False),
    "relative_humidity": ("0-1", 0.0, 1.0, True),
    "wind_speed": ("m s-1", 0.0, np.inf, True),
    "cloud_cover": ("0-1", 0.0, 1.0, True),
    "pressure": ("Pa", 0.0, np.inf, False),
}
#: Measured irradiances a series may hold; they replace the modelled ones.
OPTIONAL = {
    "global_shortwave": ("W m-2", 0.0, np.inf, True),
    "direct_normal_shortwave": ("W m-2", 0.0, np.inf, True),
    "diffuse_shortwave": ("W m-2", 0.0, np.inf, True),
    "longwave_down": ("W m-2", 0.0, np.inf, True),
}


def format_time(time) -> str:
    """ISO 8601 text of a UTC datetime64, to the minute when whole minutes (``2024-06-21T12:00Z``)."""
    t = np.datetime64(time, "ns")
    text = np.datetime_as_string(t, unit="s")
    return (text[:-3] if text.endswith(":00") else text) + "Z"


def _naive(what, key):
    return ConfigError(
        f"times must carry a time zone (e.g. '2024-06-21T12:00Z', datetime(..., tzinfo=timezone.utc) "
        f"or pandas.Timestamp(..., tz='UTC')); got a naive {what}. A numpy datetime64 is taken as UTC.",
        key=key,
    )


def to_utc_datetime64(times, key="time") -> np.ndarray:
    """Convert times to a numpy ``datetime64[ns]`` array in UTC, of the input's shape.

    Parameters
    ----------
    times : datetime64, array of datetime64, datetime, pandas.Timestamp, pandas.DatetimeIndex, str, or a list of these
        numpy datetime64 values are taken to be UTC; the others must be timezone-aware.
    key : str, optional
        Name used in error messages.

    Returns
    -------
    numpy.ndarray
        ``datetime64[ns]`` [UTC] (0-d for one time).

    Raises
    ------
    ConfigError
        A naive time (other than numpy datetime64), text that is not a time, or NaT.

    Examples
    --------
    >>> str(to_utc_datetime64("2024-06-21T14:00+02:00"))
    '2024-06-21T12:00:00.000000000'
    """
    arr = np.asarray(times) if not isinstance(times, (pd.DatetimeIndex, pd.Series)) else None
    if arr is not None and np.issubdtype(arr.dtype, np.datetime64):
        out = arr.astype("datetime64[ns]")
    else:
        shape = None
        if isinstance(times, pd.Series):
            times = pd.DatetimeIndex(times)
        if isinstance(times, pd.DatetimeIndex):
            index = times
        elif isinstance(times, (str, _dt.datetime, pd.Timestamp)):
            shape = ()
            index = _parse_index([times], key)
        else:
            flat = np.asarray(times, dtype=object)
            shape = flat.shape
            index = _parse_index(list(flat.ravel()), key)
        if index.tz is None:
            raise _naive("DatetimeIndex", key)
        out = index.tz_convert("UTC").tz_localize(None).to_numpy("datetime64[ns]")
        if shape is not None:
            out = out.reshape(shape)
    if np.any(np.isnat(out)):
        raise ConfigError("contains NaT (not a time)", key=key)
    return out


def _parse_index(values, key):
    out = []
    for v in values:
        if isinstance(v, np.datetime64):
            raise ConfigError("mix of numpy datetime64 and other times; give one kind", key=key)
        try:
            stamp = pd.Timestamp(v)
        except (ValueError, TypeError) as exc:
            raise ConfigError(f"not an ISO 8601 time: {v!r} ({exc})", key=key) from None
        if stamp is pd.NaT:
            raise ConfigError("contains NaT (not a time)", key=key)
        if stamp.tzinfo is None:
            raise _naive(f"time {v!r}" if isinstance(v, str) else type(v).__name__, key)
        out.append(stamp.tz_convert("UTC"))
    return pd.DatetimeIndex(out, tz="UTC") if out else pd.DatetimeIndex([], tz="UTC")


@dataclass(frozen=True, eq=False)
class WeatherSeries:
    """Weather at one place over a span of time, linearly interpolated between its samples.

    Attributes
    ----------
    time : numpy.ndarray
        Sample times, ``datetime64[ns]`` [UTC], strictly increasing, at least two.
    air_temperature : numpy.ndarray
        Screen-level air temperature [K].
    relative_humidity : numpy.ndarray
        Relative humidity over water [0-1].
    wind_speed : numpy.ndarray
        Wind speed near the surface [m s-1].
    cloud_cover : numpy.ndarray
        Fraction of the sky covered by cloud [0-1].
    pressure : numpy.ndarray
        Air pressure at the site [Pa].
    global_shortwave, diffuse_shortwave, longwave_down : numpy.ndarray or None
        Measured global and diffuse short-wave and downwelling long-wave irradiance on a
        horizontal plane [W m-2]; None when not measured (then modelled).
    direct_normal_shortwave : numpy.ndarray or None
        Measured direct solar irradiance normal to the beam [W m-2], with
        ``diffuse_shortwave`` the alternative to ``global_shortwave``.
    latitude, longitude : float or None
        Place of the weather [deg] (north, east positive); None for a source without a place.
    source : str
        Where the series comes from (a file path, or the diurnal model and its inputs).

    Raises
    ------
    ConfigError
        Times not strictly increasing or fewer than two; arrays not of the times' length;
        a value not finite or out of its range (the message names the source, the variable
        and the first offending sample); measured short-wave other than diffuse with one
        beam (global or direct normal).
    """

    time: np.ndarray
    air_temperature: np.ndarray
    relative_humidity: np.ndarray
    wind_speed: np.ndarray
    cloud_cover: np.ndarray
    pressure: np.ndarray
    global_shortwave: np.ndarray | None = None
    diffuse_shortwave: np.ndarray | None = None
    longwave_down: np.ndarray | None = None
    direct_normal_shortwave: np.ndarray | None = None
    latitude: float | None = None
    longitude: float | None = None
    source: str = "weather"

    def __post_init__(self):
        src = self.source
        time = np.asarray(self.time)
        if not np.issubdtype(time.dtype, np.datetime64):
            raise ConfigError(f"{src}: time must be numpy datetime64 [UTC]; got dtype {time.dtype}", key="time")
        time = time.astype("datetime64[ns]")
        if time.ndim != 1 or time.size < 2 or np.any(np.isnat(time)):
            raise ConfigError(f"{src}: time must be a 1-d array of at least two times", key="time")
        steps = np.diff(time.astype(np.int64))
        bad = np.flatnonzero(steps <= 0)
        if bad.size:
            i = int(bad[0])
            what = "repeated" if steps[i] == 0 else "goes back"
            raise ConfigError(
                f"{src}: time {what} at sample {i + 1} ({format_time(time[i + 1])} after "
                f"{format_time(time[i])}); times must be strictly increasing",
                key="time",
            )
        object.__setattr__(self, "time", time)
        for name, spec in {**REQUIRED, **OPTIONAL}.items():
            value = getattr(self, name)
            if value is None:
                if name in REQUIRED:
                    raise ConfigError(f"{src}: {name} is required", key=name)
                continue
            arr = np.array(value, dtype=float)
            if arr.ndim == 0:
                arr = np.full(time.shape, float(arr))
            if arr.shape != time.shape:
                raise ConfigError(f"{src}: {name} has shape {arr.shape}; the times have {time.shape}", key=name)
            unit, low, high, low_inclusive = spec
            ok = np.isfinite(arr) & (arr <= high) & ((arr >= low) if low_inclusive else (arr > low))
            if not np.all(ok):
                i = int(np.flatnonzero(~ok)[0])
                bracket = "[" if low_inclusive else "("
                what = f"outside {bracket}{low:g}, {high:g}] {unit}" if np.isfinite(arr[i]) else "not finite"
                raise ConfigError(f"{src}: {name} = {float(arr[i])!r} at sample {i} ({format_time(time[i])}) is {what}", key=name)
            arr.setflags(write=False)
            object.__setattr__(self, name, arr)
        beams = [n for n in ("global_shortwave", "direct_normal_shortwave") if getattr(self, n) is not None]
        if len(beams) > 1 or bool(beams) != (self.diffuse_shortwave is not None):
            given = ", ".join(beams + (["diffuse_shortwave"] if self.diffuse_shortwave is not None else []))
            raise ConfigError(
                f"{src}: measured short-wave is diffuse_shortwave with one of global_shortwave or "
                f"direct_normal_shortwave; got {given}",
                key="diffuse_shortwave",
            )
        for name, limit in (("latitude", 90.0), ("longitude", 180.0)):
            value = getattr(self, name)
            if value is not None:
                value = float(value)
                if not (np.isfinite(value) and -limit <= value <= limit):
                    raise ConfigError(f"{src}: {name} must lie in [-{limit:g}, {limit:g}] deg; got {value!r}", key=name)
                object.__setattr__(self, name, value)
        time.setflags(write=False)

    @property
    def start(self) -> np.datetime64:
        """First sample time [UTC]."""
        return self.time[0]

    @property
    def end(self) -> np.datetime64:
        """Last sample time [UTC]."""
        return self.time[-1]

    @property
    def variables(self) -> tuple[str, ...]:
        """Names of the variables the series holds (the optional ones only when present)."""
        return tuple(f.name for f in fields(self) if f.name in REQUIRED or (f.name in OPTIONAL and getattr(self, f.name) is not None))

    def span_text(self) -> str:
        """The span as text, ``'2024-06-21T00:00Z to 2024-06-23T00:00Z'``."""
        return f"{format_time(self.start)} to {format_time(self.end)}"

    def covers(self, start, end=None) -> bool:
        """Whether [start, end] [UTC] lies within the series' span."""
        s = to_utc_datetime64(start, "start")
        e = s if end is None else to_utc_datetime64(end, "end")
        return bool(self.start <= s and e <= self.end)

    def _seconds(self, times):
        return (np.asarray(times, "datetime64[ns]") - self.time[0]).astype(np.int64) / 1e9

    def at(self, times) -> dict[str, np.ndarray]:
        """The weather at the given times, linearly interpolated between samples.

        Parameters
        ----------
        times : datetime64 or array_like of times
            See ``to_utc_datetime64``: numpy datetime64 are UTC, other times carry a zone.

        Returns
        -------
        dict of str to numpy.ndarray
            One array of the shape of ``times`` per variable in ``variables``, in the series'
            units (K, 0-1, m s-1, 0-1, Pa, W m-2).

        Raises
        ------
        ConfigError
            A time outside the series' span (the message states the span and the source).

        Examples
        --------
        >>> t = np.array(["2024-06-21T00:00", "2024-06-21T01:00"], "datetime64[ns]")
        >>> w = WeatherSeries(t, [280.0, 290.0], 0.5, 2.0, 0.0, 101325.0, source="example")
        >>> float(w.at(np.datetime64("2024-06-21T00:30"))["air_temperature"])
        285.0
        """
        t = to_utc_datetime64(times, "time")
        if t.size and (t.min() < self.start or t.max() > self.end):
            outside = t[(t < self.start) | (t > self.end)].ravel()[0]
            raise ConfigError(
                f"{format_time(outside)} lies outside the weather's span, {self.span_text()} ({self.source})",
                key="time",
            )
        x = self._seconds(t)
        xp = self._seconds(self.time)
        return {name: np.interp(x, xp, getattr(self, name)) for name in self.variables}

    def sky_longwave(self, times, *, clear_sky="brutsaert", cloud="crawford_duchon") -> np.ndarray:
        """Downwelling long-wave irradiance at the given times [W m-2]: measured when the series
        has ``longwave_down``, otherwise modelled by ``sky.sky_longwave`` from the
        interpolated air temperature, humidity and cloud cover.

        Parameters
        ----------
        times : datetime64 or array_like of times
            As for ``at``.
        clear_sky, cloud : str, optional
            Names in ``CLEAR_SKY_EMISSIVITY_MODELS`` and ``CLOUD_EMISSIVITY_MODELS``.

        Returns
        -------
        numpy.ndarray
            E_sky,LW [W m-2], of the shape of ``times``.
        """
        w = self.at(times)
        if "longwave_down" in w:
            return w["longwave_down"]
        return _sky_longwave(w["air_temperature"], w["relative_humidity"], w["cloud_cover"], clear_sky=clear_sky, cloud=cloud)
