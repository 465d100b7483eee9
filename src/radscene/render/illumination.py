"""Illumination queries by ray: shadows, the visible sky over the hemisphere and under a lobe.

Rays leave a hit point offset along the surface normal so that they do not find their own
surface again. Sample patterns are stratified over the unit square and rotated per hit point
(Cranley–Patterson), with a seeded generator, so renders are repeatable.
"""

from __future__ import annotations

import numpy as np

from radscene.atmosphere import sky_node_weights

__all__ = [
    "stratified_pattern",
    "stratified_square",
    "cast_shadow",
    "sky_fractions",
    "sky_sums",
    "lobe_sky_fractions",
    "sky_fractions_reference",
    "lobe_sky_fractions_reference",
]


def stratified_pattern(n_samples: int) -> np.ndarray:
    """A stratified pattern of ``n_samples`` points on the unit square, shape (M, 2).

    A square number of samples gets one point at the centre of each cell of a regular grid;
    otherwise the first coordinate is stratified and the second follows the golden-ratio
    sequence.
    """
    side = int(np.floor(np.sqrt(n_samples)))
    if side * side == n_samples:
        i, j = np.divmod(np.arange(n_samples), side)
        return np.stack([(i + 0.5) / side, (j + 0.5) / side], axis=1)
    k = np.arange(n_samples)
    return np.stack([(k + 0.5) / n_samples, (k * 0.6180339887498949) % 1.0], axis=1)


def stratified_square(n_points: int, n_samples: int, rng: np.random.Generator):
    """The stratified pattern, rotated independently for each of ``n_points`` (Cranley–Patterson).

    Draws ``rng.random((n_points, 2))`` once, as the compiled fans do.

    Returns
    -------
    u1, u2 : numpy.ndarray
        Shape (n_points, n_samples) in [0, 1).
    """
    base = stratified_pattern(n_samples)
    shift = rng.random((n_points, 2))
    u1 = (base[None, :, 0] + shift[:, :1]) % 1.0
    u2 = (base[None, :, 1] + shift[:, 1:]) % 1.0
    return u1, u2


def cast_shadow(tracer, origins, sun_direction) -> np.ndarray:
    """1.0 where the sun is seen from ``origins`` (already offset from the surface), else 0.0.

    Parameters
    ----------
    tracer : radscene.geometry.RayTracer
    origins : (N, 3) [m]
    sun_direction : (3,) or (N, 3) unit vector towards the sun, one for all origins or one
        each (a scanner's rays see the sun of their own times)
    """
    if len(origins) == 0:
        return np.zeros(0)
    sun = np.asarray(sun_direction, dtype=float).reshape(-1, 3)
    if len(sun) not in (1, len(origins)):
        raise ValueError(f"sun_direction: one vector or one per origin ({len(origins)}); "
                         f"got {len(sun)}")
    length = np.linalg.norm(sun, axis=1)
    local = tracer.to_local(origins)
    if local is None or not (np.all(np.isfinite(sun)) and np.all(length > 0.0)):
        # points outside the scene's box, or bad input: the checked, clipped query
        dirs = np.broadcast_to(sun, np.shape(origins))
        return 1.0 - tracer.occluded(origins, dirs).astype(float)
    # the fast path: the origins lie in the box, so the clipped query would trace them as
    # they are; the direction is normalised as the checked query does
    unit = (sun / length[:, None]).astype(np.float32)
    dirs = np.repeat(unit, len(local), axis=0) if len(unit) == 1 else unit
    return 1.0 - tracer.occluded_local(local, dirs).astype(float)


def _visible_fractions(tracer, origins, directions, weights, sky_nodes):
    """Mean over samples of visibility × weight × sky-node weight; directions (N, M, 3)."""
    n, m, _ = directions.shape
    up = directions[..., 2] > 0.0
    visible = np.zeros((n, m), dtype=bool)
    if np.any(up):
        idx = np.nonzero(up)
        o = np.repeat(origins, m, axis=0).reshape(n, m, 3)[idx]
        visible[idx] = ~tracer.occluded(o, directions[idx])
    zenith_nodes, azimuth_nodes = _node_grids(sky_nodes)
    zenith = np.degrees(np.arccos(np.clip(directions[..., 2], -1.0, 1.0)))
    azimuth = np.degrees(np.arctan2(directions[..., 0], directions[..., 1]))
    hats = sky_node_weights(zenith, azimuth, zenith_nodes, azimuth_nodes)  # (N, M, K·L)
    return np.einsum("nm,nmk->nk", visible * weights, hats) / m


def _node_grids(sky_nodes):
    """(zenith nodes, azimuth nodes) from either a pair or a bare zenith grid [deg]."""
    if isinstance(sky_nodes, tuple):
        return np.asarray(sky_nodes[0], float), np.asarray(sky_nodes[1], float)
    return np.asarray(sky_nodes, float), np.array([0.0])


def sky_fractions_reference(tracer, origins, normals, n_samples, zenith_nodes, rng):
    """Cosine-weighted visible-sky fractions F_k per sky zenith node.

    F_k = (1/π) ∫_{visible sky} h_k(ω) cos θ dω, estimated with ``n_samples`` cosine-
    distributed directions about the normal; Σ_k F_k is the sky-view factor (1 for an open
    horizontal plane). Directions below the horizon never count as sky.

    Returns
    -------
    numpy.ndarray
        Shape (N, n_k) [-].
    """
    from radscene.materials.brdf import lambertian

    n = len(origins)
    if n == 0:
        zn, an = _node_grids(zenith_nodes)
        return np.zeros((0, zn.size * an.size))
    u1, u2 = stratified_square(n, n_samples, rng)
    axis = np.repeat(normals[:, None, :], n_samples, axis=1)
    directions, _ = lambertian.sample(axis, u1, u2)
    return _visible_fractions(tracer, origins, directions, 1.0, zenith_nodes)


def lobe_sky_fractions_reference(tracer, origins, normals, axes, exponents, n_samples,
                                 zenith_nodes, rng):
    """Visible-sky fractions G_k under the Phong lobe about ``axes``.

    Directions are drawn from the lobe's own distribution (n+1)/(2π) cosⁿ α, so G_k is the
    share of the lobe that sees sky node k; lobe directions below the surface or the horizon
    do not count.

    Returns
    -------
    numpy.ndarray
        Shape (N, n_k) [-].
    """
    from radscene.materials.brdf import phong

    n = len(origins)
    if n == 0:
        zn, an = _node_grids(zenith_nodes)
        return np.zeros((0, zn.size * an.size))
    u1, u2 = stratified_square(n, n_samples, rng)
    axis = np.repeat(axes[:, None, :], n_samples, axis=1)
    expo = np.repeat(np.asarray(exponents, dtype=float)[:, None], n_samples, axis=1)
    directions, _ = phong.sample(axis, expo, u1, u2)
    above_surface = np.einsum("nmc,nc->nm", directions, normals) > 0.0
    return _visible_fractions(tracer, origins, directions, above_surface, zenith_nodes)


def _fan_setup(origins, normals, n_samples, rng, shift):
    """The fans' inputs: (shift (N, 2), pattern (M, 2), its side or 0, positions, normals)."""
    n = len(origins)
    if shift is None:
        shift = rng.random((n, 2))
    elif np.shape(shift) != (n, 2):
        raise ValueError(f"shift must have shape ({n}, 2), got {np.shape(shift)}")
    base = stratified_pattern(n_samples)
    side = int(np.floor(np.sqrt(n_samples)))
    side = side if side * side == n_samples else 0  # the pattern is the regular grid
    return (shift, base, side, np.ascontiguousarray(origins, dtype=np.float64),
            np.ascontiguousarray(normals, dtype=np.float64))


def _trace_fan(tracer, fan, origins, normals, extra, n_samples, rng, shift, scratch):
    """Generate and trace one fan per point: (occluded (N·n,), float32 directions (N·n, 3),
    float64 normals (N, 3))."""
    from radscene.render import kernels

    shift, base, side, pos, nrm = _fan_setup(origins, normals, n_samples, rng, shift)
    o32, d32 = kernels.empty_fan(len(pos) * n_samples, scratch)
    fan(pos, nrm, *extra, tracer.center, 0.0, shift, base, side, o32, d32)
    return tracer.occluded_local(o32, d32), d32, nrm


def _fan_fractions(tracer, fan, origins, normals, extra, n_samples, zenith_nodes, rng,
                   check_normal, shift=None, scratch=None, blocked=None):
    from radscene.render import kernels

    n = len(origins)
    zen_nodes, az_nodes = _node_grids(zenith_nodes)
    out = np.empty((n, zen_nodes.size * az_nodes.size))
    if n == 0:
        return out
    packets = getattr(tracer, "packets", None)
    if packets is not None:  # each point's fan traced as Embree packets inside the kernel
        shift, base, side, pos, nrm = _fan_setup(origins, normals, n_samples, rng, shift)
        axis, exponent = extra if extra else (nrm, np.zeros(0))
        kernels.packet_fractions(packets, pos, nrm, np.ascontiguousarray(axis, np.float64),
                                 np.ascontiguousarray(exponent, np.float64), bool(extra),
                                 tracer.center, 0.0, shift, base, side, check_normal, zen_nodes,
                                 az_nodes, out, blocked=blocked)
        return out
    occluded, d32, nrm = _trace_fan(tracer, fan, origins, normals, extra, n_samples, rng, shift,
                                    scratch)
    kernels.fold_fractions(occluded, d32, nrm, check_normal, zen_nodes, az_nodes, n_samples, out)
    _not_sky(occluded, d32, blocked)
    return out


def _not_sky(occluded, directions, blocked):
    """Fill ``blocked`` (N, M), where given, with the traced fan's directions that are not
    sky: occluded, or at or below the horizon."""
    if blocked is not None:
        blocked[...] = (occluded | (directions[:, 2] <= 0.0)).reshape(blocked.shape)


def sky_sums(tracer, origins, normals, n_samples, sky_nodes, rng, *, rank, material, index,
             weight, table, shift=None, scratch=None, blocked=None):
    """The reflected-sky band sums and the sky-view factor of each point, from the same fan
    as :func:`sky_fractions`, without storing the fractions.

    ``sums[i, b] = Σ_s weight[h, s] Σ_k F_ik table[material[i], index[h, s], b, k]`` with
    ``h = rank[i]`` and F the fractions :func:`sky_fractions` returns for the same arguments;
    ``view[i] = Σ_k F_ik``. With ~100 sky nodes F is larger than everything else a tile holds:
    folding each point's fan straight into its band sums keeps it in cache.

    Parameters
    ----------
    tracer, origins, normals, n_samples, sky_nodes, rng, shift, scratch, blocked
        As for :func:`sky_fractions`.
    rank : (N,) int — each point's row of ``index`` and ``weight``
    material : (N,) int — each point's row of ``table``
    index, weight : (H, S) — path nodes and their weights, as
        :func:`radscene.render.node_mixing.mix_sky` takes them
    table : (n_m, n_j, n_b, K) — band sky coefficients per material, path node, band, sky node

    Returns
    -------
    sums : numpy.ndarray
        Shape (N, n_b).
    view : numpy.ndarray
        Shape (N,).
    """
    from radscene.render import kernels

    n = len(origins)
    zen_nodes, az_nodes = _node_grids(sky_nodes)
    table = np.ascontiguousarray(table, dtype=np.float64)
    if table.ndim != 4 or table.shape[3] != zen_nodes.size * az_nodes.size:
        raise ValueError(f"table must be (materials, path nodes, bands, "
                         f"{zen_nodes.size * az_nodes.size}); got {table.shape}")
    sums, view = np.empty((n, table.shape[2])), np.empty(n)
    if n == 0:
        return sums, view
    mix = (np.ascontiguousarray(rank, dtype=np.int64),
           np.ascontiguousarray(material, dtype=np.int64),
           np.ascontiguousarray(index, dtype=np.int64),
           np.ascontiguousarray(weight, dtype=np.float64), table, sums, view)
    packets = getattr(tracer, "packets", None)
    if packets is not None:  # each point's fan traced as Embree packets inside the kernel
        shift, base, side, pos, nrm = _fan_setup(origins, normals, n_samples, rng, shift)
        kernels.packet_sky_sums(packets, pos, nrm, tracer.center, 0.0, shift, base, side,
                                zen_nodes, az_nodes, *mix, blocked=blocked)
        return sums, view
    occluded, d32, nrm = _trace_fan(tracer, kernels.cosine_fan, origins, normals, (), n_samples,
                                    rng, shift, scratch)
    kernels.fold_sky_sums(occluded, d32, nrm, False, zen_nodes, az_nodes, n_samples, *mix)
    _not_sky(occluded, d32, blocked)
    return sums, view


def sky_fractions(tracer, origins, normals, n_samples, zenith_nodes, rng, *, shift=None,
                  scratch=None, blocked=None):
    """Cosine-weighted visible-sky fractions F_k per sky zenith node (compiled fan).

    Same estimator and the same random numbers as :func:`sky_fractions_reference`: F_k =
    (1/π) ∫_{visible sky} h_k(ω) cos θ dω from ``n_samples`` stratified cosine-distributed
    directions per point; directions below the horizon never count as sky.

    Parameters
    ----------
    tracer : radscene.geometry.RayTracer
    origins : (N, 3) ray origins, already offset from the surface [m]
    normals : (N, 3) unit normals
    n_samples : int
    zenith_nodes : (K,) sky zenith nodes [deg], or a pair (zenith nodes, azimuth nodes) of
        the sky grid; the result has one column per node, zenith major
    rng : numpy.random.Generator
    shift : (N, 2) array, optional
        The per-point rotations, already drawn (as ``rng.random((N, 2))``): lets a caller draw
        them in a fixed order and trace on another thread; ``rng`` is then not used.
    scratch : dict, optional
        Kept by the caller between calls: the float32 ray buffers are reused from it.
    blocked : (N, n_samples) bool array, optional
        Filled with the fan's directions that are not sky — occluded by the scene, or at or
        below the horizon (those are not traced) — for the reflected background, which
        intersects them (:mod:`radscene.render.background`); sample j of point i at [i, j],
        in the pattern's order (:func:`stratified_pattern`).

    Returns
    -------
    numpy.ndarray
        Shape (N, K) [-].
    """
    from radscene.render import kernels

    return _fan_fractions(tracer, kernels.cosine_fan, origins, normals, (), n_samples,
                          zenith_nodes, rng, False, shift, scratch, blocked)


def lobe_sky_fractions(tracer, origins, normals, axes, exponents, n_samples, zenith_nodes, rng,
                       *, shift=None, scratch=None):
    """Visible-sky fractions G_k under the Phong lobe about ``axes`` (compiled fan).

    Same estimator and random numbers as :func:`lobe_sky_fractions_reference`; ``shift`` and
    ``scratch`` as in :func:`sky_fractions`.

    Returns
    -------
    numpy.ndarray
        Shape (N, K) [-].
    """
    from radscene.render import kernels

    extra = (np.ascontiguousarray(axes, dtype=np.float64),
             np.ascontiguousarray(exponents, dtype=np.float64))
    return _fan_fractions(tracer, kernels.lobe_fan, origins, normals, extra, n_samples,
                          zenith_nodes, rng, True, shift, scratch)
