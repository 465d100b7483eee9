"""The Rahman–Pinty–Verstraete (RPV) BRDF of land surfaces (Rahman et al. 1993).

The bidirectional reflectance factor is a product of three factors (Rahman et al. 1993; the
hot-spot parameter ρ_c as in libRadtran's ``brdf_rpv h`` and DISORT's ``H0``):

.. math::
    \\mathrm{BRF} = \\rho_0\\,[\\mu_i\\,\\mu_o\\,(\\mu_i + \\mu_o)]^{k-1}\\,
    \\frac{1 - \\Theta^2}{(1 + 2\\Theta\\cos g + \\Theta^2)^{3/2}}\\,
    \\left[1 + \\frac{1 - \\rho_c}{1 + G}\\right],
    \\qquad f = \\mathrm{BRF}/\\pi\\ [\\mathrm{sr^{-1}}],

    G = \\sqrt{\\tan^2\\theta_i + \\tan^2\\theta_o - 2\\tan\\theta_i\\tan\\theta_o\\cos\\Delta\\phi},

with g the phase angle (cos g = ω_i · ω_o; g = 0 in the hot spot) and Δφ the relative
azimuth, 0 for backscatter (:mod:`.base`). The first factor (Minnaert) sets the bowl (k < 1) or
bell (k > 1) shape, the Henyey–Greenstein factor the forward (Θ > 0) or backward (Θ < 0)
scattering, the last the hot spot, whose peak is 1 + (1 − ρ_c) at g = 0. Without ρ_c, ρ_c = ρ_0
(the original model). All of ρ_0, k, Θ, ρ_c may vary with wavelength. The model is symmetric in
ω_i and ω_o (reciprocal). Its ρ_dh grows without bound at grazing incidence when k < 1 (the
Minnaert factor); for published parameter sets it stays below 1 up to θ_i ≈ 89°.

The azimuth sign is checked against libRadtran's table (``tests/validation``): libRadtran's
``phi = 180°`` (its backscatter) is Δφ = 0 here.

==========  =====  ========  =====================================================
parameter   unit   default   meaning
==========  =====  ========  =====================================================
rho0        [-]    —         ρ_0 ≥ 0, BRF level (spectrum)
k           [-]    —         k > 0, Minnaert exponent (spectrum)
theta       [-]    —         Θ in (−1, 1), Henyey–Greenstein asymmetry (spectrum)
rho_c       [-]    rho0      hot-spot parameter ρ_c ≥ 0 (spectrum); default ρ_0
==========  =====  ========  =====================================================

Config snippet (plowed field, Rahman et al. 1993 via libRadtran's example):
``{type: rpv, rho0: 0.076, k: 0.648, theta: -0.290}``.

References
----------
H. Rahman, B. Pinty, M. M. Verstraete, "Coupled surface-atmosphere reflectance (CSAR) model:
2. Semiempirical surface model usable with NOAA advanced very high resolution radiometer data",
J. Geophys. Res. 98(D11), 20791–20801 (1993), doi:10.1029/93JD02072.
"""

from __future__ import annotations

import numpy as np

from radscene.materials.brdf._compiled import parallel_ufunc
from radscene.materials.brdf.base import BRDF, Parameter

__all__ = ["RPV", "rpv_brf"]


def rpv_brf(mu_i, mu_o, cos_g, rho0, k, theta, rho_c) -> np.ndarray:
    """RPV bidirectional reflectance factor (the numpy reference implementation) [-].

    Parameters
    ----------
    mu_i, mu_o : array_like
        Cosines of the incidence and view zenith angles, > 0 [-].
    cos_g : array_like
        Cosine of the phase angle, ω_i · ω_o [-].
    rho0, k, theta, rho_c : array_like
        Model parameters [-] (module table).

    Returns
    -------
    numpy.ndarray
        BRF [-], broadcast shape.

    Examples
    --------
    >>> # libRadtran example UVSPEC_BRDF: nadir view, sun at 30 deg: BRF 0.21004
    >>> mu0 = np.cos(np.radians(30.0))
    >>> round(float(rpv_brf(mu0, 1.0, mu0, 0.076, 0.648, -0.29, 0.076)), 3)
    0.21
    """
    mu_i = np.asarray(mu_i, dtype=float)
    mu_o = np.asarray(mu_o, dtype=float)
    cos_g = np.asarray(cos_g, dtype=float)
    minnaert = np.power(mu_i * mu_o * (mu_i + mu_o), np.asarray(k) - 1.0)
    theta = np.asarray(theta, dtype=float)
    hg = (1.0 - theta * theta) / np.power(1.0 + 2.0 * theta * cos_g + theta * theta, 1.5)
    # tan_i tan_o cos(dphi) = (cos g - mu_i mu_o) / (mu_i mu_o)
    p = mu_i * mu_o
    g2 = (1.0 - mu_i * mu_i) / (mu_i * mu_i) + (1.0 - mu_o * mu_o) / (mu_o * mu_o) \
        - 2.0 * (cos_g - p) / p
    big_g = np.sqrt(np.maximum(g2, 0.0))
    return rho0 * minnaert * hg * (1.0 + (1.0 - np.asarray(rho_c)) / (1.0 + big_g))


def _rpv_brdf_scalar(mu_i, mu_o, cos_g, rho0, k, theta, rho_c):  # pragma: no cover
    """f [sr-1] of one geometry, compiled by :func:`parallel_ufunc` (the fast path)."""
    if mu_i <= 0.0 or mu_o <= 0.0:
        return 0.0
    minnaert = (mu_i * mu_o * (mu_i + mu_o)) ** (k - 1.0)
    d = 1.0 + 2.0 * theta * cos_g + theta * theta
    hg = (1.0 - theta * theta) / (d * np.sqrt(d))
    p = mu_i * mu_o
    g2 = (1.0 - mu_i * mu_i) / (mu_i * mu_i) + (1.0 - mu_o * mu_o) / (mu_o * mu_o) \
        - 2.0 * (cos_g - p) / p
    big_g = np.sqrt(g2) if g2 > 0.0 else 0.0
    return rho0 * minnaert * hg * (1.0 + (1.0 - rho_c) / (1.0 + big_g)) / np.pi


class RPV(BRDF):
    """Rahman–Pinty–Verstraete BRDF (module docstring).

    Examples
    --------
    >>> plowed = RPV(rho0=0.076, k=0.648, theta=-0.290)
    >>> round(float(plowed.f_angles(30.0, 0.0, 0.0) * np.pi), 3)   # libRadtran: 0.21004
    0.21
    """

    name = "rpv"
    PARAMETERS = {
        "rho0": Parameter("-", "rho_0, BRF level", kind="spectrum", low=0.0),
        "k": Parameter("-", "Minnaert exponent", kind="spectrum", low=0.0, low_open=True),
        "theta": Parameter("-", "Henyey-Greenstein asymmetry Theta", kind="spectrum", low=-1.0,
                           high=1.0, low_open=True, high_open=True),
        "rho_c": Parameter("-", "hot-spot parameter rho_c (default rho0)", None,
                           kind="spectrum", low=0.0),
    }

    def _params(self, wavelength):
        rho0, k, theta, rho_c = (self.parameter(n, wavelength)
                                 for n in ("rho0", "k", "theta", "rho_c"))
        return rho0, k, theta, rho0 if rho_c is None else rho_c

    def kernel(self, cos_incidence, cos_view, cos_phase, wavelength=None):
        # compiled fast path; the reference is BRDF.kernel → _kernel → rpv_brf
        fast = parallel_ufunc(_rpv_brdf_scalar, 7)
        with np.errstate(invalid="ignore", divide="ignore", over="ignore"):
            value = fast(cos_incidence, cos_view, cos_phase, *self._params(wavelength))
        return np.asarray(value, dtype=float)

    def _kernel(self, mu_i, mu_o, cos_g, wavelength):
        return rpv_brf(mu_i, mu_o, cos_g, *self._params(wavelength)) / np.pi

    def kernel_reference(self, cos_incidence, cos_view, cos_phase, wavelength=None):
        """The numpy reference evaluation (:func:`rpv_brf`), the oracle of the compiled one."""
        return BRDF.kernel(self, cos_incidence, cos_view, cos_phase, wavelength)
