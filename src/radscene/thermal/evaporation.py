"""Evaporation and transpiration, Q_v: a bulk aerodynamic latent-heat flux with a moisture
availability, its transfer coefficient from the convection coefficient by the Chilton–Colburn
(Lewis) analogy.

.. math::
    Q_v = -\\beta\\,\\rho_a L_v C_E u\\,\\big(q_{sat}(T_s) - q_a\\big), \\qquad
    \\rho_a C_E u = \\frac{h}{c_p\\,Le^{2/3}}

Q_v is negative (cooling) when the surface evaporates and positive when vapour condenses on it
(dew). β ∈ [0, 1] is the moisture availability: 1 for open water, 0 for a dry surface, between
for vegetation whose stomata limit transpiration (β = r_a/(r_a + r_s) for an aerodynamic
resistance r_a and a surface resistance r_s). The bulk form and β are those of Garratt (1992);
instead of a separate exchange coefficient C_E, the convection coefficient h of
:mod:`radscene.thermal.convection` (h = ρ_a c_p C_H u) is carried over to mass transfer by the
Chilton–Colburn analogy h/h_m = ρ c_p Le^{2/3} (Incropera et al. 2007, §6.7), so that heat and
vapour see the same wind correlation (the McAdams coefficient, which contains some radiation,
overstates both alike).

Saturation vapour pressure over liquid water, Alduchov & Eskridge (1996), their recommended
AERK form (T_c in °C, −40 to 50 °C within 0.4 %):

.. math:: e_{sat} = 610.94 \\exp\\Big(\\frac{17.625\\,T_c}{T_c + 243.04}\\Big)\\ \\mathrm{Pa}

specific humidity q = ε e / (p − (1 − ε) e) with ε = M_w/M_d = 0.62198, the vapour pressure of
the air e_a = RH · e_sat(T_air) (relative humidity over water), and the latent heat of
vaporisation of Henderson-Sellers (1984), L_v = 1.91846×10⁶ (T/(T − 33.91))² J kg-1.
Over ice and snow (sublimation) nothing is modelled: keep β = 0 there.

Constants: c_p = 1007 J kg-1 K-1 and thermal diffusivity 22.5×10⁻⁶ m2 s-1 of air at 300 K
(Incropera et al. 2007, Table A.4), diffusion coefficient of water vapour in air
0.26×10⁻⁴ m2 s-1 at 298 K (Table A.8): Le = α/D = 0.865.

In the heat balance q_sat is linearised about the surface temperature at the start of the step
(and L_v taken there), q_sat(T) ≈ q_sat(T_p) + q_sat'(T_p)(T − T_p), so that Q_v is linear in
the new surface temperature and the surface equation keeps its form; the error is
β K q_sat'' ΔT²/2 with K = L_v h/(c_p Le^{2/3}) ≈ 35 000 W m-2 for h = 13 W m-2 K-1, about
1.2 W m-2 for a step that changes the surface by 1 K at 300 K, and nil in a steady state.

References
----------
Garratt, J. R. (1992). *The Atmospheric Boundary Layer*. Cambridge University Press (bulk
transfer relations; moisture availability).
Incropera, F. P., DeWitt, D. P., Bergman, T. L. and Lavine, A. S. (2007). *Fundamentals of
Heat and Mass Transfer*, 6th ed. Wiley, §6.7 (heat and mass transfer analogy), Tables A.4
(air) and A.8 (binary diffusion coefficients).
Alduchov, O. A. and Eskridge, R. E. (1996). Improved Magnus form approximation of saturation
vapor pressure. *J. Appl. Meteor.* 35, 601–609.
doi:10.1175/1520-0450(1996)035<0601:IMFAOS>2.0.CO;2
Henderson-Sellers, B. (1984). A new formula for latent heat of vaporization of water as a
function of temperature. *Q. J. R. Meteorol. Soc.* 110, 1186–1190. doi:10.1002/qj.49711046626
"""

from __future__ import annotations

import numpy as np

from radscene.thermal.weather.humidity import (
    EPSILON,
    saturation_vapour_pressure,
    saturation_vapour_pressure_derivative,
)
from radscene.thermal.weather.humidity import specific_humidity_of_vapour_pressure as _q

__all__ = [
        "AIR_SPECIFIC_HEAT",
    "LEWIS_NUMBER",
    "latent_heat_of_vaporisation",
    "vapour_transfer_coefficient",
    "evaporative_flux",
    "linearised_evaporative_flux",
]

#: c_p of air at 300 K [J kg-1 K-1] (Incropera et al. 2007, Table A.4).
AIR_SPECIFIC_HEAT = 1007.0
#: Le = α / D_AB = 22.5e-6 / 0.26e-4 for water vapour in air near 300 K [-].
LEWIS_NUMBER = 22.5e-6 / 0.26e-4



def latent_heat_of_vaporisation(temperature):
    """L_v = 1.91846×10⁶ (T / (T − 33.91))² [J kg-1] (Henderson-Sellers 1984).

    Examples
    --------
    >>> round(float(latent_heat_of_vaporisation(273.15)) / 1e6, 4)
    2.5008
    """
    t = np.asarray(temperature, float)
    return 1.91846e6 * (t / (t - 33.91)) ** 2


def vapour_transfer_coefficient(convection_coefficient):
    """ρ_a C_E u = h / (c_p Le^{2/3}) [kg m-2 s-1] from h [W m-2 K-1] (Chilton–Colburn).

    Examples
    --------
    >>> round(float(vapour_transfer_coefficient(13.3)), 5)
    0.01454
    """
    return np.asarray(convection_coefficient, float) / (AIR_SPECIFIC_HEAT * LEWIS_NUMBER ** (2.0 / 3.0))


def _air_humidity(air_temperature, relative_humidity, pressure):
    return _q(np.asarray(relative_humidity, float) * saturation_vapour_pressure(air_temperature), pressure)


def evaporative_flux(moisture_availability, convection_coefficient, surface_temperature, air_temperature, relative_humidity, pressure):
    """Latent-heat flux into the surface, Q_v [W m-2] (negative while evaporating).

    Parameters
    ----------
    moisture_availability : array_like
        β ∈ [0, 1] [-].
    convection_coefficient : array_like
        h [W m-2 K-1].
    surface_temperature, air_temperature : array_like
        [K].
    relative_humidity : array_like
        Of the air, over water, [0, 1] [-].
    pressure : array_like
        [Pa].

    Returns
    -------
    ndarray
        Q_v = −β L_v(T_s) h/(c_p Le^{2/3}) (q_sat(T_s) − q_a) [W m-2].

    Examples
    --------
    >>> round(float(evaporative_flux(1.0, 13.3, 293.15, 293.15, 0.5, 101325.0)), 1)
    -258.9
    """
    ts = np.asarray(surface_temperature, float)
    q_surface = _q(saturation_vapour_pressure(ts), pressure)
    q_air = _air_humidity(air_temperature, relative_humidity, pressure)
    k = np.asarray(moisture_availability, float) * latent_heat_of_vaporisation(ts) * vapour_transfer_coefficient(convection_coefficient)
    return -k * (q_surface - q_air)


def linearised_evaporative_flux(moisture_availability, convection_coefficient, previous_temperature, air_temperature, relative_humidity, pressure):
    """Q_v linearised about the surface temperature at the start of a step: Q_v ≈ c − s T.

    Parameters
    ----------
    As :func:`evaporative_flux`, with ``previous_temperature`` T_p [K] in place of the surface
    temperature.

    Returns
    -------
    constant : ndarray
        c [W m-2].
    slope : ndarray
        s = β K q_sat'(T_p) ≥ 0 [W m-2 K-1], K = L_v(T_p) h / (c_p Le^{2/3}).

    Notes
    -----
    .. math::
        Q_v \\approx -\\beta K\\big(q_{sat}(T_p) + q_{sat}'(T_p)(T - T_p) - q_a\\big), \\qquad
        q_{sat}' = \\frac{\\varepsilon p}{(p - (1-\\varepsilon) e_{sat})^2}\\,\\frac{de_{sat}}{dT}
    """
    tp = np.asarray(previous_temperature, float)
    p = np.asarray(pressure, float)
    e_sat = saturation_vapour_pressure(tp)
    q_sat = _q(e_sat, p)
    dq = EPSILON * p / (p - (1.0 - EPSILON) * e_sat) ** 2 * saturation_vapour_pressure_derivative(tp)
    k = np.asarray(moisture_availability, float) * latent_heat_of_vaporisation(tp) * vapour_transfer_coefficient(convection_coefficient)
    slope = k * dq
    constant = slope * tp - k * (q_sat - _air_humidity(air_temperature, relative_humidity, pressure))
    return constant, slope
