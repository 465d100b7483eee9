"""User atmospheres for LOWTRAN (MODEL 7): profiles given as lists, into card 2C1 levels."""

from __future__ import annotations

import numpy as np

from radscene.atmosphere.lowtran.cards import MAX_LEVELS, MODELS, TOP_ALTITUDE, ProfileLevel, lookup
from radscene.errors import ConfigError, did_you_mean

__all__ = ["profile_levels"]

#: Unit names of the H2O amounts → LOWTRAN JCHAR flags.
H2O_UNITS = {"ppmv": "A", "cm-3": "B", "g/kg": "C", "g/m3": "D", "hpa": "E", "mb": "E",
             "dewpoint_k": "F", "dewpoint_c": "G", "relative_humidity": "H"}
#: Unit names of the O3 amounts → JCHAR flags.
O3_UNITS = {k: v for k, v in H2O_UNITS.items() if v in "ABCDE"}


def profile_levels(profile: dict, key: str = "atmosphere.profile") -> tuple[ProfileLevel, ...]:
    """LOWTRAN levels (card 2C1) of a user atmosphere given as a dict of lists.

    Parameters
    ----------
    profile : dict
        ``altitude`` [m], ``pressure`` [hPa], ``temperature`` [K], optionally ``h2o`` with
        ``h2o_unit`` (relative_humidity [%] default, ppmv, g/m3, g/kg, hpa, dewpoint_k,
        dewpoint_c), ``o3`` with ``o3_unit`` (ppmv default, g/m3, g/kg, hpa, cm-3), and
        ``base_model`` (a model name, default us_standard) whose profiles fill every other
        gas and any of H2O, O3 not given.
    key : str
        Key path for messages.

    Returns
    -------
    tuple of ProfileLevel
    """
    if not isinstance(profile, dict):
        raise ConfigError("a mapping with altitude, pressure and temperature lists", key=key)
    base = lookup(MODELS, profile.get("base_model", "us_standard"), f"{key}.base_model",
                  "model atmosphere")
    try:
        z = np.asarray(profile["altitude"], float) / 1e3
        p = np.asarray(profile["pressure"], float)
        t = np.asarray(profile["temperature"], float)
    except KeyError as err:
        raise ConfigError(f"missing {err.args[0]!r} (altitude m, pressure hPa, temperature K)",
                          key=key) from None
    except (TypeError, ValueError):
        raise ConfigError("altitude, pressure, temperature must be lists of numbers",
                          key=key) from None
    n = z.size
    if z.ndim != 1 or not 2 <= n <= MAX_LEVELS or p.shape != z.shape or t.shape != z.shape:
        raise ConfigError(f"altitude, pressure, temperature: equal lists of 2 to {MAX_LEVELS} levels",
                          key=key)
    if np.any(np.diff(z) <= 0) or z[0] < 0 or z[-1] > TOP_ALTITUDE:
        raise ConfigError("altitudes must increase from >= 0 to <= 100000 m", key=f"{key}.altitude")
    if np.any(~np.isfinite(p)) or np.any(p <= 0) or np.any(np.diff(p) >= 0):
        raise ConfigError("pressures must be > 0 hPa and decrease upwards", key=f"{key}.pressure")
    if np.any(~np.isfinite(t)) or np.any(t <= 0):
        raise ConfigError("temperatures must be > 0 K", key=f"{key}.temperature")

    def gas(name, units, default_unit):
        if name not in profile:
            return np.zeros(n), str(base)
        values = np.asarray(profile[name], float)
        if values.shape != z.shape or np.any(~np.isfinite(values)) or np.any(values < 0):
            raise ConfigError(f"{n} non-negative values", key=f"{key}.{name}")
        unit = str(profile.get(f"{name}_unit", default_unit)).lower()
        if unit not in units:
            raise ConfigError(f"unknown unit {unit!r}; known: {', '.join(units)}"
                              f"{did_you_mean(unit, units)}",
                              key=f"{key}.{name}_unit")
        return values, units[unit]

    h2o, h2o_flag = gas("h2o", H2O_UNITS, "relative_humidity")
    o3, o3_flag = gas("o3", O3_UNITS, "ppmv")
    jchar = "AA" + h2o_flag + str(base) + o3_flag + str(base) * 9
    return tuple(
        ProfileLevel(z=float(z[i]), p=float(p[i]), t=float(t[i]),
                     wmol=(float(h2o[i]), 0.0, float(o3[i])) + (0.0,) * 9, jchar=jchar)
        for i in range(n)
    )
