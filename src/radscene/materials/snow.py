"""Snow: spectral reflectance of a deep snowpack from the optical constants of ice.

Model
-----
* 0.4-20 um, one rule: the reflectance is the larger of (a) the spherical (white-sky) albedo of
  a semi-infinite snowpack by the asymptotic radiative transfer (ART) of Kokhanovsky & Zege
  (2004) and (b) the Fresnel reflectance at normal incidence of a flat ice surface:

  .. math:: r = \\max\\left(e^{-\\sqrt{\\alpha \\ell}},\\ R_F(0)\\right), \\quad
            \\alpha = \\frac{4\\pi k}{\\lambda}, \\quad \\ell = \\frac{16 B d}{9 (1-g)}

  with k the imaginary index of ice (Warren & Brandt 2008), d the effective optical grain
  diameter, B = 1.6 the absorption enhancement and g = 0.75 the asymmetry parameter of
  irregular ice grains (Kokhanovsky & Zege 2004).
* ART holds where absorption is weak (visible and near infrared, r ≳ 0.3); in the strong ice
  bands (1.5, 2.0, 3 um) and the thermal infrared the snow reflects little more than the ice
  surface does, and (b) takes over. In 8-14 um the result, 1 − R_F, is the emissivity of a flat
  ice surface (0.99 at 10 um, 0.95 near 12.5 um); granular snow is measured somewhat more
  emissive near 12-13 um (cavity effect), so the model is a lower bound there.

References
----------
A. A. Kokhanovsky and E. P. Zege, "Scattering optics of snow", Appl. Opt. 43, 1589-1602 (2004),
doi:10.1364/AO.43.001589.
S. G. Warren and R. E. Brandt, "Optical constants of ice from the ultraviolet to the microwave:
a revised compilation", J. Geophys. Res. 113, D14220 (2008), doi:10.1029/2007JD009744
(``data/materials/sources/ice_nk_warren_brandt_2008.csv``).

Examples
--------
>>> r = snow_reflectance([0.5, 1.03, 10.0], grain_diameter=0.25e-3)
>>> bool(r[0] > 0.98 and 0.6 < r[1] < 0.85 and r[2] < 0.02)
True
"""

from __future__ import annotations

import functools
import math

import numpy as np

from radscene.errors import ConfigError

__all__ = ["ice_refractive_index", "snow_spherical_albedo", "snow_reflectance", "ICE_NK_SOURCE"]

#: Citation of the ice optical constants.
ICE_NK_SOURCE = (
    "S. G. Warren & R. E. Brandt, J. Geophys. Res. 113, D14220 (2008), doi:10.1029/2007JD009744 "
    "(sources/ice_nk_warren_brandt_2008.csv)"
)
#: Absorption enhancement parameter B of irregular ice grains (Kokhanovsky & Zege 2004) [-].
ABSORPTION_ENHANCEMENT = 1.6
#: Asymmetry parameter g of irregular ice grains (Kokhanovsky & Zege 2004) [-].
ASYMMETRY = 0.75


@functools.lru_cache(maxsize=1)
def _table():
    from radscene.materials.library import LIBRARY_DIR

    path = LIBRARY_DIR / "sources" / "ice_nk_warren_brandt_2008.csv"
    rows = [ln for ln in path.read_text(encoding="utf-8").splitlines() if ln.strip() and not ln.startswith("#")]
    data = np.array([[float(v) for v in ln.split(",")] for ln in rows[1:]])
    data.setflags(write=False)
    return data


def ice_refractive_index(wavelength):
    """Complex refractive index of ice at −7 °C (Warren & Brandt 2008), linear in wavelength.

    Parameters
    ----------
    wavelength : array_like
        [um], 0.39-20.4.

    Returns
    -------
    (numpy.ndarray, numpy.ndarray)
        n, k [-].

    Raises
    ------
    ConfigError
        Outside the table.
    """
    t = _table()
    wl = np.asarray(wavelength, dtype=float)
    outside = np.isfinite(wl) & ((wl < t[0, 0]) | (wl > t[-1, 0]))
    if np.any(outside):
        raise ConfigError(
            f"wavelength {wl[outside].flat[0]:g} µm is outside the ice table [{t[0, 0]:g}, "
            f"{t[-1, 0]:g}] µm",
            key="wavelength",
        )
    return np.interp(wl, t[:, 0], t[:, 1]), np.interp(wl, t[:, 0], t[:, 2])


def _grain(d):
    if not (isinstance(d, (int, float)) and math.isfinite(d) and d > 0):
        raise ConfigError(f"must be a number > 0 [m]; got {d!r}", key="grain_diameter")
    return float(d)


def snow_spherical_albedo(wavelength, grain_diameter: float = 0.25e-3):
    """Spherical albedo exp(−√(αℓ)) of a semi-infinite snowpack by ART [-].

    Parameters
    ----------
    wavelength : array_like
        [um].
    grain_diameter : float
        Effective optical grain diameter d [m] (fresh snow ~1e-4, old ~1e-3).

    Returns
    -------
    numpy.ndarray
    """
    d = _grain(grain_diameter)
    wl = np.asarray(wavelength, dtype=float)
    _, k = ice_refractive_index(wl)
    alpha = 4.0 * math.pi * k / (wl * 1e-6)
    ell = 16.0 * ABSORPTION_ENHANCEMENT * d / (9.0 * (1.0 - ASYMMETRY))
    return np.exp(-np.sqrt(alpha * ell))


def snow_reflectance(wavelength, grain_diameter: float = 0.25e-3):
    """Hemispherical reflectance of deep snow: max(ART spherical albedo, ice Fresnel R(0)) [-].

    Parameters
    ----------
    wavelength : array_like
        [um], 0.39-20.4.
    grain_diameter : float
        [m].

    Returns
    -------
    numpy.ndarray
    """
    from radscene.materials.water import fresnel_reflectance

    n, k = ice_refractive_index(wavelength)
    return np.maximum(snow_spherical_albedo(wavelength, grain_diameter), fresnel_reflectance(n, k))
