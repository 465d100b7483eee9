"""Water: Fresnel reflection from a spectral complex refractive index, absorption, emissivity.

Data
----
Complex refractive index m = n + ik of liquid water at 25 °C, 0.4-20 um: G. M. Hale and
M. R. Querry, "Optical constants of water in the 200-nm to 200-um wavelength region", Appl.
Opt. 12, 555-563 (1973), doi:10.1364/AO.12.000555, Table 1 (via the public-domain
refractiveindex.info database; ``data/materials/sources/water_nk_hale_querry_1973.csv``),
interpolated linearly in wavelength. Hale & Querry's k below 0.7 um (~1e-9) is a compilation of
older measurements and is high by up to ~9x near 0.4 um compared with Pope & Fry (1997); pass
your own absorption coefficient where the blue matters.

Physics
-------
* Fresnel reflectance of a smooth interface air → water, unpolarised (:func:`fresnel_reflectance`):

  .. math:: r_s = \\frac{\\cos\\theta - \\sqrt{m^2-\\sin^2\\theta}}{\\cos\\theta + \\sqrt{m^2-\\sin^2\\theta}},\\quad
            r_p = \\frac{m^2\\cos\\theta - \\sqrt{m^2-\\sin^2\\theta}}{m^2\\cos\\theta + \\sqrt{m^2-\\sin^2\\theta}},\\quad
            R = \\tfrac12(|r_s|^2 + |r_p|^2)

* Directional emissivity of optically deep (opaque) calm water by Kirchhoff's law,
  ε(θ, λ) = 1 − R(θ, λ): 0.98-0.99 at nadir in 8-12 um, falling towards grazing angles.
* Absorption coefficient a = 4πk/λ [m-1]; transmittance of a path of length d, exp(−a d).
* Diffuse (water-leaving) reflectance of deep water from its absorption a and backscattering
  b_b: below the surface R = f b_b / (a + b_b), f = 0.33 (Morel & Prieur 1977); with
  r_rs = R/π (isotropic upwelling radiance) the above-surface remote-sensing reflectance is
  R_rs = 0.52 r_rs / (1 − 1.7 r_rs) (Lee et al. 2002), and the equivalent Lambertian
  reflectance π R_rs. Pure-seawater backscattering by default: b_b = b/2,
  b = 0.00288 (λ/0.5 um)^−4.32 m-1 (Morel 1974).

References
----------
A. Morel, "Optical properties of pure water and pure sea water", in Optical Aspects of
Oceanography, N. G. Jerlov and E. S. Nielsen (eds.), Academic Press, 1-24 (1974).
A. Morel and L. Prieur, "Analysis of variations in ocean color", Limnol. Oceanogr. 22,
709-722 (1977), doi:10.4319/lo.1977.22.4.0709.
Z. Lee, K. L. Carder, R. A. Arnone, "Deriving inherent optical properties from water color: a
multiband quasi-analytical algorithm for optically deep waters", Appl. Opt. 41, 5755-5772
(2002), doi:10.1364/AO.41.005755.
M. Born and E. Wolf, Principles of Optics, 7th ed., Sec. 14.2 (Fresnel formulae for absorbing
media).

Examples
--------
>>> round(float(water_emissivity(10.0, 0.0)), 3)
0.99
>>> bool(water_emissivity(10.0, 80.0) < water_emissivity(10.0, 0.0))
True
"""

from __future__ import annotations

import functools
import math

import numpy as np

from radscene.errors import ConfigError

__all__ = [
    "fresnel_reflectance",
    "fresnel_reflectance_polarised",
    "hemispherical_fresnel_reflectance",
    "water_refractive_index",
    "water_absorption_coefficient",
    "water_transmittance",
    "water_reflectance",
    "water_emissivity",
    "water_hemispherical_emissivity",
    "pure_seawater_backscattering",
    "deep_water_diffuse_reflectance",
    "water_material",
    "WATER_NK_SOURCE",
]

#: Citation of the refractive-index table.
WATER_NK_SOURCE = (
    "G. M. Hale & M. R. Querry, Appl. Opt. 12, 555-563 (1973), doi:10.1364/AO.12.000555 "
    "(sources/water_nk_hale_querry_1973.csv)"
)

#: f of R = f b_b / (a + b_b) (Morel & Prieur 1977) [-].
MOREL_PRIEUR_F = 0.33


def _angle(value, key: str) -> np.ndarray:
    a = np.asarray(value, dtype=float)
    bad = np.isfinite(a) & ((a < 0.0) | (a > 90.0))
    if np.any(bad):
        raise ConfigError(f"must be in [0, 90] degrees; got {a[bad].flat[0]:g}", key=key)
    return a


def _index(n, k) -> np.ndarray:
    n = np.asarray(n, dtype=float)
    k = np.asarray(k, dtype=float)
    if np.any(n <= 0.0) or np.any(k < 0.0):
        raise ConfigError("refractive index needs n > 0 and k >= 0", key="refractive_index")
    return n + 1j * k


def fresnel_reflectance_polarised(n, k, incidence_angle):
    """Reflectances for s and p polarisation of a smooth interface from vacuum/air.

    Parameters
    ----------
    n, k : array_like
        Real and imaginary parts of the complex refractive index m = n + ik of the medium
        (n > 0, k ≥ 0) [-].
    incidence_angle : array_like
        Angle of incidence from the surface normal [deg], in [0, 90].

    Returns
    -------
    (numpy.ndarray, numpy.ndarray)
        R_s, R_p [-], broadcast shape of the inputs.
    """
    m = _index(n, k)
    theta = np.deg2rad(_angle(incidence_angle, "incidence_angle"))
    cos_t = np.cos(theta)
    sin2 = np.sin(theta) ** 2
    root = np.sqrt(m * m - sin2 + 0j)  # m cos(theta_t); principal root, Re >= 0 and Im >= 0
    with np.errstate(invalid="ignore"):  # NaN angles give NaN, quietly
        rs = (cos_t - root) / (cos_t + root)
        rp = (m * m * cos_t - root) / (m * m * cos_t + root)
    return np.abs(rs) ** 2, np.abs(rp) ** 2


def fresnel_reflectance(n, k, incidence_angle=0.0):
    """Unpolarised Fresnel reflectance of a smooth interface from air to a medium n + ik.

    Parameters
    ----------
    n, k : array_like
        Complex refractive index of the medium [-] (n > 0, k ≥ 0).
    incidence_angle : array_like, optional
        Angle of incidence [deg], 0 (normal) to 90 (grazing); default 0.

    Returns
    -------
    numpy.ndarray
        R = (R_s + R_p)/2 [-]; at normal incidence ((n−1)² + k²)/((n+1)² + k²).

    Examples
    --------
    >>> round(float(fresnel_reflectance(1.5, 0.0)), 4)
    0.04
    >>> round(float(fresnel_reflectance(1.5, 0.0, 90.0)), 12)
    1.0
    """
    rs, rp = fresnel_reflectance_polarised(n, k, incidence_angle)
    return 0.5 * (rs + rp)


#: Gauss-Legendre rule on cos θ in [0, 1] for hemispherical integrals.
_GL_X, _GL_W = np.polynomial.legendre.leggauss(64)
_MU = 0.5 * (_GL_X + 1.0)
_MU_W = 0.5 * _GL_W


def hemispherical_fresnel_reflectance(n, k):
    """Fresnel reflectance averaged over a hemisphere of diffuse (cosine-weighted) incidence.

    .. math:: \\bar R = 2 \\int_0^1 R(\\mu)\\,\\mu\\,d\\mu

    Parameters
    ----------
    n, k : array_like
        Complex refractive index [-].

    Returns
    -------
    numpy.ndarray
        [-], shape of broadcast(n, k). 64-point Gauss-Legendre quadrature in μ = cos θ.
    """
    n = np.asarray(n, dtype=float)[..., None]
    k = np.asarray(k, dtype=float)[..., None]
    angles = np.rad2deg(np.arccos(_MU))
    r = fresnel_reflectance(n, k, angles)
    return np.sum(r * 2.0 * _MU * _MU_W, axis=-1)


@functools.lru_cache(maxsize=1)
def _nk_table():
    from radscene.materials.library import LIBRARY_DIR

    path = LIBRARY_DIR / "sources" / "water_nk_hale_querry_1973.csv"
    rows = [
        ln for ln in path.read_text(encoding="utf-8").splitlines()
        if ln.strip() and not ln.startswith("#")
    ]
    data = np.array([[float(v) for v in ln.split(",")] for ln in rows[1:]])
    data.setflags(write=False)
    return data


def water_refractive_index(wavelength):
    """Complex refractive index of liquid water (Hale & Querry 1973), linear in wavelength.

    Parameters
    ----------
    wavelength : array_like
        [um], within 0.4-20.

    Returns
    -------
    (numpy.ndarray, numpy.ndarray)
        n, k [-], shape of ``wavelength``.

    Raises
    ------
    ConfigError
        A wavelength outside the table (no extrapolation).
    """
    table = _nk_table()
    wl = np.asarray(wavelength, dtype=float)
    lo, hi = table[0, 0], table[-1, 0]
    outside = np.isfinite(wl) & ((wl < lo) | (wl > hi))
    if np.any(outside):
        raise ConfigError(
            f"wavelength {wl[outside].flat[0]:g} µm is outside the Hale & Querry table "
            f"[{lo:g}, {hi:g}] µm",
            key="wavelength",
        )
    return np.interp(wl, table[:, 0], table[:, 1]), np.interp(wl, table[:, 0], table[:, 2])


def water_absorption_coefficient(wavelength, k=None):
    """Bulk absorption coefficient a = 4πk/λ of water [m-1].

    Parameters
    ----------
    wavelength : array_like
        [um].
    k : array_like, optional
        Imaginary index [-]; default Hale & Querry (1973).

    Returns
    -------
    numpy.ndarray
        [m-1]; with Hale & Querry about 0.045 m-1 at 0.55 um, 36 m-1 at 1.0 um and
        1.1e6 m-1 at 3.0 um.
    """
    wl = np.asarray(wavelength, dtype=float)
    if k is None:
        _, k = water_refractive_index(wl)
    return 4.0 * math.pi * np.asarray(k, dtype=float) / (wl * 1e-6)


def water_transmittance(wavelength, path_length):
    """Beer-Lambert transmittance exp(−a d) of a water path [-].

    Parameters
    ----------
    wavelength : array_like
        [um].
    path_length : array_like
        d ≥ 0 [m].

    Returns
    -------
    numpy.ndarray
        Broadcast shape [-].
    """
    d = np.asarray(path_length, dtype=float)
    if np.any(d < 0):
        raise ConfigError("path_length must be >= 0 m", key="path_length")
    return np.exp(-water_absorption_coefficient(wavelength) * d)


def water_reflectance(wavelength, incidence_angle=0.0):
    """Fresnel reflectance of a calm water surface [-] (Hale & Querry index)."""
    n, k = water_refractive_index(wavelength)
    return fresnel_reflectance(n, k, incidence_angle)


def water_emissivity(wavelength, view_zenith=0.0):
    """Directional emissivity of calm, optically deep water, ε = 1 − R(θ) [-].

    Parameters
    ----------
    wavelength : array_like
        [um], 0.4-20.
    view_zenith : array_like, optional
        Emission angle from the surface normal [deg]; default 0 (nadir).

    Returns
    -------
    numpy.ndarray
        Broadcast shape [-]: 0.98-0.99 at nadir over 8-12 um, → 0 at 90°.
    """
    return 1.0 - water_reflectance(wavelength, view_zenith)


def water_hemispherical_emissivity(wavelength):
    """Hemispherical emissivity of calm deep water, 1 − R̄ (cosine-weighted Fresnel) [-]."""
    n, k = water_refractive_index(wavelength)
    return 1.0 - hemispherical_fresnel_reflectance(n, k)


def pure_seawater_backscattering(wavelength):
    """Backscattering coefficient of pure seawater, b_b = 0.00144 (λ/0.5 um)^−4.32 [m-1] (Morel 1974)."""
    wl = np.asarray(wavelength, dtype=float)
    return 0.5 * 0.00288 * (wl / 0.5) ** -4.32


def deep_water_diffuse_reflectance(wavelength, absorption=None, backscattering=None):
    """Equivalent Lambertian water-leaving reflectance of optically deep water [-].

    Parameters
    ----------
    wavelength : array_like
        [um].
    absorption : array_like, optional
        Total absorption coefficient a [m-1]; default pure water (Hale & Querry k).
    backscattering : array_like, optional
        Total backscattering coefficient b_b [m-1]; default pure seawater (Morel 1974).

    Returns
    -------
    numpy.ndarray
        π R_rs with R_rs = 0.52 r_rs/(1 − 1.7 r_rs), r_rs = f b_b/(a + b_b)/π, f = 0.33 [-].
    """
    wl = np.asarray(wavelength, dtype=float)
    a = water_absorption_coefficient(wl) if absorption is None else np.asarray(absorption, float)
    bb = pure_seawater_backscattering(wl) if backscattering is None else np.asarray(backscattering, float)
    if np.any(a < 0) or np.any(bb < 0):
        raise ConfigError("absorption and backscattering must be >= 0 m-1", key="water")
    r_below = MOREL_PRIEUR_F * bb / (a + bb)
    rrs_below = r_below / math.pi
    rrs = 0.52 * rrs_below / (1.0 - 1.7 * rrs_below)
    return math.pi * rrs


def water_material(
    wavelength=None,
    *,
    name: str = "water",
    diffuse_reflectance=0.0,
    specular_exponent: float = 300.0,
):
    """A calm deep-water :class:`~radscene.materials.Material`: Fresnel ρ_s at normal incidence.

    Parameters
    ----------
    wavelength : array_like, optional
        Grid [um]; default the Hale & Querry wavelengths in 0.4-20 um.
    name : str, optional
    diffuse_reflectance : spectrum-like, optional
        Water-leaving (Lambertian) part ρ_d [-], e.g. :func:`deep_water_diffuse_reflectance`
        values as ``{"wavelength": ..., "values": ...}``; default 0.
    specular_exponent : float, optional
        Phong exponent of the glint lobe [-].

    Returns
    -------
    Material
        ε = 1 − ρ_s − ρ_d (normal-incidence values; :func:`water_emissivity` gives the
        directional ones).
    """
    from radscene.materials.material import Material
    from radscene.materials.spectrum import Spectrum, linear_combination, make_spectrum

    table = _nk_table()
    wl = table[:, 0] if wavelength is None else np.asarray(wavelength, dtype=float)
    rho_s = Spectrum.from_table(
        wl, water_reflectance(wl), name=f"{name}.specular_reflectance", source=WATER_NK_SOURCE
    )
    rho_d = make_spectrum(diffuse_reflectance, key=f"{name}.diffuse_reflectance")
    total = linear_combination([(1.0, rho_s), (1.0, rho_d)], name=f"{name}.reflectance")
    return Material.create(
        name,
        reflectance=total,
        specular_reflectance=rho_s,
        specular_exponent=specular_exponent,
        source=f"Fresnel reflectance at normal incidence from {WATER_NK_SOURCE}",
        description="calm, optically deep water",
        category="water",
    )
