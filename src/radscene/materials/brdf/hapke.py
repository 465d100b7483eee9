"""Hapke's BRDF of particulate surfaces (regolith, soils, powders, snow-free sand).

A semi-infinite medium of particles with single-scattering albedo w and phase function p(g)
reflects (Hapke 1981; Hapke, *Theory of Reflectance and Emittance Spectroscopy*, ch. 10)

.. math::
    f = \\frac{w}{4\\pi}\\,\\frac{1}{\\mu_i + \\mu_o}
        \\left[\\bigl(1 + B(g)\\bigr)\\,p(g) + H(\\mu_i)\\,H(\\mu_o) - 1\\right]
        \\ [\\mathrm{sr^{-1}}],

single scattering by the phase function plus isotropic multiple scattering through
Chandrasekhar's H function, here in Hapke's (2002) approximation (error < 1 %):

.. math::
    H(x) \\approx \\left[1 - w\\,x\\left(r_0 + \\frac{1 - 2 r_0 x}{2}
    \\ln\\frac{1 + x}{x}\\right)\\right]^{-1},\\quad
    r_0 = \\frac{1 - \\gamma}{1 + \\gamma},\\quad \\gamma = \\sqrt{1 - w}.

p is a one-term Henyey–Greenstein function of asymmetry b (b < 0 backscatters; cos g = ω_i ·
ω_o, g the phase angle, the scattering angle is π − g):
:math:`p = (1 - b^2)/(1 + 2b\\cos g + b^2)^{3/2}`; the shadow-hiding opposition effect is
:math:`B(g) = B_0/(1 + \\tan(g/2)/h)` (Hapke 1986). The model is symmetric in ω_i and ω_o.
For isotropic scatterers without opposition effect the exact H gives ρ_dh = 1 − γ H(μ_i)
(Chandrasekhar 1960), which the tests use as the oracle; the approximation conserves energy to
about 1 %. Macroscopic roughness (Hapke 1984) is not included.

=======================  =====  =======  =================================================
parameter                unit   default  meaning
=======================  =====  =======  =================================================
single_scattering_albedo [-]    —        w in [0, 1] (spectrum)
asymmetry                [-]    0        b in (−1, 1), Henyey–Greenstein (spectrum)
opposition_amplitude     [-]    0        B_0 in [0, 1]
opposition_width         [-]    0.06     h > 0, angular width of the opposition surge
=======================  =====  =======  =================================================

Config snippet (lunar-like regolith): ``{type: hapke, single_scattering_albedo: 0.3,
asymmetry: -0.3, opposition_amplitude: 1.0, opposition_width: 0.06}``.

References
----------
B. Hapke, "Bidirectional reflectance spectroscopy: 1. Theory", J. Geophys. Res. 86(B4),
3039–3054 (1981), doi:10.1029/JB086iB04p03039.
B. Hapke, "Bidirectional reflectance spectroscopy: 4. The extinction coefficient and the
opposition effect", Icarus 67(2), 264–280 (1986), doi:10.1016/0019-1035(86)90108-9.
B. Hapke, "Bidirectional reflectance spectroscopy: 5. The coherent backscatter opposition
effect and anisotropic scattering", Icarus 157(2), 523–534 (2002),
doi:10.1006/icar.2002.6853.
S. Chandrasekhar, *Radiative Transfer*, Dover (1960), ch. V.
"""

from __future__ import annotations

import numpy as np

from radscene.materials.brdf.base import BRDF, Parameter

__all__ = ["Hapke", "h_function", "henyey_greenstein"]


def h_function(x, single_scattering_albedo) -> np.ndarray:
    """Hapke's (2002) approximation of Chandrasekhar's isotropic H function [-].

    Parameters
    ----------
    x : array_like
        Cosine μ in [0, 1] [-].
    single_scattering_albedo : array_like
        w in [0, 1] [-].

    Returns
    -------
    numpy.ndarray
        H(x) ≥ 1 [-]; H(0) = 1.

    Examples
    --------
    >>> round(float(h_function(1.0, 1.0)), 3)   # exact (Chandrasekhar): 2.908
    2.885
    """
    x = np.asarray(x, dtype=float)
    w = np.asarray(single_scattering_albedo, dtype=float)
    gamma = np.sqrt(1.0 - w)
    r0 = (1.0 - gamma) / (1.0 + gamma)
    with np.errstate(divide="ignore", invalid="ignore"):
        log_term = np.where(x > 0.0, np.log1p(1.0 / np.where(x > 0.0, x, 1.0)), 0.0)
        inner = r0 + 0.5 * (1.0 - 2.0 * r0 * x) * log_term
    return 1.0 / (1.0 - w * x * inner)


def henyey_greenstein(cos_g, asymmetry) -> np.ndarray:
    """Henyey–Greenstein phase function of the phase angle g, normalised to 4π [-].

    ``asymmetry`` > 0 scatters forward (towards g = π), < 0 backward (towards g = 0).
    """
    b = np.asarray(asymmetry, dtype=float)
    d = 1.0 + 2.0 * b * np.asarray(cos_g, dtype=float) + b * b
    return (1.0 - b * b) / (d * np.sqrt(d))


class Hapke(BRDF):
    """Hapke BRDF (module docstring).

    Examples
    --------
    >>> soil = Hapke(single_scattering_albedo=0.6, asymmetry=-0.2)
    >>> 0.0 < float(soil.albedo([0.0, 0.0, 1.0])) < 1.0
    True
    """

    name = "hapke"
    PARAMETERS = {
        "single_scattering_albedo": Parameter("-", "w, particle single-scattering albedo",
                                              kind="spectrum", low=0.0, high=1.0),
        "asymmetry": Parameter("-", "Henyey-Greenstein asymmetry b (<0 backscatter)", 0.0,
                               kind="spectrum", low=-1.0, high=1.0, low_open=True,
                               high_open=True),
        "opposition_amplitude": Parameter("-", "B_0, amplitude of the opposition surge", 0.0,
                                          low=0.0, high=1.0),
        "opposition_width": Parameter("-", "h, angular width of the opposition surge", 0.06,
                                      low=0.0, low_open=True),
    }

    def _kernel(self, mu_i, mu_o, cos_g, wavelength):
        w = self.parameter("single_scattering_albedo", wavelength)
        b = self.parameter("asymmetry", wavelength)
        b0 = self.parameter("opposition_amplitude")
        h = self.parameter("opposition_width")
        # tan(g/2) = sqrt((1 - cos g) / (1 + cos g))
        tan_half = np.sqrt(np.maximum(1.0 - cos_g, 0.0) / np.maximum(1.0 + cos_g, 1e-300))
        surge = b0 / (1.0 + tan_half / h)
        multiple = h_function(mu_i, w) * h_function(mu_o, w) - 1.0
        return (w / (4.0 * np.pi)) * ((1.0 + surge) * henyey_greenstein(cos_g, b)
                                      + multiple) / (mu_i + mu_o)
