"""Reading sensor configuration values at the edge: units, ranges, spectra, unknown keys.

Quantities of the kinds known to :func:`radscene.radiometry.parse_quantity` (temperature,
wavelength, length, angle, time, dimensionless) go through it; the sensor adds electrical
kinds with their own small unit tables (plain numbers are SI).
"""

from __future__ import annotations

import math
import numbers
import re
from collections.abc import Mapping

from radscene.errors import ConfigError
from radscene.materials.spectrum import Spectrum, make_spectrum
from radscene.radiometry.units import UNITS, parse_quantity

REQUIRED = object()

#: Extra unit kinds of the sensor: kind -> {unit: factor to SI}.
SENSOR_UNITS: dict[str, dict[str, float]] = {
    "frequency": {"Hz": 1.0, "kHz": 1e3, "MHz": 1e6, "GHz": 1e9},
    "current": {"A": 1.0, "mA": 1e-3, "uA": 1e-6, "µA": 1e-6, "nA": 1e-9, "pA": 1e-12,
                "fA": 1e-15, "aA": 1e-18},
    "voltage": {"V": 1.0, "mV": 1e-3, "uV": 1e-6, "µV": 1e-6, "nV": 1e-9,
                "V/DN": 1.0, "mV/DN": 1e-3, "uV/DN": 1e-6, "µV/DN": 1e-6},
    "resistance": {"ohm": 1.0, "Ohm": 1.0, "Ω": 1.0, "kohm": 1e3, "kOhm": 1e3, "kΩ": 1e3,
                   "Mohm": 1e6, "MOhm": 1e6, "MΩ": 1e6},
    "thermal_conductance": {"W/K": 1.0, "W K-1": 1.0, "uW/K": 1e-6, "nW/K": 1e-9},
    "energy": {"eV": 1.0, "meV": 1e-3},
    "electrons": {"e-": 1.0, "e": 1.0, "electrons": 1.0, "ke-": 1e3, "Me-": 1e6,
                  "e-/DN": 1.0, "e/DN": 1.0},
    "temperature_coefficient": {"K-1": 1.0, "1/K": 1.0, "%/K": 0.01},
    "responsivity": {"A/W": 1.0, "A W-1": 1.0, "V/W": 1.0, "V W-1": 1.0},
}

_QUANTITY = re.compile(r"^\s*([+-]?(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?)\s*(.*?)\s*$")


def _sensor_quantity(value, kind, key):
    table = SENSOR_UNITS[kind]
    if isinstance(value, numbers.Real) and not isinstance(value, bool):
        number = float(value)
    elif isinstance(value, str):
        match = _QUANTITY.match(value)
        if match is None:
            raise ConfigError(f"expected '<number> <unit>' for a {kind}; got {value!r}", key=key)
        unit = " ".join(match.group(2).split())
        if unit and unit not in table:
            raise ConfigError(f"unknown {kind} unit {unit!r} in {value!r}; accepted: "
                              f"{', '.join(table)}", key=key)
        number = float(match.group(1)) * (table[unit] if unit else 1.0)
    else:
        raise ConfigError(f"expected a number or a string with a unit for a {kind}; got "
                          f"{value!r}", key=key)
    if not math.isfinite(number):
        raise ConfigError(f"must be finite; got {value!r}", key=key)
    return number


def join(key: str, name: str) -> str:
    """Dotted key path ``key.name`` (``name`` alone when ``key`` is empty)."""
    return f"{key}.{name}" if key else name


def check_keys(cfg: Mapping, accepted, key: str) -> None:
    """Raise if `cfg` holds a key outside `accepted`, listing the accepted ones."""
    if not isinstance(cfg, Mapping):
        raise ConfigError(f"must be a mapping; got a {type(cfg).__name__}", key=key)
    unknown = sorted(set(cfg) - set(accepted))
    if unknown:
        raise ConfigError(f"unknown key(s) {', '.join(map(str, unknown))}; accepted: "
                          f"{', '.join(sorted(accepted))}", key=join(key, str(unknown[0])))


def quantity(cfg: Mapping, name: str, kind: str, key: str, default=REQUIRED, *,
             low=None, high=None, low_open=False, high_open=False):
    """Read ``cfg[name]`` as a quantity of `kind` in its canonical unit, with a range check.

    Canonical units: those of :data:`radscene.radiometry.units.CANONICAL_UNITS` for its
    kinds, SI for the sensor kinds (Hz, A, V, ohm, W/K, eV, e-, K-1, A/W or V/W).
    ``default=None`` makes the value optional (returns None when absent).
    """
    path = join(key, name)
    if name not in cfg or cfg[name] is None:
        if default is REQUIRED:
            raise ConfigError(f"missing required {kind}", key=path)
        return default
    value = cfg[name]
    if kind in SENSOR_UNITS:
        number = _sensor_quantity(value, kind, path)
    elif kind in UNITS:
        number = parse_quantity(value, kind, key=path)
    else:  # pragma: no cover - programming error
        raise KeyError(kind)
    check_range(number, path, low=low, high=high, low_open=low_open, high_open=high_open)
    return number


def check_range(number, path, *, low=None, high=None, low_open=False, high_open=False):
    """Raise a ConfigError naming `path` when `number` is outside the stated interval."""
    bad = ((low is not None and (number < low or (low_open and number == low)))
           or (high is not None and (number > high or (high_open and number == high))))
    if bad:
        lo = "" if low is None else ("> " if low_open else ">= ") + f"{low:g}"
        hi = "" if high is None else ("< " if high_open else "<= ") + f"{high:g}"
        raise ConfigError(f"must be {' and '.join(s for s in (lo, hi) if s)}; got {number:g}",
                          key=path)
    return number


def integer(cfg: Mapping, name: str, key: str, default=REQUIRED, *, low=None, high=None):
    """Read ``cfg[name]`` as an integer within [low, high]."""
    path = join(key, name)
    if name not in cfg or cfg[name] is None:
        if default is REQUIRED:
            raise ConfigError("missing required integer", key=path)
        return default
    value = cfg[name]
    if isinstance(value, bool) or not isinstance(value, numbers.Integral):
        raise ConfigError(f"must be an integer; got {value!r}", key=path)
    check_range(int(value), path, low=low, high=high)
    return int(value)


def spectrum(cfg: Mapping, name: str, key: str, default=REQUIRED, *, low=0.0, high=None,
             base_dir=None) -> Spectrum | None:
    """Read ``cfg[name]`` as a :class:`~radscene.materials.Spectrum` with values in range."""
    path = join(key, name)
    if name not in cfg or cfg[name] is None:
        if default is REQUIRED:
            raise ConfigError("missing required spectrum (a number or a table)", key=path)
        if default is None:
            return None
        return Spectrum.constant(float(default), name=path)
    value = cfg[name]
    if isinstance(value, str):
        value = quantity(cfg, name, "dimensionless", key)
    spec = make_spectrum(value, key=path, base_dir=base_dir)
    values = spec.values
    if (low is not None and float(values.min()) < low) or (high is not None and float(values.max()) > high):
        rng = f"[{low:g}, {high:g}]" if high is not None else f">= {low:g}"
        raise ConfigError(f"values must lie in {rng}; got {float(values.min()):g} to "
                          f"{float(values.max()):g}", key=path)
    return spec


def pair(cfg: Mapping, name: str, kind: str, key: str, default=(0.0, 0.0)):
    """Read a scalar or an (x, y) pair of quantities; a scalar applies to both axes."""
    path = join(key, name)
    if name not in cfg or cfg[name] is None:
        return tuple(float(d) for d in default)
    value = cfg[name]
    if isinstance(value, list | tuple):
        if len(value) != 2:
            raise ConfigError(f"must be a number or a pair [x, y]; got {value!r}", key=path)
        return tuple(quantity({name: v}, name, kind, key) for v in value)
    v = quantity(cfg, name, kind, key)
    return (v, v)
