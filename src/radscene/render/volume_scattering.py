"""Sunlight scattered once by a participating volume (:mod:`radscene.render.volumes`).

For a single-scattering albedo ω > 0 a volume sends towards the sensor the direct sun it
scatters once; the Henyey–Greenstein phase function sets how much goes which way. The marched
estimate and its per-ray reference live here, the volume geometry in
:mod:`radscene.render.volumes`.
"""

from __future__ import annotations

import math

import numpy as np

from radscene.render.volumes import (
    MARCH_STEPS,
    density,
    entry_exit,
    optical_path,
    optical_path_reference,
)

__all__ = ["phase_function", "single_scattering", "single_scattering_reference"]


def phase_function(cos_scattering, asymmetry=0.0):
    """Henyey–Greenstein phase function P(Θ) normalised to ∫ P dΩ = 4π [-] (1 for isotropic
    scattering, ``asymmetry`` g = 0); Henyey & Greenstein 1941, ApJ 93, 70,
    doi:10.1086/144246."""
    g = float(asymmetry)
    return (1.0 - g * g) / (1.0 + g * g - 2.0 * g * np.asarray(cos_scattering)) ** 1.5


def single_scattering(volume, extinction, weights, source, origins, directions, t_max,
                      sun_dir, steps: int = MARCH_STEPS, sun_steps: int = 16) -> np.ndarray:
    """Band radiance of sunlight scattered once by a volume towards each ray's origin (N,)
    [W m-2 sr-1].

    .. math::

        L = Σ_q w_q S_q \\frac{ω P(Θ)}{4π} k_q ∫ ρ(s) e^{−k_q (X(s) + Y(s))} ds

    with X(s) the density-weighted path from the ray's entry to s, Y(s) that from s to the
    sun out of the volume, Θ the scattering angle (cos Θ = sun · direction) and ``source``
    S_q = E_sun τ_so τ_a (q,) [W m-2 um-1]: the midpoint rule in ``steps`` steps over the
    chord, Y by :func:`optical_path` (``sun_steps`` steps where the profile is not uniform).
    Shadows of other volumes and surfaces on the sun's path inside it are left out.
    """
    origins = np.asarray(origins, dtype=float)
    directions = np.asarray(directions, dtype=float)
    sun = np.reshape(np.asarray(sun_dir, dtype=float), (3,))
    near, far = entry_exit(volume, origins, directions)
    t0 = np.maximum(near, 0.0)
    t1 = np.minimum(far, np.asarray(t_max, dtype=float))
    length = np.where(t1 > t0, t1 - t0, 0.0)
    out = np.zeros(len(origins))
    cross = np.flatnonzero(length > 0.0)
    k = np.asarray(extinction, dtype=float)
    factor = weights * np.asarray(source, dtype=float) * k * volume.albedo / (4.0 * np.pi)
    chunk = max(1, (1 << 22) // (steps * max(k.size, 1)))
    for start in range(0, len(cross), chunk):
        idx = cross[start:start + chunk]
        dt = length[idx] / steps
        t = t0[idx, None] + (np.arange(steps) + 0.5)[None, :] * dt[:, None]
        pts = (origins[idx, None, :] + t[..., None] * directions[idx, None, :]).reshape(-1, 3)
        rho = density(volume, pts).reshape(len(idx), steps) * dt[:, None]  # ρ Δ
        view = np.cumsum(rho, axis=1) - 0.5 * rho  # X at the step's midpoint
        to_sun = optical_path(volume, pts, np.broadcast_to(sun, pts.shape),
                              steps=sun_steps).reshape(len(idx), steps)
        phase = phase_function(directions[idx] @ sun, volume.asymmetry)
        depth = (view + to_sun)[..., None] * k  # (n, steps, q)
        out[idx] = phase * np.einsum("ns,nsq,q->n", rho, np.exp(-depth), factor)
    return out


def single_scattering_reference(volume, wavelength_extinction, source, origin, direction,
                                t_max, sun_dir, steps: int = MARCH_STEPS,
                                sun_steps: int = 16) -> float:
    """:func:`single_scattering` of one ray at one wavelength of weight 1, step by step."""
    d = [float(v) for v in direction]
    o = [float(v) for v in origin]
    sun = [float(v) for v in np.reshape(sun_dir, (3,))]
    near, far = (float(v[0]) for v in entry_exit(volume, [o], [d]))
    t0, t1 = max(near, 0.0), min(far, float(t_max))
    if t1 <= t0:
        return 0.0
    k = float(wavelength_extinction)
    dt = (t1 - t0) / steps
    cos_theta = sum(a * b for a, b in zip(d, sun, strict=True))
    g = volume.asymmetry
    phase = (1.0 - g * g) / (1.0 + g * g - 2.0 * g * cos_theta) ** 1.5
    total, view = 0.0, 0.0
    for i in range(steps):
        t = t0 + (i + 0.5) * dt
        p = [o[c] + t * d[c] for c in range(3)]
        rho = float(density(volume, [p])[0])
        to_sun = optical_path_reference(volume, p, sun, steps=sun_steps)
        total += rho * dt * math.exp(-k * (view + 0.5 * rho * dt + to_sun))
        view += rho * dt
    return float(source) * volume.albedo * phase / (4.0 * math.pi) * k * total
