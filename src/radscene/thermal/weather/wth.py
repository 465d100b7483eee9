"""Reader of THERM weather-history files (``.wth``), as DIRSIG uses them.

The format: a first line with the number of entries and the time between them in hours (193
and 0.25 for DIRSIG: 48 hours, both ends included), then one entry per line, the first field
the local time in hours (DIRSIG documentation, "Weather history file",
dirsig.org/docs/new/wth.html). The file states neither its date nor its place, so the caller
gives both. The fields of an entry, in order, are named by the DIRSIG manual's description of
its PRISM-to-WTH converter (dirsig.org/docs/manual/prn2wth-technical.html, Table 30-1, "WTH
Data Sources"): relative time [h], air temperature [°C], pressure [mbar], relative humidity
[0-1], dew point [°C], wind speed [m s-1], direct insolation [Langley h-1], diffuse
insolation, sky exposure [0 overcast - 1 clear], cloud type, precipitation type, precipitation
rate [cm h-1], precipitation temperature.

radscene reads the first six, and the sky exposure as the cloud cover, 1 - sky exposure (the
converter maps a cloud cover of 0-10 tenths linearly onto a sky exposure of 1-0). Every file
is checked for this layout: the relative humidity of field 4 must agree with the one of the
dew point of field 5 (``HUMIDITY_AGREEMENT``) and the sky exposure must lie in [0, 1].

The insolation fields are not read by default: the table gives the direct insolation's unit
(Langley h-1, converted from W m-2 by 0.0858) but not whether it is normal to the beam or on a
horizontal plane, nor the diffuse insolation's unit. A caller who knows declares them
(``fields``, 1-based field number -> ``"name [unit]"``, a name of ``DECLARABLE``), e.g.
``{7: "direct_normal_shortwave [Ly/h]", 8: "diffuse_shortwave [Ly/h]"}``; the measured
irradiances then replace the modelled ones, as for the CSV reader, and a declared
``cloud_cover`` replaces the sky exposure. Precipitation is not used by the heat balance.
Numbers may run together in fixed-width fields (``0.00-15.00``), so fields are split by number,
not by white space.
"""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np

from radscene.errors import ConfigError, did_you_mean
from radscene.thermal.weather._table import build_series, check_shortwave, unit_factor
from radscene.thermal.weather.humidity import dew_point_to_relative_humidity

__all__ = ["DECLARABLE", "SKY_EXPOSURE_FIELD", "parse_fields", "read_wth"]

_NUMBER = re.compile(r"[-+]?(?:\d+\.\d*|\.\d+|\d+)(?:[eE][-+]?\d+)?")
_DECLARED = re.compile(r"^\s*([A-Za-z_]\w*)\s*\[(.+)\]\s*$")
#: Largest disagreement accepted between the file's relative humidity and the one of its dew
#: point [0-1]; a file that exceeds it is not laid out as radscene reads it.
HUMIDITY_AGREEMENT = 0.1
_FIELDS = ("hour", "air temperature [°C]", "pressure [mbar]", "relative humidity [0-1]", "dew point [°C]", "wind speed [m s-1]")
#: Field (1-based) of the sky exposure [0 overcast - 1 clear].
SKY_EXPOSURE_FIELD = 9
#: Variables a caller may declare for the fields after the sixth.
DECLARABLE = ("global_shortwave", "direct_normal_shortwave", "diffuse_shortwave", "longwave_down", "cloud_cover")


def _numbers(line, path, lineno):
    values = _NUMBER.findall(line)
    if _NUMBER.sub(" ", line).strip():
        raise ConfigError(f"{path}: line {lineno}: not all numbers (a .wth file holds numbers only)",
                          key="weather")
    return [float(v) for v in values]


def parse_fields(fields, path="weather", key="fields"):
    """Check a declaration of a ``.wth`` file's fields after the sixth.

    Parameters
    ----------
    fields : dict of int to str, or None
        1-based field number (> 6) -> ``"name [unit]"``, ``name`` one of ``DECLARABLE`` and
        ``unit`` one the CSV reader accepts for it (``W m-2``, ``Ly/h``, ``tenths``, ``%``, ...).
    path : str, optional
        The file, for messages.
    key : str, optional
        The configuration key, for messages.

    Returns
    -------
    dict of int to tuple
        Field number -> (name, factor, offset) converting the field to the series' units
        (W m-2, 0-1) by ``value * factor + offset``.

    Raises
    ------
    ConfigError
        A field number that is not an integer above 6, a declaration that is not
        ``"name [unit]"``, an unknown name, a name declared twice, a unit of another kind, or
        a beam (``global_shortwave`` or ``direct_normal_shortwave``) without
        ``diffuse_shortwave`` or the reverse, or both beams.
    """
    if not fields:
        return {}
    out, seen = {}, {}
    for number, text in dict(fields).items():
        try:
            n = int(number)
        except (TypeError, ValueError):
            raise ConfigError(f"{path}: field number {number!r} is not an integer", key=key) from None
        if n != number and str(n) != str(number).strip():
            raise ConfigError(f"{path}: field number {number!r} is not an integer", key=key)
        if n <= len(_FIELDS):
            raise ConfigError(
                f"{path}: field {n} is read as {_FIELDS[n - 1]}; only fields after the sixth can be declared", key=f"{key}.{n}"
            )
        match = _DECLARED.match(str(text))
        if match is None:
            raise ConfigError(f"{path}: field {n}: {text!r} is not 'name [unit]', e.g. 'global_shortwave [W m-2]'", key=f"{key}.{n}")
        name, unit = match.group(1).lower(), match.group(2)
        if name not in DECLARABLE:
            raise ConfigError(f"{path}: field {n}: unknown name {name!r}; known: {', '.join(DECLARABLE)}"
                              f"{did_you_mean(name, DECLARABLE)}", key=f"{key}.{n}")
        if name in seen:
            raise ConfigError(f"{path}: fields {seen[name]} and {n} are both declared {name}", key=f"{key}.{n}")
        seen[name] = n
        factor, offset = unit_factor(path, name, unit, f"field {n}")
        out[n] = (name, factor, offset)
    check_shortwave(path, {name: None for name in seen}, [])
    return out


def read_wth(path, *, start, latitude, longitude, cloud_cover=None, fields=None, max_gap=None):
    """Read a THERM ``.wth`` weather-history file.

    Parameters
    ----------
    path : str or Path
        The file.
    start : numpy.datetime64
        UTC instant of the file's hour 0 (local midnight of the file's first day) [UTC].
    latitude, longitude : float
        Place the weather is for [deg]; the file does not state it.
    cloud_cover : float, optional
        Cloud cover over the whole file [0-1], for a file whose entries stop before the sky
        exposure (field 9) and that declares no ``cloud_cover`` field; refused otherwise.
    fields : dict of int to str, optional
        The meaning and unit of fields after the sixth (see ``parse_fields``); fields not
        declared are checked to be numbers and otherwise not read.
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
        not positive or longer than the span, a row with fewer than six fields or with another
        number of fields than the first entry, a field that is not a number, hours out of step
        with the header, a humidity that disagrees with the dew point, a declared field that
        is missing from the entries or out of range, diffuse above global short-wave (each
        names the file and the line; the last two from ``build_series``); a bad ``fields``
        declaration (see ``parse_fields``); a cloud cover given for a file that carries one,
        or none for a file without; a sky exposure outside [0, 1].
    """
    declared = parse_fields(fields, path)
    has_cloud = any(name == "cloud_cover" for name, _, _ in declared.values())
    if has_cloud and cloud_cover is not None:
        raise ConfigError(f"{path}: cloud cover is both a declared field and given as {cloud_cover!r}; give one", key="cloud_cover")
    text = Path(path).read_text(encoding="utf-8", errors="replace").splitlines()
    rows = [(i + 1, line) for i, line in enumerate(text) if line.strip()]
    if not rows:
        raise ConfigError(f"{path}: empty file", key="weather")
    lineno, header = rows[0]
    head = _numbers(header, path, lineno)
    if len(head) != 2 or head[0] != int(head[0]):
        raise ConfigError(f"{path}: line {lineno}: expected '<number of entries> <hours between entries>'", key="weather")
    count, step = int(head[0]), head[1]
    if step <= 0:
        raise ConfigError(f"{path}: line {lineno}: hours between entries must be > 0; got {step:g}", key="weather")
    if count < 2:
        raise ConfigError(f"{path}: line {lineno}: {count} entries: the step of {step:g} h is longer than the span", key="weather")
    entries = rows[1:]
    if len(entries) != count:
        raise ConfigError(f"{path}: line {lineno} announces {count} entries; the file has {len(entries)}", key="weather")
    width = None
    needed = max([SKY_EXPOSURE_FIELD, *declared])
    table = np.full((count, needed), np.nan)
    for k, (n, line) in enumerate(entries):
        values = _numbers(line, path, n)
        if len(values) < len(_FIELDS):
            missing = ", ".join(_FIELDS[len(values):])
            raise ConfigError(f"{path}: line {n}: {len(values)} fields; missing {missing}", key="weather")
        if width is None:
            width = len(values)
            short = [f for f in declared if f > width]
            if short:
                raise ConfigError(f"{path}: line {n}: {width} fields; no field {short[0]} as declared", key="fields")
        elif len(values) != width:
            raise ConfigError(f"{path}: line {n}: {len(values)} fields; the first entry (line {entries[0][0]}) has {width}", key="weather")
        table[k, : min(needed, len(values))] = values[:needed]
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
        "pressure": table[:, 2] * 100.0,
    }
    if not has_cloud:
        exposed = width >= SKY_EXPOSURE_FIELD and SKY_EXPOSURE_FIELD not in declared
        if exposed and cloud_cover is not None:
            raise ConfigError(
                f"{path}: the file carries its sky exposure (field {SKY_EXPOSURE_FIELD}, cloud cover = 1 - sky exposure); "
                f"cloud_cover {cloud_cover!r} is for files without it",
                key="cloud_cover",
            )
        if exposed:
            sky = table[:, SKY_EXPOSURE_FIELD - 1]
            bad = np.flatnonzero((sky < 0.0) | (sky > 1.0))
            if bad.size:
                k = int(bad[0])
                raise ConfigError(
                    f"{path}: {lines[k]}: sky exposure {sky[k]:g} (field {SKY_EXPOSURE_FIELD}) outside [0, 1] "
                    "(1 clear, 0 overcast)",
                    key="cloud_cover",
                )
            columns["cloud_cover"] = 1.0 - sky
        elif cloud_cover is None:
            raise ConfigError(
                f"{path}: entries of {width} fields carry no sky exposure (field {SKY_EXPOSURE_FIELD}): give cloud_cover, "
                "or declare the file's cloud field",
                key="cloud_cover",
            )
        else:
            columns["cloud_cover"] = np.full(count, float(cloud_cover))
    for number, (name, factor, offset) in sorted(declared.items()):
        columns[name] = table[:, number - 1] * factor + offset
    return build_series(str(path), time, columns, lines, latitude, longitude, max_gap)
