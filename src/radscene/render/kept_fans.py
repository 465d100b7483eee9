"""Sky and lobe fans kept from one frame to the next, traced again only where something moved.

A fan's answer (which of its directions see the sky) depends on its point, its normal, its
rotation and the geometry its rays pass through. Between two frames of a sequence the first
three are the same for a ray sample whose primary ray met nothing that moved, and the rays
of its fan meet what moved only if they pass through the bounding sphere of a moved object
(where it stood, or where it stands now). So a frame keeps, per ray sample, one bit per fan
direction — visible sky or not — and the next frame traces only the fans with a ray through
such a sphere (a ray–sphere test per direction, far cheaper than a trace); every fan is
folded again from its bits into its sky-node fractions, and, for the cosine fan, into the
reflected-sky band sums with the frame's own tables (which follow the sun).

The folds are those of :func:`radscene.render.kernels.packet_sky_sums` and
:func:`~radscene.render.kernels.packet_fractions`, the same directions visited in the same
order: a kept fan gives the numbers of tracing it again, bit for bit.
"""

from __future__ import annotations

import numba
import numpy as np

from radscene.geometry.embree import RAY8_FLOATS, packet_buffers
from radscene.render.kernels import _PACKET_CHUNK, _fan_point, _fold_visible, _trace_visible
from radscene.render.node_mixing import _sky_sample

__all__ = ["MAX_FAN", "kept_fans", "meets_spheres", "bounding_sphere"]

#: The most directions a kept fan may have (one bit each in a uint64).
MAX_FAN = 64


def bounding_sphere(vertices) -> np.ndarray:
    """(centre x, y, z, radius) [m] of a sphere holding ``vertices`` (N, 3): the centre of
    their box, the distance to the farthest."""
    v = np.asarray(vertices, dtype=float)
    centre = 0.5 * (v.min(axis=0) + v.max(axis=0))
    return np.array([*centre, float(np.sqrt(np.max(np.sum((v - centre) ** 2, axis=1))))])


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
def _meets_spheres(origins, directions, spheres, out):
    for i in numba.prange(origins.shape[0]):
        out[i] = _meets(origins[i, 0], origins[i, 1], origins[i, 2], directions[i, 0],
                        directions[i, 1], directions[i, 2], spheres)


def meets_spheres(origins, directions, spheres) -> np.ndarray:
    """(N,) bool: whether each ray (``origins``, ``directions`` (N, 3), world frame [m])
    passes within one of ``spheres`` (S, 4) (centre [m], radius [m])."""
    out = np.zeros(len(origins), dtype=bool)
    if len(spheres) and len(origins):
        _meets_spheres(np.ascontiguousarray(origins, dtype=np.float64),
                       np.ascontiguousarray(directions, dtype=np.float64),
                       np.ascontiguousarray(spheres, dtype=np.float64), out)
    return out


@numba.njit(parallel=True, cache=True)
def _kept_fans(occluded8, scene, position, normal, axis, exponent, lobe, center, epsilon, shift,
               base, side, check_normal, zenith_nodes, azimuth_nodes, spheres, retrace, bits,
               fractions, rank, material, index, weight, table, sums, view):
    n = position.shape[0]
    m = base.shape[0]
    levels = side if side > 0 else m
    n_k = zenith_nodes.shape[0] * azimuth_nodes.shape[0]
    fused = table.shape[0] > 0
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
            again = retrace[i]
            j = 0
            while not again and j < m:
                again = _meets(fx, fy, fz, dirs[j, 0], dirs[j, 1], dirs[j, 2], spheres)
                j += 1
            if again:  # traced, its answers kept as one bit per direction
                traced += _trace_visible(occluded8, scene, ray, words, valid, dirs, fx, fy, fz,
                                         normal, i, check_normal, visible)
                seen = np.uint64(0)
                for j in range(m):
                    if visible[j]:
                        seen |= np.uint64(1) << np.uint64(j)
                bits[i] = seen
            else:
                for j in range(m):
                    visible[j] = (bits[i] >> np.uint64(j)) & np.uint64(1) != 0
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


def kept_fans(tracer, origins, normals, n_samples, sky_nodes, shift, bits, retrace, spheres, *,
              lobe=None, sky=None):
    """The fans of a tile's points, kept where nothing moved through them, traced elsewhere.

    Parameters
    ----------
    tracer : radscene.geometry.RayTracer — with Embree packets (:attr:`~RayTracer.packets`)
    origins, normals : (N, 3) — the points, already offset from the surface [m], and their
        unit normals
    n_samples : int — directions per fan, at most :data:`MAX_FAN`
    sky_nodes : (zenith nodes, azimuth nodes) [deg]
    shift : (N, 2) — the fans' rotations (:func:`radscene.render.surface.fan_shifts`)
    bits : (N,) uint64, in and out — the visible directions of each fan; those traced are
        written
    retrace : (N,) bool — the fans traced whatever the spheres (new points)
    spheres : (S, 4) — what moved since the bits were made: centre [m], world frame, radius [m]
    lobe : (axes (N, 3), exponents (N,)), optional — Phong lobes about ``axes`` (directions
        below the surface do not count), else cosine fans about the normals
    sky : (rank, material, index, weight, table), optional — fold each cosine fan straight
        into its reflected-sky band sums, as :func:`radscene.render.illumination.sky_sums`

    Returns
    -------
    fractions (N, K) [-], or with ``sky`` (sums (N, n_b), sky view (N,)); and the number of
    rays traced.
    """
    from radscene.render.illumination import _fan_setup, _node_grids

    zen_nodes, az_nodes = _node_grids(sky_nodes)
    n_k = zen_nodes.size * az_nodes.size
    shift, base, side, pos, nrm = _fan_setup(origins, normals, n_samples, None, shift)
    if lobe is None:
        axis, exponent = nrm, np.zeros(0)
    else:
        axis = np.ascontiguousarray(lobe[0], np.float64)
        exponent = np.ascontiguousarray(lobe[1], np.float64)
    local = np.ascontiguousarray(spheres, dtype=np.float64).reshape(-1, 4).copy()
    local[:, :3] -= tracer.center
    n = len(pos)
    if sky is None:
        fractions = np.empty((n, n_k))
        rank = material = np.zeros(0, np.int64)
        index, weight, table = np.zeros((0, 0), np.int64), np.zeros((0, 0)), np.zeros((0, 0, 0, 0))
        sums, view = np.zeros((0, 0)), np.zeros(0)
    else:
        fractions = np.zeros((0, n_k))
        rank, material, index, weight, table = sky
        rank, material, index = (np.ascontiguousarray(a, dtype=np.int64)
                                 for a in (rank, material, index))
        weight = np.ascontiguousarray(weight, dtype=np.float64)
        table = np.ascontiguousarray(table, dtype=np.float64)
        sums, view = np.empty((n, table.shape[2])), np.empty(n)
    packets = tracer.packets
    traced = 0
    if n:
        traced = _kept_fans(packets.occluded8, packets.handle, pos, nrm, axis, exponent,
                            lobe is not None, tracer.center, 0.0, shift, base, side,
                            lobe is not None, zen_nodes, az_nodes, local,
                            np.ascontiguousarray(retrace, dtype=np.bool_), bits, fractions, rank,
                            material, index, weight, table, sums, view)
    return (fractions if sky is None else (sums, view)), int(traced)
