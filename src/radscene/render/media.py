"""Secondary rays through participating volumes and semi-transparent sheets.

The line of sight and the sun rays cross the scene's volumes (:mod:`radscene.render.volumes`)
and sheets (:mod:`radscene.render.sheets`); so do, here, the rays that estimate the reflected
sky and the segments of the reflected-background paths:

* **Sky rays.** A direction ω of a hit's cosine-weighted sky fan that leaves the scene upwards
  past every opaque surface brings

  .. math::

      T_b(ω) \\, L_{sky,b}(ω) + L_{v,b}(ω), \\qquad
      T_b = \\prod_{sheets} Δτ \\, \\bar τ_b \\prod_{volumes} \\bar t_b

  with the band transmittances of the sheets (response-weighted means of Δτ τ(λ)) and of the
  volumes (∫ S e^{−kX} dλ / ∫ S dλ, as their sun rays take them), and L_v the volumes' own
  band radiance along ω — their emission ∫ S (1 − ω)(1 − e^{−kX}) B(λ, T_v) dλ and the sun
  they scatter once, each volume's through the nearer ones (:func:`volumes.line_of_sight`
  without an atmosphere: the air inside the scene is clear) — times the sheets' T.
  A sheet no longer blocks a sky ray; its own radiance, a surface's, belongs to the
  reflected background as before.
* **Background segments.** A path segment from a surface to the next surface (or, from a
  later vertex, to the sky) is attenuated by the volumes' T along it and gains their L_v;
  sheets stay surfaces there (a path meets a sheet as a vertex and does not pass it).

:func:`sky_fan` regenerates each hit's sky fan, the same directions as the compiled fan of
:mod:`radscene.render.illumination`, and returns only the rays whose contribution the media
change, with the change: T_b · open − visible (open: no opaque surface; visible: no surface
at all, as the fan counted it) and L_v.

The Phong lobes of specular materials are sampled by fans of their own
(:func:`radscene.render.illumination.lobe_sky_fractions`); :func:`lobe_fan` regenerates them
as :func:`sky_fan` does the sky fans, so a window or a wet road reflects the volumes and sheets
above it and the sky dimmed by them.

Simplifications: band-mean transmittances (exact for media grey within the band, as for the
sun); the volumes' radiance along a sky ray is attenuated by every sheet on that ray, also
by a sheet above the volume.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

__all__ = ["Media", "SkyChange", "sky_fan", "sky_fan_reference", "lobe_fan", "CHUNK_RAYS"]

#: Fan rays handled at once; the results do not depend on it.
CHUNK_RAYS = 1 << 18


@dataclass(frozen=True)
class Media:
    """The scene's volumes and sheets as secondary rays see them.

    Attributes
    ----------
    volumes : sequence of radscene.render.volumes.Volume
    bands : list — objects with ``response``
    altitude : float — the scene origin's altitude [m] (the volumes' sun source)
    sun : tuple or None — (unit vector to the sun (3,), ``irradiance(wavelength, altitude)``
        → E_sun τ_so [W m-2 um-1]): the volumes' single-scattered sun; None: none
    breakpoints : numpy.ndarray — kinks of the scene's other spectra [um]
    tables : object or None — the integrator's scene tables where the scene has sheets
        (``sheet_tracer``, ``face_offset``, ``face_material``, ``epsilon``)
    sheet_transmittance : (n_m, n_b) or None — band means of each material's τ [-]
    texture : callable or None — ``texture(object, position)`` → Δτ (N,)
    """

    volumes: tuple
    bands: list
    altitude: float = 0.0
    sun: tuple | None = None
    breakpoints: np.ndarray = field(default_factory=lambda: np.zeros(0))
    tables: object = None
    sheet_transmittance: np.ndarray | None = None
    texture: Callable | None = None

    @property
    def has_sheets(self) -> bool:
        return self.tables is not None

    def along(self, origins, directions, t_max=None, sheets=True, parts=False):
        """Band transmittance T (N, n_b) [-] and radiance L_v (N, n_b) [W m-2 sr-1] that the
        media put on rays from ``origins`` (N, 3) [m] along unit ``directions`` (N, 3) up to
        ``t_max`` (N,) [m] (default: unbounded, a sky ray); with ``sheets`` the sheets'
        transmittance too (rays that leave the scene). With ``parts`` also the volumes'
        emission alone (N, n_b), the thermal part of L_v (the rest is their scattered sun)."""
        from radscene.render import volumes as vol

        origins = np.asarray(origins, dtype=float)
        directions = np.asarray(directions, dtype=float)
        n, n_b = len(origins), len(self.bands)
        trans, light, heat = np.ones((n, n_b)), np.zeros((n, n_b)), np.zeros((n, n_b))
        if n == 0:
            return (trans, light, heat) if parts else (trans, light)
        if self.volumes:
            far = np.full(n, np.inf) if t_max is None else np.asarray(t_max, dtype=float)
            _, trans, own = vol.line_of_sight(self.volumes, self.bands, origins, directions,
                                              far, None, self.altitude, self.sun,
                                              self.breakpoints)
            light, heat = own[0] + own[1], own[0]
        if sheets and self.has_sheets:
            from radscene.render import sheets as sh

            t_sheet = sh.sun_transmittance(self.tables, self.sheet_transmittance, origins,
                                           directions, directions, self.texture)
            trans = trans * t_sheet
            light = light * t_sheet
            heat = heat * t_sheet
        return (trans, light, heat) if parts else (trans, light)

    def sun_transmittance(self, points, sun) -> np.ndarray:
        """The volumes' band transmittance (N, n_b) [-] along the sun rays from ``points``
        (N, 3) towards unit vectors ``sun`` (N, 3) or (3,) (:func:`volumes.sun_transmittance`;
        not the sheets')."""
        from radscene.render import volumes as vol

        return vol.sun_transmittance(self.volumes, self.bands, points, sun, self.breakpoints)

    def crossed(self, origins, directions, sheets=True) -> np.ndarray:
        """Whether rays (to infinity) cross a volume, or with ``sheets`` a sheet (N,)."""
        from radscene.render.volumes import entry_exit

        out = np.zeros(len(origins), dtype=bool)
        for volume in self.volumes:
            near, far = entry_exit(volume, origins, directions)
            out |= far > np.maximum(near, 0.0)
        if sheets and self.has_sheets and not out.all():
            rest = np.flatnonzero(~out)
            tables = self.tables
            out[rest] = tables.sheet_tracer.occluded(
                origins[rest] + tables.epsilon * directions[rest], directions[rest])
        return out


@dataclass(frozen=True)
class SkyChange:
    """The sky-fan rays whose contribution the media change (P rays).

    Attributes
    ----------
    point : (P,) int — the ray's point (hit) among those of the fan
    direction : (P, 3) — unit directions
    delta : (P, n_b) — T_b · open − visible [-]: the change of the ray's sky weight
    light : (P, n_b) — L_v · open [W m-2 sr-1]: the media's own radiance along it
    samples : int — rays per point (each ray weighs 1/samples)
    heat : (P, n_b) — the volumes' emission in ``light`` [W m-2 sr-1] (the rest is the sun
        they scatter)
    """

    point: np.ndarray
    direction: np.ndarray
    delta: np.ndarray
    light: np.ndarray
    samples: int
    heat: np.ndarray = None

    def view(self, n_points) -> np.ndarray:
        """The change of each point's sky view, Σ delta / samples (n_points, n_b) [-]."""
        n_b = self.delta.shape[1]
        return np.stack([np.bincount(self.point, self.delta[:, b], n_points)
                         for b in range(n_b)], axis=1) / self.samples


def _fan(tracer, origins, normals, n_samples, shift, lobe=None):
    """The compiled sky fan's rays (with ``lobe`` = (axes (N, 3), exponents (N,)): the Phong
    lobe fan's): float32 local origins and directions (N·M, 3)."""
    from radscene.render import kernels
    from radscene.render.illumination import stratified_pattern

    base = stratified_pattern(n_samples)
    side = int(np.floor(np.sqrt(n_samples)))
    side = side if side * side == n_samples else 0
    o32, d32 = kernels.empty_fan(len(origins) * n_samples)
    args = (np.ascontiguousarray(origins, dtype=np.float64),
            np.ascontiguousarray(normals, dtype=np.float64))
    if lobe is not None:
        args += tuple(np.ascontiguousarray(a, dtype=np.float64) for a in lobe)
    fan = kernels.cosine_fan if lobe is None else kernels.lobe_fan
    fan(*args, tracer.center, 0.0, np.ascontiguousarray(shift, dtype=np.float64), base, side,
        o32, d32)
    return o32, d32


def _sky_directions(d, normals, n_samples, lobe):
    """Which fan directions ``d`` (N·M, 3) can be sky: above the horizon and, for a lobe's,
    above the surface of normal ``normals`` (N, 3) (as the lobe's fractions count them)."""
    ok = d[:, 2] > 0.0
    if lobe:
        ok &= np.einsum("nc,nc->n", d, np.repeat(normals, n_samples, axis=0)) > 0.0
    return ok


def _change(tracer, opaque, media, world, d, visible, first_point, n_samples,
            up=None) -> SkyChange:
    """The rays among ``world``, ``d`` (origins, unit directions) whose weight changes; ``up``
    the directions that can be sky (default: above the horizon)."""
    up = d[:, 2] > 0.0 if up is None else up
    if opaque is tracer:
        open_ = visible.copy()
    else:
        open_ = np.zeros(len(d), dtype=bool)
        idx = np.flatnonzero(up)
        open_[idx] = ~opaque.occluded(world[idx], d[idx])
    idx = np.flatnonzero(open_)
    through = np.zeros(len(d), dtype=bool)
    through[idx] = media.crossed(world[idx], d[idx])
    rows = np.flatnonzero(through | (open_ != visible))
    n_b = len(media.bands)
    delta = np.zeros((len(rows), n_b))
    light = np.zeros((len(rows), n_b))
    heat = np.zeros((len(rows), n_b))
    go = open_[rows]
    delta[go], light[go], heat[go] = media.along(world[rows[go]], d[rows[go]], parts=True)
    delta -= visible[rows][:, None]
    return SkyChange(first_point + rows // n_samples, d[rows], delta, light, n_samples, heat)


def sky_fan(tables, media, origins, normals, n_samples, shift, lobe=None) -> SkyChange:
    """The media's change to the sky fans of points (:class:`SkyChange`).

    Parameters
    ----------
    tables : the integrator's scene tables (``tracer``, ``shadow_tracer``: the scene without
        its sheets)
    media : Media
    origins : (N, 3) ray origins, already offset from the surfaces [m]
    normals : (N, 3) unit normals
    n_samples : int — rays per point
    shift : (N, 2) — the fans' rotations, those the render's fan used
    lobe : tuple, optional
        (axes (N, 3), exponents (N,)): the points' Phong lobe fans instead (:func:`lobe_fan`)
    """
    n = len(origins)
    step = max(1, CHUNK_RAYS // n_samples)
    parts = []
    for start in range(0, n, step):
        sl = slice(start, min(start + step, n))
        part = None if lobe is None else (lobe[0][sl], lobe[1][sl])
        o32, d32 = _fan(tables.tracer, origins[sl], normals[sl], n_samples, shift[sl], part)
        sky = _sky_directions(d32, normals[sl], n_samples, lobe is not None)
        visible = ~tables.tracer.occluded_local(o32, d32) & sky
        world = o32.astype(float) + tables.tracer.center
        d = d32.astype(float)
        d /= np.linalg.norm(d, axis=1, keepdims=True)
        parts.append(_change(tables.tracer, tables.shadow_tracer, media, world, d, visible,
                             start, n_samples, sky))
    if not parts:
        n_b = len(media.bands)
        return SkyChange(np.zeros(0, np.int64), np.zeros((0, 3)), np.zeros((0, n_b)),
                         np.zeros((0, n_b)), n_samples, np.zeros((0, n_b)))
    point, direction, delta, light, heat = (np.concatenate([getattr(p, f) for p in parts])
                                            for f in ("point", "direction", "delta", "light",
                                                      "heat"))
    return SkyChange(point, direction, delta, light, n_samples, heat)


def lobe_fan(tables, media, origins, normals, axes, exponents, n_samples, shift) -> SkyChange:
    """The media's change to the Phong lobe fans of specular points (:class:`SkyChange`):
    the directions of :func:`radscene.render.illumination.lobe_sky_fractions` for the same
    ``axes`` (N, 3), ``exponents`` (N,) and rotations ``shift`` (N, 2); a direction below
    the surface is never sky. Other parameters as :func:`sky_fan`."""
    return sky_fan(tables, media, origins, normals, n_samples, shift, (axes, exponents))


def sky_fan_reference(tables, media, origins, normals, n_samples, shift,
                      lobe=None) -> np.ndarray:
    """Per point and band, the fan's mean sky weight T_b · open (N, n_b), ray by ray: the
    tests' oracle for ``visible mean + sky_fan(...).view`` (``lobe`` as :func:`sky_fan`)."""
    n = len(origins)
    out = np.zeros((n, len(media.bands)))
    for i in range(n):
        part = None if lobe is None else (lobe[0][i:i + 1], lobe[1][i:i + 1])
        o32, d32 = _fan(tables.tracer, origins[i:i + 1], normals[i:i + 1], n_samples,
                        shift[i:i + 1], part)
        for j in range(n_samples):
            o = o32[j].astype(float) + tables.tracer.center
            d = d32[j].astype(float)
            d = d / np.linalg.norm(d)
            if d[2] <= 0.0 or (lobe is not None and float(d @ normals[i]) <= 0.0):
                continue
            if tables.shadow_tracer.occluded(o[None], d[None])[0]:
                continue
            out[i] += media.along(o[None], d[None])[0][0]
    return out / n_samples
