"""Band quadrature and the spectral coefficient tables of the spectral–spatial separation.

For every band the renderer builds one quadrature rule — nodes λ_i [um] and weights w_i [um]
that already contain the sensor response S(λ_i) — whose sub-intervals start and end at every
breakpoint of every tabulated spectrum that enters the integral (response, solar spectrum,
material spectra, atmosphere tables). Each sub-interval gets Gauss–Legendre nodes, so the band
integral of a product of piecewise-linear tables and smooth functions (Planck) is exact to
rounding: this is what makes the band terms noiseless.

With that rule, every spectral factor of a signature term is integrated once per material ×
band × atmospheric node (:class:`BandCoefficients`); the per-pixel work is then a few
multiply-adds of geometry scalars (ARCHITECTURE.md, "Speed comes from separating the spectrum
from space").
"""

from __future__ import annotations

import threading
from collections import OrderedDict
from dataclasses import dataclass

import numpy as np
from scipy.interpolate import CubicSpline

from radscene.radiometry import spectral_radiance

__all__ = ["band_quadrature", "BandCoefficients", "emission_coefficients", "solar_spectrum",
           "sun_toa", "breakpoints", "sky_table"]

#: Gauss–Legendre order per sub-interval.
GL_ORDER = 4
#: Largest sub-interval width [um] (smooth factors such as Planck are resolved by it).
MAX_PANEL = 0.05


def band_quadrature(response, breakpoints=(), max_panel: float = MAX_PANEL):
    """Quadrature nodes and weights for ∫ S(λ) f(λ) dλ over a band.

    Parameters
    ----------
    response : radscene.radiometry.SpectralResponse
        The band's response S.
    breakpoints : array_like
        Wavelengths [um] where some integrand factor has a kink (table samples); those inside
        the band's support become sub-interval edges.
    max_panel : float
        Largest sub-interval width [um].

    Returns
    -------
    nodes, weights : numpy.ndarray
        ``sum(weights * f(nodes))`` approximates ∫ S f dλ; weights in [um].
    """
    lo, hi = response.support
    edges = [np.array([lo, hi])]
    own = getattr(response, "wavelength", None)
    if own is not None:
        edges.append(np.asarray(own, dtype=float))
    if np.size(breakpoints):
        edges.append(np.asarray(breakpoints, dtype=float).ravel())
    edges = np.unique(np.concatenate(edges))
    edges = edges[(edges >= lo) & (edges <= hi)]
    # split wide panels evenly
    widths = np.diff(edges)
    parts = np.maximum(1, np.ceil(widths / max_panel - 1e-9).astype(int))
    starts = np.repeat(edges[:-1], parts)
    step = np.repeat(widths / parts, parts)
    starts = starts + step * (np.arange(parts.sum()) - np.repeat(np.cumsum(parts) - parts, parts))
    x, w = np.polynomial.legendre.leggauss(GL_ORDER)
    nodes = (starts[:, None] + 0.5 * step[:, None] * (x[None, :] + 1.0)).ravel()
    weights = (0.5 * step[:, None] * w[None, :]).ravel()
    return nodes, weights * np.asarray(response(nodes), dtype=float)


@dataclass
class BandCoefficients:
    """Band-integrated spectral factors, per material m, band b, node j, sky node k.

    A node ``j`` is a path node of the atmosphere under one sun node (a scanner's sun at a
    few times: ``j = s · n_path + path node``); the path radiance has a relative-azimuth node
    ``a`` too (:class:`radscene.atmosphere.PathNodes`).

    All radiances in W m-2 sr-1 (band-integrated with the response), per unit of the
    per-pixel geometry scalar that multiplies them.

    Attributes
    ----------
    sun_diffuse : (n_m, n_b, n_j)
        ∫ S E_sun τ_so (ρ_d/π) τ_a dλ — times cos θ_i · lit · Δρ.
    sun_specular : (n_m, n_b, n_j)
        ∫ S E_sun τ_so ρ_s τ_a dλ — times the Phong lobe (n+1)/(2π) cosⁿθ_r · lit · Δρ.
    sky_diffuse : (n_m, n_b, n_j, n_k)
        ∫ S ρ_d L_sky,k τ_a dλ — times the cosine-weighted visible-sky fraction F_k · Δρ.
    sky_specular : (n_m, n_b, n_j, n_k)
        ∫ S ρ_s L_sky,k τ_a dλ — times the lobe-weighted visible-sky fraction G_k · Δρ.
    path : (n_a, n_b, n_j)
        ∫ S L_path dλ, per relative-azimuth node a (one without the azimuth axis).
    transmittance : (n_b, n_j)
        Response-weighted mean τ_a [-].
    sky_view : (n_b, n_k)
        ∫ S L_sky,k dλ, the radiance of the sky itself for rays that leave the scene.
    """

    sun_diffuse: np.ndarray
    sun_specular: np.ndarray
    sky_diffuse: np.ndarray
    sky_specular: np.ndarray
    path: np.ndarray
    transmittance: np.ndarray
    sky_view: np.ndarray


def sky_table(rho, sky, tau):
    """Σ_q ρ_mq L_kq τ_jq: a material × path node × sky node table (m, j, k) from the weighted
    reflectance ``rho`` (m, q), the sky ``sky`` (k, q) and the path transmittance ``tau``
    (j, q); one matrix product."""
    n_m, n_j = rho.shape[0], tau.shape[0]
    left = (rho[:, None, :] * tau[None, :, :]).reshape(n_m * n_j, -1)
    return (left @ sky.T).reshape(n_m, n_j, sky.shape[0])



def emission_coefficients(emissivity_tau, nodes, weights, material_index, temperature,
                          exact_limit: int = 1024, distinct: bool = False):
    """∫ S ε_m B(λ, T) τ_a dλ for each sample's material and temperature.

    Parameters
    ----------
    emissivity_tau : numpy.ndarray
        ε_m(λ_i) τ_a,j(λ_i) at one band's nodes, shape (n_m, n_j, n_q) [-].
    nodes, weights : numpy.ndarray
        The band's quadrature, shape (n_q,) [um], [um].
    material_index : numpy.ndarray
        Material of each sample, shape (N,) int.
    temperature : numpy.ndarray
        Surface temperature of each sample, shape (N,) [K].
    exact_limit : int
        Up to this many distinct (material, temperature) pairs the integral is evaluated
        exactly for each pair; beyond it, on a 0.25 K temperature grid with a cubic spline
        in T (relative error below 1e-10 for 200–2000 K).
    distinct : bool
        No (material, temperature) pair comes twice (the caller grouped them): they are not
        grouped again.

    Returns
    -------
    numpy.ndarray
        Shape (N, n_j) [W m-2 sr-1].
    """
    temperature = np.asarray(temperature, dtype=float)
    material_index = np.asarray(material_index)
    n_m, n_j, _ = emissivity_tau.shape
    if temperature.size == 0:
        return np.zeros((0, n_j))
    if distinct and temperature.size > exact_limit:  # no pair twice: nothing to group
        t_low, t_high = temperature.min(), temperature.max()
    else:
        t_unique, t_inverse = np.unique(temperature, return_inverse=True)
        pair = material_index.astype(np.int64) * t_unique.size + t_inverse
        pairs, p_inverse = np.unique(pair, return_inverse=True)
        if pairs.size <= exact_limit:
            pm, pt = np.divmod(pairs, t_unique.size)
            planck = spectral_radiance(nodes[None, :], t_unique[pt][:, None])  # (P, q)
            values = np.einsum("pjq,pq,q->pj", emissivity_tau[pm], planck, weights)
            return values[p_inverse.ravel()]
        t_low, t_high = t_unique[0], t_unique[-1]
    t_grid = np.arange(np.floor(t_low) - 1.0, np.ceil(t_high) + 1.25, 0.25)
    splines = _emission_splines(emissivity_tau, nodes, weights, t_grid)
    out = np.empty((temperature.size, n_j))
    for m in np.unique(material_index):
        sel = material_index == m
        out[sel] = splines(m)(temperature[sel]).T
    return out


#: The emission splines of the last renders (:func:`_emission_splines`), the most recent
#: first to go last, within :data:`SPLINES_BYTES`: a sequence's frames integrate the same
#: tables again.
_SPLINES = OrderedDict()
_SPLINES_LOCK = threading.Lock()
#: What the kept splines may hold [bytes]: their tables and the splines' coefficients (four a
#: grid interval), counted as five times a table.
SPLINES_BYTES = 64 << 20


def _emission_splines(emissivity_tau, nodes, weights, t_grid):
    """``splines(m)``: the cubic spline in T of material ``m``'s emission at the path nodes
    on the grid ``t_grid`` [K], (n_j,) per temperature [W m-2 sr-1].

    Made once per distinct (ε τ_a table, quadrature, grid) and kept (within
    :data:`SPLINES_BYTES`, the least recently used let go first): the frames of a sequence
    meet the same tables while the lines of sight, their path nodes and the range of
    temperatures stay. A set is taken again only when its inputs are equal, value for value,
    so the splines are those made afresh."""
    key = (emissivity_tau.shape, nodes.tobytes(), weights.tobytes(), float(t_grid[0]),
           t_grid.size, hash(np.ascontiguousarray(emissivity_tau).tobytes()))
    with _SPLINES_LOCK:
        entry = _SPLINES.get(key)
        if entry is not None and np.array_equal(entry[0], emissivity_tau):
            _SPLINES.move_to_end(key)
            return entry[1]
    planck = spectral_radiance(nodes[None, :], t_grid[:, None])  # (G, q)
    table = np.einsum("mjq,gq,q->mjg", emissivity_tau, planck, weights)
    made = {}

    def splines(m):
        if m not in made:
            made[m] = CubicSpline(t_grid, table[m], axis=-1)
        return made[m]

    size = emissivity_tau.nbytes + 5 * table.nbytes
    if size <= SPLINES_BYTES:
        with _SPLINES_LOCK:
            _SPLINES[key] = (np.array(emissivity_tau, copy=True), splines, size)
            while sum(e[2] for e in _SPLINES.values()) > SPLINES_BYTES:
                _SPLINES.popitem(last=False)
    return splines


def solar_spectrum(atmosphere) -> str:
    """The solar spectrum of the renderer's sun: the atmosphere's where radscene evaluates it
    (``radscene``, ``tsis1``, ``lowtran``), else ``radscene``'s (6S's own spectrum exists only
    inside 6S): :func:`radscene.sun.engine_spectrum`."""
    from radscene.sun import engine_spectrum

    return engine_spectrum(atmosphere)


def sun_toa(atmosphere, sun, wavelength):
    """The scene's sun at the top of the atmosphere [W m-2 um-1]: the atmosphere's spectrum
    (:func:`solar_spectrum`) at the Earth–Sun distance its sun shines from
    (:func:`radscene.sun.engine_distance`), so the direct sun and the engine's scattered light
    share one sun."""
    from radscene.sun import engine_distance, toa_solar_irradiance

    return toa_solar_irradiance(wavelength, engine_distance(atmosphere, sun.distance),
                                solar_spectrum(atmosphere))


def breakpoints(scene) -> np.ndarray:
    """Every table wavelength that enters a band integral: materials, atmosphere, sun [um]."""
    from radscene.sun import spectrum as sun_spectrum

    name = solar_spectrum(scene.atmosphere)
    solar_wl, _ = sun_spectrum.toa_solar_spectrum(name)
    # the measured parts have kinks at their samples; the blackbody head and tail are smooth
    # (LOWTRAN's table has kinks beyond 4 um too, where they move band integrals < 1e-6)
    start = 0.28 if name == "radscene" else 0.25
    points = [solar_wl[(solar_wl >= start) & (solar_wl <= 4.0)]]
    for m in scene.materials:
        for spec in (m.diffuse_reflectance, m.specular_reflectance, m.transmittance):
            if spec.wavelength is not None:
                points.append(np.asarray(spec.wavelength, dtype=float))
    for attr in ("transmittance", "sun_transmittance", "path_radiance", "sky_radiance"):
        spec = getattr(scene.atmosphere, attr, None)
        if spec is not None and getattr(spec, "wavelength", None) is not None:
            points.append(np.asarray(spec.wavelength, dtype=float))
    return np.unique(np.concatenate(points))
