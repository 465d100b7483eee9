"""Lambertian (perfectly diffuse) reflection.

A Lambertian surface of directional-hemispherical reflectance ρ reflects the same radiance in
every direction; its BRDF is a constant,

.. math:: f_r = \\frac{\\rho}{\\pi}\\quad[\\mathrm{sr^{-1}}],

so that :math:`\\int_{2\\pi} f_r \\cos\\theta_r\\,d\\omega_r = \\rho`. Directions are unit vectors
``(..., 3)`` in any right-handed frame (radscene's world frame is east-north-up); arrays
broadcast by numpy rules and are float64.

===========  =====  =======  ===========================================
parameter    unit   default  meaning
===========  =====  =======  ===========================================
reflectance  [-]    —        directional-hemispherical reflectance ρ_d
===========  =====  =======  ===========================================

Config snippet (material entry): ``{reflectance: 0.3}`` — the diffuse part of every
:class:`~radscene.materials.Material` is Lambertian. As a registered model (see
:mod:`radscene.materials.brdf`): ``{type: lambertian, reflectance: 0.3}``.

The module functions (:func:`brdf`, :func:`albedo`, :func:`sample`, :func:`pdf`) are the
array kernels the renderer calls; :class:`Lambertian` is the same model under the common
:class:`~radscene.materials.brdf.base.BRDF` contract.
"""

from __future__ import annotations

import numpy as np

from radscene.errors import ConfigError
from radscene.geometry.frames import to_world
from radscene.materials.brdf.base import BRDF, Parameter

__all__ = ["brdf", "albedo", "sample", "pdf", "Lambertian"]


def brdf(reflectance) -> np.ndarray:
    """Lambertian BRDF ρ/π.

    Parameters
    ----------
    reflectance : array_like
        Directional-hemispherical reflectance ρ [-].

    Returns
    -------
    numpy.ndarray
        f_r [sr-1], shape of ``reflectance``.

    Examples
    --------
    >>> float(brdf(np.pi))
    1.0
    """
    return np.asarray(np.asarray(reflectance, dtype=float) / np.pi)


def albedo(reflectance) -> np.ndarray:
    """Directional-hemispherical reflectance of the Lambertian BRDF: ρ itself [-]."""
    return np.asarray(reflectance, dtype=float)


def pdf(direction, normal) -> np.ndarray:
    """Density of :func:`sample`: cos θ / π for directions above the surface, else 0 [sr-1].

    Parameters
    ----------
    direction, normal : array_like
        Unit vectors, shape ``(..., 3)``, broadcastable.

    Returns
    -------
    numpy.ndarray
        Shape of the broadcast leading dimensions [sr-1].
    """
    cos = np.sum(np.asarray(direction, dtype=float) * np.asarray(normal, dtype=float), axis=-1)
    return np.asarray(np.where(cos > 0.0, cos, 0.0) / np.pi)


def sample(normal, u1, u2) -> tuple[np.ndarray, np.ndarray]:
    """Cosine-weighted directions on the hemisphere about ``normal``.

    Parameters
    ----------
    normal : array_like
        Unit normals, shape ``(..., 3)``.
    u1, u2 : array_like
        Uniform random numbers in [0, 1) [-], broadcastable with ``normal[..., 0]``.

    Returns
    -------
    directions : numpy.ndarray
        Unit vectors, shape ``broadcast(normal[..., 0], u1, u2).shape + (3,)`` [-].
    pdf : numpy.ndarray
        Their density cos θ / π with respect to solid angle [sr-1].

    Notes
    -----
    Malley's method: a point uniform on the unit disc, :math:`r = \\sqrt{u_1}`,
    :math:`\\phi = 2\\pi u_2`, projected up onto the hemisphere, so
    :math:`\\cos\\theta = \\sqrt{1 - u_1}` and :math:`p(\\omega) = \\cos\\theta/\\pi`
    (Pharr, Jakob & Humphreys, *Physically Based Rendering*, 3rd ed., 2016, §13.6.3).

    Examples
    --------
    >>> d, p = sample([0.0, 0.0, 1.0], 0.0, 0.0)
    >>> d.round(12), round(float(p), 5)
    (array([0., 0., 1.]), 0.31831)
    """
    n = np.asarray(normal, dtype=float)
    u1 = _unit_interval(u1, "u1")
    u2 = _unit_interval(u2, "u2")
    shape = np.broadcast_shapes(n.shape[:-1], u1.shape, u2.shape)
    u1 = np.broadcast_to(u1, shape)
    u2 = np.broadcast_to(u2, shape)
    r = np.sqrt(u1)
    phi = 2.0 * np.pi * u2
    cos_theta = np.sqrt(np.maximum(1.0 - u1, 0.0))
    local = np.stack([r * np.cos(phi), r * np.sin(phi), cos_theta], axis=-1)
    directions = to_world(local, np.broadcast_to(n, shape + (3,)))
    return directions, np.asarray(cos_theta / np.pi)


def _unit_interval(u, key: str) -> np.ndarray:
    u = np.asarray(u, dtype=float)
    if not np.all((u >= 0.0) & (u <= 1.0)):
        raise ConfigError("random numbers must lie in [0, 1]", key=key)
    return u


class Lambertian(BRDF):
    """Lambertian reflector f = ρ/π [sr-1]; ρ_dh = ρ at every incidence, ε = 1 − ρ.

    Parameters
    ----------
    reflectance : spectrum-like
        ρ in [0, 1] [-] (module table).

    Examples
    --------
    >>> m = Lambertian(reflectance=0.3)
    >>> round(float(m.f([0, 0, 1.0], [0.6, 0, 0.8])) * np.pi, 12)
    0.3
    >>> round(float(m.emissivity([0.0, 0.0, 1.0])), 12)
    0.7
    """

    name = "lambertian"
    PARAMETERS = {
        "reflectance": Parameter("-", "directional-hemispherical reflectance rho", kind="spectrum",
                                 low=0.0, high=1.0),
    }

    def kernel(self, cos_incidence, cos_view, cos_phase=None, wavelength=None):
        mu_i = np.asarray(cos_incidence, dtype=float)
        mu_o = np.asarray(cos_view, dtype=float)
        rho = self.parameter("reflectance", wavelength)
        # 0 below the horizon; NaN directions give NaN
        value = np.where((mu_i <= 0.0) | (mu_o <= 0.0), 0.0, np.asarray(rho) / np.pi + 0.0 * mu_i
                         * mu_o)
        shape = np.broadcast_shapes(value.shape, np.shape(cos_phase))
        return value if value.shape == shape else np.array(np.broadcast_to(value, shape))

    def _kernel(self, mu_i, mu_o, cos_g, wavelength):
        return np.asarray(self.parameter("reflectance", wavelength)) / np.pi + 0.0 * cos_g

    def _hemispherical(self, mu_i, wavelength):
        mu = np.asarray(mu_i, dtype=float)
        rho = np.asarray(self.parameter("reflectance", wavelength), dtype=float)
        rho = np.where(mu > 0.0, rho, 0.0)
        return rho, np.zeros_like(rho)
