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

Kept or traced, a fan goes through the kernel of every render's fans
(:func:`radscene.render.kernels.packet_sky_sums`, :func:`~radscene.render.kernels.packet_fractions`),
its visible directions folded in the same order: a kept fan gives the numbers of tracing it
again, bit for bit.
"""

from __future__ import annotations

import math

import numba
import numpy as np

from radscene.render.kernels import (
    _FAN_CHUNK,
    _fan_outputs,
    _fan_point,
    _flags,
    _meets,
    _packet_fans,
    fan_axis,
    fan_level,
)

__all__ = ["MAX_FAN", "kept_fans", "meets_spheres", "bounding_sphere", "fans_meet_spheres"]

#: The most directions a kept fan may have (one bit each in a uint64).
MAX_FAN = 64


def bounding_sphere(vertices) -> np.ndarray:
    """(centre x, y, z, radius) [m] of a sphere holding ``vertices`` (N, 3): the centre of
    their box, the distance to the farthest."""
    v = np.asarray(vertices, dtype=float)
    centre = 0.5 * (v.min(axis=0) + v.max(axis=0))
    return np.array([*centre, float(np.sqrt(np.max(np.sum((v - centre) ** 2, axis=1))))])


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


#: What the polar-angle bound of :func:`_may_meet` gives away [-, in cos]: far more than the
#: float32 rounding of the fans' directions (about 1e-7).
_BOUND_MARGIN = 1e-6


@numba.njit(cache=True)
def _may_meet(i, position, normal, axis, exponent, lobe, shift, base, side, spheres):
    """Whether a direction of point ``i``'s fan (a regular grid of ``side`` polar levels by
    ``side`` azimuths) may pass within one of ``spheres``: False only where, for every
    sphere, no level's polar angle comes within the sphere's angular radius of it. A
    direction at polar angle θ about the fan's axis makes with the unit vector ŵ towards a
    sphere's centre cos γ ≤ sin θ sin θ_w + cos θ cos θ_w, and it meets the sphere only if
    cos γ ≥ √(1 − r²/|w|²)."""
    ax, ay, az, power = fan_axis(i, normal, axis, exponent, lobe)
    for s in range(spheres.shape[0]):
        wx = spheres[s, 0] - position[i, 0]
        wy = spheres[s, 1] - position[i, 1]
        wz = spheres[s, 2] - position[i, 2]
        w2 = wx * wx + wy * wy + wz * wz
        r2 = spheres[s, 3] * spheres[s, 3]
        if w2 <= r2:
            return True
        cos_w = (wx * ax + wy * ay + wz * az) / math.sqrt(w2)
        sin_w = math.sqrt(max(0.0, 1.0 - cos_w * cos_w))
        least = math.sqrt(1.0 - r2 / w2) - _BOUND_MARGIN
        for a in range(side):
            u1 = base[a * side, 0] + shift[i, 0]
            u1 = u1 - 1.0 if u1 >= 1.0 else u1
            sin_t, cos_t = fan_level(u1, lobe, power)
            if sin_t * sin_w + cos_t * cos_w >= least:
                return True
    return False


@numba.njit(parallel=True, cache=True)
def _fans_meet(position, normal, axis, exponent, lobe, shift, base, side, spheres, out):
    n = position.shape[0]
    m = base.shape[0]
    levels = side if side > 0 else m
    origin = np.zeros(3)
    for c in numba.prange((n + _FAN_CHUNK - 1) // _FAN_CHUNK):
        sin_t, cos_t = np.empty(levels), np.empty(levels)
        cos_phi, sin_phi = np.empty(levels), np.empty(levels)
        dirs = np.empty((m, 3), np.float32)
        for i in range(c * _FAN_CHUNK, min(n, (c + 1) * _FAN_CHUNK)):
            if side > 0 and not _may_meet(i, position, normal, axis, exponent, lobe, shift,
                                          base, side, spheres):
                out[i] = False
                continue
            ox, oy, oz = _fan_point(i, position, normal, axis, exponent, lobe, origin, 0.0,
                                    shift, base, side, sin_t, cos_t, cos_phi, sin_phi, dirs, 0)
            met = False
            for j in range(m):
                if _meets(ox, oy, oz, dirs[j, 0], dirs[j, 1], dirs[j, 2], spheres):
                    met = True
                    break
            out[i] = met


def fans_meet_spheres(origins, normals, n_samples, shift, spheres, lobe=None) -> np.ndarray:
    """(N,) bool: whether a direction of each point's fan passes within one of ``spheres``
    (S, 4) (centre [m], radius [m], the frame of ``origins``): the test :func:`kept_fans`
    makes before keeping a fan, without tracing or folding anything. ``origins``,
    ``normals``, ``n_samples``, ``shift`` and ``lobe`` as :func:`kept_fans` takes them; the
    directions are those the fan would trace, in float64."""
    from radscene.render.illumination import _fan_setup

    shift, base, side, pos, nrm = _fan_setup(origins, normals, n_samples, None, shift)
    out = np.zeros(len(pos), dtype=bool)
    spheres = np.ascontiguousarray(spheres, dtype=np.float64).reshape(-1, 4)
    if not len(pos) or not len(spheres):
        return out
    if lobe is None:
        axis, exponent = nrm, np.zeros(0)
    else:
        axis = np.ascontiguousarray(lobe[0], np.float64)
        exponent = np.ascontiguousarray(lobe[1], np.float64)
    _fans_meet(pos, nrm, axis, exponent, lobe is not None, shift, base, side, spheres, out)
    return out


def kept_fans(tracer, origins, normals, n_samples, sky_nodes, shift, bits, retrace, spheres, *,
              lobe=None, sky=None, blocked=None):
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
    blocked : (N, n_samples) bool, optional, out — each fan's directions that are not sky,
        kept or traced (the reflected background's first bounce,
        :mod:`radscene.render.background_first`)

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
        outputs = _fan_outputs(n_k, fractions=fractions)
    else:
        rank, material, index, weight, table = sky
        table = np.ascontiguousarray(table, dtype=np.float64)
        sums, view = np.empty((n, table.shape[2])), np.empty(n)
        outputs = _fan_outputs(n_k, sky=(*(np.ascontiguousarray(a, dtype=np.int64)
                                           for a in (rank, material, index)),
                                         np.ascontiguousarray(weight, dtype=np.float64), table,
                                         sums, view))
    packets = tracer.packets
    traced = 0
    if n:
        traced = _packet_fans(packets.occluded8, packets.handle, pos, nrm, axis, exponent,
                              lobe is not None, tracer.center, 0.0, shift, base, side,
                              lobe is not None, zen_nodes, az_nodes, local,
                              np.ascontiguousarray(retrace, dtype=np.bool_), bits,
                              _flags(blocked, n_samples), *outputs)
    return (fractions if sky is None else (sums, view)), int(traced)
