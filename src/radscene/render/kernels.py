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

from radscene.geometry.embree import LANES as _LANES
from radscene.geometry.embree import RAY8_FLOATS, packet_buffers, set_lane
from radscene.render.node_mixing import _sky_sample

__all__ = ["cosine_fan", "lobe_fan", "fold_fractions", "fold_sky_sums", "packet_fractions",
           "packet_sky_sums", "packet_shadows", "surface_state"]

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


@numba.njit(inline="always")
def fan_axis(i, normal, axis, exponent, lobe):
    """The axis of point ``i``'s fan (its lobe's axis, or its normal) and the power of its
    levels (0: cosine-weighted)."""
    if lobe:
        return axis[i, 0], axis[i, 1], axis[i, 2], 1.0 / (exponent[i] + 1.0)
    return normal[i, 0], normal[i, 1], normal[i, 2], 0.0


@numba.njit(inline="always")
def fan_level(u1, lobe, power):
    """(sin, cos) of the polar angle of a fan's level at ``u1``: cos α = u1^power about a
    lobe's axis, sin θ = √u1 for a cosine-weighted fan."""
    if lobe:
        cos_t = u1**power
        return math.sqrt(max(0.0, 1.0 - cos_t * cos_t)), cos_t
    return math.sqrt(u1), math.sqrt(max(0.0, 1.0 - u1))


@numba.njit(inline="always")
def _fan_point(i, position, normal, axis, exponent, lobe, center, epsilon, shift, base, side,
               sin_t, cos_t, cos_phi, sin_phi, directions, row0):
    """Point ``i``'s fan: its directions into ``directions[row0:row0 + M]`` (float32 rows)
    and its local-frame origin, returned as (x, y, z); ``sin_t`` … ``sin_phi`` are scratch
    arrays of the pattern's level count."""
    m = base.shape[0]
    levels = side if side > 0 else m
    ax, ay, az, power = fan_axis(i, normal, axis, exponent, lobe)
    tx, ty, tz, bx, by, bz = _basis(ax, ay, az)
    # the regular grid's columns (b + 1/2) / side are spaced evenly in azimuth: with side a
    # multiple of four, column b + side/4 is column b turned by a quarter turn
    quarter = side // 4 if side > 0 and side % 4 == 0 else 0
    for a in range(levels):
        u1 = base[a * side if side > 0 else a, 0] + shift[i, 0]
        u1 = u1 - 1.0 if u1 >= 1.0 else u1
        sin_t[a], cos_t[a] = fan_level(u1, lobe, power)
        if quarter > 0 and a >= quarter:  # cos(φ + π/2) = −sin φ, sin(φ + π/2) = cos φ
            cos_phi[a] = -sin_phi[a - quarter]
            sin_phi[a] = cos_phi[a - quarter]
            continue
        u2 = base[a, 1] + shift[i, 1]
        u2 = u2 - 1.0 if u2 >= 1.0 else u2
        phi = _TWO_PI * u2
        cos_phi[a] = math.cos(phi)
        sin_phi[a] = math.sin(phi)
    for j in range(m):
        a, b = _levels(j, side)
        lx, ly, lz = sin_t[a] * cos_phi[b], sin_t[a] * sin_phi[b], cos_t[a]
        directions[row0 + j, 0] = lx * tx + ly * bx + lz * ax
        directions[row0 + j, 1] = lx * ty + ly * by + lz * ay
        directions[row0 + j, 2] = lx * tz + ly * bz + lz * az
    return (position[i, 0] + epsilon * normal[i, 0] - center[0],
            position[i, 1] + epsilon * normal[i, 1] - center[1],
            position[i, 2] + epsilon * normal[i, 2] - center[2])


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
            ox, oy, oz = _fan_point(i, position, normal, axis, exponent, lobe, center, epsilon,
                                    shift, base, side, sin_t, cos_t, cos_phi, sin_phi,
                                    directions, i * m)
            for j in range(m):
                k = i * m + j
                origins[k, 0], origins[k, 1], origins[k, 2] = ox, oy, oz


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


#: Abramowitz & Stegun (1964), eq. 4.4.46: arccos x = √(1 − x) Σ_k a_k x^k for 0 ≤ x ≤ 1, with
#: an error ≤ 2e-8 rad (2.2e-8 measured) — below the precision of the float32 directions.
_ACOS = (1.5707963050, -0.2145988016, 0.0889789874, -0.0501743046, 0.0308918810,
         -0.0170881256, 0.0066700901, -0.0012624911)


@numba.njit(inline="always")
def _zenith_degrees(z):
    """Zenith angle [deg] of a direction whose vertical component is 0 ≤ z ≤ 1 (A&S 4.4.46:
    the library arc cosine was a twentieth of a render's CPU time)."""
    z = min(1.0, z)
    p = ((((((_ACOS[7] * z + _ACOS[6]) * z + _ACOS[5]) * z + _ACOS[4]) * z + _ACOS[3]) * z
          + _ACOS[2]) * z + _ACOS[1]) * z + _ACOS[0]
    return math.degrees(math.sqrt(1.0 - z) * p)


@numba.njit(inline="always")
def _fold_direction(row, dx, dy, dz, zenith_nodes, azimuth_nodes):
    """Add one visible sky direction's (dz > 0) bilinear sky-node weights to ``row`` (K·L,)."""
    _fold_zenith(row, dx, dy, _zenith_degrees(dz), zenith_nodes, azimuth_nodes)


@numba.njit(inline="always")
def _fold_zenith(row, dx, dy, zen, zenith_nodes, azimuth_nodes):
    """:func:`_fold_direction` with the direction's zenith angle ``zen`` [deg] given."""
    n_az = azimuth_nodes.shape[0]
    z0, z1, fz = _hat(zen, zenith_nodes, False)
    if n_az == 1:  # a sky uniform in azimuth: no azimuth to find
        row[z0] += 1.0 - fz
        row[z1] += fz
        return
    azi = math.degrees(math.atan2(dx, dy))
    a0, a1, fa = _hat(azi, azimuth_nodes, True)
    row[z0 * n_az + a0] += (1.0 - fz) * (1.0 - fa)
    row[z0 * n_az + a1] += (1.0 - fz) * fa
    row[z1 * n_az + a0] += fz * (1.0 - fa)
    row[z1 * n_az + a1] += fz * fa


@numba.njit(inline="always")
def _fold_point(occluded, directions, normal, check_normal, zenith_nodes, azimuth_nodes,
                n_samples, i, row):
    """:func:`fold_fractions` for point ``i`` into ``row`` (K·L,)."""
    for k in range(row.shape[0]):
        row[k] = 0.0
    for j in range(n_samples):
        r = i * n_samples + j
        dx, dy, dz = directions[r, 0], directions[r, 1], directions[r, 2]
        if occluded[r] or dz <= 0.0:
            continue
        if check_normal and dx * normal[i, 0] + dy * normal[i, 1] + dz * normal[i, 2] <= 0.0:
            continue
        _fold_direction(row, dx, dy, dz, zenith_nodes, azimuth_nodes)
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


# -- fans traced as Embree packets, from inside the kernels --------------------------------
# The packet kernels generate each point's fan, trace it in packets of eight
# (radscene.geometry.embree) and fold its visible directions, point by point: no ray arrays.
# Directions at or below the horizon (or, for lobes, below the surface) are not traced, as the
# folds above skip them whatever Embree says. Same directions, same answers, same sums.

#: Points per parallel work item of the packet kernels.
_PACKET_CHUNK = 64


@numba.njit(inline="always")
def _trace_visible(occluded8, scene, ray, words, valid, dirs, ox, oy, oz, normal, i, check_normal,
                   visible):
    """Trace point ``i``'s fan ``dirs`` (M, 3) from (ox, oy, oz) in packets: ``visible[j]``
    (M,) whether direction j sees the sky — above the horizon (and, with ``check_normal``,
    the surface) and not occluded. Returns the number of rays traced."""
    m = dirs.shape[0]
    traced = 0
    for j in range(m):
        visible[j] = False
    for start in range(0, m, _LANES):
        lanes = 0
        for lane in range(_LANES):
            j = start + lane
            valid[lane] = 0
            if j >= m:
                continue
            dx, dy, dz = dirs[j, 0], dirs[j, 1], dirs[j, 2]
            if dz <= 0.0:
                continue
            if check_normal and dx * normal[i, 0] + dy * normal[i, 1] + dz * normal[i, 2] <= 0.0:
                continue
            valid[lane] = -1
            set_lane(ray, words, lane, ox, oy, oz, dx, dy, dz)
            lanes += 1
        if lanes == 0:
            continue
        traced += lanes
        occluded8(valid.ctypes.data, scene, ray.ctypes.data, 0)
        for lane in range(_LANES):
            if valid[lane] != 0 and ray[8 * _LANES + lane] >= 0.0:  # occluded: tfar = -inf
                visible[start + lane] = True
    return traced


@numba.njit(inline="always")
def _fold_visible(visible, dirs, zen, zenith_nodes, azimuth_nodes, row):
    """Fold a fan's visible directions into ``row``: the mean over its M samples, as
    :func:`_fold_point`; ``zen`` (M,) is scratch for the directions' zenith angles."""
    m = dirs.shape[0]
    for k in range(row.shape[0]):
        row[k] = 0.0
    for j in range(m):  # independent of each other: the compiler takes them four at a time
        zen[j] = _zenith_degrees(max(np.float64(dirs[j, 2]), 0.0))
    for j in range(m):
        if visible[j]:
            _fold_zenith(row, dirs[j, 0], dirs[j, 1], zen[j], zenith_nodes, azimuth_nodes)
    for k in range(row.shape[0]):
        row[k] /= m


@numba.njit(inline="always")
def _meets(ox, oy, oz, dx, dy, dz, spheres):
    """Whether the ray o + t d (t ≥ 0; d need not be a unit vector) passes within one of
    ``spheres`` (S, 4): centre and radius."""
    for s in range(spheres.shape[0]):
        wx, wy, wz = spheres[s, 0] - ox, spheres[s, 1] - oy, spheres[s, 2] - oz
        r2 = spheres[s, 3] * spheres[s, 3]
        w2 = wx * wx + wy * wy + wz * wz
        if w2 <= r2:
            return True
        b = wx * dx + wy * dy + wz * dz
        if b <= 0.0:
            continue
        if w2 - b * b / (dx * dx + dy * dy + dz * dz) <= r2:
            return True
    return False


@numba.njit(parallel=True, cache=True)
def _packet_fans(occluded8, scene, position, normal, axis, exponent, lobe, center, epsilon, shift,
                 base, side, check_normal, zenith_nodes, azimuth_nodes, spheres, retrace, bits,
                 blocked, fractions, rank, material, index, weight, table, sums, view):
    """:func:`packet_fractions` (``table`` empty: the fractions into ``fractions``) and
    :func:`packet_sky_sums` (into ``sums`` and ``view``); with ``bits`` (N,) uint64 not empty,
    the fans kept between frames (:mod:`radscene.render.kept_fans`): a fan is traced where
    ``retrace`` says or a direction passes through one of ``spheres``, its answers written
    into ``bits``, else folded from them. Where ``blocked`` has rows (N, M), row i gets the
    directions of fan i that are not sky (traced or kept alike): occluded, or at or below the
    horizon (and, with ``check_normal``, the surface), for the reflected background."""
    n = position.shape[0]
    m = base.shape[0]
    levels = side if side > 0 else m
    n_k = zenith_nodes.shape[0] * azimuth_nodes.shape[0]
    fused = table.shape[0] > 0
    keep = bits.shape[0] > 0
    flags = blocked.shape[0] > 0
    traced = 0
    for c in numba.prange((n + _PACKET_CHUNK - 1) // _PACKET_CHUNK):
        lo, hi = c * _PACKET_CHUNK, min(n, (c + 1) * _PACKET_CHUNK)
        sin_t, cos_t = np.empty(levels), np.empty(levels)
        cos_phi, sin_phi = np.empty(levels), np.empty(levels)
        dirs, zen = np.empty((m, 3), np.float32), np.empty(m)
        visible = np.empty(m, np.bool_)
        ray, words, valid = packet_buffers(RAY8_FLOATS)
        rows = np.empty((hi - lo, n_k))
        for i in range(lo, hi):
            ox, oy, oz = _fan_point(i, position, normal, axis, exponent, lobe, center, epsilon,
                                    shift, base, side, sin_t, cos_t, cos_phi, sin_phi, dirs, 0)
            fx, fy, fz = np.float32(ox), np.float32(oy), np.float32(oz)
            again = not keep or retrace[i]
            j = 0
            while not again and j < m:
                again = _meets(fx, fy, fz, dirs[j, 0], dirs[j, 1], dirs[j, 2], spheres)
                j += 1
            if again:
                traced += _trace_visible(occluded8, scene, ray, words, valid, dirs, fx, fy, fz,
                                         normal, i, check_normal, visible)
                if keep:  # one bit per direction
                    seen = np.uint64(0)
                    for j in range(m):
                        if visible[j]:
                            seen |= np.uint64(1) << np.uint64(j)
                    bits[i] = seen
            else:
                for j in range(m):
                    visible[j] = (bits[i] >> np.uint64(j)) & np.uint64(1) != 0
            if flags:
                for j in range(m):
                    blocked[i, j] = not visible[j]
            _fold_visible(visible, dirs, zen, zenith_nodes, azimuth_nodes, rows[i - lo])
            if not fused:
                for k in range(n_k):
                    fractions[i, k] = rows[i - lo, k]
                continue
            total = 0.0
            for k in range(n_k):
                total += rows[i - lo, k]
            view[i] = total
            for b in range(table.shape[2]):
                sums[i, b] = _sky_sample(table, material[i], index, weight, rank[i], rows,
                                         i - lo, b)
    return traced


def _fan_outputs(n_k, fractions=None, sky=None):
    """The arguments of :func:`_packet_fans` from ``fractions`` (N, K·L) out or
    ``sky`` = (rank, material, index, weight, table, sums, view); the other left empty."""
    if sky is None:
        return (fractions, np.zeros(0, np.int64), np.zeros(0, np.int64), np.zeros((0, 0), np.int64),
                np.zeros((0, 0)), np.zeros((0, 0, 0, 0)), np.zeros((0, 0)), np.zeros(0))
    return (np.zeros((0, n_k)), *sky)


#: Hits per parallel work item of :func:`_packet_shadows`.
_SHADOW_CHUNK = 4096


@numba.njit(parallel=True, cache=True)
def _packet_shadows(occluded8, scene, position, normal, view, center, half, epsilon, sun,
                    trace, lit, counts):
    """:func:`packet_shadows`; ``counts[c]`` gets work item c's (rays traced, rays left)."""
    n = position.shape[0]
    per_hit = 1 if sun.shape[0] > 1 else 0
    for c in numba.prange((n + _SHADOW_CHUNK - 1) // _SHADOW_CHUNK):
        traced = 0
        outside = 0
        ray, words, valid = packet_buffers(RAY8_FLOATS)
        for start in range(c * _SHADOW_CHUNK, min(n, (c + 1) * _SHADOW_CHUNK), _LANES):
            lanes = 0
            for lane in range(_LANES):
                i = start + lane
                valid[lane] = 0
                if i >= n:
                    continue
                nx, ny, nz = normal[i, 0], normal[i, 1], normal[i, 2]
                if nx * view[i, 0] + ny * view[i, 1] + nz * view[i, 2] > 0.0:  # face the viewer
                    nx, ny, nz = -nx, -ny, -nz
                lit[i] = 0.0
                r = i * per_hit  # each hit's sun, or one for all
                sx, sy, sz = sun[r, 0], sun[r, 1], sun[r, 2]
                if nx * sx + ny * sy + nz * sz <= 0.0:
                    continue
                lit[i] = 1.0
                if not trace:
                    continue
                ox = position[i, 0] + epsilon * nx - center[0]
                oy = position[i, 1] + epsilon * ny - center[1]
                oz = position[i, 2] + epsilon * nz - center[2]
                if abs(ox) > half[0] or abs(oy) > half[1] or abs(oz) > half[2]:
                    lit[i] = -1.0  # outside the scene's box: for the checked query
                    outside += 1
                    continue
                valid[lane] = -1
                set_lane(ray, words, lane, np.float32(ox), np.float32(oy), np.float32(oz),
                         np.float32(sx), np.float32(sy), np.float32(sz))
                lanes += 1
            if lanes == 0:
                continue
            traced += lanes
            occluded8(valid.ctypes.data, scene, ray.ctypes.data, 0)
            for lane in range(_LANES):
                if valid[lane] != 0 and ray[8 * _LANES + lane] < 0.0:  # occluded: tfar = -inf
                    lit[start + lane] = 0.0
        counts[c, 0] = traced
        counts[c, 1] = outside


def packet_shadows(packets, position, normal, view, center, half, epsilon, sun, trace, lit):
    """Sunlit (1) or not (0) for each hit, into ``lit`` (N,): the normal is turned to face
    the viewer (``view``, the primary ray's direction, points away from it), a face turned
    from the sun is not lit, and with ``trace`` a shadow ray towards ``sun`` (unit, world
    frame; (N, 3), one per hit, or (1, 3) or (3,), one for all) leaves
    ``position + epsilon · normal``, as Embree packets of eight neighbouring
    hits. Where that origin lies outside the tracer's box (``center`` ± ``half``), ``lit`` is
    -1: such rays are left to the caller. Returns (rays traced, rays left)."""
    counts = np.zeros(((len(position) + _SHADOW_CHUNK - 1) // _SHADOW_CHUNK, 2), np.int64)
    _packet_shadows(packets.occluded8, packets.handle, position, normal, view, center, half,
                    epsilon, _sun_rows(sun, len(position)), bool(trace), lit, counts)
    traced, outside = counts.sum(axis=0)
    return int(traced), int(outside)


def _flags(blocked, n_samples):
    """``blocked`` as the kernels take it: (N, M) bool, or no rows where none is wanted."""
    return np.zeros((0, n_samples), dtype=np.bool_) if blocked is None else blocked


def packet_fractions(packets, position, normal, axis, exponent, lobe, center, epsilon, shift,
                     base, side, check_normal, zenith_nodes, azimuth_nodes, out, blocked=None):
    """:func:`cosine_fan` (or :func:`lobe_fan`) then :func:`fold_fractions`, tracing each
    point's fan as Embree packets in ``packets`` (a
    :class:`radscene.geometry.embree.PacketScene` of the same local frame): writes ``out``
    (N, K·L) without any ray arrays, and where given ``blocked`` (N, M) bool: the fan's
    directions that are not sky (occluded, or at or below the horizon). Returns the number
    of rays traced."""
    none = np.zeros(0, np.uint64)
    return _packet_fans(packets.occluded8, packets.handle, position, normal, axis, exponent, lobe,
                        center, epsilon, shift, base, side, check_normal, zenith_nodes,
                        azimuth_nodes, np.zeros((0, 4)), np.zeros(0, np.bool_), none,
                        _flags(blocked, len(base)), *_fan_outputs(out.shape[1], fractions=out))


def packet_sky_sums(packets, position, normal, center, epsilon, shift, base, side, zenith_nodes,
                    azimuth_nodes, rank, material, index, weight, table, sums, view,
                    blocked=None):
    """:func:`cosine_fan` then :func:`fold_sky_sums`, as :func:`packet_fractions` traces
    (``blocked`` alike). Returns the number of rays traced."""
    return _packet_fans(packets.occluded8, packets.handle, position, normal, normal, np.zeros(0),
                        False, center, epsilon, shift, base, side, False, zenith_nodes,
                        azimuth_nodes, np.zeros((0, 4)), np.zeros(0, np.bool_),
                        np.zeros(0, np.uint64), _flags(blocked, len(base)), *_fan_outputs(
                            table.shape[3], sky=(rank, material, index, weight, table, sums, view)))


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


@numba.njit(parallel=True, cache=True)
def _surface_state(normal, direction, position, index, epsilon, sun, nrm, wo, cos_v, cos_i,
                   origin):
    per_hit = 1 if sun.shape[0] > 1 else 0
    for n in numba.prange(index.shape[0]):
        i = index[n]
        nx, ny, nz = normal[i, 0], normal[i, 1], normal[i, 2]
        dx, dy, dz = direction[i, 0], direction[i, 1], direction[i, 2]
        if nx * dx + ny * dy + nz * dz > 0.0:  # two-sided: face the viewer
            nx, ny, nz = -nx, -ny, -nz
        nrm[n, 0], nrm[n, 1], nrm[n, 2] = nx, ny, nz
        wo[n, 0], wo[n, 1], wo[n, 2] = -dx, -dy, -dz
        cos_v[n] = nx * -dx + ny * -dy + nz * -dz
        r = n * per_hit  # each hit's sun, or one for all
        cos_i[n] = nx * sun[r, 0] + ny * sun[r, 1] + nz * sun[r, 2]
        origin[n, 0] = position[i, 0] + epsilon * nx
        origin[n, 1] = position[i, 1] + epsilon * ny
        origin[n, 2] = position[i, 2] + epsilon * nz


def _sun_rows(sun, n) -> np.ndarray:
    """``sun`` as a contiguous (1, 3) or (n, 3) float64 array, or ValueError."""
    rows = np.ascontiguousarray(np.reshape(sun, (-1, 3)), dtype=np.float64)
    if len(rows) not in (1, n):
        raise ValueError(f"sun: one vector or one per point ({n}); got {len(rows)}")
    return rows


def surface_state(normal, direction, position, index, epsilon, sun):
    """The geometry at hits ``index`` of the primary rays, in one pass.

    Parameters
    ----------
    normal, direction, position : (N, 3) float64 — each ray's hit normal, direction of
        travel and hit point
    index : (n,) int — the rays whose hits are wanted
    epsilon : float — offset of secondary-ray origins along the normal [m]
    sun : (3,), (1, 3) or (n, 3) float64 — unit vector towards the sun, one for all hits or
        one per hit of ``index`` (a scanner's rays see the sun of their own times)

    Returns
    -------
    nrm, wo : (n, 3) — the normal turned to face the viewer, the unit vector to the viewer
    cos_v, cos_i : (n,) — nrm · wo and nrm · sun
    origin : (n, 3) — position + epsilon · nrm
    """
    n = len(index)
    nrm, wo, origin = np.empty((n, 3)), np.empty((n, 3)), np.empty((n, 3))
    cos_v, cos_i = np.empty(n), np.empty(n)
    _surface_state(normal, direction, position, np.ascontiguousarray(index, dtype=np.int64),
                   float(epsilon), _sun_rows(sun, n), nrm, wo, cos_v, cos_i, origin)
    return nrm, wo, cos_v, cos_i, origin
