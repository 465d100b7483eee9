"""Illumination queries by ray: shadows, the visible sky over the hemisphere and under a lobe.

Rays leave a hit point offset along the surface normal so that they do not find their own
surface again. Sample patterns are stratified over the unit square and rotated per hit point
(Cranley–Patterson), with a seeded generator, so renders are repeatable.
"""

from __future__ import annotations

import numpy as np

from radscene.atmosphere import zenith_hat_weights

__all__ = ["stratified_square", "cast_shadow", "sky_fractions", "lobe_sky_fractions"]


def stratified_square(n_points: int, n_samples: int, rng: np.random.Generator):
    """Stratified points on the unit square, rotated independently for each of ``n_points``.

    Returns
    -------
    u1, u2 : numpy.ndarray
        Shape (n_points, n_samples) in [0, 1).
    """
    side = int(np.floor(np.sqrt(n_samples)))
    if side * side == n_samples:
        i, j = np.divmod(np.arange(n_samples), side)
        base1, base2 = (i + 0.5) / side, (j + 0.5) / side
    else:  # stratify the first coordinate, golden-ratio sequence on the second
        k = np.arange(n_samples)
        base1, base2 = (k + 0.5) / n_samples, (k * 0.6180339887498949) % 1.0
    shift = rng.random((n_points, 2))
    u1 = (base1[None, :] + shift[:, :1]) % 1.0
    u2 = (base2[None, :] + shift[:, 1:]) % 1.0
    return u1, u2


def cast_shadow(tracer, origins, sun_direction) -> np.ndarray:
    """1.0 where the sun is seen from ``origins`` (already offset from the surface), else 0.0.

    Parameters
    ----------
    tracer : radscene.geometry.RayTracer
    origins : (N, 3) [m]
    sun_direction : (3,) unit vector towards the sun
    """
    if len(origins) == 0:
        return np.zeros(0)
    dirs = np.broadcast_to(np.asarray(sun_direction, dtype=float), origins.shape)
    return 1.0 - tracer.occluded(origins, dirs).astype(float)


def _visible_fractions(tracer, origins, directions, weights, zenith_nodes):
    """Mean over samples of visibility × weight × hat_k(zenith); directions (N, M, 3)."""
    n, m, _ = directions.shape
    up = directions[..., 2] > 0.0
    visible = np.zeros((n, m), dtype=bool)
    if np.any(up):
        idx = np.nonzero(up)
        o = np.repeat(origins, m, axis=0).reshape(n, m, 3)[idx]
        visible[idx] = ~tracer.occluded(o, directions[idx])
    zenith = np.degrees(np.arccos(np.clip(directions[..., 2], -1.0, 1.0)))
    hats = zenith_hat_weights(zenith, zenith_nodes)  # (N, M, K)
    return np.einsum("nm,nmk->nk", visible * weights, hats) / m


def sky_fractions(tracer, origins, normals, n_samples, zenith_nodes, rng):
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
        return np.zeros((0, np.size(zenith_nodes)))
    u1, u2 = stratified_square(n, n_samples, rng)
    axis = np.repeat(normals[:, None, :], n_samples, axis=1)
    directions, _ = lambertian.sample(axis, u1, u2)
    return _visible_fractions(tracer, origins, directions, 1.0, zenith_nodes)


def lobe_sky_fractions(tracer, origins, normals, axes, exponents, n_samples, zenith_nodes, rng):
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
        return np.zeros((0, np.size(zenith_nodes)))
    u1, u2 = stratified_square(n, n_samples, rng)
    axis = np.repeat(axes[:, None, :], n_samples, axis=1)
    expo = np.repeat(np.asarray(exponents, dtype=float)[:, None], n_samples, axis=1)
    directions, _ = phong.sample(axis, expo, u1, u2)
    above_surface = np.einsum("nmc,nc->nm", directions, normals) > 0.0
    return _visible_fractions(tracer, origins, directions, above_surface, zenith_nodes)
