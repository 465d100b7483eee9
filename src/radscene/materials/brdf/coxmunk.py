"""Wind-roughened water surface of Cox & Munk (1954) with Fresnel reflection: the sun glint.

Cox & Munk measured, from photographs of the sun glitter, that the slopes (z_x, z_y) of the sea
surface are nearly Gaussian with a mean-square slope that grows linearly with the wind speed W
measured 12.5 m (41 ft) above the sea (clean surface; the sum of the upwind and crosswind variances σ_u² + σ_c²):

.. math:: \\sigma^2 = 0.003 + 5.12\\times10^{-3}\\,W\\ [\\mathrm{m\\,s^{-1}}]\\quad(\\pm 0.004).

With the isotropic Gaussian slope density :math:`p(z_x, z_y) = \\exp(-\\tan^2\\theta_h/\\sigma^2)
/(\\pi\\sigma^2)` the facet-normal distribution is :math:`D(\\mathbf h) = p/\\cos^4\\theta_h`,
which is the Beckmann distribution with α² = σ² (:mod:`.microfacet`). The glint BRDF is then
the microfacet form

.. math:: f = \\frac{F(\\omega_i\\cdot\\mathbf h)\\,p(\\tan\\theta_h)}
               {4\\,\\mu_i\\,\\mu_o\\,\\cos^4\\theta_h}\\,G_2,

the form used by 6S and libRadtran's ``cox_and_munk`` (Nakajima & Tanaka 1983) with Smith's
shadowing G₂ of Beckmann facets, and F the Fresnel reflectance of water (complex index n + ik).
Its directional emissivity 1 − ρ_dh follows 1 − F(θ) of a flat surface at small winds — about
0.99 at nadir in 8–12 µm, falling toward grazing angles — and roughness flattens the fall at
grazing view. Light reflected twice between waves and the whitecaps and water-leaving radiance
are not included (they can be added as a diffuse material).

The slope distribution is taken isotropic (upwind and crosswind variances summed); the
anisotropy and the Gram–Charlier skewness and peakedness terms are neglected.

=======================  ========  =======  ==================================================
parameter                unit      default  meaning
=======================  ========  =======  ==================================================
wind_speed               [m s-1]   —        W ≥ 0 at 12.5 m above the surface
mean_square_slope        [-]       —        σ² > 0 itself, instead of ``wind_speed``
refractive_index         [-]       water    n (spectrum); default liquid water (below)
extinction_coefficient   [-]       water    k (spectrum); default 0 if n is given, else water
=======================  ========  =======  ==================================================

Without ``refractive_index`` the surface is liquid water with Hale & Querry's (1973) n and k,
0.4–20 µm (:func:`radscene.materials.water.water_refractive_index`); a wavelength is then
needed at every evaluation. Exactly one of ``wind_speed`` and ``mean_square_slope`` is given:
the latter sets σ² directly, e.g. the slope variance of the waves shorter than a resolved sea
surface's mesh (:mod:`radscene.geometry.sea`). Config snippets: ``{type: coxmunk, wind_speed: 5}`` (water);
``{type: coxmunk, wind_speed: 5, refractive_index: 1.34}`` (grey, visible).

References
----------
C. Cox, W. Munk, "Measurement of the roughness of the sea surface from photographs of the sun's
glitter", J. Opt. Soc. Am. 44(11), 838–850 (1954), doi:10.1364/JOSA.44.000838.
T. Nakajima, M. Tanaka, "Effect of wind-generated waves on the transfer of solar radiation in
the atmosphere-ocean system", J. Quant. Spectrosc. Radiat. Transfer 29(6), 521–537 (1983),
doi:10.1016/0022-4073(83)90129-2.
G. M. Hale, M. R. Querry, "Optical constants of water in the 200-nm to 200-µm wavelength
region", Appl. Opt. 12(3), 555–563 (1973), doi:10.1364/AO.12.000555.
"""

from __future__ import annotations

import numpy as np

from radscene.errors import ConfigError
from radscene.materials.brdf.base import Parameter
from radscene.materials.brdf.fresnel import fresnel_reflectance
from radscene.materials.brdf.microfacet import Beckmann

__all__ = ["CoxMunk", "mean_square_slope"]

#: Cox & Munk (1954) clean-surface mean-square slope: σ² = a + b W.
SLOPE_VARIANCE_OFFSET = 0.003
#: [s m-1]
SLOPE_VARIANCE_PER_WIND = 5.12e-3


def mean_square_slope(wind_speed) -> np.ndarray:
    """Cox & Munk (1954) mean-square slope σ² of a clean sea surface [-].

    Parameters
    ----------
    wind_speed : array_like
        Wind speed 12.5 m above the sea [m s-1].

    Returns
    -------
    numpy.ndarray
        σ² = 0.003 + 5.12e-3 W [-].

    Examples
    --------
    >>> round(float(mean_square_slope(10.0)), 6)
    0.0542
    """
    return np.asarray(SLOPE_VARIANCE_OFFSET + SLOPE_VARIANCE_PER_WIND
                      * np.asarray(wind_speed, dtype=float))


class CoxMunk(Beckmann):
    """Cox–Munk wind-roughened water with Fresnel reflection (module docstring).

    Examples
    --------
    >>> sea = CoxMunk(wind_speed=5.0)
    >>> round(float(sea.emissivity([0.0, 0.0, 1.0], wavelength=10.0)), 3)   # nadir
    0.99
    """

    name = "coxmunk"
    PARAMETERS = {
        "wind_speed": Parameter("m s-1", "wind speed at 12.5 m", None, low=0.0),
        "mean_square_slope": Parameter("-", "sigma^2 itself, instead of wind_speed", None,
                                       low=0.0, low_open=True),
        "refractive_index": Parameter("-", "n (default: liquid water, Hale & Querry 1973)",
                                      None, kind="spectrum", low=0.0, low_open=True),
        "extinction_coefficient": Parameter("-", "k (default: 0 if n is given, else water)",
                                            None, kind="spectrum", low=0.0),
    }

    def _check(self):
        given = [p for p in ("wind_speed", "mean_square_slope") if self.parameter(p) is not None]
        if len(given) != 1:
            raise ConfigError("give exactly one of wind_speed [m s-1] and mean_square_slope [-]"
                              + (f"; got {' and '.join(given)}" if given else ""),
                              key=f"{self.key}.wind_speed")
        if self.parameter("refractive_index") is None and (
                self.parameter("extinction_coefficient") is not None):
            raise ConfigError("extinction_coefficient needs refractive_index (without both, "
                              "the surface is water)", key=f"{self.key}.extinction_coefficient")

    def _alpha(self) -> float:
        sigma2 = self.parameter("mean_square_slope")
        if sigma2 is None:
            sigma2 = mean_square_slope(self.parameter("wind_speed"))
        return float(np.sqrt(sigma2))

    def fresnel(self, cos_d, wavelength=None):
        if self.parameter("refractive_index") is not None:
            k = self.parameter("extinction_coefficient", wavelength)
            return fresnel_reflectance(cos_d, self.parameter("refractive_index", wavelength),
                                       0.0 if k is None else k)
        if wavelength is None:
            raise ConfigError("the Cox-Munk water surface needs a wavelength [µm] (its "
                              "refractive index varies with it)", key=f"{self.key}.wavelength")
        from radscene.materials.water import water_refractive_index

        n, k = water_refractive_index(wavelength)
        return fresnel_reflectance(cos_d, n, k)
