"""The first vertex of the reflected background's paths: the hit's own BRDF, split by lobe.

From a hit x of a plain material (ρ_d, ρ_s, n; the registry's ``phong`` model) each of the
``samples`` paths has up to two first directions, one per part of the BRDF:

* its **diffuse** direction, cosine-weighted, weight ρ_d (f cos θ / pdf of the Lambertian
  part). Path s < M takes the render's sky fan (:func:`radscene.render.illumination.
  sky_sums`): the fan's sample ``fan_order(M)[s]``, the stratified pattern's point rotated
  by the hit's own shift (Cranley–Patterson), so that only the fan's directions that the sky
  pass found blocked are traced again (for their hit); the paths beyond the fan's M draw their
  direction from their own uniforms;
* its **lobe** direction, drawn with probability q = ρ_s / (ρ_d + ρ_s) (the sampler's weight
  of :func:`radscene.render.background_tables.band_tables`; 1 where that is 0 but ρ_s is not)
  from the Phong lobe alone, weight ρ_s f_lobe cos θ / (q pdf_lobe), its uniforms those of
  path index P + path (P = points × samples), so that they are independent of the diffuse
  direction's.

Each direction is drawn with the density it is weighted by, whatever the others are: the sum is
an unbiased estimate of ∫ f L cos θ dω for every split. A material with a BRDF model draws one
direction per path through its registry ``sample`` (no split).

Which fan sample a path takes: the k-th point of the Sobol' (0, 2)-sequence (Sobol' 1967;
the first two dimensions, offset by half of its finest cell) is matched to the nearest fan
sample not yet taken (distances on the torus). For a square fan of side 2^m the first M points
fall one in each of the pattern's cells, so the order is a permutation in which the first
2^j samples fall in distinct rows and columns of the pattern at every scale (a (0, j, 2)-net):
the paths that use part of the fan still spread over it.

References
----------
I. M. Sobol', "On the distribution of points in a cube and the approximate evaluation of
integrals", USSR Comput. Math. Math. Phys. 7(4), 86-112 (1967),
doi:10.1016/0041-5553(67)90144-9.
R. Cranley, T. N. L. Patterson, "Randomization of number theoretic methods for multiple
integration", SIAM J. Numer. Anal. 13(6), 904-914 (1976), doi:10.1137/0713071.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache

import numpy as np

from radscene.render import background_kernels as kernels
from radscene.render.background_tables import brdf_weight, brdf_weight_reference, directions

__all__ = ["Fan", "fan_order", "sobol_points", "lobe_probability", "first_vertices",
           "first_reference", "take", "concat"]


@dataclass(frozen=True)
class Fan:
    """A tile's sky fan, as the render traced it for the reflected sky.

    Attributes
    ----------
    shift : (N, 2) float — each point's rotation of the pattern, in [0, 1)
    samples : int — the fan's directions per point M (``sky_samples``)
    blocked : (N, M) bool or None — the fan's directions that are not sky: occluded, or at or
        below the horizon (:func:`radscene.render.illumination.sky_fractions`); None: not
        known, every fan direction is intersected
    """

    shift: np.ndarray
    samples: int
    blocked: np.ndarray | None = None

    def uniforms(self, point, sample) -> np.ndarray:
        """(P, 2) rotated pattern points of fan samples ``sample`` of points ``point``."""
        from radscene.render.illumination import stratified_pattern

        u = stratified_pattern(self.samples)[sample] + self.shift[point]
        return np.where(u >= 1.0, u - 1.0, u)


def sobol_points(n: int) -> np.ndarray:
    """The first ``n`` points of the two-dimensional Sobol' sequence, (n, 2) in [0, 1): the van
    der Corput sequence in base 2 and Sobol's second dimension (direction numbers
    v_1 = 1/2, v_(k+1) = v_k XOR v_k / 2)."""
    k = np.arange(n, dtype=np.uint64)
    x, y = np.zeros(n, np.uint64), np.zeros(n, np.uint64)
    first, second = np.uint64(1 << 31), np.uint64(1 << 31)
    for bit in range(32):
        on = ((k >> np.uint64(bit)) & np.uint64(1)).astype(bool)
        x[on] ^= first
        y[on] ^= second
        first >>= np.uint64(1)
        second ^= second >> np.uint64(1)
    return np.stack([x, y], axis=1).astype(float) / 2.0**32


@lru_cache(maxsize=32)
def _order(n_samples: int) -> tuple:
    from radscene.render.illumination import stratified_pattern

    base = stratified_pattern(n_samples)
    finest = 2.0 ** -np.ceil(np.log2(max(n_samples, 1)))
    targets = (sobol_points(n_samples) + 0.5 * finest) % 1.0
    free = np.ones(n_samples, dtype=bool)
    order = np.empty(n_samples, dtype=np.int64)
    for k, target in enumerate(targets):
        gap = np.abs(base - target)
        gap = np.minimum(gap, 1.0 - gap)
        distance = np.where(free, np.einsum("mc,mc->m", gap, gap), np.inf)
        order[k] = int(np.argmin(distance))
        free[order[k]] = False
    return tuple(order)


def fan_order(n_samples: int) -> np.ndarray:
    """The fan sample (0 … M − 1, :func:`radscene.render.illumination.stratified_pattern`'s
    order) that path s of a point takes, for s < M = ``n_samples``: a permutation (see the
    module's description)."""
    return np.array(_order(int(n_samples)), dtype=np.int64)


def lobe_probability(tables) -> np.ndarray:
    """(n_m,) the probability q that a plain material's path draws a lobe direction."""
    return np.where(tables.p_lobe > 0.0, tables.p_lobe, 1.0)


def _parts(tables):
    """(modelled, diffuse, lobe) (n_m,) bool: materials with a BRDF model; plain ones with a
    diffuse part, with a lobe."""
    modelled = np.zeros(len(tables.exponent), dtype=bool)
    modelled[list(tables.brdfs)] = True
    return (modelled, np.any(tables.diffuse > 0.0, axis=1) & ~modelled,
            np.any(tables.specular > 0.0, axis=1) & ~modelled)


def first_vertices(tracer, tables, origin, normal, wo, material, u, fan, lo, hi, kept=None,
                   record=None, active=None):
    """The first vertices of the paths of points ``lo`` to ``hi`` that meet the scene.

    ``kept`` (:meth:`radscene.render.frame_cache.FrameCache.background`), where given: the
    last frame's answers of the drawn directions (diffuse and lobe), taken where nothing moved
    through them, and this frame's written into ``kept.out``. The fan's directions come with
    the fan's ``blocked`` flags (kept or traced by the sky pass). ``record``, where given, is
    called as ``record(points, directions)`` with every direction drawn beyond the fan, met
    or not (:mod:`radscene.render.background_record`). ``active`` (N,) bool, where given: only
    those points' paths are returned (every point's directions are still drawn, and answered
    with ``kept``).

    Returns (path indices (P,), their points (P,), directions (P, 3), Hits, weights
    (P, n_b)): the fan's diffuse directions, the drawn diffuse ones, the lobes' and those of
    the BRDF models, in that order, each in the order of its points and samples.
    """
    samples = u.samples
    modelled, diffuse, lobe = _parts(tables)
    q = lobe_probability(tables)
    count = 0 if fan is None else min(samples, fan.samples)
    groups = []  # (path indices, points, directions) of the diffuse parts, then the lobes'
    if count and np.any(diffuse[material[lo:hi]]):
        size = (hi - lo) * count
        path, d = np.empty(size, np.int64), np.empty((size, 3))
        blocked = np.zeros((0, fan.samples), dtype=bool) if fan.blocked is None else fan.blocked
        taken = kernels.fan_directions(blocked, np.ascontiguousarray(fan.shift, np.float64),
                                       _pattern(fan.samples), fan_order(fan.samples), count, lo,
                                       hi, samples, wo, normal, material, diffuse, path, d)
        groups.append((path[:taken], path[:taken] // samples, d[:taken]))
    offset = u.points * samples  # the lobes' path indices
    n_diffuse = 0
    for lobes, parts, first, at in ((False, diffuse, count, 0), (True, lobe, 0, offset)):
        if first < samples and np.any(parts[material[lo:hi]]):
            path, d = _drawn(tracer, tables, origin, normal, wo, material, u, lo, hi, first,
                             at, lobes, parts, q, kept, record)
            groups.append((path, (path - at) // samples, d))
        if not lobes:
            n_diffuse = sum(len(g[0]) for g in groups)
    if kept is not None:
        kept.out.filled[lo:hi] = True
    if groups:
        paths, point, d = (np.concatenate(part) for part in zip(*groups, strict=True))
    else:
        paths, point, d = np.zeros(0, np.int64), np.zeros(0, np.int64), np.zeros((0, 3))
    if active is not None:
        chosen = active[point]
        n_diffuse = int(np.count_nonzero(chosen[:n_diffuse]))
        paths, point, d = paths[chosen], point[chosen], d[chosen]
    hits = tracer.intersect(origin[point], d)
    keep = hits.hit
    beta = np.empty((len(paths), tables.bands))
    beta[:n_diffuse] = tables.diffuse[material[point[:n_diffuse]]]
    if n_diffuse < len(paths):
        at = slice(n_diffuse, None)
        kernels.lobe_weights(d[at], np.ascontiguousarray(wo[point[at]]),
                             np.ascontiguousarray(normal[point[at]]), material[point[at]], q,
                             tables.exponent, tables.specular, beta[at])
    paths, point, d, hits, beta = paths[keep], point[keep], d[keep], take(hits, keep), beta[keep]
    if not np.any(modelled[material[lo:hi]]):
        return paths, point, d, hits, beta
    # the materials with a BRDF model: one direction per path through the registry
    others = lo + np.flatnonzero(modelled[material[lo:hi]])
    if active is not None:
        others = others[active[others]]
    more = (others[:, None] * samples + np.arange(samples)).ravel()
    m_point = more // samples
    wi, valid = directions(tables, material, wo, normal, m_point, u.at(more, 0))
    alive = np.flatnonzero(valid)
    if record is not None:
        record(m_point[alive], wi[alive])
    m_hits = tracer.intersect(origin[m_point[alive]], wi[alive])
    alive = alive[m_hits.hit]
    m_point = m_point[alive]
    _, m_beta = brdf_weight(tables, material[m_point], wo[m_point], normal[m_point],
                            u.at(more[alive], 0))
    return (np.concatenate([paths, more[alive]]), np.concatenate([point, m_point]),
            np.concatenate([d, wi[alive]]), concat(hits, take(m_hits, m_hits.hit)),
            np.concatenate([beta, m_beta]))


def _pattern(n_samples):
    from radscene.render.illumination import stratified_pattern

    return np.ascontiguousarray(stratified_pattern(n_samples), dtype=np.float64)


def _drawn(tracer, tables, origin, normal, wo, material, u, lo, hi, first, offset, lobe,
           traced, q, kept=None, record=None):
    """The drawn first directions of samples ``first`` … of points ``lo`` to ``hi`` that may
    meet the scene: (path indices, directions). With Embree's packets only the blocked ones
    (:func:`~radscene.render.background_kernels.first_blocked`, with ``kept`` as
    :func:`first_vertices` takes it); else every valid one."""
    samples = u.samples
    packets = tracer.packets
    if packets is None:
        path = (np.arange(lo, hi)[:, None] * samples + np.arange(first, samples)).ravel()
        point = path // samples
        wi, valid = np.empty((len(path), 3)), np.empty(len(path), dtype=bool)
        kernels.first_directions(wo, normal, point, u.at(path + offset, 0), material, traced,
                                 q, tables.exponent, lobe, wi, valid)
        if record is not None:
            record(point[valid], wi[valid])
        return path[valid] + offset, wi[valid]
    n = (hi - lo) * samples
    # rows not drawn stay zero
    direction = np.zeros((n, 3)) if record is not None else np.empty((n, 3))
    blocked = np.empty(n, dtype=bool)
    kernels.first_blocked(packets.occluded8, packets.handle, np.uint64(u.key), u.bounces + 1,
                          lo, hi, samples, first, offset, lobe, wo, normal, origin, material,
                          traced, q, tables.exponent, tracer.center, tracer.half_size,
                          direction, blocked, *(() if kept is None else
                                                (kept.retrace, kept.known, kept.spheres)))
    if kept is not None:  # path indices: the diffuse paths', then the lobes' (offset)
        kept.out.blocked[offset + lo * samples:offset + hi * samples] = blocked
    if record is not None:
        drawn = np.flatnonzero(np.any(direction != 0.0, axis=1))
        record(lo + drawn // samples, direction[drawn])
    rows = np.flatnonzero(blocked)
    return offset + lo * samples + rows, direction[rows]


def first_reference(tables, material, wo, normal, u, fan, point, sample):
    """The first directions of path ``sample`` of point ``point``, one at a time (the
    reference pass): [(path index, ω_i (1, 3), weight (1, n_b))], its diffuse then its lobe
    direction for a plain material, its registry model's for one with a BRDF model."""
    from radscene.materials.brdf import make_brdf

    i, s, m = point, sample, int(material[point])
    path = i * u.samples + s
    wo_i, n_i = wo[i:i + 1], normal[i:i + 1]
    wavelength = float(np.median(tables.centre))
    if m in tables.brdfs:
        wi, w = brdf_weight_reference(tables, material[i:i + 1], wo_i, n_i, u.at([path], 0))
        return [(path, wi, w)]
    out = []
    mu_o = float(wo_i[0] @ n_i[0])
    if np.any(tables.diffuse[m] > 0.0) and mu_o > 0.0:
        uniform = (fan.uniforms([i], [fan_order(fan.samples)[s]])
                   if fan is not None and s < fan.samples else u.at([path], 0))
        lambertian = make_brdf({"type": "lambertian", "reflectance": 1.0})
        wi, pdf = lambertian.sample(wo_i, uniform[:, 0], uniform[:, 1], wavelength, n_i)
        cos_i = float(wi[0] @ n_i[0])
        if cos_i > 0.0 and pdf[0] > 0.0:
            out.append((path, wi, (tables.diffuse[m] / np.pi * cos_i / pdf[0])[None, :]))
    q = float(lobe_probability(tables)[m])
    lobe_path = u.points * u.samples + path
    uniform = u.at([lobe_path], 0)
    if np.any(tables.specular[m] > 0.0) and mu_o > 0.0 and uniform[0, 0] < q:
        wi, pdf = tables.lobes[m].sample(wo_i, uniform[:, 0] / q, uniform[:, 1], wavelength,
                                         n_i)
        cos_i = float(wi[0] @ n_i[0])
        if cos_i > 0.0 and pdf[0] > 0.0 and np.isfinite(pdf[0]):
            f = tables.lobes[m].f(wi, wo_i, None, n_i)
            out.append((lobe_path, wi,
                        (tables.specular[m] * np.ravel(f)[0] * cos_i / (q * pdf[0]))[None, :]))
    return out


def concat(a, b):
    """Two Hits batches, one after the other."""
    from radscene.geometry.raytracer import Hits

    return Hits(*(np.concatenate([getattr(a, f), getattr(b, f)]) for f in
                  ("distance", "object", "primitive", "u", "v", "normal", "position", "hit")))


def take(hits, keep):
    """The rows ``keep`` of a Hits batch (object, primitive, normal, position, hit)."""
    from radscene.geometry.raytracer import Hits

    return Hits(hits.distance[keep], hits.object[keep], hits.primitive[keep], hits.u[keep],
                hits.v[keep], hits.normal[keep], hits.position[keep], hits.hit[keep])
