"""Surface–atmosphere coupling: the diffusely transmitted surface radiance, the multiple
reflection between the ground and the atmosphere, and the adjacency effect.

The direct terms of :mod:`radscene.render.terms` carry a surface's radiance to the sensor
through the direct transmittance τ_a and light it with the sun and the sky of a black ground.
A scattering atmosphere adds three things (6S's formulation, Vermote et al. 1997, *6S User
Guide* version 2, chapter on the signal; Tanré, Herman & Deschamps 1981, *Appl. Opt.* 20,
3676):

* **multiple reflection**: the ground's own light sent back down by the atmosphere, an extra
  diffuse irradiance E_0 S ρ_e / (1 − S ρ_e) on every surface, with E_0 the irradiance of a
  horizontal surface over black ground, S the spherical albedo and ρ_e the reflectance of the
  surroundings;
* **diffuse transmission**: radiance leaving the surface that is scattered on its way up and
  still reaches the sensor, t_d L_e, with t_d the diffuse upward transmittance and L_e the
  surface-leaving radiance of the surroundings weighted by the atmospheric point-spread
  function; with uniform surroundings L_e is the pixel's own;
* **adjacency**: the difference the point-spread function makes, t_d (L_e − L_0), zero over a
  uniform scene, positive on a dark target amid bright surroundings.

The point-spread function is 6S's environment function F(r) (Vermote et al. 1997, subroutine
ENVIRO): the share of the diffusely transmitted radiance that comes from within r of the
target, a pair of exponentials for molecules and for aerosol whose coefficients depend on the
sensor altitude, corrected for the view zenith, mixed by the molecular and aerosol shares of
t_d. It is integrated over the cells of a map of the surface-leaving radiance built from the
image's own hits, and applied by FFT convolution; beyond the map the surroundings are taken as
the mean of its border (6S's "uniform surroundings beyond r").
"""

from __future__ import annotations

import functools
from dataclasses import dataclass

import numba
import numpy as np

__all__ = ["environment_function", "psf_kernel", "psf_kernel_fast", "environment_map",
           "blur_environment", "surroundings", "coupling_terms", "image_layers",
           "NodeTransmittances", "BOUNDARY_LAYER_HEIGHT", "SATELLITE_HEIGHT_KM", "MAP_CELLS"]

#: Observers higher than this above the ground see the adjacency effect by default [m].
BOUNDARY_LAYER_HEIGHT = 2000.0
#: From this sensor height on, 6S uses its satellite environment functions [km].
SATELLITE_HEIGHT_KM = 60.0

# 6S ENVIRO: sensor heights [km] and the coefficients of the two-exponential fits
_HEIGHTS = np.array([0.5, 1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0, 10.0, 12.0, 14.0, 16.0, 18.0,
                     20.0, 60.0])
_R1 = np.array([0.73, 0.71, 0.656, 0.606, 0.56, 0.516, 0.473, 0.433, 0.395, 0.323, 0.258,
                0.209, 0.171, 0.142, 0.122, 0.07])
_R2 = np.array([2.8, 1.51, 0.845, 0.634, 0.524, 0.465, 0.429, 0.405, 0.39, 0.386, 0.409, 0.445,
                0.488, 0.545, 0.608, 0.868])
_A1 = np.array([0.239, 0.396, 0.588, 0.626, 0.612, 0.505, 0.454, 0.448, 0.444, 0.445, 0.444,
                0.448, 0.448, 0.448, 0.448, 0.448])
_A2 = np.array([1.4, 1.2, 1.02, 0.86, 0.74, 0.56, 0.46, 0.42, 0.38, 0.34, 0.3, 0.28, 0.27, 0.27,
                0.27, 0.27])
_A3 = np.array([9.17, 6.26, 5.48, 5.16, 4.74, 3.65, 3.24, 3.15, 3.07, 2.97, 2.88, 2.83, 2.83,
                2.83, 2.83, 2.83])
# view-zenith correction of the aerosol function
_VA0, _VB0, _VA1, _VB1 = 1.3347, 0.57757, -1.479, -1.5275


def _nadir_functions(r_km, height_km):
    """(F_R, F_A) at nadir for distances ``r_km`` and a sensor ``height_km`` above the target."""
    r = np.asarray(r_km, dtype=float)
    if height_km >= SATELLITE_HEIGHT_KM:
        f_a = 1.0 - 0.448 * np.exp(-0.27 * r) - 0.552 * np.exp(-2.83 * r)
        f_r = 1.0 - 0.930 * np.exp(-0.08 * r) - 0.070 * np.exp(-1.10 * r)
        return f_r, f_a
    h = min(max(float(height_km), _HEIGHTS[0]), _HEIGHTS[-1])
    r1, r2, a1, a2, a3 = (float(np.interp(h, _HEIGHTS, c)) for c in (_R1, _R2, _A1, _A2, _A3))
    f_r = 1.0 - r1 * np.exp(-r * r2) - (1.0 - r1) * np.exp(-r * 0.08)
    f_a = 1.0 - a1 * np.exp(-r * a2) - (1.0 - a1) * np.exp(-r * a3)
    return f_r, f_a


def environment_function(r_km, height_km, cos_view, rayleigh_share):
    """6S's environment function F(r): share of t_d L_e from within ``r_km`` of the target.

    Parameters
    ----------
    r_km : array_like
        Distance from the target [km], >= 0.
    height_km : float
        Sensor height above the target [km], > 0; from 60 km on, the satellite functions;
        below 0.5 km 6S's lowest row (6S's own rule).
    cos_view : float
        Cosine of the view zenith angle, in (0, 1].
    rayleigh_share : float
        Molecular share of the diffuse upward transmittance, in [0, 1].

    Returns
    -------
    numpy.ndarray
        F(r) in [0, 1], 0 at r = 0 and 1 far away.

    Raises
    ------
    ValueError
        A negative or non-finite distance, a height <= 0, a cosine outside (0, 1] or a share
        outside [0, 1].
    """
    r = np.asarray(r_km, dtype=float)
    if r.size and not (np.all(np.isfinite(r)) and r.min() >= 0.0):
        raise ValueError("r_km: distances must be finite and >= 0")
    if not float(height_km) > 0.0:
        raise ValueError(f"height_km: must be > 0; got {height_km!r}")
    if not 0.0 < float(cos_view) <= 1.0:
        raise ValueError(f"cos_view: must lie in (0, 1]; got {cos_view!r}")
    if not 0.0 <= float(rayleigh_share) <= 1.0:
        raise ValueError(f"rayleigh_share: must lie in [0, 1]; got {rayleigh_share!r}")
    f_r0, f_a0 = _nadir_functions(r, height_km)
    ln_mu = np.log(float(cos_view))
    f_r = f_r0 * (ln_mu * (1.0 - f_r0) + 1.0)
    f_a = f_a0 * (_VA0 * ln_mu + 1.0 + _VB0 * ln_mu**2
                  + f_a0 * (_VA1 * ln_mu + _VB1 * ln_mu**2)
                  + f_a0**2 * ((-_VA1 - _VA0) * ln_mu + (-_VB1 - _VB0) * ln_mu**2))
    s = float(rayleigh_share)
    return s * f_r + (1.0 - s) * f_a


def psf_kernel(cell_m, half_width, height_km, cos_view, rayleigh_share, subsamples=4):
    """Weights of the cells of a square map around a target: each cell's share of F.

    Parameters
    ----------
    cell_m : float
        Cell size [m].
    half_width : int
        The kernel spans (2·half_width + 1)² cells.
    height_km, cos_view, rayleigh_share
        As in :func:`environment_function`.
    subsamples : int
        Sub-cells per side over which the radial density is integrated.

    Returns
    -------
    numpy.ndarray
        (2·half_width + 1, 2·half_width + 1) weights >= 0 summing to at most 1; the rest,
        1 − sum, comes from beyond the kernel.
    """
    n = 2 * half_width + 1
    k = int(subsamples)
    # sub-cell centres, in cells from the kernel centre
    offsets = (np.arange(n * k) + 0.5) / k - n / 2.0
    xx, yy = np.meshgrid(offsets, offsets, indexing="ij")
    r_m = np.hypot(xx, yy) * cell_m
    # the radial density dF/dr / (2π r) by a central difference [m-2]
    dr = 0.25 * cell_m / k
    lo = np.maximum(r_m - dr, 0.0)
    f_hi = environment_function((r_m + dr) / 1000.0, height_km, cos_view, rayleigh_share)
    f_lo = environment_function(lo / 1000.0, height_km, cos_view, rayleigh_share)
    with np.errstate(divide="ignore", invalid="ignore"):
        density = np.where(r_m > 0, (f_hi - f_lo) / (r_m + dr - lo) / (2.0 * np.pi * r_m), 0.0)
    area = (cell_m / k) ** 2
    weights = (np.maximum(density, 0.0) * area).reshape(n, k, n, k).sum(axis=(1, 3))
    # the centre cell holds the singular part: the disc of its area, exactly
    r_eq = cell_m / np.sqrt(np.pi)
    weights[half_width, half_width] = float(environment_function(r_eq / 1000.0, height_km,
                                                                  cos_view, rayleigh_share))
    total = weights.sum()
    if total > 1.0:  # discretisation beyond the exact F of the whole window: rescale
        weights /= total
    return weights


def environment_map(x, y, values, weights, cell, bounds):
    """Average ``values`` (n_b, N) at points (x, y) [m] on a grid of ``cell`` [m].

    ``bounds`` is (x0, y0, nx, ny): the lower-left corner and the grid's size in cells.
    Cells no point falls in take the value of the nearest cell that has one.

    Returns
    -------
    numpy.ndarray
        (n_b, nx, ny).
    """
    x0, y0, nx, ny = bounds
    ix = np.clip(((x - x0) / cell).astype(np.int64), 0, nx - 1)
    iy = np.clip(((y - y0) / cell).astype(np.int64), 0, ny - 1)
    flat = ix * ny + iy
    w = np.bincount(flat, weights, nx * ny)
    sums = np.empty((values.shape[0], nx * ny))
    for b in range(values.shape[0]):
        sums[b] = np.bincount(flat, values[b] * weights, nx * ny)
    return _cell_means(sums, w, nx, ny)


def _cell_means(sums, w, nx, ny):
    """The map (n_b, nx, ny) of weighted sums ``sums`` (n_b, nx·ny) over the cells' weights
    ``w`` (nx·ny,): empty cells take the value of the nearest cell that has one."""
    from scipy import ndimage

    seen = w > 0
    out = np.empty_like(sums)
    for b in range(sums.shape[0]):
        out[b] = np.divide(sums[b], w, out=np.zeros_like(sums[b]), where=seen)
    out = out.reshape(-1, nx, ny)
    empty = ~seen.reshape(nx, ny)
    if np.any(empty) and not np.all(empty):
        nearest = ndimage.distance_transform_edt(empty, return_distances=False,
                                                 return_indices=True)
        out = out[:, nearest[0], nearest[1]]
    return out


def blur_environment(grid, kernels, shares):
    """Each band of ``grid`` (n_b, nx, ny) seen through the point-spread function.

    ``kernels`` is (molecular, aerosol), each from :func:`psf_kernel` with share 1 and 0;
    ``shares`` (n_b,) the molecular share of each band. Beyond the grid the surroundings are
    the mean of its border cells; the kernel's missing weight (F beyond its window) goes to
    them too, so a uniform grid comes back unchanged.
    """
    size = _fft_size(grid.shape, kernels[0].shape)
    return _blur_spectra(grid, _spectra(kernels, size), kernels[0].shape, size, shares)


def _fft_size(grid_shape, kernel_shape):
    """FFT sizes for the linear convolution of a grid with a kernel of half-width h, of which
    only the grid's own window is kept: n + h per axis (whatever wraps around falls outside
    that window; the kernel's entries beyond it never reach it)."""
    from scipy import fft

    return tuple(fft.next_fast_len(n + (k - 1) // 2, real=True)
                 for n, k in zip(grid_shape[1:], kernel_shape, strict=True))


def _spectra(kernels, size):
    """The kernels' real FFTs at ``size``."""
    from scipy import fft

    return tuple(fft.rfft2(k, s=size, workers=-1) for k in kernels)


def _blur_spectra(grid, spectra, kernel_shape, size, shares):
    """:func:`blur_environment` with the kernels' spectra at ``size`` given."""
    from scipy import fft

    border = np.concatenate([grid[:, 0, :], grid[:, -1, :], grid[:, 1:-1, 0],
                             grid[:, 1:-1, -1]], axis=1).mean(axis=1)
    dev = grid - border[:, None, None]
    n_b, nx, ny = grid.shape
    hx, hy = (kernel_shape[0] - 1) // 2, (kernel_shape[1] - 1) // 2
    k_r, k_a = spectra
    spectrum = fft.rfft2(dev, s=size, axes=(1, 2), workers=-1)
    for b, s in enumerate(np.asarray(shares, dtype=float)):
        spectrum[b] *= s * k_r + (1.0 - s) * k_a
    full = fft.irfft2(spectrum, s=size, axes=(1, 2), workers=-1)
    return border[:, None, None] + full[:, hx:hx + nx, hy:hy + ny]


#: Grid cells per side of the environment map, at most.
MAP_CELLS = 256
#: Cells around the kernel's centre whose density is integrated finely.
_FINE_CELLS = 6


def _map_grid(x, y):
    """(x0, y0, nx, ny) and the cell size [m] of a map holding the points (x, y); the
    extreme points lie at the centres of the corner cells."""
    x0, x1, y0, y1 = float(x.min()), float(x.max()), float(y.min()), float(y.max())
    extent = max(x1 - x0, y1 - y0, 1e-6)
    spacing = np.sqrt(max((x1 - x0) * (y1 - y0), 1e-12) / x.size)
    cell = max(extent / (MAP_CELLS - 1), spacing)
    nx = int(np.floor((x1 - x0) / cell + 0.5)) + 1
    ny = int(np.floor((y1 - y0) / cell + 0.5)) + 1
    return (x0 - 0.5 * cell, y0 - 0.5 * cell, nx, ny), cell


def surroundings(x, y, values, weights, height_km, cos_view, shares):
    """The surface-leaving radiance of each point's surroundings, through the PSF.

    Parameters
    ----------
    x, y : (N,) positions of the points [m], scene frame
    values : (n_b, N) surface-leaving band radiance of each point [W m-2 sr-1]
    weights : (N,) the points' weights in the map (their pixels' surface coverage)
    height_km, cos_view : the sensor's height above the ground [km] and the cosine of the
        mean view zenith
    shares : (n_b,) molecular share of the diffuse transmittance per band

    Returns
    -------
    numpy.ndarray
        (n_b, N): L_e at every point, the map blurred by 6S's environment function.
    """
    bounds, cell = _map_grid(x, y)
    x0, y0, nx, ny = bounds
    grid = environment_map(x, y, values, weights, cell, bounds)
    blurred = _blur(grid, cell, height_km, cos_view, shares)
    return _bilinear(blurred, (x - x0) / cell - 0.5, (y - y0) / cell - 0.5)


def _blur(grid, cell, height_km, cos_view, shares):
    """``grid`` (n_b, nx, ny) of cells ``cell`` [m] through the PSF of each band
    (:func:`blur_environment` with :func:`psf_kernel_fast`'s kernels as wide as the grid)."""
    half = max(grid.shape[1], grid.shape[2])
    shape = (2 * half + 1, 2 * half + 1)
    size = _fft_size(grid.shape, shape)
    spectra = _kernel_spectra(float(cell), half, float(height_km), float(cos_view), size)
    return _blur_spectra(grid, spectra, shape, size, shares)


@functools.lru_cache(maxsize=4)
def _kernel_spectra(cell_m, half_width, height_km, cos_view, size):
    """The spectra of the molecular and aerosol kernels of :func:`psf_kernel_fast`, kept for
    the next render of the same geometry (read-only)."""
    kernels = [psf_kernel_fast(cell_m, half_width, height_km, cos_view, s) for s in (1.0, 0.0)]
    spectra = _spectra(kernels, size)
    for k in spectra:
        k.flags.writeable = False
    return spectra


@numba.njit(inline="always")
def _cell_weights(fx, fy, nx, ny):
    """Bilinear corners and weights (ix, iy, jx, jy, wx, wy) at cell coordinates (fx, fy),
    cell centres at integers, held at the edges of an nx × ny grid."""
    fx = min(max(fx, 0.0), nx - 1.0)
    fy = min(max(fy, 0.0), ny - 1.0)
    ix = min(int(fx), nx - 2) if nx > 1 else 0
    iy = min(int(fy), ny - 2) if ny > 1 else 0
    return ix, iy, min(ix + 1, nx - 1), min(iy + 1, ny - 1), fx - ix, fy - iy


@numba.njit(inline="always")
def _bilinear_value(grid, b, ix, iy, jx, jy, wx, wy):
    """Band ``b`` of ``grid`` at the corners and weights of :func:`_cell_weights`."""
    return ((1.0 - wx) * ((1.0 - wy) * grid[b, ix, iy] + wy * grid[b, ix, jy])
            + wx * ((1.0 - wy) * grid[b, jx, iy] + wy * grid[b, jx, jy]))


@numba.njit(parallel=True, cache=True)
def _bilinear(grid, cx, cy):  # pragma: no cover - compiled
    """Bilinear interpolation of every band of ``grid`` (n_b, nx, ny) at cell coordinates
    (cx, cy), cell centres at integers, held at the edges: (n_b, N)."""
    n_b, nx, ny = grid.shape
    out = np.empty((n_b, cx.size))
    for i in numba.prange(cx.size):
        ix, iy, jx, jy, wx, wy = _cell_weights(cx[i], cy[i], nx, ny)
        for b in range(n_b):
            out[b, i] = _bilinear_value(grid, b, ix, iy, jx, jy, wx, wy)
    return out


def psf_kernel_fast(cell_m, half_width, height_km, cos_view, rayleigh_share):
    """:func:`psf_kernel` with the density integrated finely only near the centre, where it
    changes within a cell; one sample per cell beyond (same weights to < 0.1 %)."""
    coarse = psf_kernel(cell_m, half_width, height_km, cos_view, rayleigh_share, subsamples=1)
    m = min(_FINE_CELLS, half_width)
    fine = psf_kernel(cell_m, m, height_km, cos_view, rayleigh_share, subsamples=8)
    c = half_width
    coarse[c - m:c + m + 1, c - m:c + m + 1] = fine
    total = coarse.sum()
    if total > 1.0:
        coarse /= total
    return coarse


def coupling_terms(reflected, emitted, sky_reflected, coverage, tau, t_d, spherical_albedo,
                   e0, e_dif, environment=None, out=None, pixel=None):
    """Multiple reflection, diffusely transmitted and adjacency radiance of pixels.

    Parameters
    ----------
    reflected : (n_b, N) the pixels' reflected sun and sky at the sensor (direct terms)
        [W m-2 sr-1]
    emitted : (n_b, N) their self-emitted radiance at the sensor [W m-2 sr-1]
    sky_reflected : (n_b, N) the reflected sky part of ``reflected`` [W m-2 sr-1]
    coverage : (N,) share of each pixel covered by surface [-]
    tau, t_d : (n_b, N) direct and diffuse upward transmittances of the pixels' paths [-]
    spherical_albedo : (n_b,) S [-]
    e0, e_dif : (n_b,) band irradiance of a horizontal surface over black ground, total and
        diffuse [W m-2]
    environment : callable, optional
        ``environment(values (n_b, N)) -> (n_b, N)``: the surroundings of each pixel seen
        through the PSF (:func:`surroundings`); None: uniform surroundings, each pixel's own.
    out : dict, optional
        Arrays (n_b, P) to write the layers into at columns ``pixel`` (N,) instead of new
        (n_b, N) arrays.

    Returns
    -------
    dict
        ``multiple_reflection``, ``diffuse_transmitted`` and ``adjacency`` [W m-2 sr-1] (see
        the module docstring).
    """
    n_b, n = reflected.shape
    if out is None:
        out = {k: np.zeros((n_b, n)) for k in ("multiple_reflection", "diffuse_transmitted",
                                                "adjacency")}
        pixel = np.arange(n)
    blurred = environment is not None
    if blurred:  # the surface-leaving map the PSF blurs
        l_refl = np.empty((n_b, n))
        _leaving(_f64(reflected), _f64(coverage), _f64(tau), l_refl)
        env = _f64(environment(l_refl))
    else:  # each pixel's own: computed in the kernel
        env = np.empty((n_b, 0))
    _layers(_f64(reflected), _f64(emitted), _f64(sky_reflected), _f64(coverage), _f64(tau),
            _f64(t_d), env, blurred, _f64(spherical_albedo), _f64(e0), _f64(e_dif),
            np.ascontiguousarray(pixel, dtype=np.int64), out["multiple_reflection"],
            out["diffuse_transmitted"], out["adjacency"])
    return out


@dataclass(frozen=True)
class NodeTransmittances:
    """The direct and diffuse upward transmittances of pixels, mixed from path nodes.

    Pixel ``i``'s τ in band ``b`` is Σ_s weight[h, s] · tau[b, index[h, s]] with
    h = rank[i] (zero weights skipped), its t_d the same from ``t_d``: the renderer's
    path-node mixing (:func:`radscene.render.node_mixing.mix_rows`).

    Attributes
    ----------
    tau, t_d : (n_b, n_nodes) band transmittances at the path nodes [-]
    index, weight : (H, S) the nodes each row mixes and their weights
    rank : (N,) each pixel's row of ``index`` and ``weight``
    """

    tau: np.ndarray
    t_d: np.ndarray
    index: np.ndarray
    weight: np.ndarray
    rank: np.ndarray

    def arrays(self) -> tuple:
        """The compiled kernels' arguments: contiguous float64 and int64 arrays."""
        return (np.ascontiguousarray(self.tau, dtype=np.float64),
                np.ascontiguousarray(self.t_d, dtype=np.float64),
                np.ascontiguousarray(self.index, dtype=np.int64),
                np.ascontiguousarray(self.weight, dtype=np.float64),
                np.ascontiguousarray(self.rank, dtype=np.int64))


def image_layers(sun_diffuse, sun_specular, sky_reflected, emitted, coverage, transmittances,
                 spherical_albedo, e0, e_dif, out, pixel, psf=None, total=None):
    """:func:`coupling_terms` for the pixels of a rendered image, in compiled passes that
    write the three layers and nothing else (no band × pixel intermediates).

    The reflected radiance is sun_diffuse + sun_specular + sky_reflected, the transmittances
    are mixed from path nodes per pixel and band (:class:`NodeTransmittances`), and with a
    ``psf`` the surface-leaving map is binned, blurred and interpolated back as
    :func:`surroundings` does. The results equal those of :func:`coupling_terms` given the
    same quantities as arrays.

    Parameters
    ----------
    sun_diffuse, sun_specular, sky_reflected, emitted : (n_b, N) the pixels' terms at the
        sensor [W m-2 sr-1] (views of any layout)
    coverage : (N,) share of each pixel covered by surface [-]
    transmittances : NodeTransmittances
    spherical_albedo, e0, e_dif : (n_b,) as in :func:`coupling_terms`
    out : dict
        ``multiple_reflection``, ``diffuse_transmitted`` and ``adjacency``, (n_b, P) float64
        arrays written at the columns ``pixel`` (N,) (distinct).
    psf : tuple, optional
        (x, y, height_km, cos_view, shares): the pixels' positions (N,) [m] and the PSF's
        settings, as in :func:`surroundings`; None: uniform surroundings, each pixel's own
        (the adjacency layer is zero).
    total : (n_b, P) float64, optional
        The image's total radiance: the three layers are added to it at the columns
        ``pixel``, in the order above.

    Returns
    -------
    dict
        ``out``.
    """
    n_b, n = np.shape(sun_diffuse)
    terms = tuple(_f64(a) for a in (sun_diffuse, sun_specular, sky_reflected, emitted))
    cover = _f64(coverage)
    tau, t_d, index, weight, rank = transmittances.arrays()
    bands = tuple(_f64(a) for a in (spherical_albedo, e0, e_dif))
    layers = (out["multiple_reflection"], out["diffuse_transmitted"], out["adjacency"])
    pixel = np.ascontiguousarray(pixel, dtype=np.int64)
    sink = (np.empty((n_b, 0)), False) if total is None else (total, True)
    if n == 0:
        return out
    if psf is None:
        none = np.empty(0)
        _image_layers(*terms, cover, tau, t_d, index, weight, rank, np.empty((n_b, 0, 0)),
                      False, none, none, 0.0, 0.0, 1.0, *bands, pixel, *layers, *sink)
        return out
    x, y, height_km, cos_view, shares = psf
    x, y = _f64(x), _f64(y)
    bounds, cell = _map_grid(x, y)
    x0, y0, nx, ny = float(bounds[0]), float(bounds[1]), bounds[2], bounds[3]
    sums, w = np.zeros((n_b, nx * ny)), np.zeros(nx * ny)
    _leaving_sums(*terms[:3], cover, tau, index, weight, rank, x, y, x0, y0, float(cell), nx,
                  ny, sums, w)
    blurred = _blur(_cell_means(sums, w, nx, ny), cell, height_km, cos_view, shares)
    _image_layers(*terms, cover, tau, t_d, index, weight, rank, np.ascontiguousarray(blurred),
                  True, x, y, x0, y0, float(cell), *bands, pixel, *layers, *sink)
    return out


#: Pixels per work item of the image kernels: each item runs through the bands one after the
#: other over its pixels (the band rows lie a whole image apart and share cache sets).
_CHUNK = 256


@numba.njit(inline="always")
def _mix(table, b, index, weight, h):
    """Σ_s weight[h, s] table[b, index[h, s]], zero weights skipped (node_mixing's order)."""
    acc = 0.0
    for s in range(index.shape[1]):
        w = weight[h, s]
        if w == 0.0:
            continue
        acc += w * table[b, index[h, s]]
    return acc


@numba.njit(parallel=True, cache=True)
def _leaving_sums(sun_d, sun_s, sky, coverage, tau, index, weight, rank, x, y, x0, y0, cell,
                  nx, ny, sums, w):  # pragma: no cover - compiled
    """The surface-leaving reflected radiance of every pixel, weighted by its coverage and
    summed per map cell into ``sums`` (n_b, nx·ny), the coverage into ``w``: the sums
    :func:`environment_map` forms, each in the same order (pixel after pixel; the bands in
    parallel)."""
    n_b, n = sun_d.shape
    flat = np.empty(n, dtype=np.int64)
    for i in numba.prange(n):
        ix = min(max(int((x[i] - x0) / cell), 0), nx - 1)
        iy = min(max(int((y[i] - y0) / cell), 0), ny - 1)
        flat[i] = ix * ny + iy
    for i in range(n):
        w[flat[i]] += coverage[i]
    for b in numba.prange(n_b):
        for i in range(n):
            c = coverage[i]
            t = _mix(tau, b, index, weight, rank[i])
            reflected = sun_d[b, i] + sun_s[b, i] + sky[b, i]
            leaving = reflected / (t * c) if (t > 0.0 and c > 0.0) else 0.0
            sums[b, flat[i]] += leaving * c


@numba.njit(parallel=True, cache=True)
def _image_layers(sun_d, sun_s, sky, emitted, coverage, tau, t_d, index, weight, rank, blurred,
                  use_psf, x, y, x0, y0, cell, s_alb, e0, e_dif, pixel, multiple, diffuse,
                  adjacency, total, add_total):  # pragma: no cover - compiled
    """The three layers of :func:`image_layers` for every pixel and band (added to ``total``
    where ``add_total``). Per chunk of pixels: their node rows and map cells once, then band
    by band the mixed transmittances and surroundings, the layers, and their writes, each in
    its own loop (the layers' loop has no gathers and no scattered writes)."""
    n_b, n = sun_d.shape
    nx, ny = blurred.shape[1], blurred.shape[2]
    n_s = index.shape[1]
    for chunk in numba.prange((n + _CHUNK - 1) // _CHUNK):
        lo, hi = chunk * _CHUNK, min(n, (chunk + 1) * _CHUNK)
        m = hi - lo
        node = np.empty((n_s, m), dtype=np.int64)
        node_w = np.empty((n_s, m))
        corner = np.zeros((4, m), dtype=np.int64)
        corner_w = np.zeros((2, m))
        for k in range(m):
            h = rank[lo + k]
            for s in range(n_s):
                node[s, k] = index[h, s]
                node_w[s, k] = weight[h, s]
            if use_psf:
                ix, iy, jx, jy, wx, wy = _cell_weights((x[lo + k] - x0) / cell - 0.5,
                                                       (y[lo + k] - y0) / cell - 0.5, nx, ny)
                corner[0, k], corner[1, k], corner[2, k], corner[3, k] = ix, iy, jx, jy
                corner_w[0, k], corner_w[1, k] = wx, wy
        t_dir = np.empty(m)
        t_dif = np.empty(m)
        env = np.zeros(m)
        layer = np.empty((3, m))
        for b in range(n_b):
            for k in range(m):  # Σ_s w_s table[b, j_s], zero weights skipped (_mix's order)
                a_dir = 0.0
                a_dif = 0.0
                for s in range(n_s):
                    w = node_w[s, k]
                    if w != 0.0:
                        a_dir += w * tau[b, node[s, k]]
                        a_dif += w * t_d[b, node[s, k]]
                t_dir[k] = a_dir
                t_dif[k] = a_dif
                if use_psf:
                    env[k] = _bilinear_value(blurred, b, corner[0, k], corner[1, k],
                                             corner[2, k], corner[3, k], corner_w[0, k],
                                             corner_w[1, k])
            sd, ss, sk = sun_d[b, lo:hi], sun_s[b, lo:hi], sky[b, lo:hi]
            em, cv = emitted[b, lo:hi], coverage[lo:hi]
            for k in range(m):
                layer[0, k], layer[1, k], layer[2, k] = _pixel_layers(
                    sd[k] + ss[k] + sk[k], em[k], sk[k], cv[k], t_dir[k], t_dif[k], env[k],
                    use_psf, s_alb[b], e0[b], e_dif[b])
            for k in range(m):
                p = pixel[lo + k]
                multiple[b, p] = layer[0, k]
                diffuse[b, p] = layer[1, k]
                adjacency[b, p] = layer[2, k]
                if add_total:
                    total[b, p] = total[b, p] + layer[0, k] + layer[1, k] + layer[2, k]


def _f64(a):
    """``a`` as float64 without a copy where it is one already (views of any layout)."""
    return np.asarray(a, dtype=np.float64)


@numba.njit(parallel=True, cache=True)
def _leaving(reflected, coverage, tau, l_refl):  # pragma: no cover - compiled
    """The surface-leaving reflected radiance reflected / (τ c) into ``l_refl`` (n_b, N);
    zero where nothing is covered."""
    n_b, n = reflected.shape
    for i in numba.prange(n):
        c = coverage[i]
        for b in range(n_b):
            t = tau[b, i]
            l_refl[b, i] = reflected[b, i] / (t * c) if (t > 0.0 and c > 0.0) else 0.0


@numba.njit(inline="always")
def _pixel_layers(reflected, emitted, sky, c, t, t_d, env, blurred, s_alb, e0, e_dif):
    """(multiple reflection, diffusely transmitted, adjacency) of one pixel in one band, from
    its reflected, emitted and reflected-sky radiance at the sensor, its coverage ``c``, its
    transmittances τ and t_d and, where ``blurred``, the surroundings' leaving radiance
    ``env`` (else the pixel's own)."""
    inv = 1.0 / (t * c) if (t > 0.0 and c > 0.0) else 0.0
    own = env if blurred else reflected * inv
    # the surroundings' albedo: π L / E_0, at most 1 (a glint's radiance is not albedo)
    rho_e = min(np.pi * own / e0, 1.0) if e0 > 0.0 else 0.0
    s_rho = s_alb * rho_e
    # extra diffuse irradiance E_0 S ρ_e / (1 − S ρ_e), reflected as the sky's is
    gain = e0 / e_dif if e_dif > 0.0 else 0.0
    m = sky * gain * s_rho / (1.0 - s_rho)
    l_own = (reflected + emitted + m) * inv
    diffuse = t_d * c * l_own
    adjacency = 0.0
    if blurred:
        # the surroundings' own multiple reflection: 1 / (1 − S ρ_e) on their light
        env_total = own / (1.0 - s_rho) + emitted * inv
        adjacency = t_d * c * (env_total - l_own)
    return m, diffuse, adjacency


@numba.njit(parallel=True, cache=True)
def _layers(reflected, emitted, sky, coverage, tau, t_d, env, blurred, s_alb, e0, e_dif,
            pixel, multiple, diffuse, adjacency):  # pragma: no cover - compiled
    """The three layers of :func:`coupling_terms` for every pixel and band, written at the
    columns ``pixel`` of the outputs; ``env`` the blurred surroundings where ``blurred``
    (else each pixel's own leaving radiance, computed here)."""
    n_b, n = reflected.shape
    for i in numba.prange(n):
        p = pixel[i]
        c = coverage[i]
        for b in range(n_b):
            m, d, a = _pixel_layers(reflected[b, i], emitted[b, i], sky[b, i], c, tau[b, i],
                                    t_d[b, i], env[b, i] if blurred else 0.0, blurred,
                                    s_alb[b], e0[b], e_dif[b])
            multiple[b, p] = m
            diffuse[b, p] = d
            adjacency[b, p] = a
