"""User atmospheres for LOWTRAN (MODEL 7): profiles given as lists, into card 2C1 levels, and
LOWTRAN's own model atmospheres with their water-vapour and ozone columns scaled.

LOWTRAN7 takes no column amounts: its gases are its model's profiles. A model with another
water-vapour or ozone column is given to it as a user atmosphere at the model's 33 levels whose
pressure, temperature and other gases are the model's own (card 2C1 JCHAR flags 1-6, which make
LOWTRAN use its built-in values) and whose H2O or O3 mixing ratios are the model's times
column / model column (:func:`scaled_model_levels`). The models' mixing ratios, pressures and
temperatures are LOWTRAN's own (``radscene/data/atmosphere/lowtran7_profiles.csv``, from its
block data MLATMB: McClatchey et al. 1972, AFCRL-72-0497, with the constituent profiles of
Anderson et al. 1986, AFGL-TR-86-0110). Their columns (:func:`model_columns`), integrated
with the density exponential between levels: water 4.115, 2.922, 0.852, 2.081, 0.416,
1.416 g cm-2 and ozone 0.277, 0.332, 0.377, 0.345, 0.376, 0.343 cm-atm for the tropical,
midlatitude summer and winter, subarctic summer and winter and US standard models (6SV1.1
prints water 4.12, 2.93, 0.853, 2.10, 0.419, 1.42 g cm-2 for its versions of them).
"""

from __future__ import annotations

from functools import lru_cache
from importlib import resources

import numpy as np

from radscene.atmosphere.lowtran.cards import MAX_LEVELS, MODELS, TOP_ALTITUDE, ProfileLevel, lookup
from radscene.errors import ConfigError, did_you_mean

__all__ = ["profile_levels", "model_columns", "scaled_model_levels", "COLUMN_LIMITS"]

_MODEL_FILE = "lowtran7_profiles.csv"
_BOLTZMANN = 1.380649e-23  # [J K-1]
_AVOGADRO = 6.02214076e23  # [mol-1]
_LOSCHMIDT = 2.6867811e25  # [m-3] at 273.15 K and 1013.25 hPa
_H2O_MOLAR_MASS = 18.015  # [g mol-1]

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


@lru_cache(maxsize=1)
def _models() -> dict[str, np.ndarray]:
    """LOWTRAN's model atmospheres: ``{name: (33, 5)}`` of altitude [km], pressure [mb],
    temperature [K], H2O and O3 [ppmv]."""
    text = (resources.files("radscene") / "data" / "atmosphere" / _MODEL_FILE).read_text(
        encoding="utf-8")
    rows: dict[str, list] = {}
    for line in text.splitlines():
        if line and not line.startswith(("#", "model,")):
            name, *values = line.split(",")
            rows.setdefault(name, []).append([float(v) for v in values])
    return {name: np.array(values) for name, values in rows.items()}


def _column(z_km, density):
    """∫ density dz over the levels [density × m], the density exponential between levels
    (linear where a level holds none)."""
    dz = np.diff(z_km) * 1e3
    lo, hi = density[:-1], density[1:]
    both = (lo > 0) & (hi > 0) & (np.abs(lo - hi) > 1e-12 * np.maximum(lo, hi))
    ratio = np.log(np.where(both, lo, 1.0) / np.where(both, hi, 1.0))
    safe = np.where(both, ratio, 1.0)
    return float(np.sum(np.where(both, (lo - hi) / safe, 0.5 * (lo + hi)) * dz))


def model_columns(model) -> tuple[float, float]:
    """The water-vapour [g cm-2] and ozone [cm-atm] columns of a LOWTRAN model atmosphere,
    sea level to 100 km.

    Examples
    --------
    >>> [round(v, 3) for v in model_columns("us_standard")]
    [1.416, 0.343]
    """
    code = lookup(MODELS, model, "atmosphere.model", "model atmosphere")
    if code not in range(1, 7):
        raise ConfigError("the columns of a user profile are its own", key="atmosphere.model")
    name = next(k for k, v in MODELS.items() if v == code and k in _models())
    z, p, t, h2o, o3 = _models()[name].T
    air = p * 100.0 / (_BOLTZMANN * t)  # [m-3]
    water = _column(z, h2o * 1e-6 * air * _H2O_MOLAR_MASS / _AVOGADRO) / 1e4  # g m-2 -> g cm-2
    ozone = _column(z, o3 * 1e-6 * air) / _LOSCHMIDT * 100.0  # atm-m -> atm-cm
    return water, ozone


#: The largest columns the engine scales a model to: (limit, unit). Beyond any measured
#: column (about 7 g cm-2 and 0.6 cm-atm), with room for three times the models' own.
COLUMN_LIMITS = {"water": (15.0, "g cm-2"), "ozone": (1.5, "cm-atm")}


def scaled_model_levels(model, water=None, ozone=None,
                        key: str = "atmosphere") -> tuple[ProfileLevel, ...]:
    """A LOWTRAN model atmosphere as a user atmosphere with its water-vapour and/or ozone column
    scaled to ``water`` [g cm-2] and ``ozone`` [cm-atm] (None: the model's own).

    Pressure, temperature and every gas not scaled are flagged as the model's (JCHAR 1-6), so
    LOWTRAN takes its own values; a scaled gas is given in ppmv, the model's times the ratio of
    the columns (:func:`model_columns`).
    """
    code = lookup(MODELS, model, f"{key}.model", "model atmosphere")
    if code not in range(1, 7):
        raise ConfigError("a user profile gives its own water vapour and ozone; water and "
                          "ozone scale a model atmosphere", key=f"{key}.model")
    name = next(k for k, v in MODELS.items() if v == code and k in _models())
    z, p, t, h2o, o3 = _models()[name].T
    own_water, own_ozone = model_columns(name)
    flag = str(code)
    factors = []
    for gas, value, own in (("water", water, own_water), ("ozone", ozone, own_ozone)):
        limit, unit = COLUMN_LIMITS[gas]
        if value is None:
            factors.append(None)
            continue
        try:
            v = float(value)
        except (TypeError, ValueError):
            raise ConfigError(f"a number in {unit}; got {value!r}", key=f"{key}.{gas}") from None
        if not (np.isfinite(v) and 0.0 < v <= limit):
            raise ConfigError(f"must lie in (0, {limit:g}] {unit}; got {value!r}",
                              key=f"{key}.{gas}")
        factors.append(v / own)
    f_w, f_o = factors
    jchar = flag * 2 + ("A" if f_w is not None else flag) + flag + (
        "A" if f_o is not None else flag) + flag * 9
    return tuple(
        ProfileLevel(z=float(z[i]), p=float(p[i]), t=float(t[i]),
                     wmol=(0.0 if f_w is None else float(h2o[i] * f_w), 0.0,
                           0.0 if f_o is None else float(o3[i] * f_o)) + (0.0,) * 9,
                     jchar=jchar)
        for i in range(z.size)
    )
