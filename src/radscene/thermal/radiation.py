"""Radiative flux terms of the surface heat balance: absorbed short-wave, absorbed sky
long-wave, emitted long-wave.

Sign convention of the heat balance (seed 001, eqs. 3 and 5): a flux *into* the surface is
positive; these functions return magnitudes [W m-2] with the sign stated in each docstring.

References
----------
Willers, C. J., Willers, M. S. and Lapierre, F. (2011). Signature modelling and radiometric
rendering equations in infrared scene simulation systems. Proc. SPIE 8187, 81870R
(the project's seed paper 001): the OSMOSIS and OSSIM heat balances, eqs. 3 and 5,
Q_a + Q_sky + Q_env + Q_t + Q_k + Q_d = Q_net → 0. doi:10.1117/12.903352
Duffie, J. A. and Beckman, W. A. (2013). *Solar Engineering of Thermal Processes*, 4th ed.
Wiley, §1.6 (angle of incidence), §3.8 (sky radiation). doi:10.1002/9781118671603
"""

from __future__ import annotations

import numpy as np

from radscene.radiometry.constants import SIGMA  # σ = 2π⁵k⁴/(15h³c²) [W m-2 K-4], CODATA

__all__ = ["absorbed_shortwave", "absorbed_sky_longwave", "emitted_longwave", "emitted_longwave_derivative", "SIGMA"]


def absorbed_shortwave(absorptance, direct_irradiance, cos_incidence, diffuse_irradiance, lit=1.0, sky_view_fraction=1.0):
    """Short-wave flux absorbed by a surface element, Q_a ≥ 0 [W m-2].

    Parameters
    ----------
    absorptance : array_like
        Broadband solar absorptance α [-].
    direct_irradiance : array_like
        Direct (beam) irradiance on a plane normal to the sun's direction, E_dir [W m-2].
    cos_incidence : array_like
        Cosine of the angle between the sun's direction and the surface normal [-]; negative
        values (sun behind the surface) give no direct term.
    diffuse_irradiance : array_like
        Diffuse sky irradiance on a horizontal plane under a full sky, E_dif [W m-2].
    lit : array_like, optional
        Sunlit fraction of the element, 1 − shadow [-].
    sky_view_fraction : array_like, optional
        Sky view factor of the element [-] (isotropic sky).

    Returns
    -------
    ndarray
        Q_a [W m-2], broadcast over the inputs.

    Notes
    -----
    .. math:: Q_a = \\alpha\\,(E_{dir}\\max(\\cos i, 0)\\,\\mathrm{lit} + E_{dif}\\,V_{sky})

    Examples
    --------
    >>> float(absorbed_shortwave(0.9, 800.0, 0.5, 100.0, lit=1.0, sky_view_fraction=0.8))
    432.0
    """
    cos_i = np.maximum(np.asarray(cos_incidence, float), 0.0)
    return np.asarray(absorptance, float) * (
        np.asarray(direct_irradiance, float) * cos_i * np.asarray(lit, float)
        + np.asarray(diffuse_irradiance, float) * np.asarray(sky_view_fraction, float)
    )


def absorbed_sky_longwave(emissivity, sky_irradiance, sky_view_fraction=1.0):
    """Long-wave flux from the sky absorbed by a surface element, Q_sky ≥ 0 [W m-2].

    Parameters
    ----------
    emissivity : array_like
        Broadband long-wave emissivity ε [-], equal to the absorptance (Kirchhoff; grey).
    sky_irradiance : array_like
        Downwelling long-wave irradiance on a horizontal plane under a full sky [W m-2].
    sky_view_fraction : array_like, optional
        Sky view factor [-].

    Returns
    -------
    ndarray
        Q_sky [W m-2].

    Notes
    -----
    .. math:: Q_{sky} = \\varepsilon\\,E_{sky,LW}\\,V_{sky}

    Examples
    --------
    >>> float(absorbed_sky_longwave(0.95, 300.0, 0.5))
    142.5
    """
    return np.asarray(emissivity, float) * np.asarray(sky_irradiance, float) * np.asarray(sky_view_fraction, float)


def emitted_longwave(emissivity, temperature):
    """Long-wave exitance of a grey surface, εσT⁴ ≥ 0 [W m-2]; in the balance Q_t = −εσT⁴.

    Parameters
    ----------
    emissivity : array_like
        ε [-].
    temperature : array_like
        Surface temperature T [K].

    Returns
    -------
    ndarray
        [W m-2].

    Examples
    --------
    >>> round(float(emitted_longwave(1.0, 300.0)), 2)
    459.3
    """
    t = np.asarray(temperature, float)
    return np.asarray(emissivity, float) * SIGMA * t**4


def emitted_longwave_derivative(emissivity, temperature):
    """d(εσT⁴)/dT = 4εσT³ [W m-2 K-1] (for the surface node's Newton iteration)."""
    t = np.asarray(temperature, float)
    return 4.0 * np.asarray(emissivity, float) * SIGMA * t**3
