"""Parsing of quantities with units at the edges of radscene (config files, CLI).

``parse_quantity("25 degC", "temperature")`` returns 298.15: the value in the canonical
unit of its kind. Inside radscene only canonical units are used:

==============  =============  ==========================================================
kind            canonical      also accepted (see ``UNITS``)
==============  =============  ==========================================================
temperature     K              degC, °C, degF, °F, kelvin, celsius, fahrenheit
wavelength      um             µm, μm, micron, nm, Å, mm, cm, m
length          m              km, cm, mm, um, nm, ft, mi, nmi
angle           deg            degree(s), °, rad, mrad, urad, arcmin, arcsec
time            s              ms, min, h, hr, hour(s), d, day(s)
irradiance      W m-2          W/m2, kW m-2, W cm-2, mW cm-2, uW cm-2
radiance        W m-2 sr-1     W/m2/sr, W cm-2 sr-1, mW cm-2 sr-1, uW cm-2 sr-1
speed           m/s            m s-1, km/h, kn, knots, mph
angular_speed   deg/s          deg s-1, rad/s, rad s-1, rpm, rev/s, Hz (revolutions)
pressure        Pa             hPa, mbar, kPa, bar, atm
power           W              kW, MW
dimensionless   1              %, percent, ppm
==============  =============  ==========================================================

Each unit maps to (factor, offset): ``canonical = value * factor + offset``. A plain
number is taken to be in the canonical unit.
"""

from __future__ import annotations

import math
import numbers
import re

from radscene.errors import ConfigError, did_you_mean

__all__ = ["UNITS", "CANONICAL_UNITS", "parse_quantity"]

_MICRO = ("µ", "μ")  # micro sign U+00B5 and Greek mu U+03BC, both seen in files


def _with_micro(table: dict[str, tuple[float, float]]) -> dict[str, tuple[float, float]]:
    """Add 'µ' and 'μ' spellings of every unit written with a leading 'u' (micro)."""
    extra = {
        mu + unit[1:]: conv
        for unit, conv in table.items()
        if unit.startswith("u") and unit[1:2] in ("m", "W", "r", "s")
        for mu in _MICRO
    }
    return {**table, **extra}


_F = 5.0 / 9.0

#: Unit tables: kind -> {unit: (factor, offset)} with canonical = value * factor + offset.
UNITS: dict[str, dict[str, tuple[float, float]]] = {
    "temperature": {
        "K": (1.0, 0.0),
        "kelvin": (1.0, 0.0),
        "degC": (1.0, 273.15),
        "°C": (1.0, 273.15),
        "℃": (1.0, 273.15),
        "celsius": (1.0, 273.15),
        "degF": (_F, 273.15 - 32.0 * _F),
        "°F": (_F, 273.15 - 32.0 * _F),
        "℉": (_F, 273.15 - 32.0 * _F),
        "fahrenheit": (_F, 273.15 - 32.0 * _F),
    },
    "wavelength": _with_micro(
        {
            "um": (1.0, 0.0),
            "micron": (1.0, 0.0),
            "microns": (1.0, 0.0),
            "micrometer": (1.0, 0.0),
            "micrometre": (1.0, 0.0),
            "nm": (1.0e-3, 0.0),
            "Å": (1.0e-4, 0.0),
            "A": (1.0e-4, 0.0),
            "mm": (1.0e3, 0.0),
            "cm": (1.0e4, 0.0),
            "m": (1.0e6, 0.0),
        }
    ),
    "length": _with_micro(
        {
            "m": (1.0, 0.0),
            "meter": (1.0, 0.0),
            "meters": (1.0, 0.0),
            "metre": (1.0, 0.0),
            "metres": (1.0, 0.0),
            "km": (1.0e3, 0.0),
            "cm": (1.0e-2, 0.0),
            "mm": (1.0e-3, 0.0),
            "um": (1.0e-6, 0.0),
            "nm": (1.0e-9, 0.0),
            "ft": (0.3048, 0.0),
            "mi": (1609.344, 0.0),
            "nmi": (1852.0, 0.0),
        }
    ),
    "angle": _with_micro(
        {
            "deg": (1.0, 0.0),
            "degree": (1.0, 0.0),
            "degrees": (1.0, 0.0),
            "°": (1.0, 0.0),
            "rad": (180.0 / math.pi, 0.0),
            "mrad": (0.18 / math.pi, 0.0),
            "urad": (1.8e-4 / math.pi, 0.0),
            "arcmin": (1.0 / 60.0, 0.0),
            "arcsec": (1.0 / 3600.0, 0.0),
        }
    ),
    "time": {
        "s": (1.0, 0.0),
        "sec": (1.0, 0.0),
        "second": (1.0, 0.0),
        "seconds": (1.0, 0.0),
        "ms": (1.0e-3, 0.0),
        "min": (60.0, 0.0),
        "minute": (60.0, 0.0),
        "minutes": (60.0, 0.0),
        "h": (3600.0, 0.0),
        "hr": (3600.0, 0.0),
        "hour": (3600.0, 0.0),
        "hours": (3600.0, 0.0),
        "d": (86400.0, 0.0),
        "day": (86400.0, 0.0),
        "days": (86400.0, 0.0),
    },
    "irradiance": _with_micro(
        {
            "W m-2": (1.0, 0.0),
            "W/m2": (1.0, 0.0),
            "W/m^2": (1.0, 0.0),
            "W m^-2": (1.0, 0.0),
            "kW m-2": (1.0e3, 0.0),
            "kW/m2": (1.0e3, 0.0),
            "W cm-2": (1.0e4, 0.0),
            "W/cm2": (1.0e4, 0.0),
            "mW cm-2": (10.0, 0.0),
            "mW/cm2": (10.0, 0.0),
            "uW cm-2": (1.0e-2, 0.0),
            "uW/cm2": (1.0e-2, 0.0),
        }
    ),
    "radiance": _with_micro(
        {
            "W m-2 sr-1": (1.0, 0.0),
            "W/m2/sr": (1.0, 0.0),
            "W/(m2 sr)": (1.0, 0.0),
            "W m^-2 sr^-1": (1.0, 0.0),
            "W cm-2 sr-1": (1.0e4, 0.0),
            "W/cm2/sr": (1.0e4, 0.0),
            "mW cm-2 sr-1": (10.0, 0.0),
            "mW/cm2/sr": (10.0, 0.0),
            "uW cm-2 sr-1": (1.0e-2, 0.0),
            "uW/cm2/sr": (1.0e-2, 0.0),
        }
    ),
    "speed": {
        "m/s": (1.0, 0.0),
        "m s-1": (1.0, 0.0),
        "km/h": (1.0 / 3.6, 0.0),
        "km h-1": (1.0 / 3.6, 0.0),
        "kn": (1852.0 / 3600.0, 0.0),
        "knot": (1852.0 / 3600.0, 0.0),
        "knots": (1852.0 / 3600.0, 0.0),
        "mph": (0.44704, 0.0),
    },
    "angular_speed": {
        "deg/s": (1.0, 0.0),
        "deg s-1": (1.0, 0.0),
        "rad/s": (180.0 / math.pi, 0.0),
        "rad s-1": (180.0 / math.pi, 0.0),
        "rpm": (6.0, 0.0),  # 360 deg / 60 s
        "rev/s": (360.0, 0.0),
        "Hz": (360.0, 0.0),
    },
    "pressure": {
        "Pa": (1.0, 0.0),
        "hPa": (100.0, 0.0),
        "mbar": (100.0, 0.0),
        "kPa": (1.0e3, 0.0),
        "bar": (1.0e5, 0.0),
        "atm": (101325.0, 0.0),
    },
    "power": {
        "W": (1.0, 0.0),
        "kW": (1.0e3, 0.0),
        "MW": (1.0e6, 0.0),
    },
    "dimensionless": {
        "1": (1.0, 0.0),
        "%": (0.01, 0.0),
        "percent": (0.01, 0.0),
        "ppm": (1.0e-6, 0.0),
    },
}

#: The canonical unit of each kind: the unit of plain numbers and of every result.
CANONICAL_UNITS: dict[str, str] = {
    "temperature": "K",
    "wavelength": "um",
    "length": "m",
    "angle": "deg",
    "time": "s",
    "irradiance": "W m-2",
    "radiance": "W m-2 sr-1",
    "speed": "m/s",
    "angular_speed": "deg/s",
    "pressure": "Pa",
    "power": "W",
    "dimensionless": "1",
}

_QUANTITY = re.compile(r"^\s*([+-]?(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?)\s*(.*?)\s*$")


def parse_quantity(value, kind: str, key: str | None = None) -> float:
    """Convert a number or a string with a unit to the canonical unit of its kind.

    Parameters
    ----------
    value : float or str
        A number (already in the canonical unit) or a string ``"<number> <unit>"``,
        e.g. ``"25 degC"``, ``"550 nm"``, ``"10 µm"``, ``"5 min"``.
    kind : str
        One of ``UNITS``: temperature, wavelength, length, angle, time, irradiance,
        radiance, dimensionless.
    key : str, optional
        Config key path of the value, used in error messages.

    Returns
    -------
    float
        The value in the canonical unit (K, um, m, deg, s, W m-2, W m-2 sr-1, 1).

    Raises
    ------
    ConfigError
        Unknown kind, unknown unit (the message lists the accepted ones), a string that
        is not a number and a unit, a non-finite value, or a temperature below 0 K.

    Examples
    --------
    >>> parse_quantity("25 degC", "temperature")
    298.15
    >>> parse_quantity("550 nm", "wavelength")
    0.55
    """
    if kind not in UNITS:
        raise ConfigError(f"unknown quantity kind {kind!r}; known: {', '.join(UNITS)}"
                          f"{did_you_mean(kind, UNITS)}", key="kind")
    key = key if key is not None else kind
    table = UNITS[kind]
    if isinstance(value, numbers.Real) and not isinstance(value, bool):
        number, factor, offset = float(value), 1.0, 0.0
    elif isinstance(value, str):
        match = _QUANTITY.match(value)
        if match is None:
            raise ConfigError(f"expected '<number> <unit>' for a {kind}; got {value!r}", key=key)
        number = float(match.group(1))
        unit = " ".join(match.group(2).split())
        if not unit:
            factor, offset = 1.0, 0.0
        elif unit in table:
            factor, offset = table[unit]
        else:
            raise ConfigError(
                f"unknown {kind} unit {unit!r} in {value!r}; accepted: {', '.join(table)}",
                key=key,
            )
    else:
        raise ConfigError(
            f"expected a number or a string with a unit for a {kind}; got {value!r}", key=key
        )
    if not math.isfinite(number):
        raise ConfigError(f"must be finite; got {value!r}", key=key)
    result = number * factor + offset
    if kind == "temperature" and result < 0:
        raise ConfigError(f"temperature below 0 K: {value!r} = {result:g} K", key=key)
    return result
