"""Participating volumes (smoke, dust, cloud, gas): Beer–Lambert transmittance and emission.

A volume is an axis-aligned box or ellipsoid filled with a medium of extinction coefficient
k(λ) [m-1] at relative density 1, scaled by a density profile ρ(x) [-] (uniform, exponential
in height, Gaussian about the centre, or a 3-D grid), single-scattering albedo ω and one
temperature T.
Along a ray the medium's optical depth is τ(λ) = k(λ) X with the density-weighted path
X = ∫ ρ ds [m] through the volume (the chord length for a uniform medium, ray marching
otherwise). A ray's radiance leaving the volume towards the sensor is

.. math::

    L = t(λ) L_{behind} + (1 − ω) (1 − t(λ)) B(λ, T),  \\qquad t(λ) = e^{−τ(λ)}

(the seeds' transmitted term, seed 000 eq. 1, and an isothermal slab's emission, exact for
ω = 0; for ω > 0 the absorbed share emits, and the direct sun scattered once is added as
``volume_scattered`` by :mod:`radscene.render.volume_scattering`; multiple scattering and
scattered sky and surface light are left out). Sun rays crossing a volume are attenuated by
the same t(λ) along their own path, which makes the shadows volumes cast partial.

The pass runs after the surface passes of a render, on its per-pixel layers: the layers of
the light from behind (every surface term; the path radiance only of pixels that see no
surface, where it is the sky's) are moved in the share of their pixel's samples that cross
a volume, times the volumes' band transmittance, into the ``transmitted`` layer; the
volumes' emission goes into ``volume_emission``, attenuated by the atmosphere between the
sensor and each volume's centre. With supersampling the pixel's mean transmittance
multiplies the pixel's mean radiance from behind (exact where that radiance does not vary
across the pixel's crossing samples).

Band transmittances are the response-weighted means ``∫ S e^{−k X} dλ / ∫ S dλ`` (exact for
a medium grey across the band); the emission is integrated spectrally with the band
response, ``∫ S τ_a (1 − ω)(1 − e^{−k X}) B dλ``.

A gas volume (:class:`radscene.materials.gas.GasAbsorption` as its ``extinction``) carries a
line-overlap parameter β(λ) too: its lines saturate, and a path's mean transmittance is
t = 1 − min(1, k X, √(k X β)) instead of e^{−k X} (:func:`path_transmittance`), in the same
integrals; the band's spectral nodes come from the gas model.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from radscene.render.sky_split import PART_LAYERS

__all__ = ["Volume", "VOLUME_TERMS", "VOLUME_LONG_NAMES", "MARCH_STEPS", "entry_exit",
           "density", "optical_path", "optical_path_reference", "path_transmittance",
           "band_transmittance",
           "band_emission", "line_of_sight", "sun_transmittance", "apply"]

#: Output layers of the volume pass, summed into the radiance after the other layers.
VOLUME_TERMS = ("transmitted", "volume_emission", "volume_scattered")
VOLUME_LONG_NAMES = {
    "transmitted": "radiance from behind semi-transparent volumes, attenuated by their "
                   "transmittance (Beer-Lambert)",
    "volume_emission": "thermal emission of volumes, (1 - albedo)(1 - t) B(T), through the "
                       "atmosphere to the sensor",
    "volume_scattered": "sunlight scattered once by volumes towards the sensor",
}
#: Midpoint-rule steps along a ray's chord through a non-uniform volume.
MARCH_STEPS = 64


@dataclass(frozen=True)
class Volume:
    """One participating volume (see the module docstring).

    Attributes
    ----------
    name : str
    shape : {"box", "ellipsoid"}
    center : numpy.ndarray
        (3,) centre in the scene frame [m].
    half_size : numpy.ndarray
        (3,) half edge lengths of the box, or the ellipsoid's semi-axes [m].
    extinction : callable
        k(λ) at relative density 1: wavelength [um] → [m-1].
    profile : {"uniform", "exponential", "gaussian"}
    scale_height : float
        Of the exponential profile, e-folding height above the volume's base [m].
    sigma : numpy.ndarray
        (3,) standard deviations of the Gaussian profile about the centre [m].
    density : float
        Relative density at the profile's reference (base or centre) [-].
    albedo : float
        Single-scattering albedo ω [-].
    temperature : float
        [K].
    wavelengths : numpy.ndarray
        Table wavelengths of k (kinks for the band quadrature) [um]; empty for a constant.
    asymmetry : float
        Henyey–Greenstein asymmetry parameter g of the scattering [-] (0: isotropic).
    grid : numpy.ndarray or None
        (n_z, n_y, n_x) relative density of the ``grid`` profile at nodes evenly spaced over
        the bounding box, corners included [-].
    line_overlap : callable or None
        β(λ): wavelength [um] → [-] of a gas's band model (``extinction`` then its weak-line
        absorption coefficient); None: Beer–Lambert.
    """

    name: str
    shape: str
    center: np.ndarray
    half_size: np.ndarray
    extinction: object
    profile: str = "uniform"
    scale_height: float = math.inf
    sigma: np.ndarray | None = None
    density: float = 1.0
    albedo: float = 0.0
    temperature: float = 293.15
    wavelengths: np.ndarray = field(default_factory=lambda: np.zeros(0))
    asymmetry: float = 0.0
    grid: np.ndarray | None = None
    line_overlap: object = None


def entry_exit(volume: Volume, origins, directions) -> tuple[np.ndarray, np.ndarray]:
    """Ray parameters where rays enter and leave a volume (N,), (N,) [m along the unit
    direction]; entry > exit where a ray misses it. Unbounded on both sides."""
    o = np.asarray(origins, dtype=float) - volume.center
    d = np.asarray(directions, dtype=float)
    h = volume.half_size
    if volume.shape == "box":
        with np.errstate(divide="ignore", invalid="ignore"):
            t1, t2 = (-h - o) / d, (h - o) / d
        inside = np.abs(o) <= h
        parallel = d == 0.0
        near = np.where(parallel, np.where(inside, -np.inf, np.inf), np.minimum(t1, t2))
        far = np.where(parallel, np.where(inside, np.inf, -np.inf), np.maximum(t1, t2))
        return near.max(axis=1), far.min(axis=1)
    os, ds = o / h, d / h  # the unit sphere's frame: |os + t ds| = 1
    a = np.einsum("nc,nc->n", ds, ds)
    b = np.einsum("nc,nc->n", os, ds)
    c = np.einsum("nc,nc->n", os, os) - 1.0
    disc = b * b - a * c
    root = np.sqrt(np.maximum(disc, 0.0))
    near = np.where(disc > 0.0, (-b - root) / a, np.inf)
    far = np.where(disc > 0.0, (-b + root) / a, -np.inf)
    return near, far


def density(volume: Volume, points) -> np.ndarray:
    """Relative density ρ [-] at points (N, 3) inside the volume (the profile, not clipped
    to the shape)."""
    p = np.asarray(points, dtype=float)
    if volume.profile == "uniform":
        return np.full(len(p), volume.density)
    if volume.profile == "exponential":
        base = volume.center[2] - volume.half_size[2]
        return volume.density * np.exp(-(p[:, 2] - base) / volume.scale_height)
    if volume.profile == "grid":
        return volume.density * _trilinear(volume, p)
    u = (p - volume.center) / volume.sigma
    return volume.density * np.exp(-0.5 * np.einsum("nc,nc->n", u, u))


def _trilinear(volume, points):
    """The grid profile at points (N, 3), trilinear between its nodes, 0 outside the box."""
    grid = volume.grid
    lo = volume.center - volume.half_size
    # node coordinates (x, y, z) → fractional indices (along the grid's x, y, z axes)
    steps = np.array(grid.shape[::-1], dtype=float) - 1.0
    f = (points - lo) / (2.0 * volume.half_size) * steps
    inside = np.all((f >= 0.0) & (f <= steps), axis=1)
    f = np.clip(f, 0.0, steps)
    i0 = np.minimum(np.floor(f).astype(np.int64), (steps - 1).astype(np.int64))
    t = f - i0
    out = np.zeros(len(points))
    for dx in (0, 1):
        for dy in (0, 1):
            for dz in (0, 1):
                w = ((t[:, 0] if dx else 1 - t[:, 0]) * (t[:, 1] if dy else 1 - t[:, 1])
                     * (t[:, 2] if dz else 1 - t[:, 2]))
                out += w * grid[i0[:, 2] + dz, i0[:, 1] + dy, i0[:, 0] + dx]
    return np.where(inside, out, 0.0)


def optical_path(volume: Volume, origins, directions, t_max=None,
                 steps: int = MARCH_STEPS) -> np.ndarray:
    """Density-weighted path X = ∫ ρ ds [m] of each ray through a volume, from its origin
    up to ``t_max`` [m] (N,; default unbounded).

    A uniform volume's X is its density times the chord length (exact); other profiles are
    marched with the midpoint rule in ``steps`` equal steps over the chord.
    """
    origins = np.asarray(origins, dtype=float)
    directions = np.asarray(directions, dtype=float)
    near, far = entry_exit(volume, origins, directions)
    t0 = np.maximum(near, 0.0)
    t1 = far if t_max is None else np.minimum(far, np.asarray(t_max, dtype=float))
    length = np.where(t1 > t0, t1 - t0, 0.0)
    if volume.profile == "uniform":
        return volume.density * length
    out = np.zeros(len(origins))
    cross = np.flatnonzero(length > 0.0)
    chunk = max(1, 1 << 20 // steps)
    for start in range(0, len(cross), chunk):
        idx = cross[start:start + chunk]
        dt = length[idx] / steps
        t = t0[idx, None] + (np.arange(steps) + 0.5)[None, :] * dt[:, None]  # (n, steps)
        pts = origins[idx, None, :] + t[..., None] * directions[idx, None, :]
        rho = density(volume, pts.reshape(-1, 3)).reshape(len(idx), steps)
        out[idx] = rho.sum(axis=1) * dt
    return out


def optical_path_reference(volume: Volume, origin, direction, t_max=math.inf,
                           steps: int = MARCH_STEPS) -> float:
    """:func:`optical_path` of one ray, written out step by step (the tests' oracle)."""
    ox, oy, oz = (float(v) for v in origin)
    dx, dy, dz = (float(v) for v in direction)
    cx, cy, cz = (float(v) for v in volume.center)
    hx, hy, hz = (float(v) for v in volume.half_size)
    if volume.shape == "box":
        near, far = -math.inf, math.inf
        for o, d, c, h in ((ox, dx, cx, hx), (oy, dy, cy, hy), (oz, dz, cz, hz)):
            if d == 0.0:
                if abs(o - c) > h:
                    return 0.0
                continue
            a, b = (c - h - o) / d, (c + h - o) / d
            near, far = max(near, min(a, b)), min(far, max(a, b))
    else:
        # |(o + t d - c) / h|^2 = 1, a quadratic in t
        qa = (dx / hx) ** 2 + (dy / hy) ** 2 + (dz / hz) ** 2
        qb = 2.0 * ((ox - cx) * dx / hx**2 + (oy - cy) * dy / hy**2 + (oz - cz) * dz / hz**2)
        qc = ((ox - cx) / hx) ** 2 + ((oy - cy) / hy) ** 2 + ((oz - cz) / hz) ** 2 - 1.0
        disc = qb * qb - 4.0 * qa * qc
        if disc <= 0.0:
            return 0.0
        near = (-qb - math.sqrt(disc)) / (2.0 * qa)
        far = (-qb + math.sqrt(disc)) / (2.0 * qa)
    t0, t1 = max(near, 0.0), min(far, t_max)
    if t1 <= t0:
        return 0.0
    if volume.profile == "uniform":
        return volume.density * (t1 - t0)
    total, dt = 0.0, (t1 - t0) / steps
    for i in range(steps):
        t = t0 + (i + 0.5) * dt
        total += float(density(volume, [[ox + t * dx, oy + t * dy, oz + t * dz]])[0]) * dt
    return total


def path_transmittance(depth, line_overlap=None) -> np.ndarray:
    """Mean transmittance [-] of paths of weak-line optical depth ``depth`` = k X [-]:
    e^{−kX} where ``line_overlap`` β is None or ``inf``, else a gas band's
    1 − min(1, kX, √(kX β)) (:func:`radscene.materials.gas.edwards.absorptance`)."""
    depth = np.asarray(depth, dtype=float)
    if line_overlap is None:
        return np.exp(-depth)
    from radscene.materials.gas.edwards import absorptance

    beta = np.broadcast_to(np.asarray(line_overlap, dtype=float), depth.shape)
    grey = np.isinf(beta)
    with np.errstate(invalid="ignore"):
        return np.where(grey, np.exp(-depth), 1.0 - absorptance(depth, np.where(grey, 1.0, beta)))


def band_transmittance(extinction, weights, path, line_overlap=None) -> np.ndarray:
    """Response-weighted band transmittance Σ w t(k X) / Σ w of paths X (N,) [m] through a
    medium of extinction ``extinction`` (q,) [m-1] at quadrature nodes of weights (q,) [um];
    t = e^{−kX}, or :func:`path_transmittance` with a gas's ``line_overlap`` β (q,) [-]."""
    path = np.asarray(path, dtype=float)
    k = np.asarray(extinction, dtype=float)
    out = np.empty(len(path))
    for at in _chunks(len(path), k.size):
        out[at] = path_transmittance(path[at, None] * k[None, :], line_overlap) @ weights
    return out / weights.sum()


def band_emission(extinction, weights, path, planck, albedo=0.0,
                  transmittance=1.0, line_overlap=None) -> np.ndarray:
    """Band emission Σ w τ_a (1 − ω)(1 − t(kX)) B [W m-2 sr-1] of paths X (N,) [m]
    through an isothermal medium; ``planck`` (q,) B(λ, T) [W m-2 sr-1 um-1] at the nodes,
    ``transmittance`` (q,) or scalar, that of the atmosphere to the sensor [-];
    t as in :func:`band_transmittance`."""
    path = np.asarray(path, dtype=float)
    k = np.asarray(extinction, dtype=float)
    source = weights * (1.0 - albedo) * np.asarray(planck, dtype=float) * transmittance
    out = np.empty(len(path))
    for at in _chunks(len(path), k.size):
        depth = path[at, None] * k[None, :]
        absorbed = (-np.expm1(-depth) if line_overlap is None
                    else 1.0 - path_transmittance(depth, line_overlap))
        out[at] = absorbed @ source
    return out


def _grouping(group, n):
    """``sums(values)``: the sums of (q,) values over each of ``n`` groups (q,)."""
    def sums(values):
        return np.bincount(group, np.broadcast_to(values, group.shape), n)
    return sums


def _chunks(n, width, budget=1 << 22):
    """Slices of ``n`` rows such that each slice times ``width`` columns stays within
    ``budget`` values."""
    step = max(1, budget // max(int(width), 1))
    return [slice(i, min(i + step, n)) for i in range(0, n, step)]


def _quadrature(volume, band, breakpoints=()):
    from radscene.render.spectral import band_quadrature

    return band_quadrature(band.response, np.concatenate(
        [volume.wavelengths, np.asarray(breakpoints, dtype=float).ravel()]))


def _atmosphere_transmittance(atmosphere, location_altitude, origins, volume, nodes):
    """τ_a (q,) from the mean of ``origins`` (the sensor) to the volume's centre."""
    if atmosphere is None:
        return 1.0
    start = np.mean(origins, axis=0)
    to_sensor = start - volume.center
    distance = float(np.linalg.norm(to_sensor))
    if distance == 0.0:
        return 1.0
    zenith = math.degrees(math.acos(max(-1.0, min(1.0, to_sensor[2] / distance))))
    path = atmosphere.path(np.array([start[2] + location_altitude]),
                           np.array([volume.center[2] + location_altitude]),
                           np.array([zenith]), nodes)
    return np.asarray(path.transmittance, dtype=float).reshape(-1, len(nodes))[0]


def _per_volume(volumes, bands, origins, directions, t_max, atmosphere=None, altitude=0.0,
                emission=True, sun=None, breakpoints=()):
    """Entry distance (V, N), band transmittance (V, N, n_b) and light (2, V, N, n_b): the
    emission and, where ``sun`` = (unit vector to the sun (3,), ``irradiance(wavelength,
    altitude)`` → E_sun τ_so (q,) [W m-2 um-1]) is given, the scattered sunlight.
    ``breakpoints`` [um]: the kinks of the other spectra (sun, atmosphere) for the band
    quadrature."""
    from radscene.radiometry import spectral_radiance
    from radscene.render import volume_scattering

    n, n_b = len(origins), len(bands)
    entry = np.full((len(volumes), n), np.inf)
    trans = np.ones((len(volumes), n, n_b))
    light = np.zeros((2, len(volumes), n, n_b))
    for v, vol in enumerate(volumes):
        x = optical_path(vol, origins, directions, t_max)
        cross = np.flatnonzero(x > 0.0)
        if len(cross) == 0:
            continue
        entry[v, cross] = np.maximum(entry_exit(vol, origins[cross], directions[cross])[0], 0.0)
        for b, band in enumerate(bands):
            nodes, weights = _quadrature(vol, band, breakpoints)
            # the sums over the band's nodes grouped by extinction (and a gas's line overlap;
            # exact): one group for a grey medium, however many nodes the sun's spectrum asks for
            k_nodes = np.asarray(vol.extinction(nodes), float)
            beta = None
            if vol.line_overlap is None:
                k, group = np.unique(k_nodes, return_inverse=True)
            else:
                pairs, group = np.unique(np.stack(
                    [k_nodes, np.asarray(vol.line_overlap(nodes), float)], axis=1),
                    axis=0, return_inverse=True)
                k, beta = pairs[:, 0], pairs[:, 1]
            grouped = _grouping(group.ravel(), k.size)
            trans[v, cross, b] = band_transmittance(k, grouped(weights), x[cross], beta)
            if not emission:
                continue
            tau_a = _atmosphere_transmittance(atmosphere, altitude, origins[cross], vol, nodes)
            light[0, v, cross, b] = band_emission(
                k, grouped(weights * spectral_radiance(nodes, vol.temperature) * tau_a),
                x[cross], 1.0, vol.albedo, line_overlap=beta)
            if sun is not None and vol.albedo > 0.0:
                source = sun[1](nodes, float(vol.center[2]) + altitude) * tau_a
                light[1, v, cross, b] = volume_scattering.single_scattering(
                    vol, k, grouped(weights * source), 1.0, origins[cross], directions[cross],
                    np.asarray(t_max, float)[cross], sun[0])
    return entry, trans, light


def line_of_sight(volumes, bands, origins, directions, t_max, atmosphere=None,
                  altitude=0.0, sun=None, breakpoints=()
                  ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Per ray: whether it crosses a volume (N,), the volumes' combined band transmittance
    (N, n_b) and their emission and scattered sunlight reaching the ray's origin
    (2, N, n_b) [W m-2 sr-1] (``sun`` as for :func:`_per_volume`).

    Volumes along a ray are taken in the order the ray enters them, each nearer one
    attenuating the light of those behind it (overlapping volumes are treated as if
    they followed each other).
    """
    entry, trans, own = _per_volume(volumes, bands, origins, directions, t_max, atmosphere,
                                    altitude, sun=sun, breakpoints=breakpoints)
    order = np.argsort(entry, axis=0)
    through = np.ones(trans.shape[1:])
    light = np.zeros((2,) + trans.shape[1:])
    rows = np.arange(trans.shape[1])
    for rank in range(len(volumes)):
        v = order[rank]
        light += through * own[:, v, rows]
        through *= trans[v, rows]
    return np.isfinite(entry).any(axis=0), through, light


def sun_transmittance(volumes, bands, points, sun_dir, breakpoints=()) -> np.ndarray:
    """The volumes' band transmittance (N, n_b) along the sun rays from ``points`` (N, 3)."""
    sun = np.broadcast_to(np.reshape(sun_dir, (-1, 3)), np.shape(points))
    _, trans, _ = _per_volume(volumes, bands, np.asarray(points, float), sun,
                              np.full(len(points), np.inf), emission=False,
                              breakpoints=breakpoints)
    return trans.prod(axis=0)


def apply(ds, scene, bands, rays, hits, sun_dir, sun_up, atmosphere, layers,
          sun_irradiance=None, breakpoints=()):
    """The volume pass on a rendered Dataset ``ds`` (see the module docstring); returns it
    with ``transmitted``, ``volume_emission`` and ``volume_transmittance`` added and the
    other layers, ``radiance``, ``brightness_temperature`` and ``shadow_fraction`` updated.

    ``layers`` are the names of the surface and path layers that sum to the radiance,
    ``sun_dir`` the unit vector to the sun per hit (or one row), ``sun_up`` False when the
    sun is below the horizon for every hit; ``sun_irradiance(wavelength, altitude)`` → E_sun
    τ_so [W m-2 um-1] lights the volumes that scatter (their mean sun direction's), None: no
    scattered sunlight; ``breakpoints`` [um] the kinks of the scene's other spectra (the
    band quadrature's sub-interval edges).
    """
    from radscene.radiometry import band_brightness_temperature

    volumes = scene.volumes
    ny, nx = rays.shape
    n_pix, n_b = ny * nx, len(bands)
    pix, w = rays.pixel, rays.weight
    coverage = np.bincount(pix, w, n_pix)
    coverage = np.where(coverage > 0.0, coverage, 1.0)

    def per_pixel(rows, select=None):
        """Weighted sums per pixel of (N, n_b) rows: of every sample, or of the ``select``ed
        ones (rows of every sample, or of those only)."""
        p, ww = (pix, w) if select is None else (pix[select], w[select])
        if select is not None and len(rows) == len(pix):
            rows = rows[select]
        return np.stack([np.bincount(p, ww * rows[:, b], n_pix) for b in range(n_b)])

    def cube(a):
        return a.reshape(n_b, ny, nx)

    hit = hits.hit
    # partial shadows: the sun terms of every hit through the volumes on its sun ray
    if sun_up and scene.settings.shadows and np.any(hit):
        sun_rows = np.reshape(sun_dir, (-1, 3))
        points = hits.position[hit] + 1e-6 * np.broadcast_to(sun_rows, (int(hit.sum()), 3))
        t_sun = sun_transmittance(volumes, bands, points, sun_rows, breakpoints)
        hit_w = np.bincount(pix[hit], w[hit], n_pix)
        seen = hit_w > 0.0
        factor = np.ones((n_b, n_pix))
        factor[:, seen] = per_pixel(t_sun, hit)[:, seen] / hit_w[seen]
        for name in ("sun_diffuse", "sun_specular"):
            ds[name].values[...] *= cube(factor)
        lit = 1.0 - ds["shadow_fraction"].values
        ds["shadow_fraction"].values[...] = 1.0 - lit * factor.mean(axis=0).reshape(ny, nx)
    t_max = np.where(hit, hits.distance, np.inf)
    sun = None
    if sun_up and sun_irradiance is not None:
        mean_sun = np.reshape(sun_dir, (-1, 3)).mean(axis=0)
        sun = (mean_sun / np.linalg.norm(mean_sun), sun_irradiance)
    crosses, through, light = line_of_sight(volumes, bands, rays.origins, rays.directions,
                                            t_max, atmosphere, scene.location.altitude, sun,
                                            breakpoints)
    crossing_share = per_pixel(through, crosses) / coverage  # Σ_cross w t / Σ w
    clear_share = np.bincount(pix[~crosses], w[~crosses], n_pix) / coverage
    transmittance = crossing_share + clear_share
    surface_seen = np.bincount(pix[hit], w[hit], n_pix) > 0.0
    transmitted = np.zeros((n_b, n_pix))
    for name in layers:
        values = ds[name].values.reshape(n_b, n_pix)
        behind = np.ones(n_pix, dtype=bool) if name != "path_radiance" else ~surface_seen
        transmitted[:, behind] += crossing_share[:, behind] * values[:, behind]
        values[:, behind] *= clear_share[behind]
        for part in (p for p in PART_LAYERS.get(name, ()) if p in ds):  # its parts as it
            ds[part].values.reshape(n_b, n_pix)[:, behind] *= clear_share[behind]
    emission, scattered = per_pixel(light[0]), per_pixel(light[1])
    total = ds["radiance"].values
    total[...] = 0.0
    for name in layers:
        if name != "transmitted":
            total += ds[name].values
    if "transmitted" in layers:  # a sheet's, where no volume is in front of it
        transmitted += ds["transmitted"].values.reshape(n_b, n_pix)
    total += cube(transmitted)
    total += cube(emission)
    total += cube(scattered)
    attrs = {"units": "W m-2 sr-1"}
    ds["transmitted"] = (("band", "y", "x"), cube(transmitted),
                         {**attrs, "long_name": VOLUME_LONG_NAMES["transmitted"]})
    ds["volume_emission"] = (("band", "y", "x"), cube(emission),
                             {**attrs, "long_name": VOLUME_LONG_NAMES["volume_emission"]})
    ds["volume_scattered"] = (("band", "y", "x"), cube(scattered),
                              {**attrs, "long_name": VOLUME_LONG_NAMES["volume_scattered"]})
    ds["volume_transmittance"] = (("band", "y", "x"), cube(transmittance), {
        "units": "1", "long_name": "band transmittance of the volumes along the line of sight "
                                   "(pixel mean; 1 where no volume)"})
    bt = ds["brightness_temperature"].values
    for b, band in enumerate(bands):
        if np.any(np.isfinite(bt[b])):
            bt[b] = band_brightness_temperature(total[b], band.response)
    return ds
