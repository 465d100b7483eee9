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
``mixed``    h_n(ΔT, tilt) + 3.0 u            free convection of Walton (1983) plus the
                                             wind term of Watmuff et al. (1977)
============ ============================== ==========================================

Duffie & Beckman note that the McAdams form, from a 0.5 m plate in a wind tunnel, probably
includes some radiative exchange, and that Watmuff et al. removed it; both are fits for wind
speeds of 0–7 m s⁻¹ measured near the surface, whose still-air intercept stands for the free
convection whatever the surface's temperature and orientation.

``mixed`` separates the two: the forced part is Watmuff's wind term alone and the free part
depends on the surface-to-air difference ΔT = T − T_air and on the surface's orientation, as in
the TARP algorithm (Walton 1983), the sum of the two as there. With cos Σ the vertical
component of the outward normal (1 facing up, −1 facing down):

* buoyancy away from the surface (a warm face up, or a cool face down):
  h_n = 9.482 |ΔT|^⅓ / (7.238 − |cos Σ|);
* buoyancy against it (a cool face up, or a warm face down):
  h_n = 1.810 |ΔT|^⅓ / (1.382 + |cos Σ|);

both 1.31 |ΔT|^⅓ on a vertical face, the turbulent free convection of air at a vertical plate,
and 1.52 |ΔT|^⅓ on a warm face up (the simplified air correlations tabulated by Holman 2010,
Table 7-2). The free part is taken at the surface temperature of the start of each step.

References
----------
McAdams, W. H. (1954). *Heat Transmission*, 3rd ed. New York: McGraw-Hill.
Watmuff, J. H., Charters, W. W. S. and Proctor, D. (1977). Solar and wind induced external
coefficients for solar collectors. *COMPLES* 2, 56.
Duffie, J. A. and Beckman, W. A. (2013). *Solar Engineering of Thermal Processes*, 4th ed.
Wiley. doi:10.1002/9781118671603
Walton, G. N. (1983). *Thermal Analysis Research Program Reference Manual*. NBSIR 83-2655,
National Bureau of Standards.
Holman, J. P. (2010). *Heat Transfer*, 10th ed. McGraw-Hill.
"""

from __future__ import annotations

import numpy as np

from radscene.errors import ConfigError, did_you_mean

__all__ = ["CONVECTION_MODELS", "FREE_CONVECTION_MODELS", "convection_coefficient", "convective_flux", "free_convection",
           "mcadams", "mixed", "no_convection", "watmuff"]


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


def free_convection(temperature_difference, cos_tilt):
    """Free-convection coefficient h_n [W m-2 K-1] of Walton (1983) (module docstring).

    Parameters
    ----------
    temperature_difference : array_like
        ΔT = T_surface − T_air [K].
    cos_tilt : array_like
        Vertical component of the surface's outward unit normal, in [−1, 1].

    Examples
    --------
    >>> round(float(free_convection(8.0, 1.0)), 2)  # warm face up: 1.52 ΔT^(1/3)
    3.04
    >>> round(float(free_convection(8.0, 0.0)), 2)  # vertical: 1.31 ΔT^(1/3)
    2.62
    >>> round(float(free_convection(-8.0, 1.0)), 2)  # cool face up: stable, reduced
    1.52
    """
    dt = np.asarray(temperature_difference, float)
    c = np.clip(np.asarray(cos_tilt, float), -1.0, 1.0)
    root = np.cbrt(np.abs(dt))
    away = dt * c > 0.0  # warm face up or cool face down: the buoyant air leaves the surface
    return np.where(away, 9.482 * root / (7.238 - np.abs(c)), 1.810 * root / (1.382 + np.abs(c)))


def mixed(wind_speed, temperature_difference=0.0, cos_tilt=1.0):
    """h = h_n(ΔT, tilt) + 3.0 u [W m-2 K-1]: Walton's (1983) free convection plus the wind term
    of Watmuff et al. (1977) (module docstring).

    Examples
    --------
    >>> round(float(mixed(2.0, 8.0, 1.0)), 2)
    9.04
    >>> float(mixed(0.0))  # no wind, no temperature difference: no exchange
    0.0
    """
    return 3.0 * _wind(wind_speed) + free_convection(temperature_difference, cos_tilt)


#: Registered wind-speed correlations, by lower-case name.
CONVECTION_MODELS = {"mcadams": mcadams, "watmuff": watmuff, "mixed": mixed, "none": no_convection}
#: The correlations that also depend on the surface-to-air difference and the orientation.
FREE_CONVECTION_MODELS = frozenset({"mixed"})


def convection_coefficient(wind_speed, model="mcadams", temperature_difference=0.0, cos_tilt=1.0):
    """Convective heat-transfer coefficient h [W m-2 K-1] from the wind speed [m s-1].

    Parameters
    ----------
    wind_speed : array_like
        u ≥ 0 [m s-1].
    model : str, optional
        A name in ``CONVECTION_MODELS`` (case-insensitive).
    temperature_difference, cos_tilt : array_like, optional
        T_surface − T_air [K] and the outward normal's vertical component, for the models in
        ``FREE_CONVECTION_MODELS``; the others ignore them.

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
    if fn is mixed:
        return fn(wind_speed, temperature_difference, cos_tilt)
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
