"""Compiled kernels of the background pass (numba): the plain materials' BRDF sampling.

A plain material (ρ_d, ρ_s, n) is the registry's ``phong`` model
(:class:`radscene.materials.brdf.Phong`); these kernels draw its directions and weigh them
in one pass per path, with the same formulas and the same random numbers as its ``sample``,
``pdf`` and ``f``, which :func:`radscene.render.background_tables.brdf_weight_reference` calls and
the tests hold them to. The first vertex's kernels (:func:`fan_directions`,
:func:`first_blocked`, :func:`first_directions`, :func:`lobe_weights`) draw its diffuse part
and its lobe apart (:mod:`radscene.render.background_first`), against
:func:`radscene.render.background_first.first_reference`.
"""

from __future__ import annotations

import math

import numba
import numpy as np

from radscene.geometry.embree import LANES, RAY8_FLOATS, packet_buffers, set_lane
from radscene.geometry.raytracer import clip_ray
from radscene.render.kernels import _basis, _meets

__all__ = ["phong_weights", "phong_directions", "phong_values", "counter_uniforms",
           "first_blocked", "first_directions", "fan_directions", "lobe_weights", "add_rows"]

_TWO_PI = 2.0 * math.pi


@numba.njit(inline="always")
def _lobe_f(mu_i, mu_o, cos_g, n):
    """f of a Phong lobe of unit albedo: (n+1)/(2π) max(cos θ_r, 0)^n / max(μ_i, μ_o)."""
    cos_r = 2.0 * mu_i * mu_o - cos_g
    if n == 0.0:
        value = 1.0 if cos_r >= 0.0 else 0.0
    else:
        value = max(cos_r, 0.0) ** n
    return value / max(mu_i, mu_o) * (n + 1.0) / _TWO_PI


@numba.njit(inline="always")
def _draw(ox, oy, oz, nx, ny, nz, u1, u2, p_s, n):
    """One direction from a Phong model about normal n for ω_o = (ox, oy, oz), as the
    registry's ``sample``: (ω_i, its pdf, μ_i, μ_o, cos g)."""
    tx, ty, tz, bx, by, bz = _basis(nx, ny, nz)
    lx, ly = ox * tx + oy * ty + oz * tz, ox * bx + oy * by + oz * bz
    lz = ox * nx + oy * ny + oz * nz
    pick = u1 < p_s
    if pick:
        v = u1 / p_s if p_s > 0.0 else u1
    else:
        v = (u1 - p_s) / (1.0 - p_s) if p_s < 1.0 else u1 - p_s
    v = min(max(v, 0.0), 1.0)
    phi = _TWO_PI * u2
    if pick:  # about the mirror of ω_o, in the local frame, then into it
        cos_a = v ** (1.0 / (n + 1.0))
        sin_a = math.sqrt(max(1.0 - cos_a * cos_a, 0.0))
        ax, ay, az = -lx, -ly, lz
        a_tx, a_ty, a_tz, a_bx, a_by, a_bz = _basis(ax, ay, az)
        px, py, pz = sin_a * math.cos(phi), sin_a * math.sin(phi), cos_a
        qx = px * a_tx + py * a_bx + pz * ax
        qy = px * a_ty + py * a_by + pz * ay
        qz = px * a_tz + py * a_bz + pz * az
    else:  # cosine-weighted (Malley)
        r = math.sqrt(v)
        qx, qy, qz = r * math.cos(phi), r * math.sin(phi), math.sqrt(max(1.0 - v, 0.0))
    dx = qx * tx + qy * bx + qz * nx
    dy = qx * ty + qy * by + qz * ny
    dz = qx * tz + qy * bz + qz * nz
    mu_i = dx * nx + dy * ny + dz * nz
    cos_g = min(max(dx * ox + dy * oy + dz * oz, -1.0), 1.0)
    cos_a = 2.0 * mu_i * lz - cos_g
    lobe_pdf = (max(cos_a, 0.0) ** n) * ((n + 1.0) / _TWO_PI) if cos_a >= 0.0 else 0.0
    pdf = p_s * lobe_pdf + (1.0 - p_s) * max(mu_i, 0.0) / math.pi
    return dx, dy, dz, pdf, mu_i, lz, cos_g


@numba.njit(parallel=True, cache=True)
def phong_weights(wo, normal, u, material, p_lobe, exponent, diffuse, specular, wi, weight):
    """Draw ω_i from each point's Phong model and weigh it by f cos θ_i / pdf.

    Parameters
    ----------
    wo, normal : (N, 3) float64 unit vectors (ω_o, the normal facing it)
    u : (N, 2) float64 uniforms in [0, 1]
    material : (N,) int64
    p_lobe : (M,) probability of drawing from the lobe, ρ_s / (ρ_d + ρ_s) of the sampler
    exponent : (M,) Phong exponent
    diffuse, specular : (M, B) band-mean ρ_d and ρ_s
    wi : (N, 3) out — the directions
    weight : (N, B) out — f cos θ_i / pdf per band (0 below the horizon or at pdf 0)
    """
    n_b = diffuse.shape[1]
    for i in numba.prange(len(material)):
        m = material[i]
        dx, dy, dz, pdf, mu_i, mu_o, cos_g = _draw(
            wo[i, 0], wo[i, 1], wo[i, 2], normal[i, 0], normal[i, 1], normal[i, 2], u[i, 0],
            u[i, 1], p_lobe[m], exponent[m])
        wi[i, 0], wi[i, 1], wi[i, 2] = dx, dy, dz
        if not (mu_i > 0.0 and mu_o > 0.0 and pdf > 0.0 and math.isfinite(pdf)):
            for b in range(n_b):
                weight[i, b] = 0.0
            continue
        lobe = _lobe_f(mu_i, mu_o, cos_g, exponent[m])
        scale = mu_i / pdf
        for b in range(n_b):
            weight[i, b] = (diffuse[m, b] / math.pi + specular[m, b] * lobe) * scale


@numba.njit(parallel=True, cache=True)
def phong_directions(wo, normal, point, u, material, p_lobe, exponent, reflects, wi, valid):
    """The directions of :func:`phong_weights` for paths from points, without the weights.

    ``point`` (N,) is each path's point (a row of ``wo``, ``normal`` and ``material``), ``u``
    (N, 2) its uniforms, ``reflects`` (M,) whether a material reflects at all; ``valid`` (N,)
    is set where the weight can be non-zero (above the horizon, pdf > 0).
    """
    for i in numba.prange(len(point)):
        j = point[i]
        m = material[j]
        dx, dy, dz, pdf, mu_i, mu_o, _ = _draw(
            wo[j, 0], wo[j, 1], wo[j, 2], normal[j, 0], normal[j, 1], normal[j, 2], u[i, 0],
            u[i, 1], p_lobe[m], exponent[m])
        wi[i, 0], wi[i, 1], wi[i, 2] = dx, dy, dz
        valid[i] = (reflects[m] and mu_i > 0.0 and mu_o > 0.0 and pdf > 0.0
                    and math.isfinite(pdf))


@numba.njit(parallel=True, cache=True)
def phong_values(wi, wo, normal, material, exponent, diffuse, specular, out):
    """The band-mean Phong f(ω_i, ω_o) of each point [sr-1] into ``out`` (N, B)."""
    n_b = diffuse.shape[1]
    for i in numba.prange(len(material)):
        m = material[i]
        mu_i = wi[i, 0] * normal[i, 0] + wi[i, 1] * normal[i, 1] + wi[i, 2] * normal[i, 2]
        mu_o = wo[i, 0] * normal[i, 0] + wo[i, 1] * normal[i, 1] + wo[i, 2] * normal[i, 2]
        if not (mu_i > 0.0 and mu_o > 0.0):
            for b in range(n_b):
                out[i, b] = 0.0
            continue
        cos_g = min(max(wi[i, 0] * wo[i, 0] + wi[i, 1] * wo[i, 1] + wi[i, 2] * wo[i, 2],
                        -1.0), 1.0)
        lobe = _lobe_f(mu_i, mu_o, cos_g, exponent[m])
        for b in range(n_b):
            out[i, b] = diffuse[m, b] / math.pi + specular[m, b] * lobe



_GOLDEN = np.uint64(0x9E3779B97F4A7C15)
_MIX1 = np.uint64(0xBF58476D1CE4E5B9)
_MIX2 = np.uint64(0x94D049BB133111EB)


@numba.njit(inline="always")
def _splitmix(state):
    """SplitMix64's output function of a 64-bit state (Steele, Lea & Flood 2014)."""
    z = state
    z = (z ^ (z >> np.uint64(30))) * _MIX1
    z = (z ^ (z >> np.uint64(27))) * _MIX2
    return z ^ (z >> np.uint64(31))


@numba.njit(inline="always")
def _uniform(key, path, bounce, depth, d):
    """The uniform of path ``path``, vertex ``bounce``, dimension ``d`` (see
    :func:`counter_uniforms`)."""
    counter = (np.uint64(path) * np.uint64(depth) + np.uint64(bounce)) * np.uint64(2)
    state = key + (counter + np.uint64(d) + np.uint64(1)) * _GOLDEN
    return np.float64(_splitmix(state) >> np.uint64(11)) * (1.0 / 9007199254740992.0)


@numba.njit(parallel=True, cache=True)
def counter_uniforms(key, paths, bounce, depth, out):
    """Uniforms in [0, 1) of paths at one vertex, from their counters (SplitMix64).

    The counter of path p, vertex b and dimension d is c = (p · depth + b) · 2 + d; the
    uniform is the top 53 bits of SplitMix64's output for the state key + (c + 1) · γ, so
    any path's numbers can be drawn alone, in any order.

    Parameters
    ----------
    key : uint64 — the tile's key
    paths : (N,) int64 path indices
    bounce : int — the vertex (0 for the point itself)
    depth : int — vertices per path (bounces + 1)
    out : (N, 2) float64 out
    """
    for i in numba.prange(len(paths)):
        for d in range(2):
            out[i, d] = _uniform(key, paths[i], bounce, depth, d)


#: Points per parallel work item of :func:`first_blocked`.
_POINT_BLOCK = 256


@numba.njit(inline="always")
def _first_direction(ox, oy, oz, nx, ny, nz, u1, u2, lobe, q, n):
    """The first direction of a path from a plain material, from its uniforms: cosine-
    weighted (``lobe`` False), or, with probability ``q``, from the Phong lobe of exponent
    ``n`` (its ``u1`` rescaled to u1 / q). Returns (ω_i, whether its weight may be non-zero)."""
    if lobe:
        if not u1 < q:
            return 0.0, 0.0, 0.0, False
        dx, dy, dz, pdf, mu_i, mu_o, _ = _draw(ox, oy, oz, nx, ny, nz, u1 / q, u2, 1.0, n)
    else:
        dx, dy, dz, pdf, mu_i, mu_o, _ = _draw(ox, oy, oz, nx, ny, nz, u1, u2, 0.0, 0.0)
    return dx, dy, dz, mu_i > 0.0 and mu_o > 0.0 and pdf > 0.0 and math.isfinite(pdf)


@numba.njit(inline="always")
def _trace_lanes(occluded8, scene, ray, valid, slot, lanes, blocked):
    """Trace the first ``lanes`` lanes of a packet; flag rows ``slot`` that are blocked."""
    for lane in range(lanes, LANES):
        valid[lane] = 0
    occluded8(valid.ctypes.data, scene, ray.ctypes.data, 0)
    for lane in range(lanes):
        blocked[slot[lane]] = ray[8 * LANES + lane] < 0.0


def first_blocked(occluded8, scene, key, depth, lo, hi, samples, first, offset, lobe, wo,
                  normal, origin, material, traced, q, exponent, center, half, direction,
                  blocked, retrace=None, known=None, spheres=None):
    """The drawn first directions of the paths from points ``lo`` to ``hi`` and whether they
    meet the scene, in one pass: each path's uniforms (:func:`counter_uniforms`, vertex 0),
    its direction (:func:`_first_direction`), its ray clipped as :meth:`RayTracer.intersect`
    clips it and traced by Embree's ``rtcOccluded8``, the valid rays packed eight to a packet
    (a point's paths share their origin).

    Row k of the outputs is sample k % samples of point lo + k // samples; its path index is
    ``offset`` + (lo · samples + k). Samples below ``first`` are not drawn.

    Parameters
    ----------
    occluded8, scene : Embree's ``rtcOccluded8`` and the packet scene's handle
    key : uint64 — the tile's key; depth : vertices per path (bounces + 1)
    samples, first, offset : int — paths per point, the first drawn, the path index offset
    lobe : bool — draw from the Phong lobes (else cosine-weighted)
    wo, normal, origin : (N, 3) float64 — each point's ω_o, normal facing it, ray origin [m]
    material : (N,) int64
    traced : (M,) bool — materials drawn here; the paths of the others are not blocked
    q, exponent : (M,) — the lobe's probability and Phong exponent
    center, half : (3,) — the tracer's box (:attr:`RayTracer.center`, ``half_size``) [m]
    direction : ((hi - lo) · samples, 3) float64 out — the drawn directions (rows of traced
        paths whose weight may be non-zero)
    blocked : ((hi - lo) · samples,) bool out — the direction meets the scene
    retrace, known, spheres : optional — a sequence's last frame
        (:mod:`radscene.render.frame_cache`): ``known`` its answers, indexed by path index
        (``offset`` included: (2 · N · samples,) for the diffuse and the lobe paths), taken
        where ``retrace`` (N,) bool is False for the point and the ray passes through none of ``spheres`` (S, 4) (centre in the tracer's local frame [m], radius
        [m]); by default every path is traced
    """
    if retrace is None:
        retrace, known, spheres = np.ones(len(material), np.bool_), np.zeros(0, np.bool_), np.zeros((0, 4))
    _first_blocked(occluded8, scene, key, depth, lo, hi, samples, first, offset, lobe, wo, normal,
                   origin, material, traced, q, exponent, center, half, direction, blocked,
                   retrace, known, spheres)


@numba.njit(parallel=True, cache=True, error_model="numpy")
def _first_blocked(occluded8, scene, key, depth, lo, hi, samples, first, offset, lobe, wo, normal,
                   origin, material, traced, q, exponent, center, half, direction, blocked,
                   retrace, known, spheres):
    n_blocks = (hi - lo + _POINT_BLOCK - 1) // _POINT_BLOCK
    for c in numba.prange(n_blocks):
        ray, words, valid = packet_buffers(RAY8_FLOATS)
        slot = np.empty(LANES, np.int64)
        lanes = 0
        for i in range(lo + c * _POINT_BLOCK, min(hi, lo + (c + 1) * _POINT_BLOCK)):
            m = material[i]
            for s in range(samples):
                k = (i - lo) * samples + s
                blocked[k] = False
                if s < first or not traced[m]:
                    continue
                path = offset + i * samples + s
                dx, dy, dz, ok = _first_direction(
                    wo[i, 0], wo[i, 1], wo[i, 2], normal[i, 0], normal[i, 1], normal[i, 2],
                    _uniform(key, path, 0, depth, 0), _uniform(key, path, 0, depth, 1), lobe,
                    q[m], exponent[m])
                if not ok:
                    continue
                length = math.sqrt(dx * dx + dy * dy + dz * dz)
                ux, uy, uz = dx / length, dy / length, dz / length
                enter, leave, sx, sy, sz = clip_ray(origin[i, 0], origin[i, 1], origin[i, 2],
                                                    ux, uy, uz, center, half)
                if not enter <= leave:
                    continue
                direction[k, 0], direction[k, 1], direction[k, 2] = dx, dy, dz
                if not retrace[i] and not _meets(sx, sy, sz, ux, uy, uz, spheres):
                    blocked[k] = known[path]  # nothing moved through it: as it was
                    continue
                set_lane(ray, words, lanes, sx, sy, sz, np.float32(ux), np.float32(uy),
                         np.float32(uz))
                valid[lanes] = -1
                slot[lanes] = k
                lanes += 1
                if lanes == LANES:
                    _trace_lanes(occluded8, scene, ray, valid, slot, lanes, blocked)
                    lanes = 0
        if lanes:
            _trace_lanes(occluded8, scene, ray, valid, slot, lanes, blocked)


@numba.njit(parallel=True, cache=True)
def first_directions(wo, normal, point, u, material, traced, q, exponent, lobe, wi, valid):
    """The directions of :func:`first_blocked` for paths from points, drawn, not traced.

    ``point`` (P,) is each path's point (a row of ``wo``, ``normal`` and ``material``), ``u``
    (P, 2) its uniforms; ``valid`` (P,) is set where the weight may be non-zero.
    """
    for i in numba.prange(len(point)):
        j = point[i]
        m = material[j]
        wi[i, 0], wi[i, 1], wi[i, 2], ok = _first_direction(
            wo[j, 0], wo[j, 1], wo[j, 2], normal[j, 0], normal[j, 1], normal[j, 2], u[i, 0],
            u[i, 1], lobe, q[m], exponent[m])
        valid[i] = ok and traced[m]


@numba.njit(cache=True)
def fan_directions(blocked, shift, base, order, count, lo, hi, samples, wo, normal, material,
                   traced, path, direction):
    """The first directions that points ``lo`` to ``hi`` take from their sky fans.

    Path s < ``count`` of point i takes the fan's sample ``order[s]``: the cosine-weighted
    direction about ``normal[i]`` of the pattern point ``base[order[s]]`` rotated by
    ``shift[i]`` (modulo 1), as the fan draws it. Only the samples flagged in ``blocked``
    (N, M) are kept (all where it has no rows), and only those of materials ``traced``.

    Writes the kept paths' indices (i · samples + s) into ``path`` and their directions into
    ``direction``, in the order of the points and their samples; returns their number.
    """
    flags = blocked.shape[0] > 0
    kept = 0
    for i in range(lo, hi):
        if not traced[material[i]]:
            continue
        for s in range(count):
            j = order[s]
            if flags and not blocked[i, j]:
                continue
            u1 = base[j, 0] + shift[i, 0]
            u1 = u1 - 1.0 if u1 >= 1.0 else u1
            u2 = base[j, 1] + shift[i, 1]
            u2 = u2 - 1.0 if u2 >= 1.0 else u2
            dx, dy, dz, ok = _first_direction(wo[i, 0], wo[i, 1], wo[i, 2], normal[i, 0],
                                              normal[i, 1], normal[i, 2], u1, u2, False, 1.0,
                                              0.0)
            if not ok:
                continue
            path[kept] = i * samples + s
            direction[kept, 0], direction[kept, 1], direction[kept, 2] = dx, dy, dz
            kept += 1
    return kept


@numba.njit(parallel=True, cache=True)
def lobe_weights(wi, wo, normal, material, q, exponent, specular, weight):
    """The weights of directions drawn from the Phong lobes alone with probability q:
    ρ_s f_lobe cos θ_i / (q · pdf_lobe) per band into ``weight`` (N, B), f_lobe and pdf_lobe
    those of a lobe of unit albedo (0 below the horizon or at pdf 0)."""
    n_b = specular.shape[1]
    for i in numba.prange(len(material)):
        m = material[i]
        mu_i = wi[i, 0] * normal[i, 0] + wi[i, 1] * normal[i, 1] + wi[i, 2] * normal[i, 2]
        mu_o = wo[i, 0] * normal[i, 0] + wo[i, 1] * normal[i, 1] + wo[i, 2] * normal[i, 2]
        cos_g = min(max(wi[i, 0] * wo[i, 0] + wi[i, 1] * wo[i, 1] + wi[i, 2] * wo[i, 2],
                        -1.0), 1.0)
        n = exponent[m]
        cos_a = 2.0 * mu_i * mu_o - cos_g
        pdf = (max(cos_a, 0.0) ** n) * ((n + 1.0) / _TWO_PI) if cos_a >= 0.0 else 0.0
        if not (mu_i > 0.0 and mu_o > 0.0 and pdf > 0.0 and math.isfinite(pdf)):
            for b in range(n_b):
                weight[i, b] = 0.0
            continue
        scale = _lobe_f(mu_i, mu_o, cos_g, n) * mu_i / (q[m] * pdf)
        for b in range(n_b):
            weight[i, b] = specular[m, b] * scale


@numba.njit(cache=True)
def add_rows(out, rows, values):
    """out[rows[i]] += values[i] for each i in order (rows may repeat)."""
    for i in range(len(rows)):
        r = rows[i]
        for b in range(out.shape[1]):
            out[r, b] += values[i, b]
