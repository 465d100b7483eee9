"""Fresnel reflectance of a smooth interface between air and a medium of complex index n + ik.

One formula covers dielectrics (k = 0, e.g. glass, water in the visible), absorbing dielectrics
(water and paints in the thermal infrared, k ≈ 0.01–0.5) and conductors (metals, k ≫ 1). For
light arriving from a medium of index 1 at angle θ from the normal, with the complex relative
index :math:`\\eta = n + i k` (the sign convention in which k ≥ 0 attenuates),

.. math::
    w = \\sqrt{\\eta^2 - \\sin^2\\theta},\\qquad
    r_s = \\frac{\\cos\\theta - w}{\\cos\\theta + w},\\qquad
    r_p = \\frac{\\eta^2\\cos\\theta - w}{\\eta^2\\cos\\theta + w},\\qquad
    R = \\tfrac12\\left(|r_s|^2 + |r_p|^2\\right),

with the principal square root (Im w ≥ 0 when k ≥ 0: the transmitted wave decays). At normal
incidence :math:`R = ((n-1)^2 + k^2)/((n+1)^2 + k^2)`. R rises to 1 at grazing incidence; for a
dielectric, :math:`r_p` vanishes at Brewster's angle :math:`\\tan\\theta_B = n`.

References
----------
M. Born, E. Wolf, *Principles of Optics*, 7th ed., Cambridge University Press (1999), §1.5 and
§14.2, doi:10.1017/CBO9781139644181.
"""

from __future__ import annotations

import numpy as np

__all__ = ["fresnel_reflectance", "fresnel_amplitudes"]


def fresnel_amplitudes(cos_theta, refractive_index, extinction_coefficient=0.0):
    """Complex amplitude reflection coefficients r_s and r_p [-].

    Parameters
    ----------
    cos_theta : array_like
        Cosine of the angle of incidence, in [0, 1] [-].
    refractive_index : array_like
        Real part n of the medium's index relative to the incidence medium [-].
    extinction_coefficient : array_like, optional
        Imaginary part k ≥ 0 [-]; default 0.

    Returns
    -------
    r_s, r_p : numpy.ndarray
        Complex, broadcast shape.
    """
    c = np.clip(np.asarray(cos_theta, dtype=float), 0.0, 1.0)
    eta = np.asarray(refractive_index, dtype=float) + 1j * np.asarray(extinction_coefficient,
                                                                      dtype=float)
    eta2 = eta * eta
    w = np.sqrt(eta2 - (1.0 - c * c))
    r_s = (c - w) / (c + w)
    r_p = (eta2 * c - w) / (eta2 * c + w)
    return r_s, r_p


def fresnel_reflectance(cos_theta, refractive_index, extinction_coefficient=0.0) -> np.ndarray:
    """Unpolarised Fresnel reflectance of a smooth surface [-].

    Parameters
    ----------
    cos_theta : array_like
        Cosine of the angle of incidence, in [0, 1] [-] (values outside are clipped to the
        interval: it is a cosine computed from unit vectors, not user input).
    refractive_index : array_like
        n > 0 [-].
    extinction_coefficient : array_like, optional
        k ≥ 0 [-]; default 0.

    Returns
    -------
    numpy.ndarray
        R in [0, 1] [-], broadcast shape.

    Examples
    --------
    >>> round(float(fresnel_reflectance(1.0, 1.5)), 12)  # glass at normal incidence
    0.04
    >>> round(float(fresnel_reflectance(0.0, 1.5)), 12)  # grazing
    1.0
    """
    r_s, r_p = fresnel_amplitudes(cos_theta, refractive_index, extinction_coefficient)
    return np.asarray(0.5 * (np.abs(r_s) ** 2 + np.abs(r_p) ** 2))
