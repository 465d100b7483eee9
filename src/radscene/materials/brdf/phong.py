"""The normalised Phong specular lobe of OSSIM (Willers, Willers & Lapierre 2011, eq. 4).

Derivation of the specular term
-------------------------------
OSSIM writes the sunshine reflected specularly by a surface as (Willers et al. 2011, eq. 4)

.. math::
    L_{spec} = \\frac{\\alpha_s (n+1) \\rho_s \\cos^n\\theta_r}{2}
               \\int_\\lambda \\epsilon_s L(T_s)\\,\\tau_{so}\\,\\tau_a\\,S\\,d\\lambda ,

with ρ_s the "wideband Fresnel reflection", n the specular exponent, θ_r the angle between the
reflected sun ray and the line of sight, and :math:`\\alpha_s = A_{sun}/(d_{sun}^2\\pi)
= \\Omega_{sun}/\\pi` (2.17e-5). The sun's radiance :math:`\\epsilon_s L(T_s)` times its solid
angle :math:`\\Omega_{sun}` is the solar irradiance on a plane normal to the beam,
:math:`E_{sun}`; so :math:`\\alpha_s\\,\\epsilon_s L(T_s) = E_{sun}/\\pi` and, per wavelength,

.. math::
    L_{spec} = E_{sun}\\,\\rho_s\\,\\frac{n+1}{2\\pi}\\cos^n\\theta_r
             = E_{sun}\\,\\rho_s\\,\\mathrm{lobe}(\\cos\\theta_r, n),
    \\qquad \\mathrm{lobe}(c, n) = \\frac{n+1}{2\\pi}\\max(c, 0)^n\\ [\\mathrm{sr^{-1}}].

The lobe integrates to 1 over the hemisphere about its axis (the mirror direction),
:math:`\\int_0^{2\\pi}\\int_0^{\\pi/2} \\frac{n+1}{2\\pi}\\cos^n\\alpha\\sin\\alpha\\,d\\alpha\\,d\\phi = 1`,
so ρ_s is the fraction of the incident beam power reflected into the lobe: its albedo. Note the
absence of the cos θ_i that the diffuse term carries: E_sun is the irradiance normal to the
beam, and the lobe spreads the reflected flux over solid angle about the mirror direction.

As a BRDF, :math:`f = L/(E_{sun}\\cos\\theta_i) = \\rho_s\\,\\mathrm{lobe}/\\cos\\theta_i`. This
module's :func:`brdf` divides by :math:`\\max(\\cos\\theta_i, \\cos\\theta_o)` instead (as
Ashikhmin & Shirley 2000 do): identical to OSSIM wherever :math:`\\cos\\theta_o \\le
\\cos\\theta_i`, in particular along the mirror direction where :math:`\\theta_o = \\theta_i`,
but reciprocal, :math:`f(\\omega_i, \\omega_o) = f(\\omega_o, \\omega_i)`, and energy conserving,
:math:`\\int f\\cos\\theta_o\\,d\\omega_o \\le \\rho_s` — the plain 1/cos θ_i form can exceed
ρ_s at grazing incidence when the lobe is broad.

Conventions: directions are unit vectors ``(..., 3)`` pointing *away* from the surface (towards
the sun, towards the sensor); arrays broadcast by numpy rules; float64.

===================  =====  =======  ==================================================
parameter            unit   default  meaning
===================  =====  =======  ==================================================
specular_reflectance [-]    0        ρ_s, albedo of the lobe ("wideband Fresnel reflection")
specular_exponent    [-]    0        n ≥ 0; larger is narrower (water ≈ 200–1000)
===================  =====  =======  ==================================================

Config snippet (material entry): ``{reflectance: 0.3, specular_reflectance: 0.04,
specular_exponent: 50}``. As a registered model (:class:`Phong`, the Lambertian part plus the
lobe): ``{type: phong, diffuse_reflectance: 0.26, specular_reflectance: 0.04,
specular_exponent: 50}``, with

====================  =====  =======  =================================================
parameter             unit   default  meaning
====================  =====  =======  =================================================
diffuse_reflectance   [-]    0        ρ_d, Lambertian part (spectrum)
specular_reflectance  [-]    —        ρ_s, albedo of the lobe (spectrum); ρ_d + ρ_s ≤ 1
specular_exponent     [-]    —        n ≥ 0
====================  =====  =======  =================================================

Its :meth:`~Phong.sample` draws from the lobe about the mirror of ω_o with probability
ρ_s/(ρ_d + ρ_s) and cosine-weighted otherwise.

References
----------
"Signature modelling and radiometric rendering equations in infrared scene simulation
systems" (C. J. Willers, M. S. Willers, F. Lapierre, Proc. SPIE 8187, 2011).
B. T. Phong, "Illumination for computer generated pictures", Commun. ACM 18(6), 311-317 (1975),
doi:10.1145/360825.360839.
M. Ashikhmin, P. Shirley, "An anisotropic Phong BRDF model", J. Graphics Tools 5(2), 25-32
(2000), doi:10.1080/10867651.2000.10487522.
"""

from __future__ import annotations

import numpy as np

from radscene.errors import ConfigError
from radscene.geometry.frames import to_world
from radscene.materials.brdf.base import BRDF, Parameter, cosine_hemisphere

__all__ = ["mirror", "lobe", "brdf", "albedo_bound", "sample", "pdf", "Phong"]


def mirror(direction, normal) -> np.ndarray:
    """Reflect a direction about the normal: :math:`2(\\mathbf{d}\\cdot\\mathbf{n})\\mathbf{n} -
    \\mathbf{d}`.

    The mirror of the direction *to* the sun is the direction in which the specularly reflected
    ray *leaves* the surface.

    Parameters
    ----------
    direction, normal : array_like
        Unit vectors, shape ``(..., 3)``, broadcastable.

    Returns
    -------
    numpy.ndarray
        Unit vectors, broadcast shape ``(..., 3)`` [-].

    Examples
    --------
    >>> mirror([1.0, 0.0, 1.0], [0.0, 0.0, 1.0])
    array([-1.,  0.,  1.])
    """
    d = np.asarray(direction, dtype=float)
    n = np.asarray(normal, dtype=float)
    return 2.0 * np.sum(d * n, axis=-1, keepdims=True) * n - d


def lobe(cos_theta_r, exponent) -> np.ndarray:
    """Normalised Phong lobe (n + 1)/(2π) max(cos θ_r, 0)^n.

    Parameters
    ----------
    cos_theta_r : array_like
        Cosine of the angle between the lobe axis (mirror direction) and the direction [-].
    exponent : array_like
        Specular exponent n ≥ 0 [-].

    Returns
    -------
    numpy.ndarray
        Lobe value [sr-1], broadcast shape. For n = 0 it is 1/(2π) on the whole hemisphere
        (cos θ_r ≥ 0).

    Raises
    ------
    ConfigError
        A negative or non-finite exponent.

    Examples
    --------
    >>> round(float(lobe(1.0, 1.0)), 12) == round(1.0 / np.pi, 12)
    True
    """
    c = np.asarray(cos_theta_r, dtype=float)
    n = _exponent(exponent)
    above = c >= 0.0
    power = np.power(np.where(above, c, 0.0), n)
    return np.asarray(np.where(above, power, 0.0) * (n + 1.0) / (2.0 * np.pi))


def brdf(wi, wo, normal, specular_reflectance, exponent) -> np.ndarray:
    """Reciprocal Phong BRDF ρ_s lobe(ω_o · mirror(ω_i), n) / max(cos θ_i, cos θ_o).

    Parameters
    ----------
    wi : array_like
        Unit directions towards the source, ``(..., 3)``.
    wo : array_like
        Unit directions towards the viewer, ``(..., 3)``.
    normal : array_like
        Unit surface normals, ``(..., 3)``.
    specular_reflectance : array_like
        ρ_s [-].
    exponent : array_like
        n ≥ 0 [-].

    Returns
    -------
    numpy.ndarray
        f_r [sr-1]; 0 where either direction is at or below the horizon.

    Notes
    -----
    Equal to the OSSIM form ρ_s lobe / cos θ_i wherever cos θ_o ≤ cos θ_i, hence at the
    mirror direction (module docstring).
    """
    wi = np.asarray(wi, dtype=float)
    wo = np.asarray(wo, dtype=float)
    n = np.asarray(normal, dtype=float)
    cos_i = np.sum(wi * n, axis=-1)
    cos_o = np.sum(wo * n, axis=-1)
    cos_r = np.sum(wo * mirror(wi, n), axis=-1)
    visible = (cos_i > 0.0) & (cos_o > 0.0)
    denom = np.where(visible, np.maximum(cos_i, cos_o), 1.0)
    value = np.asarray(specular_reflectance, dtype=float) * lobe(cos_r, exponent) / denom
    return np.asarray(np.where(visible, value, 0.0))


def albedo_bound(specular_reflectance) -> np.ndarray:
    """Upper bound of the directional-hemispherical reflectance of :func:`brdf`: ρ_s [-]."""
    return np.asarray(specular_reflectance, dtype=float)


def pdf(direction, axis, exponent) -> np.ndarray:
    """Density of :func:`sample` for ``direction``: lobe(direction · axis, n) [sr-1]."""
    cos = np.sum(np.asarray(direction, dtype=float) * np.asarray(axis, dtype=float), axis=-1)
    return lobe(cos, exponent)


def sample(axis, exponent, u1, u2) -> tuple[np.ndarray, np.ndarray]:
    """Directions distributed as the lobe about ``axis``.

    Parameters
    ----------
    axis : array_like
        Unit lobe axes (mirror directions), ``(..., 3)``.
    exponent : array_like
        n ≥ 0 [-].
    u1, u2 : array_like
        Uniform random numbers in [0, 1] [-].

    Returns
    -------
    directions : numpy.ndarray
        Unit vectors, ``broadcast(axis[..., 0], exponent, u1, u2).shape + (3,)``. They may lie
        below the surface's horizon, where :func:`brdf` is 0.
    pdf : numpy.ndarray
        lobe(cos α, n) [sr-1], α the angle from the axis.

    Notes
    -----
    Inverting the marginal CDF of cos α, :math:`P(\\cos\\alpha \\le c) = 1 - c^{n+1}`, gives
    :math:`\\cos\\alpha = u_1^{1/(n+1)}` (1 − u_1 has the same law); :math:`\\phi = 2\\pi u_2`.

    Examples
    --------
    >>> d, p = sample([0.0, 0.0, 1.0], 10.0, 1.0, 0.0)
    >>> d.round(12), round(float(p) * 2 * np.pi, 12)
    (array([0., 0., 1.]), 11.0)
    """
    a = np.asarray(axis, dtype=float)
    n = _exponent(exponent)
    u1 = _unit_interval(u1, "u1")
    u2 = _unit_interval(u2, "u2")
    shape = np.broadcast_shapes(a.shape[:-1], n.shape, u1.shape, u2.shape)
    cos_a = np.power(np.broadcast_to(u1, shape), 1.0 / (np.broadcast_to(n, shape) + 1.0))
    sin_a = np.sqrt(np.maximum(1.0 - cos_a * cos_a, 0.0))
    phi = 2.0 * np.pi * np.broadcast_to(u2, shape)
    local = np.stack([sin_a * np.cos(phi), sin_a * np.sin(phi), cos_a], axis=-1)
    directions = to_world(local, np.broadcast_to(a, shape + (3,)))
    return directions, lobe(cos_a, n)


def _exponent(exponent) -> np.ndarray:
    n = np.asarray(exponent, dtype=float)
    if not np.all(np.isfinite(n) & (n >= 0.0)):
        raise ConfigError("specular exponent must be finite and >= 0", key="exponent")
    return n


def _unit_interval(u, key: str) -> np.ndarray:
    u = np.asarray(u, dtype=float)
    if not np.all((u >= 0.0) & (u <= 1.0)):
        raise ConfigError("random numbers must lie in [0, 1]", key=key)
    return u


class Phong(BRDF):
    """Lambertian part plus the reciprocal OSSIM Phong lobe (module docstring).

    .. math:: f = \\frac{\\rho_d}{\\pi} + \\rho_s\\,
              \\frac{\\mathrm{lobe}(\\omega_o\\cdot\\mathrm{mirror}(\\omega_i), n)}
              {\\max(\\cos\\theta_i, \\cos\\theta_o)},
       \\qquad \\omega_o\\cdot\\mathrm{mirror}(\\omega_i) = 2\\mu_i\\mu_o - \\cos g .

    Examples
    --------
    >>> m = Phong(specular_reflectance=0.04, specular_exponent=100.0)
    >>> sun = np.array([0.5, 0.0, np.sqrt(0.75)])
    >>> glint = np.array([-0.5, 0.0, np.sqrt(0.75)])
    >>> round(float(m.f(sun, glint) * sun[2]), 10) == round(0.04 * 101 / (2 * np.pi), 10)
    True
    """

    name = "phong"
    PARAMETERS = {
        "diffuse_reflectance": Parameter("-", "rho_d, Lambertian part", 0.0, kind="spectrum",
                                         low=0.0, high=1.0),
        "specular_reflectance": Parameter("-", "rho_s, albedo of the Phong lobe",
                                          kind="spectrum", low=0.0, high=1.0),
        "specular_exponent": Parameter("-", "Phong exponent n; larger is narrower", low=0.0),
    }
    albedo_rule = "sampling"

    def _check(self):
        self._check_sum_at_most_one(("diffuse_reflectance", "specular_reflectance"))

    def _kernel(self, mu_i, mu_o, cos_g, wavelength):
        rho_d = self.parameter("diffuse_reflectance", wavelength)
        rho_s = self.parameter("specular_reflectance", wavelength)
        n = self.parameter("specular_exponent")
        cos_r = mu_i * mu_o
        cos_r = 2.0 * cos_r - cos_g
        if n == 0.0:
            lobe_value = np.asarray(np.where(cos_r >= 0.0, 1.0, 0.0 * cos_r))  # NaN stays
        else:
            lobe_value = np.asarray(np.maximum(cos_r, 0.0))
            np.power(lobe_value, n, out=lobe_value)  # in place: this is the hot path
        lobe_value /= np.maximum(mu_i, mu_o)
        if isinstance(rho_s, float) and isinstance(rho_d, float):
            lobe_value *= rho_s * (n + 1.0) / (2.0 * np.pi)
            lobe_value += rho_d / np.pi
            return lobe_value
        return rho_d / np.pi + rho_s * (n + 1.0) / (2.0 * np.pi) * lobe_value

    def _sample_local(self, wo, u1, u2, wavelength):
        p_s = self._mixture_weight("specular_reflectance", "diffuse_reflectance", wavelength)
        n = self.parameter("specular_exponent")
        lobe_pick = u1 < p_s
        with np.errstate(divide="ignore", invalid="ignore"):
            v = np.where(lobe_pick, u1 / np.where(p_s > 0.0, p_s, 1.0),
                         (u1 - p_s) / np.where(p_s < 1.0, 1.0 - p_s, 1.0))
        v = np.clip(v, 0.0, 1.0)
        axis = wo * np.array([-1.0, -1.0, 1.0])  # mirror of wo about the local z
        cos_a = np.power(v, 1.0 / (n + 1.0))
        sin_a = np.sqrt(np.maximum(1.0 - cos_a * cos_a, 0.0))
        phi = 2.0 * np.pi * u2
        local = np.stack([sin_a * np.cos(phi), sin_a * np.sin(phi), cos_a], axis=-1)
        from_lobe = to_world(local, axis)
        diffuse = cosine_hemisphere(v, u2)
        return np.where(lobe_pick[..., None], from_lobe, diffuse)

    def _pdf(self, mu_o, mu_i, cos_g, wavelength):
        p_s = self._mixture_weight("specular_reflectance", "diffuse_reflectance", wavelength)
        n = self.parameter("specular_exponent")
        cos_a = 2.0 * mu_i * mu_o - cos_g  # wi . mirror(wo)
        lobe_pdf = np.where(cos_a >= 0.0, np.power(np.maximum(cos_a, 0.0), n), 0.0)
        lobe_pdf = lobe_pdf * ((n + 1.0) / (2.0 * np.pi))
        return p_s * lobe_pdf + (1.0 - p_s) * np.maximum(mu_i, 0.0) / np.pi

