"""Reader of THERM weather-history files (``.wth``), as DIRSIG uses them.

The format (DIRSIG documentation, "Weather history file", dirsig.org/docs/new/wth.html): a first
line with the number of entries and the time between them in hours (193 and 0.25 for DIRSIG:
48 hours, both ends included), then one entry per line, the first field the local time in hours.
The file states neither its date nor its place, so the caller gives both.

radscene reads the first six fields of each entry — hour [h, local], air temperature [°C],
pressure [mbar], relative humidity [0-1], dew point [°C], wind speed [m s-1]. The header and
its constraints are what the documentation states; this field layout was read off a public
example file, so every file is checked for it: the relative humidity of field 4 must agree
with the one of the dew point of field 5 (``HUMIDITY_AGREEMENT``).
The fields after the wind speed (insolation, cloud and precipitation) are not read; the
caller states the cloud cover. Numbers may run together in fixed-width fields
(``0.00-15.00``), so fields are split by number, not by white space.
"""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np

from radscene.errors import ConfigError
from radscene.thermal.weather._table import build_series
from radscene.thermal.weather.humidity import dew_point_to_relative_humidity

__all__ = ["read_wth"]

_NUMBER = re.compile(r"[-+]?(?:\d+\.\d*|\.\d+|\d+)(?:[eE][-+]?\d+)?")
#: Largest disagreement accepted between the file's relative humidity and the one of its dew
#: point [0-1]; a file that exceeds it is not laid out as radscene reads it.
HUMIDITY_AGREEMENT = 0.1
_FIELDS = ("hour", "air temperature [°C]", "pressure [mbar]", "relative humidity [0-1]", "dew point [°C]", "wind speed [m s-1]")


def _numbers(line, path, lineno):
    values = _NUMBER.findall(line)
    rest = _NUMBER.sub(" ", line).strip()
    if rest:
        raise ConfigError(f"{path}: line {lineno}: {rest.split()[0]!r} is not a number", key="weather")
    return [float(v) for v in values]


def read_wth(path, *, start, latitude, longitude, cloud_cover, max_gap=None):
    """Read a THERM ``.wth`` weather-history file.

    Parameters
    ----------
    path : str or Path
        The file.
    start : numpy.datetime64
        UTC instant of the file's hour 0 (local midnight of the file's first day) [UTC].
    latitude, longitude : float
        Place the weather is for [deg]; the file does not state it.
    cloud_cover : float
        Cloud cover over the whole file [0-1].
    max_gap : float, optional
        Longest step between entries accepted [s], for the row checks shared with the other
        readers; the header's fixed step already forbids gaps.

    Returns
    -------
    WeatherSeries

    Raises
    ------
    ConfigError
        A header that is not two numbers, a count that differs from the rows, a step that is
        not positive or longer than the span, a row with fewer than six fields or a field that
        is not a number, hours out of step with the header, or a humidity that disagrees with
        the dew point (each names the file and the line).
    """
    text = Path(path).read_text(encoding="utf-8", errors="replace").splitlines()
    rows = [(i + 1, line) for i, line in enumerate(text) if line.strip()]
    if not rows:
        raise ConfigError(f"{path}: empty file", key="weather")
    lineno, header = rows[0]
    head = _numbers(header, path, lineno)
    if len(head) != 2 or head[0] != int(head[0]):
        raise ConfigError(f"{path}: line {lineno}: expected '<number of entries> <hours between entries>'; got {header.strip()!r}", key="weather")
    count, step = int(head[0]), head[1]
    if step <= 0:
        raise ConfigError(f"{path}: line {lineno}: hours between entries must be > 0; got {step:g}", key="weather")
    if count < 2:
        raise ConfigError(f"{path}: line {lineno}: {count} entries: the step of {step:g} h is longer than the span", key="weather")
    entries = rows[1:]
    if len(entries) != count:
        raise ConfigError(f"{path}: line {lineno} announces {count} entries; the file has {len(entries)}", key="weather")
    table = np.empty((count, 6))
    for k, (n, line) in enumerate(entries):
        values = _numbers(line, path, n)
        if len(values) < 6:
            missing = ", ".join(_FIELDS[len(values):])
            raise ConfigError(f"{path}: line {n}: {len(values)} fields; missing {missing}", key="weather")
        table[k] = values[:6]
    hours = table[:, 0]
    lines = [f"line {n}" for n, _ in entries]
    for k in range(1, count):
        expected = hours[0] + k * step
        if abs(hours[k] - expected) > 1e-3:
            what = "repeats" if hours[k] == hours[k - 1] else "goes back" if hours[k] < hours[k - 1] else "is out of step"
            raise ConfigError(
                f"{path}: {lines[k]}: hour {hours[k]:g} {what}; expected {expected:g} ({step:g} h after the previous entry, as the header says)",
                key="time",
            )
    air = table[:, 1] + 273.15
    dew = table[:, 4] + 273.15
    rh = table[:, 3]
    for k in range(count):
        if not 0.0 <= rh[k] <= 1.0:
            raise ConfigError(f"{path}: {lines[k]}: relative humidity {rh[k]:g} outside [0, 1] (field 4 is a fraction)", key="relative_humidity")
        if dew[k] > air[k] + 1e-9:
            raise ConfigError(f"{path}: {lines[k]}: dew point {table[k, 4]:g} °C above the air temperature {table[k, 1]:g} °C", key="dew_point")
    from_dew = dew_point_to_relative_humidity(air, dew)
    worst = int(np.argmax(np.abs(from_dew - rh)))
    if abs(from_dew[worst] - rh[worst]) > HUMIDITY_AGREEMENT:
        raise ConfigError(
            f"{path}: {lines[worst]}: relative humidity {rh[worst]:g} (field 4) and dew point {table[worst, 4]:g} °C "
            f"(field 5, giving {from_dew[worst]:.2f}) disagree by more than {HUMIDITY_AGREEMENT:g}; the file is not "
            "laid out as hour, air temperature, pressure, relative humidity, dew point, wind speed",
            key="relative_humidity",
        )
    time = np.asarray(start, "datetime64[ns]") + np.round(hours * 3.6e12).astype("timedelta64[ns]")
    columns = {
        "air_temperature": air,
        "relative_humidity": rh,
        "wind_speed": table[:, 5],
        "cloud_cover": np.full(count, float(cloud_cover)),
        "pressure": table[:, 2] * 100.0,
    }
    return build_series(str(path), time, columns, lines, latitude, longitude, max_gap)
