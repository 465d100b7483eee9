"""Moist-air relations: saturation vapour pressure, dew point, relative and specific humidity.

Saturation over liquid water (also below 0 °C, as meteorological stations report relative
humidity) by the Magnus form with the coefficients of Alduchov & Eskridge (1996), "AERK":

.. math:: e_s(T) = 610.94\\,\\exp\\left(\\frac{17.625\\,t}{t + 243.04}\\right)\\ \\mathrm{Pa},
          \\quad t = T - 273.15\\ [°C]

Alduchov & Eskridge give its relative error against Wexler's (1976) formulation as below
0.4 % from −40 to +50 °C; the dew point is the exact inverse of the same form.

References
----------
Alduchov, O. A. and Eskridge, R. E. (1996). Improved Magnus form approximation of saturation
vapor pressure. *J. Appl. Meteorol.* 35(4), 601–609.
doi:10.1175/1520-0450(1996)035<0601:IMFAOS>2.0.CO;2
Wallace, J. M. and Hobbs, P. V. (2006). *Atmospheric Science: An Introductory Survey*, 2nd ed.
Academic Press, ch. 3 (specific humidity). ISBN 978-0-12-732951-2
"""

from __future__ import annotations

import numpy as np

from radscene.errors import ConfigError

__all__ = [
    "EPSILON",
    "saturation_vapour_pressure_derivative",
    "specific_humidity_of_vapour_pressure",
    "dew_point_to_relative_humidity",
    "relative_humidity_to_dew_point",
    "saturation_vapour_pressure",
    "specific_humidity",
    "vapour_pressure",
]

# Magnus coefficients of Alduchov & Eskridge (1996), over water.
_MAGNUS_E0 = 610.94  # [Pa]
_MAGNUS_A = 17.625  # [-]
_MAGNUS_B = 243.04  # [°C]
_ZERO_CELSIUS = 273.15  # [K]

#: Ratio of the gas constants of dry air and water vapour, R_d / R_v [-]
#: (R_d = 287.05, R_v = 461.5 J kg-1 K-1; Wallace & Hobbs 2006, ch. 3).
EPSILON = 0.622


def _temperature(value, key):
    t = np.asarray(value, float)
    if np.any(t <= 0):
        raise ConfigError("temperature must be > 0 K", key=key)
    return t


def _fraction(value, key):
    f = np.asarray(value, float)
    if np.any((f < 0) | (f > 1)):
        raise ConfigError("must lie in [0, 1] (a fraction, not a percentage)", key=key)
    return f


def saturation_vapour_pressure(temperature):
    """Saturation vapour pressure over liquid water, e_s [Pa] (Magnus, Alduchov & Eskridge 1996).

    Parameters
    ----------
    temperature : array_like
        Air temperature T [K].

    Returns
    -------
    ndarray
        e_s [Pa], of the shape of ``temperature``.

    Raises
    ------
    ConfigError
        A temperature ≤ 0 K.

    Notes
    -----
    .. math:: e_s = 610.94\\,\\exp\\left(\\frac{17.625\\,t}{t + 243.04}\\right),\\quad t = T - 273.15

    References
    ----------
    Alduchov & Eskridge (1996), doi:10.1175/1520-0450(1996)035<0601:IMFAOS>2.0.CO;2

    Examples
    --------
    >>> round(float(saturation_vapour_pressure(293.15)), 1)
    2333.4
    """
    t = _temperature(temperature, "temperature") - _ZERO_CELSIUS
    return _MAGNUS_E0 * np.exp(_MAGNUS_A * t / (t + _MAGNUS_B))


def saturation_vapour_pressure_derivative(temperature):
    """d e_s / dT = e_s · A B / (t + B)² [Pa K-1] of :func:`saturation_vapour_pressure`.

    Examples
    --------
    >>> round(float(saturation_vapour_pressure_derivative(293.15)), 2)
    144.46
    """
    t = _temperature(temperature, "temperature") - _ZERO_CELSIUS
    return saturation_vapour_pressure(temperature) * _MAGNUS_A * _MAGNUS_B / (t + _MAGNUS_B) ** 2


def specific_humidity_of_vapour_pressure(vapour_pressure, pressure):
    """Specific humidity q = ε e / (p − (1 − ε) e) [kg kg-1] of a vapour pressure e [Pa] at a
    pressure p [Pa] (Wallace & Hobbs 2006, ch. 3), unchecked (for inner loops).

    Examples
    --------
    >>> round(float(specific_humidity_of_vapour_pressure(2333.4, 101325.0)), 5)
    0.01445
    """
    e = np.asarray(vapour_pressure, float)
    return EPSILON * e / (np.asarray(pressure, float) - (1.0 - EPSILON) * e)


def vapour_pressure(temperature, relative_humidity):
    """Partial pressure of water vapour, e = RH · e_s(T) [Pa].

    Parameters
    ----------
    temperature : array_like
        Air temperature T [K].
    relative_humidity : array_like
        RH over liquid water [0-1].

    Returns
    -------
    ndarray
        e [Pa].

    Examples
    --------
    >>> round(float(vapour_pressure(293.15, 0.5)), 1)
    1166.7
    """
    return _fraction(relative_humidity, "relative_humidity") * saturation_vapour_pressure(temperature)


def dew_point_to_relative_humidity(temperature, dew_point):
    """Relative humidity from the air temperature and the dew point, RH = e_s(T_d)/e_s(T) [0-1].

    Parameters
    ----------
    temperature : array_like
        Air temperature T [K].
    dew_point : array_like
        Dew-point temperature T_d ≤ T [K].

    Returns
    -------
    ndarray
        RH [0-1].

    Raises
    ------
    ConfigError
        A temperature ≤ 0 K, or a dew point above the air temperature (supersaturation is not
        a weather station's reading; the message gives the largest excess).

    Examples
    --------
    >>> round(float(dew_point_to_relative_humidity(293.15, 283.15)), 4)
    0.5254
    """
    t = _temperature(temperature, "temperature")
    td = _temperature(dew_point, "dew_point")
    excess = np.max(td - t, initial=-np.inf)
    if excess > 1e-9:
        raise ConfigError(f"dew point above the air temperature (by up to {excess:.3g} K)", key="dew_point")
    return np.minimum(saturation_vapour_pressure(td) / saturation_vapour_pressure(t), 1.0)


def relative_humidity_to_dew_point(temperature, relative_humidity):
    """Dew point from the air temperature and relative humidity, the inverse of the Magnus form [K].

    Parameters
    ----------
    temperature : array_like
        Air temperature T [K].
    relative_humidity : array_like
        RH (0, 1] [-].

    Returns
    -------
    ndarray
        T_d [K].

    Raises
    ------
    ConfigError
        RH outside (0, 1]: dry air (RH = 0) has no dew point.

    Notes
    -----
    .. math:: t_d = \\frac{b\\,\\gamma}{a - \\gamma},\\quad
              \\gamma = \\ln \\mathrm{RH} + \\frac{a\\,t}{b + t}

    Examples
    --------
    >>> round(float(relative_humidity_to_dew_point(293.15, 0.5)) - 273.15, 2)
    9.26
    """
    rh = _fraction(relative_humidity, "relative_humidity")
    if np.any(rh <= 0):
        raise ConfigError("must be > 0 for a dew point", key="relative_humidity")
    t = _temperature(temperature, "temperature") - _ZERO_CELSIUS
    gamma = np.log(rh) + _MAGNUS_A * t / (_MAGNUS_B + t)
    return _MAGNUS_B * gamma / (_MAGNUS_A - gamma) + _ZERO_CELSIUS


def specific_humidity(temperature, relative_humidity, pressure):
    """Specific humidity, the mass of water vapour per mass of moist air, q [kg kg-1].

    Parameters
    ----------
    temperature : array_like
        Air temperature T [K].
    relative_humidity : array_like
        RH [0-1].
    pressure : array_like
        Air pressure p [Pa].

    Returns
    -------
    ndarray
        q [kg kg-1].

    Raises
    ------
    ConfigError
        A pressure ≤ 0 or not above the vapour pressure.

    Notes
    -----
    With e = RH · e_s(T) and ε = R_d/R_v = 0.622 (Wallace & Hobbs 2006, ch. 3):

    .. math:: q = \\frac{\\varepsilon\\,e}{p - (1 - \\varepsilon)\\,e}

    Examples
    --------
    >>> round(float(specific_humidity(293.15, 0.5, 101325.0)) * 1000, 3)
    7.193
    """
    e = vapour_pressure(temperature, relative_humidity)
    p = np.asarray(pressure, float)
    if np.any(p <= e):
        raise ConfigError("must be > 0 Pa and above the water vapour pressure", key="pressure")
    return specific_humidity_of_vapour_pressure(e, p)
