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

import numba
import numpy as np

__all__ = ["environment_function", "psf_kernel", "psf_kernel_fast", "environment_map",
           "blur_environment", "surroundings", "coupling_terms", "BOUNDARY_LAYER_HEIGHT",
           "SATELLITE_HEIGHT_KM", "MAP_CELLS"]

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
    from scipy import ndimage

    x0, y0, nx, ny = bounds
    ix = np.clip(((x - x0) / cell).astype(np.int64), 0, nx - 1)
    iy = np.clip(((y - y0) / cell).astype(np.int64), 0, ny - 1)
    flat = ix * ny + iy
    w = np.bincount(flat, weights, nx * ny)
    seen = w > 0
    out = np.empty((values.shape[0], nx * ny))
    for b in range(values.shape[0]):
        s = np.bincount(flat, values[b] * weights, nx * ny)
        out[b] = np.divide(s, w, out=np.zeros_like(s), where=seen)
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
    from scipy import fft

    border = np.concatenate([grid[:, 0, :], grid[:, -1, :], grid[:, 1:-1, 0],
                             grid[:, 1:-1, -1]], axis=1).mean(axis=1)
    dev = grid - border[:, None, None]
    n_b, nx, ny = grid.shape
    hx, hy = (kernels[0].shape[0] - 1) // 2, (kernels[0].shape[1] - 1) // 2
    # linear (not circular) convolution: pad to the full size, then keep the grid's window
    size = (fft.next_fast_len(nx + 2 * hx, real=True), fft.next_fast_len(ny + 2 * hy, real=True))
    spectrum = fft.rfft2(dev, s=size, axes=(1, 2), workers=-1)
    out = np.empty_like(grid)
    k_r, k_a = (fft.rfft2(k, s=size, workers=-1) for k in kernels)
    for b in range(n_b):
        s = float(shares[b])
        full = fft.irfft2(spectrum[b] * (s * k_r + (1.0 - s) * k_a), s=size, workers=-1)
        out[b] = border[b] + full[hx:hx + nx, hy:hy + ny]
    return out


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
    half = max(nx, ny)
    kernels = [psf_kernel_fast(cell, half, height_km, cos_view, s) for s in (1.0, 0.0)]
    blurred = blur_environment(grid, kernels, shares)
    return _bilinear(blurred, (x - x0) / cell - 0.5, (y - y0) / cell - 0.5)


@numba.njit(parallel=True, cache=True)
def _bilinear(grid, cx, cy):  # pragma: no cover - compiled
    """Bilinear interpolation of every band of ``grid`` (n_b, nx, ny) at cell coordinates
    (cx, cy), cell centres at integers, held at the edges: (n_b, N)."""
    n_b, nx, ny = grid.shape
    out = np.empty((n_b, cx.size))
    for i in numba.prange(cx.size):
        fx = min(max(cx[i], 0.0), nx - 1.0)
        fy = min(max(cy[i], 0.0), ny - 1.0)
        ix = min(int(fx), nx - 2) if nx > 1 else 0
        iy = min(int(fy), ny - 2) if ny > 1 else 0
        wx = fx - ix
        wy = fy - iy
        jx = min(ix + 1, nx - 1)
        jy = min(iy + 1, ny - 1)
        for b in range(n_b):
            out[b, i] = ((1.0 - wx) * ((1.0 - wy) * grid[b, ix, iy] + wy * grid[b, ix, jy])
                         + wx * ((1.0 - wy) * grid[b, jx, iy] + wy * grid[b, jx, jy]))
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
            t = tau[b, i]
            inv = 1.0 / (t * c) if (t > 0.0 and c > 0.0) else 0.0
            own = env[b, i] if blurred else reflected[b, i] * inv
            # the surroundings' albedo: π L / E_0, at most 1 (a glint's radiance is not albedo)
            rho_e = min(np.pi * own / e0[b], 1.0) if e0[b] > 0.0 else 0.0
            s_rho = s_alb[b] * rho_e
            # extra diffuse irradiance E_0 S ρ_e / (1 − S ρ_e), reflected as the sky's is
            gain = e0[b] / e_dif[b] if e_dif[b] > 0.0 else 0.0
            m = sky[b, i] * gain * s_rho / (1.0 - s_rho)
            multiple[b, p] = m
            l_own = (reflected[b, i] + emitted[b, i] + m) * inv
            diffuse[b, p] = t_d[b, i] * c * l_own
            if blurred:
                # the surroundings' own multiple reflection: 1 / (1 − S ρ_e) on their light
                env_total = own / (1.0 - s_rho) + emitted[b, i] * inv
                adjacency[b, p] = t_d[b, i] * c * (env_total - l_own)
            else:
                adjacency[b, p] = 0.0
