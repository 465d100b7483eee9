"""Tabulated 6-DOF tracks: times, positions and attitudes read from a CSV or NetCDF file.

A CSV track has one header line (lines before it starting with ``#`` are comments), then one
row per sample::

    time [s], x [m], y [m], z [m], yaw [deg], pitch [deg], roll [deg]
    0.0,      -100,  0,     0,     90,        0,           0
    2.5,      -60,   5,     0,     80,        2,           0

A NetCDF track holds the same names as 1-D variables along one dimension, each with a
``units`` attribute. Units are required for the dimensional columns and are converted to
s, m and deg (any unit of :mod:`radscene.radiometry.units` of the right kind: ``[ms]``,
``[km]``, ``[rad]`` ...).

===============================  ======  ========  ==========================================
column                           unit    required  meaning
===============================  ======  ========  ==========================================
``time``                         time    yes       strictly increasing, from the start [s]
``x``, ``y``, ``z``              length  yes       position, scene frame (east, north, up)
``yaw``, ``pitch``, ``roll``     angle   no        attitude, :func:`radscene.geometry.rotation_matrix`
``qw``, ``qx``, ``qy``, ``qz``   none    no        or a body-to-world quaternion, scalar first
===============================  ======  ========  ==========================================

Every error is one line naming ``key`` (the scene key of the file), the file and the row.
"""

from __future__ import annotations

import csv
import re
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from radscene.errors import ConfigError, did_you_mean, unreadable
from radscene.radiometry.units import UNITS

__all__ = ["Track", "read_track"]

KINDS = {"time": "time", "x": "length", "y": "length", "z": "length", "yaw": "angle",
         "pitch": "angle", "roll": "angle", "qw": None, "qx": None, "qy": None, "qz": None}
EULER = ("yaw", "pitch", "roll")
QUATERNION = ("qw", "qx", "qy", "qz")
_HEADER = re.compile(r"^\s*([A-Za-z_]+)\s*(?:\[\s*([^\]]*?)\s*\])?\s*$")


@dataclass(frozen=True)
class Track:
    """Samples of a track in canonical units.

    Attributes
    ----------
    times : numpy.ndarray
        ``(n,)`` [s], strictly increasing.
    positions : numpy.ndarray
        ``(n, 3)`` [m].
    attitudes : numpy.ndarray or None
        ``(n, 3)`` (yaw, pitch, roll) [deg].
    quaternions : numpy.ndarray or None
        ``(n, 4)`` unit quaternions (w, x, y, z).
    """

    times: np.ndarray
    positions: np.ndarray
    attitudes: np.ndarray | None = None
    quaternions: np.ndarray | None = None


def read_track(path: str | Path, key: str = "file") -> Track:
    """Read a track file (``.csv`` or ``.nc``), checked row by row.

    Raises
    ------
    ConfigError
        Naming ``key``: a missing or unknown column, a missing or wrong unit, a cell that is
        not a finite number, times that do not increase, a zero quaternion; the row (1 the
        first after the header) and its line.
    """
    path = Path(path)
    if path.suffix.lower() in (".nc", ".nc4", ".netcdf"):
        columns, rows, where = _read_netcdf(path, key)
    else:
        columns, rows, where = _read_csv(path, key)
    return _check(path, columns, rows, where, key)


def _scale(path, name, unit, key) -> float:
    """The factor that converts a column's unit to the canonical one."""
    if name not in KINDS:
        raise ConfigError(f"{path.name}: unknown column {name!r}; accepted: {', '.join(KINDS)}", key=key)
    kind = KINDS[name]
    if kind is None:
        if unit not in (None, "", "1", "-"):
            raise ConfigError(f"{path.name}: column {name!r} is a quaternion component, without "
                              "unit (or [1])", key=key)
        return 1.0
    if not unit:
        canonical = {"time": "s", "length": "m", "angle": "deg"}[kind]
        raise ConfigError(f"{path.name}: column {name!r} has no unit; write it as '{name} [{canonical}]'",
                          key=key)
    if unit not in UNITS[kind]:
        raise ConfigError(f"{path.name}: column {name!r}: its unit is not one of {kind}; accepted: "
                          f"{', '.join(UNITS[kind])}", key=key)
    return UNITS[kind][unit][0]  # lengths, times and angles convert by a factor alone


def _read_csv(path, key):
    try:
        lines = path.read_text(encoding="utf-8").splitlines()
    except (OSError, UnicodeDecodeError) as err:
        raise ConfigError(f"{path.name}: not a readable text file ({unreadable(err)})", key=key) from None
    numbered = [(n, line) for n, line in enumerate(lines, start=1)
                if line.strip() and not line.lstrip().startswith("#")]
    if not numbered:
        raise ConfigError(f"{path.name}: no header line (e.g. 'time [s], x [m], y [m], z [m]')", key=key)
    parsed = list(csv.reader([line for _, line in numbered]))
    columns = []
    for number, cell in enumerate(parsed[0], start=1):
        match = _HEADER.match(cell)
        if match is None:
            raise ConfigError(f"{path.name}: header column {number} is not 'name [unit]' "
                              f"(line {numbered[0][0]})", key=key)
        name = match.group(1).lower()
        if name not in KINDS:  # named by its place: the header may be any file's first line
            hint = did_you_mean(name, list(KINDS), cutoff=0.8)
            raise ConfigError(f"{path.name}: header column {number} is none of "
                              f"{', '.join(KINDS)}{hint} (line {numbered[0][0]})", key=key)
        columns.append((name, match.group(2)))
    rows = parsed[1:]
    where = [f"row {r} (line {n})" for r, (n, _) in enumerate(numbered[1:], start=1)]
    return columns, rows, where


def _read_netcdf(path, key):
    import xarray as xr

    try:
        ds = xr.open_dataset(path, decode_times=False, decode_timedelta=False)
    except (OSError, ValueError):
        raise ConfigError(f"{path.name}: not a readable NetCDF file", key=key) from None
    with ds:
        names = [n for n in ds.variables if str(n).lower() in KINDS]
        dims = {ds[n].dims for n in names}
        if len(dims) > 1 or any(len(d) != 1 for d in dims):
            raise ConfigError(f"{path.name}: the track's variables must be 1-D along one dimension; "
                              f"got {sorted(map(str, dims))}", key=key)
        extra = [str(n) for n in ds.data_vars if str(n).lower() not in KINDS]
        if extra:
            raise ConfigError(f"{path.name}: unknown variable {extra[0]!r}; accepted: {', '.join(KINDS)}",
                              key=key)
        columns = [(str(n).lower(), ds[n].attrs.get("units")) for n in names]
        data = np.column_stack([ds[n].values for n in names]) if names else np.empty((0, 0))
    rows = data.tolist()
    where = [f"row {r} (index {r - 1})" for r in range(1, len(rows) + 1)]
    return columns, rows, where


def _check(path, columns, rows, where, key) -> Track:
    names = [c for c, _ in columns]
    for name in set(names):
        if names.count(name) > 1:
            raise ConfigError(f"{path.name}: column {name!r} appears twice", key=key)
    missing = [c for c in ("time", "x", "y", "z") if c not in names]
    if missing:
        raise ConfigError(f"{path.name}: missing column {', '.join(map(repr, missing))}; a track has "
                          "time [s], x [m], y [m], z [m] and optionally yaw, pitch, roll [deg] or qw, qx, qy, qz",
                          key=key)
    euler = [c for c in EULER if c in names]
    quat = [c for c in QUATERNION if c in names]
    if euler and quat:
        raise ConfigError(f"{path.name}: give yaw, pitch, roll or qw, qx, qy, qz, not both", key=key)
    for group, full in ((euler, EULER), (quat, QUATERNION)):
        if group and len(group) != len(full):
            lacking = [c for c in full if c not in group]
            raise ConfigError(f"{path.name}: missing column {', '.join(map(repr, lacking))} (with "
                              f"{', '.join(group)})", key=key)
    scale = np.array([_scale(path, name, unit, key) for name, unit in columns])
    if len(rows) < 2:
        raise ConfigError(f"{path.name}: a track needs at least two rows; got {len(rows)}", key=key)
    data = np.empty((len(rows), len(columns)))
    for r, row in enumerate(rows):
        if len(row) != len(columns):
            raise ConfigError(f"{path.name}: {where[r]} has {len(row)} values for {len(columns)} columns",
                              key=key)
        for c, cell in enumerate(row):
            try:
                value = float(cell.strip() if isinstance(cell, str) else cell)
            except ValueError:
                raise ConfigError(f"{path.name}: {where[r]}, column {names[c]!r}: not a number",
                                  key=key) from None
            if not np.isfinite(value):
                raise ConfigError(f"{path.name}: {where[r]}, column {names[c]!r}: {value!r} is not "
                                  "finite", key=key)
            data[r, c] = value
    data *= scale
    column = {name: data[:, c] for c, name in enumerate(names)}
    t = column["time"]
    for r in range(1, len(t)):
        if not t[r] > t[r - 1]:
            raise ConfigError(f"{path.name}: {where[r]}: time {t[r]:g} s does not follow {t[r - 1]:g} s "
                              "of the row before; times must increase", key=key)
    positions = np.column_stack([column[c] for c in ("x", "y", "z")])
    attitudes = np.column_stack([column[c] for c in EULER]) if euler else None
    quaternions = None
    if quat:
        quaternions = np.column_stack([column[c] for c in QUATERNION])
        zero = np.linalg.norm(quaternions, axis=1) == 0
        if zero.any():
            raise ConfigError(f"{path.name}: {where[int(np.argmax(zero))]}: the quaternion is zero", key=key)
    return Track(t, positions, attitudes, quaternions)
