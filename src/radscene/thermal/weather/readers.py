"""Weather files: CSV and NetCDF with units in their headers, and THERM ``.wth`` files, read
into a ``WeatherSeries`` and checked against the scene's place and time span.

CSV — ``#`` comment lines state the place; the first other line names the columns, each with
its unit in brackets; one row per time::

    # latitude: 43.16
    # longitude: -77.61
    time [UTC],air_temperature [degC],dew_point [degC],wind_speed [m/s],cloud_cover [%],pressure [hPa]
    2024-06-21T00:00,15.2,11.0,2.1,20,1013.2

Times are ISO 8601; a time without an offset takes the zone of the time column (``[UTC]``,
``[UTC+02:00]``, ``[UTC-05:00]``), and a time with neither is refused.

NetCDF — a ``time`` coordinate (CF-encoded), one variable per column along it with a
``units`` attribute, found by name (as in the CSV) or by CF ``standard_name``; the place as
global attributes ``latitude``/``longitude`` or scalar variables ``latitude``/``lat``,
``longitude``/``lon``.

Columns (name | unit accepted | meaning): ``air_temperature`` (K, degC, degF, ...) screen-level
air; ``relative_humidity`` (%, 1, fraction) or ``dew_point`` (K, degC, ...), one of the two;
``wind_speed`` (m/s, km/h, knots, mph); ``cloud_cover`` (%, 1, oktas, tenths); ``pressure``
(Pa, hPa, mbar, kPa); optional measured ``global_shortwave``, ``diffuse_shortwave``,
``longwave_down`` (W m-2, Ly/h, ...) on a horizontal plane, and ``direct_normal_shortwave``
(normal to the beam), which replace the modelled ones (diffuse with one of the two beams).
"""

from __future__ import annotations

import csv
import re
from pathlib import Path

import numpy as np
import pandas as pd

from radscene.errors import ConfigError, did_you_mean
from radscene.radiometry.units import parse_quantity
from radscene.thermal.weather._table import (
    COLUMNS,
    build_series,
    check_place,
    check_span,
    unit_factor,
)
from radscene.thermal.weather.series import to_utc_datetime64
from radscene.thermal.weather.wth import parse_fields, read_wth

__all__ = ["read_weather", "read_weather_csv", "read_weather_netcdf", "WEATHER_FORMATS"]

_REQUIRED = ("air_temperature", "wind_speed", "cloud_cover", "pressure")
_HUMIDITY = ("relative_humidity", "dew_point")
_HEADER = re.compile(r"^\s*([A-Za-z_][\w ]*?)\s*(?:\[(.*)\])?\s*$")
_ZONE = re.compile(r"^(?:UTC|Z|GMT)\s*(?:([+-])(\d{1,2})(?::?(\d{2}))?)?$", re.IGNORECASE)

#: CF standard names of the variables a NetCDF weather file may hold.
CF_STANDARD_NAMES = {
    "air_temperature": "air_temperature",
    "dew_point_temperature": "dew_point",
    "relative_humidity": "relative_humidity",
    "wind_speed": "wind_speed",
    "cloud_area_fraction": "cloud_cover",
    "air_pressure": "pressure",
    "surface_air_pressure": "pressure",
    "surface_downwelling_shortwave_flux_in_air": "global_shortwave",
    "surface_diffuse_downwelling_shortwave_flux_in_air": "diffuse_shortwave",
    "surface_downwelling_longwave_flux_in_air": "longwave_down",
}


def _check_columns(path, names):
    missing = [c for c in _REQUIRED if c not in names]
    if not any(h in names for h in _HUMIDITY):
        missing.append("relative_humidity or dew_point")
    if missing:
        raise ConfigError(f"{path}: missing column(s): {', '.join(missing)}", key=missing[0].split()[0])
    if all(h in names for h in _HUMIDITY):
        raise ConfigError(f"{path}: give relative_humidity or dew_point, not both", key="dew_point")


def _zone_offset(path, unit):
    """Offset of the time column's zone [ns], or None when the column states none."""
    if unit is None or not unit.strip():
        return None
    match = _ZONE.match(unit.strip())
    if match is None:
        raise ConfigError(f"{path}: the time column's unit is not a zone: give one such as UTC, UTC+02:00, "
                          "UTC-05:00", key="time")
    sign, hours, minutes = match.groups()
    if sign is None:
        return 0
    offset = (int(hours) * 60 + int(minutes or 0)) * 60 * 10**9
    return offset if sign == "+" else -offset


def read_weather_csv(path, *, max_gap=None):
    """Read a CSV weather file (see the module's docstring for its layout).

    Parameters
    ----------
    path : str or Path
        The file.
    max_gap : float or str, optional
        Longest step between rows accepted [s] (or a string such as ``"2 h"``); by default
        three times the file's most frequent step.

    Returns
    -------
    WeatherSeries

    Raises
    ------
    ConfigError
        Naming the file and the line or column: no header, a missing, unknown or repeated
        column, a column without a unit or with a wrong one, an empty value (a gap), a value
        that is not a number, a time without a zone, unsorted or repeated times, a step longer
        than ``max_gap``, a value out of range, no stated place.
    """
    meta, header, rows = {}, None, []
    with open(path, encoding="utf-8-sig", newline="") as handle:
        for lineno, fields in enumerate(csv.reader(handle), start=1):
            if not fields or not "".join(fields).strip():
                continue
            if fields[0].lstrip().startswith("#"):
                text = ",".join(fields).lstrip()[1:]
                if ":" in text:
                    key, value = text.split(":", 1)
                    meta[key.strip().lower()] = (value.strip(), lineno)
                continue
            if header is None:
                header = (lineno, fields)
            else:
                rows.append((lineno, fields))
    if header is None:
        raise ConfigError(f"{path}: no header line naming the columns", key="weather")
    header_line, cells = header
    names, units = [], []
    for number, cell in enumerate(cells, start=1):
        match = _HEADER.match(cell)
        if match is None:
            raise ConfigError(f"{path}: line {header_line}: column {number} is not 'name [unit]'", key="weather")
        name = "_".join(match.group(1).lower().split())
        if name != "time" and name not in COLUMNS:
            hint = did_you_mean(name, ["time", *COLUMNS], cutoff=0.8)
            raise ConfigError(f"{path}: line {header_line}: column {number} is none of time, "
                              f"{', '.join(COLUMNS)}{hint}", key="weather")
        if name in names:
            raise ConfigError(f"{path}: line {header_line}: column {name!r} appears twice", key=name)
        names.append(name)
        units.append(match.group(2))
    if "time" not in names:
        raise ConfigError(f"{path}: missing column(s): time", key="time")
    _check_columns(path, names)
    conversions = {n: unit_factor(path, n, u, "column") for n, u in zip(names, units, strict=True) if n != "time"}
    zone = _zone_offset(path, units[names.index("time")])
    if not rows:
        raise ConfigError(f"{path}: no rows of weather after the header (line {header_line})", key="weather")
    values = {n: np.empty(len(rows)) for n in conversions}
    times = np.empty(len(rows), "datetime64[ns]")
    labels = []
    for k, (lineno, fields) in enumerate(rows):
        label = f"line {lineno}"
        labels.append(label)
        if len(fields) != len(names):
            raise ConfigError(f"{path}: {label}: {len(fields)} values; the header has {len(names)} columns", key="weather")
        for name, cell in zip(names, fields, strict=True):
            cell = cell.strip()
            if not cell or cell.lower() in ("nan", "na", "n/a", "null", "-", "--"):
                raise ConfigError(f"{path}: {label}: no {name} (a gap); weather files must be complete", key=name)
            if name == "time":
                times[k] = _parse_time(path, label, cell, zone)
                continue
            try:
                number = float(cell)
            except ValueError:
                raise ConfigError(f"{path}: {label}: the {name} is not a number", key=name) from None
            if not np.isfinite(number):
                raise ConfigError(f"{path}: {label}: the {name} is not finite", key=name)
            factor, offset = conversions[name]
            values[name][k] = number * factor + offset
    latitude, longitude = (_place(path, meta, name) for name in ("latitude", "longitude"))
    return build_series(str(path), times, values, labels, latitude, longitude, _max_gap(max_gap))


def _parse_time(path, label, cell, zone):
    try:
        stamp = pd.Timestamp(cell)
    except (ValueError, TypeError):
        raise ConfigError(f"{path}: {label}: the time is not an ISO 8601 time", key="time") from None
    if stamp.tzinfo is not None:
        return stamp.tz_convert("UTC").tz_localize(None).to_datetime64()
    if zone is None:
        raise ConfigError(
            f"{path}: {label}: the time has no zone; write it with one ('...Z', '...+02:00') or "
            "name the column's zone in the header: time [UTC]",
            key="time",
        )
    return stamp.to_datetime64().astype("datetime64[ns]") - np.timedelta64(zone, "ns")


def _place(path, meta, name):
    if name not in meta:
        raise ConfigError(f"{path}: no '# {name}: ...' line; a weather file states its place", key=name)
    value, lineno = meta[name]
    try:
        return parse_quantity(value, "angle", key=name)
    except ConfigError:
        raise ConfigError(f"{path}: line {lineno}: the {name} is not an angle such as '45.2' or "
                          "'45.2 deg'", key=name) from None


def _max_gap(max_gap):
    if max_gap is None:
        return None
    return parse_quantity(max_gap, "time", key="max_gap")


def read_weather_netcdf(path, *, max_gap=None):
    """Read a NetCDF weather file (see the module's docstring for its layout).

    Parameters
    ----------
    path : str or Path
        The file.
    max_gap : float or str, optional
        As for ``read_weather_csv``.

    Returns
    -------
    WeatherSeries

    Raises
    ------
    ConfigError
        Naming the file and the variable or time index, as for ``read_weather_csv``.
    """
    import xarray as xr

    try:
        ds = xr.load_dataset(path)
    except (OSError, ValueError):
        raise ConfigError(f"{path}: not a readable NetCDF file", key="weather") from None
    if "time" not in ds.variables:
        raise ConfigError(f"{path}: no 'time' coordinate", key="time")
    if not np.issubdtype(ds["time"].dtype, np.datetime64) or ds["time"].ndim != 1:
        raise ConfigError(f"{path}: 'time' is not a 1-d CF time (its 'units' should read 'hours since 2024-06-21 00:00:00')", key="time")
    time = ds["time"].values.astype("datetime64[ns]")
    labels = [f"time index {i}" for i in range(time.size)]
    found = {}
    for var_name, var in ds.data_vars.items():
        name = var_name if var_name in COLUMNS else CF_STANDARD_NAMES.get(var.attrs.get("standard_name", ""))
        if name is None:
            continue
        if name in found:
            raise ConfigError(f"{path}: both {found[name][0]!r} and {var_name!r} hold {name}", key=name)
        found[name] = (var_name, var)
    _check_columns(path, list(found))
    values = {}
    for name, (var_name, var) in found.items():
        var = var.squeeze(drop=True)
        if var.dims != ("time",):
            raise ConfigError(f"{path}: variable {var_name!r} has dimensions {var.dims}; expected ('time',)", key=name)
        factor, offset = unit_factor(path, name, var.attrs.get("units"), "variable")
        data = np.asarray(var.values, float)
        bad = np.flatnonzero(~np.isfinite(data))
        if bad.size:
            i = int(bad[0])
            raise ConfigError(f"{path}: {labels[i]}: no {var_name} (a missing value, a gap); weather files must be complete", key=name)
        values[name] = data * factor + offset
    latitude, longitude = (_netcdf_place(path, ds, name) for name in ("latitude", "longitude"))
    return build_series(str(path), time, values, labels, latitude, longitude, _max_gap(max_gap))


def _netcdf_place(path, ds, name):
    for candidate in (name, name[:3]):
        if candidate in ds.variables and ds[candidate].size == 1:
            return float(ds[candidate].values.ravel()[0])
    if name in ds.attrs:
        try:
            return float(np.asarray(ds.attrs[name]).ravel()[0])
        except (TypeError, ValueError):
            raise ConfigError(f"{path}: global attribute {name} is not a number", key=name) from None
    raise ConfigError(f"{path}: no {name} (a global attribute or a scalar variable); a weather file states its place", key=name)


#: Readers by file suffix.
WEATHER_FORMATS = {".csv": "csv", ".txt": "csv", ".nc": "netcdf", ".nc4": "netcdf", ".cdf": "netcdf", ".wth": "wth"}


def read_weather(path, *, latitude=None, longitude=None, start=None, end=None, tolerance_deg=1.0, max_gap=None, cloud_cover=None,
                 fields=None):
    """Read a weather file and check it against the scene's place and time span.

    Parameters
    ----------
    path : str or Path
        A CSV (``.csv``, ``.txt``), NetCDF (``.nc``, ``.nc4``, ``.cdf``) or THERM (``.wth``) file.
    latitude, longitude : float, optional
        The scene's place [deg]; the file's stated place must lie within ``tolerance_deg``.
        Required for ``.wth`` files, which state none.
    start, end : time, optional
        The span the scene needs [UTC or zoned; see ``to_utc_datetime64``]; the file must
        cover it. For a ``.wth`` file ``start`` is required and is the instant of the file's
        hour 0 (local midnight of its first day, with its zone, e.g. ``"2024-06-20T00:00-04:00"``).
    tolerance_deg : float, optional
        Largest accepted difference in latitude and in longitude [deg].
    max_gap : float or str, optional
        Longest step between rows accepted [s], or a string such as ``"2 h"``; by default
        three times the file's most frequent step.
    cloud_cover : float, optional
        Cloud cover [0-1] for a ``.wth`` file whose entries stop before the sky exposure (field
        9) and that declares no cloud field (see ``fields``); refused for the other files,
        which carry their own.
    fields : dict of int to str, optional
        For a ``.wth`` file, the meaning and unit of fields after the sixth, which the format's
        documentation does not state: 1-based field number -> ``"name [unit]"``, e.g.
        ``{7: "direct_normal_shortwave [Ly/h]", 8: "diffuse_shortwave [Ly/h]"}`` (see
        ``radscene.thermal.weather.wth.parse_fields``); refused for the other formats.

    Returns
    -------
    WeatherSeries

    Raises
    ------
    ConfigError
        One line naming the file and the row or key: a missing file, an unknown suffix, start
        after end, a bad file (see the readers), a place or span that does not match the scene.

    Examples
    --------
    >>> import pathlib, tempfile
    >>> path = pathlib.Path(tempfile.mkdtemp()) / "site.csv"
    >>> _ = path.write_text("# latitude: 43.16\\n# longitude: -77.61\\n"
    ...     "time [UTC],air_temperature [degC],relative_humidity [%],wind_speed [m/s],cloud_cover [%],pressure [hPa]\\n"
    ...     "2024-06-21T00:00,15,70,2,20,1013\\n2024-06-21T01:00,14,75,2,20,1013\\n")
    >>> w = read_weather(path, latitude=43.2, longitude=-77.6, start="2024-06-21T00:30Z")
    >>> float(w.at(np.datetime64("2024-06-21T00:30"))["air_temperature"])
    287.65
    """
    path = Path(path)
    if not path.is_file():
        raise ConfigError(f"{path}: no such weather file", key="weather")
    kind = WEATHER_FORMATS.get(path.suffix.lower())
    if kind is None:
        raise ConfigError(f"{path}: unknown weather file suffix {path.suffix!r}; known: {', '.join(WEATHER_FORMATS)}"
                          f"{did_you_mean(path.suffix, WEATHER_FORMATS)}", key="weather")
    t_start = None if start is None else to_utc_datetime64(start, "start")
    t_end = None if end is None else to_utc_datetime64(end, "end")
    if t_start is not None and t_end is not None and t_start > t_end:
        raise ConfigError(f"{path}: start {start!s} is after end {end!s}", key="start")
    if kind == "wth":
        parse_fields(fields, path)
        missing = [n for n, v in (("start", start), ("latitude", latitude), ("longitude", longitude)) if v is None]
        if missing:
            raise ConfigError(
                f"{path}: a THERM .wth file states no date or place; give {', '.join(missing)} "
                "(start: the zoned local time of its hour 0, e.g. '2024-06-20T00:00-04:00')",
                key=missing[0],
            )
        if isinstance(start, np.datetime64) or (isinstance(start, np.ndarray) and np.issubdtype(start.dtype, np.datetime64)):
            raise ConfigError(f"{path}: a .wth file's hours are local: give start with its zone, e.g. '2024-06-20T00:00-04:00'", key="start")
        cover = None
        if cloud_cover is not None:
            cover = float(cloud_cover)
            if not 0.0 <= cover <= 1.0:
                raise ConfigError(f"must lie in [0, 1]; got {cloud_cover!r}", key="cloud_cover")
        series = read_wth(path, start=t_start, latitude=latitude, longitude=longitude, cloud_cover=cover, fields=fields,
                          max_gap=_max_gap(max_gap))
        check_span(series, None, t_end)
        return series
    if cloud_cover is not None:
        raise ConfigError(f"{path}: cloud_cover is for .wth files; a {kind} weather file carries its own", key="cloud_cover")
    if fields:
        raise ConfigError(f"{path}: fields are declared for .wth files; a {kind} weather file names its own columns", key="fields")
    series = read_weather_csv(path, max_gap=max_gap) if kind == "csv" else read_weather_netcdf(path, max_gap=max_gap)
    check_place(series, latitude, longitude, tolerance_deg)
    check_span(series, t_start, t_end)
    return series
