"""Compiled kernels for the secondary-ray fans (numba).

Generating 16 sky rays for each of a million hit points is as costly as tracing them when done
with numpy temporaries; these kernels write the float32 rays Embree takes directly, in the ray
tracer's local frame, and fold the visibility back into per-point fractions. Their plain numpy
counterparts in :mod:`radscene.render.illumination` (``*_reference``) are the oracle they are
tested against.
"""

from __future__ import annotations

import math

import numba
import numpy as np

from radscene.render.node_mixing import _sky_sample

__all__ = ["cosine_fan", "lobe_fan", "fold_fractions", "fold_sky_sums"]

_TWO_PI = 2.0 * math.pi


@numba.njit(inline="always")
def _basis(nx, ny, nz):
    # Duff et al. (2017), JCGT 6(1): branchless orthonormal basis about (nx, ny, nz)
    sign = 1.0 if nz >= 0.0 else -1.0
    a = -1.0 / (sign + nz)
    b = nx * ny * a
    return (1.0 + sign * nx * nx * a, sign * b, -sign * nx,
            b, sign + ny * ny * a, -ny)


#: Points per parallel work item of the fans (each item keeps its own small level tables).
_FAN_CHUNK = 512


@numba.njit(inline="always")
def _levels(j, side):
    """Indices of sample ``j``'s first and second coordinate among the pattern's levels."""
    if side > 0:
        return j // side, j % side
    return j, j


@numba.njit(parallel=True, cache=True)
def _fan(position, normal, axis, exponent, lobe, center, epsilon, shift, base, side, origins,
         directions):
    """The fans of :func:`cosine_fan` (``lobe`` False) and :func:`lobe_fan` (``lobe`` True)."""
    n = position.shape[0]
    m = base.shape[0]
    levels = side if side > 0 else m
    for c in numba.prange((n + _FAN_CHUNK - 1) // _FAN_CHUNK):
        # per point: sine and cosine of the polar angle per row, of the azimuth per column
        sin_t = np.empty(levels)
        cos_t = np.empty(levels)
        cos_phi = np.empty(levels)
        sin_phi = np.empty(levels)
        for i in range(c * _FAN_CHUNK, min(n, (c + 1) * _FAN_CHUNK)):
            if lobe:
                ax, ay, az = axis[i, 0], axis[i, 1], axis[i, 2]
                power = 1.0 / (exponent[i] + 1.0)
            else:
                ax, ay, az = normal[i, 0], normal[i, 1], normal[i, 2]
                power = 0.0
            tx, ty, tz, bx, by, bz = _basis(ax, ay, az)
            ox = position[i, 0] + epsilon * normal[i, 0] - center[0]
            oy = position[i, 1] + epsilon * normal[i, 1] - center[1]
            oz = position[i, 2] + epsilon * normal[i, 2] - center[2]
            for a in range(levels):
                u1 = base[a * side if side > 0 else a, 0] + shift[i, 0]
                u1 = u1 - 1.0 if u1 >= 1.0 else u1
                if lobe:  # cos α = u1^(1/(n+1))
                    cos_t[a] = u1**power
                    sin_t[a] = math.sqrt(max(0.0, 1.0 - cos_t[a] * cos_t[a]))
                else:  # cosine-weighted: sin θ = √u1
                    sin_t[a] = math.sqrt(u1)
                    cos_t[a] = math.sqrt(max(0.0, 1.0 - u1))
                u2 = base[a, 1] + shift[i, 1]
                u2 = u2 - 1.0 if u2 >= 1.0 else u2
                phi = _TWO_PI * u2
                cos_phi[a] = math.cos(phi)
                sin_phi[a] = math.sin(phi)
            for j in range(m):
                a, b = _levels(j, side)
                lx, ly, lz = sin_t[a] * cos_phi[b], sin_t[a] * sin_phi[b], cos_t[a]
                k = i * m + j
                origins[k, 0], origins[k, 1], origins[k, 2] = ox, oy, oz
                directions[k, 0] = lx * tx + ly * bx + lz * ax
                directions[k, 1] = lx * ty + ly * by + lz * ay
                directions[k, 2] = lx * tz + ly * bz + lz * az


def cosine_fan(position, normal, center, epsilon, shift, base, side, origins, directions):
    """Cosine-distributed directions about each normal, from offset points, as float32 rays.

    Parameters
    ----------
    position, normal : (N, 3) float64 — hit points [m] and unit normals
    center : (3,) float64 — the ray tracer's local-frame origin [m]
    epsilon : float — offset of ray origins along the normal [m]
    shift : (N, 2) float64 — per-point Cranley–Patterson rotation in [0, 1)
    base : (M, 2) float64 — stratified pattern in [0, 1)
    side : int — M = side² when ``base`` is the regular grid of
        :func:`radscene.render.illumination.stratified_pattern` (sample j at row j // side,
        column j % side): each point's square roots and sines are then taken once per row and
        column instead of once per sample; 0 for any other pattern
    origins, directions : (N*M, 3) float32 — written: local-frame origins, unit directions
    """
    _fan(position, normal, normal, np.zeros(0), False, center, epsilon, shift, base, side,
         origins, directions)


def lobe_fan(position, normal, axis, exponent, center, epsilon, shift, base, side, origins,
             directions):
    """Directions distributed as the Phong lobe (n+1)/(2π) cosⁿ α about ``axis``.

    Parameters as :func:`cosine_fan`, plus ``axis`` (N, 3) unit lobe axes and ``exponent``
    (N,) lobe exponents n.
    """
    _fan(position, normal, axis, exponent, True, center, epsilon, shift, base, side, origins,
         directions)


@numba.njit(inline="always")
def _hat(value, nodes, periodic):
    """(lower index, upper index, weight of the upper) of a value on a node grid."""
    n = nodes.shape[0]
    if n == 1:
        return 0, 0, 0.0
    if periodic:
        v = value % 360.0
        if v < nodes[0]:
            v += 360.0
        lo = 0
        while lo < n - 1 and nodes[lo + 1] <= v:
            lo += 1
        upper = nodes[lo + 1] if lo < n - 1 else nodes[0] + 360.0
        return lo, (lo + 1) % n, (v - nodes[lo]) / (upper - nodes[lo])
    if value <= nodes[0]:
        return 0, 0, 0.0
    if value >= nodes[n - 1]:
        return n - 1, n - 1, 0.0
    lo = 0
    while nodes[lo + 1] < value:
        lo += 1
    return lo, lo + 1, (value - nodes[lo]) / (nodes[lo + 1] - nodes[lo])


@numba.njit(inline="always")
def _fold_point(occluded, directions, normal, check_normal, zenith_nodes, azimuth_nodes,
                n_samples, i, row):
    """:func:`fold_fractions` for point ``i`` into ``row`` (K·L,)."""
    n_az = azimuth_nodes.shape[0]
    for k in range(row.shape[0]):
        row[k] = 0.0
    for j in range(n_samples):
        r = i * n_samples + j
        dx, dy, dz = directions[r, 0], directions[r, 1], directions[r, 2]
        if occluded[r] or dz <= 0.0:
            continue
        if check_normal and dx * normal[i, 0] + dy * normal[i, 1] + dz * normal[i, 2] <= 0.0:
            continue
        zen = math.degrees(math.acos(min(1.0, dz)))
        z0, z1, fz = _hat(zen, zenith_nodes, False)
        if n_az == 1:  # a sky uniform in azimuth: no azimuth to find
            row[z0] += 1.0 - fz
            row[z1] += fz
            continue
        azi = math.degrees(math.atan2(dx, dy))
        a0, a1, fa = _hat(azi, azimuth_nodes, True)
        row[z0 * n_az + a0] += (1.0 - fz) * (1.0 - fa)
        row[z0 * n_az + a1] += (1.0 - fz) * fa
        row[z1 * n_az + a0] += fz * (1.0 - fa)
        row[z1 * n_az + a1] += fz * fa
    for k in range(row.shape[0]):
        row[k] /= n_samples


@numba.njit(parallel=True, cache=True)
def fold_fractions(occluded, directions, normal, check_normal, zenith_nodes, azimuth_nodes,
                   n_samples, out):
    """Per-point mean of visibility × bilinear sky-node weight over its fan; writes ``out``.

    ``out`` is (N, K·L) with node (i, j) of the zenith × azimuth grid at ``i * L + j``. A
    direction counts as sky when it is unoccluded and above the horizon (and, with
    ``check_normal``, above the surface).
    """
    for i in numba.prange(out.shape[0]):
        _fold_point(occluded, directions, normal, check_normal, zenith_nodes, azimuth_nodes,
                    n_samples, i, out[i])


#: Points per parallel work item of :func:`fold_sky_sums` (each keeps its fractions locally).
_SKY_CHUNK = 64


@numba.njit(parallel=True, cache=True)
def fold_sky_sums(occluded, directions, normal, check_normal, zenith_nodes, azimuth_nodes,
                  n_samples, rank, material, index, weight, table, sums, view):
    """:func:`fold_fractions` and the reflected-sky sum in one pass, never storing F.

    For point ``i`` (hit ``h = rank[i]``, material ``m``): its fractions F_k as
    :func:`fold_fractions` makes them, then ``sums[i, b] = Σ_s weight[h, s] Σ_k F_k
    table[m, index[h, s], b, k]`` (the sum of :func:`radscene.render.node_mixing.mix_sky`, in
    the same order) and ``view[i] = Σ_k F_k``.
    """
    n = sums.shape[0]
    n_k = table.shape[3]
    for c in numba.prange((n + _SKY_CHUNK - 1) // _SKY_CHUNK):
        lo, hi = c * _SKY_CHUNK, min(n, (c + 1) * _SKY_CHUNK)
        rows = np.empty((hi - lo, n_k))
        for i in range(lo, hi):
            _fold_point(occluded, directions, normal, check_normal, zenith_nodes,
                        azimuth_nodes, n_samples, i, rows[i - lo])
            total = 0.0
            for k in range(n_k):
                total += rows[i - lo, k]
            view[i] = total
            for b in range(table.shape[2]):
                sums[i, b] = _sky_sample(table, material[i], index, weight, rank[i], rows,
                                         i - lo, b)


def empty_fan(n_rays: int, scratch: dict | None = None):
    """float32 arrays for a fan of ``n_rays`` rays: (origins, directions).

    With a ``scratch`` dict, the arrays are views of buffers kept in it and reused by later
    calls (growing when needed): a fresh 50 MB array per tile costs its page faults again.
    """
    if scratch is None:
        return np.empty((n_rays, 3), np.float32), np.empty((n_rays, 3), np.float32)
    held = scratch.get("fan")
    if held is None or len(held[0]) < n_rays:
        held = scratch["fan"] = (np.empty((n_rays, 3), np.float32),
                                 np.empty((n_rays, 3), np.float32))
    return held[0][:n_rays], held[1][:n_rays]
