"""Aerodynamic heating of airborne elements: convection to the recovery temperature with a
turbulent flat-plate coefficient from the airspeed.

An element moving through the air at a speed u (Mach number M = u/a, a = √(γ R T_air)) sees
the adiabatic-wall (recovery) temperature

.. math:: T_r = T_{air}\\Big(1 + r\\,\\frac{\\gamma - 1}{2}\\,M^2\\Big), \\qquad r = Pr^{1/3}

(r for a turbulent boundary layer; White 2006, §7.7), and exchanges h (T_r − T) with it, h
from the average Nusselt number of a flat plate with a turbulent boundary layer from its
leading edge (Incropera et al. 2007, §7.2, the fully turbulent limit of mixed conditions):

.. math:: \\overline{Nu}_L = 0.037\\,Re_L^{4/5}\\,Pr^{1/3}, \\qquad
          h = \\overline{Nu}_L\\,k/L, \\quad Re_L = \\rho u L/\\mu

L is the element's characteristic length along the flow (the caller's; 1 m by default). Air
properties are taken at T_air: ρ = p/(R T_air), μ by Sutherland's law with White's (2006,
Table 1-2) constants for air (μ₀ = 1.716×10⁻⁵ Pa s at T₀ = 273 K, S = 111 K), k = μ c_p/Pr,
Pr = 0.707 and c_p = 1007 J kg-1 K-1 (Incropera et al. 2007, Table A.4, 300 K), γ = 1.4,
R = R*/M_d = 287.05 J kg-1 K-1. The correlation is for 5×10⁵ ≲ Re_L ≲ 10⁸ (about 8 m s-1 to
1500 m s-1 over 1 m at sea level); low-speed heating by the recovery term is negligible anyway
(T_r − T_air = 0.9 K at 45 m s-1). A reference-temperature correction of the properties for
hot walls (Eckert 1955) is not applied.

In the heat balance the two are split: Q_k = h (T_air − T) is the convection the element would
get at T_air, and the aerodynamic heating h (T_r − T_air) goes into Q_i.

References
----------
White, F. M. (2006). *Viscous Fluid Flow*, 3rd ed. McGraw-Hill, Table 1-2 (Sutherland's law),
§7.7 (compressible turbulent boundary layers: recovery factor).
Incropera, F. P., DeWitt, D. P., Bergman, T. L. and Lavine, A. S. (2007). *Fundamentals of
Heat and Mass Transfer*, 6th ed. Wiley, §7.2 (flat plate in parallel flow), Table A.4.
"""

from __future__ import annotations

import numpy as np
from scipy import constants

__all__ = [
    "HEAT_CAPACITY_RATIO",
    "GAS_CONSTANT_AIR",
    "PRANDTL_AIR",
    "speed_of_sound",
    "recovery_temperature",
    "air_viscosity",
    "flat_plate_coefficient",
]

#: γ = c_p / c_v of air [-].
HEAT_CAPACITY_RATIO = 1.4
#: R = R* / M_d of dry air [J kg-1 K-1].
GAS_CONSTANT_AIR = constants.R / 0.0289645
#: Pr of air at 300 K [-] (Incropera et al. 2007, Table A.4).
PRANDTL_AIR = 0.707
_CP = 1007.0  # J kg-1 K-1, Table A.4 at 300 K


def speed_of_sound(air_temperature):
    """a = √(γ R T) [m s-1] of air at T [K].

    Examples
    --------
    >>> round(float(speed_of_sound(288.15)), 1)
    340.3
    """
    return np.sqrt(HEAT_CAPACITY_RATIO * GAS_CONSTANT_AIR * np.asarray(air_temperature, float))


def recovery_temperature(air_temperature, air_speed, recovery_factor=PRANDTL_AIR ** (1.0 / 3.0)):
    """Adiabatic-wall temperature of a surface moving through air, T_r [K].

    Parameters
    ----------
    air_temperature : array_like
        Static temperature of the air [K].
    air_speed : array_like
        Speed relative to the air [m s-1].
    recovery_factor : array_like, optional
        r [-]; default Pr^{1/3} (turbulent boundary layer).

    Returns
    -------
    ndarray
        T_r = T_air (1 + r (γ − 1)/2 M²) [K].

    Examples
    --------
    >>> t = 223.15
    >>> round(float(recovery_temperature(t, 0.8 * speed_of_sound(t))), 1)
    248.6
    """
    t = np.asarray(air_temperature, float)
    mach = np.asarray(air_speed, float) / speed_of_sound(t)
    return t * (1.0 + np.asarray(recovery_factor, float) * 0.5 * (HEAT_CAPACITY_RATIO - 1.0) * mach**2)


def air_viscosity(air_temperature):
    """Dynamic viscosity of air by Sutherland's law, μ [Pa s].

    Examples
    --------
    >>> round(float(air_viscosity(300.0)) * 1e5, 3)
    1.847
    """
    t = np.asarray(air_temperature, float)
    return 1.716e-5 * (t / 273.0) ** 1.5 * (273.0 + 111.0) / (t + 111.0)


def flat_plate_coefficient(air_speed, characteristic_length, air_temperature, pressure):
    """Average convection coefficient of a turbulent flat plate, h [W m-2 K-1].

    Parameters
    ----------
    air_speed : array_like
        u ≥ 0 [m s-1].
    characteristic_length : array_like
        L > 0 along the flow [m].
    air_temperature : array_like
        [K].
    pressure : array_like
        [Pa].

    Returns
    -------
    ndarray
        h = 0.037 Re_L^{4/5} Pr^{1/3} k / L [W m-2 K-1].

    Examples
    --------
    >>> round(float(flat_plate_coefficient(100.0, 1.0, 288.15, 101325.0)), 1)
    247.0
    """
    t = np.asarray(air_temperature, float)
    length = np.asarray(characteristic_length, float)
    mu = air_viscosity(t)
    density = np.asarray(pressure, float) / (GAS_CONSTANT_AIR * t)
    reynolds = density * np.asarray(air_speed, float) * length / mu
    conductivity = mu * _CP / PRANDTL_AIR
    return 0.037 * reynolds**0.8 * PRANDTL_AIR ** (1.0 / 3.0) * conductivity / length
