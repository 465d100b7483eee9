"""Lambertian reflection and transmission of a thin sheet: leaves, paper, fabric, thin plastic.

A two-sided diffuse sheet reflects a fraction ρ and transmits a fraction τ of the light that
falls on either face, each spread uniformly in radiance over its hemisphere (the leaf model of
radiative-transfer codes such as SAIL and DART). As a bidirectional scattering function
(BSDF) of directions on the whole sphere, μ = ω · n of either sign,

.. math::
    f(\\omega_i, \\omega_o) = \\begin{cases} \\rho/\\pi & \\mu_i\\,\\mu_o > 0
    \\ \\text{(same side: reflection)}\\\\
    \\tau/\\pi & \\mu_i\\,\\mu_o < 0\\ \\text{(opposite sides: transmission)}
    \\end{cases}\\ [\\mathrm{sr^{-1}}],

so that ρ_dh = ρ, τ_dh = τ and, by Kirchhoff's law, ε = 1 − ρ − τ on both faces, at every
angle. f is symmetric in ω_i and ω_o. :meth:`LambertianTransmission.sample` picks the side with
probability ρ/(ρ + τ) (1/2 where both vanish) and draws cosine-weighted on it.

===============  =====  =======  ===============================================
parameter        unit   default  meaning
===============  =====  =======  ===============================================
reflectance      [-]    —        ρ in [0, 1] (spectrum)
transmittance    [-]    —        τ in [0, 1] (spectrum); ρ + τ ≤ 1
===============  =====  =======  ===============================================

Config snippet (a green leaf in the NIR): ``{type: lambertian_transmission, reflectance: 0.48,
transmittance: 0.45}``.

References
----------
W. Verhoef, "Light scattering by leaf layers with application to canopy reflectance modeling:
the SAIL model", Remote Sens. Environ. 16(2), 125–141 (1984),
doi:10.1016/0034-4257(84)90057-9.
"""

from __future__ import annotations

import numpy as np

from radscene.materials.brdf.base import BRDF, Parameter, cosine_hemisphere

__all__ = ["LambertianTransmission"]


class LambertianTransmission(BRDF):
    """Two-sided Lambertian reflector and transmitter (module docstring).

    Examples
    --------
    >>> leaf = LambertianTransmission(reflectance=0.48, transmittance=0.45)
    >>> round(float(leaf.f([0, 0, 1.0], [0, 0, -1.0]) * np.pi), 12)   # through the leaf
    0.45
    >>> round(float(leaf.emissivity([0.0, 0.0, -1.0])), 12)             # either face
    0.07
    """

    name = "lambertian_transmission"
    PARAMETERS = {
        "reflectance": Parameter("-", "rho, diffuse reflectance of either face",
                                 kind="spectrum", low=0.0, high=1.0),
        "transmittance": Parameter("-", "tau, diffuse transmittance", kind="spectrum",
                                   low=0.0, high=1.0),
    }
    two_sided = True

    def _check(self):
        self._check_sum_at_most_one(("reflectance", "transmittance"))

    def kernel(self, cos_incidence, cos_view, cos_phase=None, wavelength=None):
        mu_i = np.asarray(cos_incidence, dtype=float)
        mu_o = np.asarray(cos_view, dtype=float)
        rho = np.asarray(self.parameter("reflectance", wavelength)) / np.pi
        tau = np.asarray(self.parameter("transmittance", wavelength)) / np.pi
        side = mu_i * mu_o
        value = np.where(side > 0.0, rho, np.where(side < 0.0, tau, 0.0 * side))
        shape = np.broadcast_shapes(value.shape, np.shape(cos_phase))
        return value if value.shape == shape else np.array(np.broadcast_to(value, shape))

    def _sample_local(self, wo, u1, u2, wavelength):
        p_r = self._mixture_weight("reflectance", "transmittance", wavelength)
        reflect = u1 < p_r
        with np.errstate(divide="ignore", invalid="ignore"):
            v = np.where(reflect, u1 / np.where(p_r > 0.0, p_r, 1.0),
                         (u1 - p_r) / np.where(p_r < 1.0, 1.0 - p_r, 1.0))
        v = np.clip(v, 0.0, 1.0)
        face = np.where(wo[..., 2] >= 0.0, 1.0, -1.0)
        return cosine_hemisphere(v, u2, np.where(reflect, face, -face))

    def _pdf(self, mu_o, mu_i, cos_g, wavelength):
        p_r = self._mixture_weight("reflectance", "transmittance", wavelength)
        same = mu_i * np.where(mu_o >= 0.0, 1.0, -1.0) > 0.0
        return np.where(same, p_r, 1.0 - p_r) * np.abs(mu_i) / np.pi

    def _hemispherical(self, mu_i, wavelength):
        mu = np.asarray(mu_i, dtype=float)
        rho = np.asarray(self.parameter("reflectance", wavelength), dtype=float)
        tau = np.asarray(self.parameter("transmittance", wavelength), dtype=float)
        lit = mu != 0.0
        return np.where(lit, rho, 0.0) + 0.0 * mu, np.where(lit, tau, 0.0) + 0.0 * mu
