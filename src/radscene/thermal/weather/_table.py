"""What the weather readers share: the variables a file may hold and their units, the checks of
rows (order, gaps, ranges) with messages naming the file and the row, and the checks of a
series' place and span against the scene's."""

from __future__ import annotations

import numpy as np

from radscene.errors import ConfigError
from radscene.radiometry.units import UNITS
from radscene.thermal.weather.humidity import dew_point_to_relative_humidity
from radscene.thermal.weather.series import OPTIONAL, REQUIRED, WeatherSeries, format_time

_TEMPERATURE = {
    **UNITS["temperature"],
    "C": (1.0, 273.15),
    "F": (5.0 / 9.0, 273.15 - 32.0 * 5.0 / 9.0),
    "degree_Celsius": (1.0, 273.15),
    "degrees_Celsius": (1.0, 273.15),
    "degree_C": (1.0, 273.15),
    "degK": (1.0, 0.0),
}
_FRACTION = {"1": (1.0, 0.0), "-": (1.0, 0.0), "0-1": (1.0, 0.0), "fraction": (1.0, 0.0), "%": (0.01, 0.0), "percent": (0.01, 0.0)}
_CLOUD = {**_FRACTION, "okta": (0.125, 0.0), "oktas": (0.125, 0.0), "tenths": (0.1, 0.0)}
_SPEED = {
    "m/s": (1.0, 0.0),
    "m s-1": (1.0, 0.0),
    "m s^-1": (1.0, 0.0),
    "km/h": (1.0 / 3.6, 0.0),
    "km h-1": (1.0 / 3.6, 0.0),
    "kn": (1852.0 / 3600.0, 0.0),
    "kt": (1852.0 / 3600.0, 0.0),
    "knot": (1852.0 / 3600.0, 0.0),
    "knots": (1852.0 / 3600.0, 0.0),
    "mph": (0.44704, 0.0),
    "ft/s": (0.3048, 0.0),
}
_PRESSURE = {
    "Pa": (1.0, 0.0),
    "hPa": (100.0, 0.0),
    "mbar": (100.0, 0.0),
    "mb": (100.0, 0.0),
    "kPa": (1000.0, 0.0),
    "bar": (1.0e5, 0.0),
    "atm": (101325.0, 0.0),
    "inHg": (3386.389, 0.0),
    "mmHg": (133.322387415, 0.0),
}

#: A Langley per hour: 1 cal_th cm-2 h-1 = 41840 J m-2 / 3600 s [W m-2] (the unit of a THERM
#: ``.wth`` file's insolation, DIRSIG manual, prn2wth, Table 30-1).
LANGLEY_PER_HOUR = 41840.0 / 3600.0
_IRRADIANCE = {
    **UNITS["irradiance"],
    "Ly/h": (LANGLEY_PER_HOUR, 0.0),
    "Ly h-1": (LANGLEY_PER_HOUR, 0.0),
    "Ly/hr": (LANGLEY_PER_HOUR, 0.0),
    "langley/h": (LANGLEY_PER_HOUR, 0.0),
    "Langley/hr": (LANGLEY_PER_HOUR, 0.0),
    "Langleys/hr": (LANGLEY_PER_HOUR, 0.0),
}

#: Columns of a weather file: name -> (kind, unit table). Units are to the series' units
#: (K, 0-1, m s-1, 0-1, Pa, W m-2) by canonical = value * factor + offset.
COLUMNS = {
    "air_temperature": ("temperature", _TEMPERATURE),
    "dew_point": ("temperature", _TEMPERATURE),
    "relative_humidity": ("fraction", _FRACTION),
    "wind_speed": ("speed", _SPEED),
    "cloud_cover": ("cloud fraction", _CLOUD),
    "pressure": ("pressure", _PRESSURE),
    "global_shortwave": ("irradiance", _IRRADIANCE),
    "direct_normal_shortwave": ("irradiance", _IRRADIANCE),
    "diffuse_shortwave": ("irradiance", _IRRADIANCE),
    "longwave_down": ("irradiance", _IRRADIANCE),
}

#: Bounds of plausible screen-level weather, beyond which a value most likely carries the wrong
#: unit (world records: air 184-330 K; sea-level pressure 870-1084 hPa, 337 hPa on Everest's
#: summit; a 113 m s-1 gust).
PLAUSIBLE = {
    "air_temperature": (170.0, 340.0),
    "pressure": (3.0e4, 1.1e5),
    "wind_speed": (0.0, 120.0),
    "global_shortwave": (0.0, 1500.0),
    "direct_normal_shortwave": (0.0, 1500.0),
    "diffuse_shortwave": (0.0, 1500.0),
    "longwave_down": (0.0, 700.0),
}


def unit_factor(path, column, unit, where):
    """(factor, offset) of ``unit`` for ``column``, or a ConfigError naming the file and column."""
    kind, table = COLUMNS[column]
    if unit is None or not unit.strip():
        raise ConfigError(f"{path}: {where} {column!r} has no unit; give one of: {', '.join(table)}", key=column)
    unit = " ".join(unit.split())
    if unit not in table:
        raise ConfigError(
            f"{path}: {where} {column!r} has a unit that is not a unit of {kind}; accepted: {', '.join(table)}",
            key=column,
        )
    return table[unit]


def build_series(path, time, columns, labels, latitude, longitude, max_gap=None):
    """Check rows and build a WeatherSeries.

    Parameters
    ----------
    path : str
        The file, for messages and the series' ``source``.
    time : numpy.ndarray
        datetime64[ns] [UTC] of each row.
    columns : dict of str to numpy.ndarray
        Values in the series' units, by column name (``dew_point`` in K is turned into
        ``relative_humidity``).
    labels : list of str
        How to name each row in a message: ``"line 12"``, ``"time index 3"``.
    latitude, longitude : float or None
        Place stated in the file [deg].
    max_gap : float or None
        Longest step between rows accepted [s]; None: three times the most frequent step.
    """
    n = time.size
    if n < 2:
        raise ConfigError(f"{path}: {n} row(s) of weather; at least two are needed", key="time")
    ns = time.astype(np.int64)
    steps = np.diff(ns)
    for i in range(n - 1):
        if steps[i] <= 0:
            first = int(np.flatnonzero(ns[: i + 1] == ns[i + 1])[0]) if steps[i] == 0 else i
            problem = f"repeats the time of {labels[first]}" if steps[i] == 0 else f"is before {labels[i]} ({format_time(time[i])})"
            raise ConfigError(f"{path}: {labels[i + 1]}: time {format_time(time[i + 1])} {problem}; times must be sorted and unique", key="time")
    values, counts = np.unique(steps, return_counts=True)
    usual = float(values[np.argmax(counts)]) / 1e9  # the most frequent step, the shortest of ties
    limit = 3.0 * usual if max_gap is None else float(max_gap)
    if limit <= 0 or not np.isfinite(limit):
        raise ConfigError(f"must be > 0 s; got {max_gap!r}", key="max_gap")
    long = np.flatnonzero(steps / 1e9 > limit * (1 + 1e-9))
    if long.size:
        i = int(long[0])
        rule = f"3 x the file's usual step ({_hours(usual)})" if max_gap is None else f"max_gap = {_hours(limit)}"
        raise ConfigError(
            f"{path}: gap of {_hours(steps[i] / 1e9)} between {labels[i]} ({format_time(time[i])}) and "
            f"{labels[i + 1]} ({format_time(time[i + 1])}), longer than {rule}; fill the gap or give max_gap (a scene's thermal.weather.max_gap)",
            key="time",
        )
    if "dew_point" in columns:
        dew, air = columns.pop("dew_point"), columns["air_temperature"]
        above = np.flatnonzero(dew > air + 1e-9)
        if above.size:
            i = int(above[0])
            raise ConfigError(
                f"{path}: {labels[i]}: dew point {dew[i] - 273.15:.2f} °C above the air temperature {air[i] - 273.15:.2f} °C",
                key="dew_point",
            )
        columns["relative_humidity"] = dew_point_to_relative_humidity(air, dew)
    check_shortwave(path, columns, labels)
    for name, values in columns.items():
        unit, low, high, low_inclusive = {**REQUIRED, **OPTIONAL}[name]
        ok = (values >= low) if low_inclusive else (values > low)
        ok &= values <= high
        if not np.all(ok):
            i = int(np.flatnonzero(~ok)[0])
            hint = "; is the unit right (a fraction, not a percentage)?" if high == 1.0 else "; is the unit right?"
            raise ConfigError(f"{path}: {labels[i]}: {name} = {values[i]:g} {unit} is outside [{low:g}, {high:g}]{hint}", key=name)
        if name in PLAUSIBLE:
            lo, hi = PLAUSIBLE[name]
            bad = np.flatnonzero((values < lo) | (values > hi))
            if bad.size:
                i = int(bad[0])
                raise ConfigError(
                    f"{path}: {labels[i]}: {name} = {values[i]:g} {unit} is outside the plausible "
                    f"[{lo:g}, {hi:g}] {unit} of weather near the ground; is the unit right?",
                    key=name,
                )
    return WeatherSeries(time=time, **columns, latitude=latitude, longitude=longitude, source=str(path))


def check_shortwave(path, columns, labels):
    """Refuse measured short-wave that cannot replace the modelled one: diffuse without a beam
    (global or direct normal) or the reverse, both beams, diffuse above global."""
    beams = [name for name in ("global_shortwave", "direct_normal_shortwave") if name in columns]
    if len(beams) == 2:
        raise ConfigError(f"{path}: both global_shortwave and direct_normal_shortwave; give one with diffuse_shortwave",
                          key="direct_normal_shortwave")
    if bool(beams) != ("diffuse_shortwave" in columns):
        given = beams[0] if beams else "diffuse_shortwave"
        other = "diffuse_shortwave" if beams else "global_shortwave or direct_normal_shortwave"
        raise ConfigError(
            f"{path}: {given} without {other}; the measured short-wave replaces the modelled one only as a pair",
            key="diffuse_shortwave" if beams else "global_shortwave",
        )
    if columns.get("global_shortwave") is not None:
        above = np.flatnonzero(columns["diffuse_shortwave"] > columns["global_shortwave"] + 1e-6)
        if above.size:
            i = int(above[0])
            raise ConfigError(
                f"{path}: {labels[i]}: diffuse_shortwave {columns['diffuse_shortwave'][i]:g} W m-2 above "
                f"global_shortwave {columns['global_shortwave'][i]:g} W m-2; is the column or field right?",
                key="diffuse_shortwave",
            )


def _hours(seconds):
    seconds = float(seconds)
    if seconds >= 3600 and seconds % 900 == 0:
        return f"{seconds / 3600:g} h"
    if seconds >= 60 and seconds % 60 == 0:
        return f"{seconds / 60:g} min"
    return f"{seconds:g} s"


def check_place(series, latitude, longitude, tolerance_deg):
    """Refuse a series whose stated place differs from the scene's by more than the tolerance."""
    tol = float(tolerance_deg)
    if not (np.isfinite(tol) and tol > 0):
        raise ConfigError(f"must be > 0 deg; got {tolerance_deg!r}", key="tolerance_deg")
    for name, scene, wrap in (("latitude", latitude, False), ("longitude", longitude, True)):
        if scene is None:
            continue
        scene = float(scene)
        own = getattr(series, name)
        if own is None:
            raise ConfigError(f"{series.source}: states no {name}; the scene's is {scene:g} deg", key=name)
        diff = (own - scene + 180.0) % 360.0 - 180.0 if wrap else own - scene
        if abs(diff) > tol:
            raise ConfigError(
                f"{series.source}: weather at {name} {own:g} deg, the scene at {scene:g} deg: "
                f"{abs(diff):g} deg apart, more than tolerance_deg = {tol:g}; weather from another place",
                key=name,
            )


def check_span(series, start, end):
    """Refuse a series that does not cover [start, end] (datetime64 UTC, either may be None)."""
    if start is None and end is None:
        return
    s = series.start if start is None else start
    e = series.end if end is None else end
    if s < series.start or e > series.end:
        raise ConfigError(
            f"{series.source}: covers {series.span_text()}; the scene needs {format_time(s)} to "
            f"{format_time(e)} (weather of another date?)",
            key="start" if s < series.start else "end",
        )
