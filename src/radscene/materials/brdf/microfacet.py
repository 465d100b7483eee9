"""Microfacet BRDFs (Cook–Torrance form) with the GGX and Beckmann distributions and Fresnel.

A rough surface is a field of mirror facets whose normals h are distributed as D(h). Light
reflected from ω_i into ω_o comes from the facets with h along the half vector
:math:`\\mathbf h = (\\omega_i + \\omega_o)/|\\omega_i + \\omega_o|`, so (Walter et al. 2007)

.. math::
    f(\\omega_i, \\omega_o) = \\frac{F(\\omega_i\\cdot\\mathbf h)\\,D(\\mathbf h)\\,
    G_2(\\omega_i, \\omega_o)}{4\\,\\mu_i\\,\\mu_o},

with F the Fresnel reflectance of the facet material (:mod:`.fresnel`; dielectric for k = 0,
absorbing dielectric or conductor for k > 0) and :math:`G_2 = 1/(1 + \\Lambda(\\mu_i) +
\\Lambda(\\mu_o))` Smith's height-correlated masking–shadowing function (Heitz 2014).
In terms of the invariants: :math:`|\\omega_i + \\omega_o| = \\sqrt{2 + 2\\cos g}`,
:math:`\\cos\\theta_h = (\\mu_i + \\mu_o)/\\sqrt{2 + 2\\cos g}`,
:math:`\\omega_i\\cdot\\mathbf h = \\sqrt{(1 + \\cos g)/2}`.

GGX (Trowbridge–Reitz; Walter et al. 2007):

.. math:: D = \\frac{\\alpha^2}{\\pi\\,(\\cos^2\\theta_h(\\alpha^2 - 1) + 1)^2},\\qquad
          \\Lambda(\\mu) = \\frac{-1 + \\sqrt{1 + \\alpha^2\\tan^2\\theta}}{2}.

Beckmann (Walter et al. 2007):

.. math:: D = \\frac{\\exp(-\\tan^2\\theta_h/\\alpha^2)}{\\pi\\alpha^2\\cos^4\\theta_h},\\qquad
          \\Lambda(\\mu) = \\frac{\\operatorname{erf}(a) - 1}{2}
          + \\frac{e^{-a^2}}{2a\\sqrt\\pi},\\quad a = \\frac{1}{\\alpha\\tan\\theta},

α being the RMS facet slope times √2 (Beckmann) or the GGX width. The model is single
scattering: light reflected more than once among the facets is not counted, so ρ_dh falls a
little short of F at large roughness and grazing incidence (≤ ~10 % at α = 0.5), and the
emissivity 1 − ρ_dh is correspondingly a little high there.

Sampling draws h with density D(h) cos θ_h and reflects ω_o about it; the density of
ω_i is :math:`D(\\mathbf h)\\,|\\cos\\theta_h| / (4\\,|\\omega_o\\cdot\\mathbf h|)` (Walter et al.
2007), with h the half vector oriented into the upper hemisphere.

=======================  =====  =======  ===================================================
parameter                unit   default  meaning
=======================  =====  =======  ===================================================
roughness                [-]    —        α > 0 (≈ 0.01 polished … 0.5 very rough)
refractive_index         [-]    —        n > 0 of the facet material (spectrum)
extinction_coefficient   [-]    0        k ≥ 0 (spectrum): 0 for a clear dielectric
=======================  =====  =======  ===================================================

Config snippets: ``{type: ggx, roughness: 0.2, refractive_index: 1.5}`` (glossy glass or
plastic coat); ``{type: beckmann, roughness: 0.1, refractive_index: 0.96,
extinction_coefficient: 6.69}`` (aluminium at 0.55 µm).

References
----------
B. Walter, S. R. Marschner, H. Li, K. E. Torrance, "Microfacet models for refraction through
rough surfaces", Proc. EGSR 2007, 195–206, doi:10.2312/EGWR/EGSR07/195-206.
E. Heitz, "Understanding the masking-shadowing function in microfacet-based BRDFs", J. Comput.
Graph. Tech. 3(2), 48–107 (2014), https://jcgt.org/published/0003/02/03/.
R. L. Cook, K. E. Torrance, "A reflectance model for computer graphics", ACM Trans. Graph.
1(1), 7–24 (1982), doi:10.1145/357290.357293.
"""

from __future__ import annotations

import numpy as np
from scipy.special import erf

from radscene.materials.brdf.base import BRDF, Parameter
from radscene.materials.brdf.fresnel import fresnel_reflectance

__all__ = ["Microfacet", "GGX", "Beckmann", "ggx_distribution", "beckmann_distribution",
           "ggx_lambda", "beckmann_lambda"]

_SQRT_PI = np.sqrt(np.pi)


def ggx_distribution(cos_h, alpha) -> np.ndarray:
    """GGX normal distribution D(h) [sr-1] (projected area normalised: ∫ D cos θ_h dω = 1)."""
    c2 = np.asarray(cos_h, dtype=float) ** 2
    a2 = np.asarray(alpha, dtype=float) ** 2
    denom = c2 * (a2 - 1.0) + 1.0
    return np.where(cos_h > 0.0, a2 / (np.pi * denom * denom), 0.0)


def beckmann_distribution(cos_h, alpha) -> np.ndarray:
    """Beckmann normal distribution D(h) [sr-1] (∫ D cos θ_h dω = 1)."""
    c = np.asarray(cos_h, dtype=float)
    a2 = np.asarray(alpha, dtype=float) ** 2
    c2 = np.where(c > 0.0, c * c, 1.0)
    tan2 = (1.0 - c2) / c2
    return np.where(c > 0.0, np.exp(-tan2 / a2) / (np.pi * a2 * c2 * c2), 0.0)


def ggx_lambda(mu, alpha) -> np.ndarray:
    """Smith Λ(μ) of GGX [-] (0 at normal incidence, → ∞ at grazing)."""
    m2 = np.asarray(mu, dtype=float) ** 2
    tan2 = (1.0 - m2) / m2
    return 0.5 * (np.sqrt(1.0 + np.asarray(alpha, dtype=float) ** 2 * tan2) - 1.0)


def beckmann_lambda(mu, alpha) -> np.ndarray:
    """Smith Λ(μ) of Beckmann [-]."""
    m = np.asarray(mu, dtype=float)
    tan = np.sqrt(np.maximum(1.0 - m * m, 0.0)) / m
    with np.errstate(divide="ignore", invalid="ignore"):
        a = 1.0 / (np.asarray(alpha, dtype=float) * tan)
        value = 0.5 * (erf(a) - 1.0) + np.exp(-a * a) / (2.0 * a * _SQRT_PI)
    return np.where(np.isfinite(a), value, 0.0)


class Microfacet(BRDF):
    """Cook–Torrance microfacet reflector (module docstring); subclasses set the distribution."""

    PARAMETERS = {
        "roughness": Parameter("-", "alpha, facet slope width", low=0.0, low_open=True),
        "refractive_index": Parameter("-", "n of the facet material", kind="spectrum",
                                      low=0.0, low_open=True),
        "extinction_coefficient": Parameter("-", "k of the facet material (0: dielectric)", 0.0,
                                            kind="spectrum", low=0.0),
    }
    albedo_rule = "sampling"

    # --- distribution hooks
    def _alpha(self) -> float:
        return self.parameter("roughness")

    def distribution(self, cos_h) -> np.ndarray:  # pragma: no cover - abstract
        """D(h) [sr-1] for the cosine of the facet normal's zenith."""
        raise NotImplementedError

    def smith_lambda(self, mu) -> np.ndarray:  # pragma: no cover - abstract
        """Smith Λ(μ) [-]."""
        raise NotImplementedError

    def _sample_tan2(self, u) -> np.ndarray:  # pragma: no cover - abstract
        """tan² θ_h of facet normals drawn with density D cos θ_h."""
        raise NotImplementedError

    def fresnel(self, cos_d, wavelength=None) -> np.ndarray:
        """Fresnel reflectance of the facet material at cos θ_d = ω_i · h [-]."""
        return fresnel_reflectance(cos_d, self.parameter("refractive_index", wavelength),
                                   self.parameter("extinction_coefficient", wavelength))

    # --- model
    def _kernel(self, mu_i, mu_o, cos_g, wavelength):
        s = np.maximum(2.0 + 2.0 * cos_g, 1e-300)
        cos_h = (mu_i + mu_o) / np.sqrt(s)
        cos_d = np.sqrt(0.25 * s)
        g2 = 1.0 / (1.0 + self.smith_lambda(mu_i) + self.smith_lambda(mu_o))
        return self.fresnel(cos_d, wavelength) * self.distribution(cos_h) * g2 / (
            4.0 * mu_i * mu_o)

    def _sample_local(self, wo, u1, u2, wavelength):
        tan2 = self._sample_tan2(u1)
        cos_h = 1.0 / np.sqrt(1.0 + tan2)
        sin_h = np.sqrt(np.maximum(1.0 - cos_h * cos_h, 0.0))
        phi = 2.0 * np.pi * u2
        h = np.stack([sin_h * np.cos(phi), sin_h * np.sin(phi), cos_h], axis=-1)
        d = np.sum(wo * h, axis=-1, keepdims=True)
        return 2.0 * d * h - wo

    def _pdf(self, mu_o, mu_i, cos_g, wavelength):
        s = 2.0 + 2.0 * cos_g
        ok = s > 1e-12
        s = np.where(ok, s, 1.0)
        cos_h = np.abs(mu_i + mu_o) / np.sqrt(s)
        cos_d = np.sqrt(0.25 * s)
        return np.where(ok, self.distribution(cos_h) * cos_h / (4.0 * cos_d), 0.0)


class GGX(Microfacet):
    """Microfacet BRDF with the GGX (Trowbridge–Reitz) distribution.

    Examples
    --------
    >>> m = GGX(roughness=0.3, refractive_index=1.5)
    >>> rho = m.albedo([0.0, 0.0, 1.0])
    >>> 0.035 < float(rho) < 0.04   # Fresnel 0.04, less a little single-scattering loss
    True
    """

    name = "ggx"

    def distribution(self, cos_h):
        return ggx_distribution(cos_h, self._alpha())

    def smith_lambda(self, mu):
        return ggx_lambda(mu, self._alpha())

    def _sample_tan2(self, u):
        # P(tan^2 <= x) = x / (a^2 + x)  for density D cos
        u = np.minimum(u, 1.0 - 1e-16)
        return self._alpha() ** 2 * u / (1.0 - u)


class Beckmann(Microfacet):
    """Microfacet BRDF with the Beckmann (Gaussian slope) distribution.

    Examples
    --------
    >>> m = Beckmann(roughness=0.05, refractive_index=0.96, extinction_coefficient=6.69)
    >>> round(float(m.albedo([0.0, 0.0, 1.0])), 2)   # aluminium at 0.55 um: R(0) = 0.916
    0.92
    """

    name = "beckmann"

    def distribution(self, cos_h):
        return beckmann_distribution(cos_h, self._alpha())

    def smith_lambda(self, mu):
        return beckmann_lambda(mu, self._alpha())

    def _sample_tan2(self, u):
        # P(tan^2 <= x) = 1 - exp(-x / a^2)
        return -self._alpha() ** 2 * np.log1p(-np.minimum(u, 1.0 - 1e-16))

