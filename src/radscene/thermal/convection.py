"""Convective exchange between a surface and the air: Q_k = h (T_air − T), with a registry of
wind-speed correlations for h.

Registered correlations (``CONVECTION_MODELS``, case-insensitive):

============ ============================== ==========================================
name         h [W m-2 K-1], u [m s-1]        source
============ ============================== ==========================================
``mcadams``  5.7 + 3.8 u                     McAdams (1954), as quoted by Duffie &
                                             Beckman (2013) §3.15; Jürges' plate data
``watmuff``  2.8 + 3.0 u                     Watmuff, Charters & Proctor (1977), as
                                             quoted by Duffie & Beckman (2013) §3.15
============ ============================== ==========================================

Duffie & Beckman note that the McAdams form, from a 0.5 m plate in a wind tunnel, probably
includes some radiative exchange, and that Watmuff et al. removed it; both are fits for wind
speeds of 0–7 m s⁻¹ measured near the surface. Free convection (no wind) is not separated.

References
----------
McAdams, W. H. (1954). *Heat Transmission*, 3rd ed. New York: McGraw-Hill.
Watmuff, J. H., Charters, W. W. S. and Proctor, D. (1977). Solar and wind induced external
coefficients for solar collectors. *COMPLES* 2, 56.
Duffie, J. A. and Beckman, W. A. (2013). *Solar Engineering of Thermal Processes*, 4th ed.
Wiley. doi:10.1002/9781118671603
"""

from __future__ import annotations

import numpy as np

from radscene.errors import ConfigError, did_you_mean

__all__ = ["CONVECTION_MODELS", "convection_coefficient", "convective_flux", "mcadams", "no_convection", "watmuff"]


def _wind(wind_speed):
    u = np.asarray(wind_speed, float)
    if np.any(u < 0):
        raise ConfigError("wind speed must be >= 0 m s-1", key="wind_speed")
    return u


def mcadams(wind_speed):
    """h = 5.7 + 3.8 u [W m-2 K-1] for a wind speed u [m s-1] (McAdams 1954).

    Examples
    --------
    >>> float(mcadams(2.0))
    13.3
    """
    return 5.7 + 3.8 * _wind(wind_speed)


def watmuff(wind_speed):
    """h = 2.8 + 3.0 u [W m-2 K-1] for a wind speed u [m s-1] (Watmuff et al. 1977).

    Examples
    --------
    >>> float(watmuff(2.0))
    8.8
    """
    return 2.8 + 3.0 * _wind(wind_speed)


def no_convection(wind_speed):
    """h = 0: no air (a surface in vacuum, or a test of the radiative balance alone).

    Examples
    --------
    >>> float(no_convection(2.0))
    0.0
    """
    return np.zeros_like(_wind(wind_speed))


#: Registered wind-speed correlations, by lower-case name.
CONVECTION_MODELS = {"mcadams": mcadams, "watmuff": watmuff, "none": no_convection}


def convection_coefficient(wind_speed, model="mcadams"):
    """Convective heat-transfer coefficient h [W m-2 K-1] from the wind speed [m s-1].

    Parameters
    ----------
    wind_speed : array_like
        u ≥ 0 [m s-1].
    model : str, optional
        A name in ``CONVECTION_MODELS`` (case-insensitive).

    Returns
    -------
    ndarray
        h [W m-2 K-1].

    Raises
    ------
    ConfigError
        Unknown model (the message lists the registered ones) or a negative wind speed.
    """
    fn = CONVECTION_MODELS.get(str(model).strip().lower())
    if fn is None:
        raise ConfigError(f"unknown convection model {model!r}; known: {', '.join(sorted(CONVECTION_MODELS))}"
                          f"{did_you_mean(model, sorted(CONVECTION_MODELS))}", key="convection")
    return fn(wind_speed)


def convective_flux(coefficient, air_temperature, temperature):
    """Convective flux into the surface, Q_k = h (T_air − T) [W m-2].

    Parameters
    ----------
    coefficient : array_like
        h [W m-2 K-1].
    air_temperature : array_like
        T_air [K].
    temperature : array_like
        Surface temperature T [K].

    Returns
    -------
    ndarray
        [W m-2], positive when the air warms the surface.

    Examples
    --------
    >>> float(convective_flux(10.0, 300.0, 310.0))
    -100.0
    """
    return np.asarray(coefficient, float) * (np.asarray(air_temperature, float) - np.asarray(temperature, float))
