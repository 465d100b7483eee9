"""Real-time frames: the tables of a first render kept, only what moved traced again.

A :class:`RealtimeRenderer` renders one observer frame after frame. Its first frame (a *key
frame*) does what :func:`radscene.render` does up to the terms and keeps, per pixel, what
does not depend on the moving geometry: the band tables of every material (sun, sky, path
radiance and transmittance at the atmosphere's path nodes), each pixel's mixing of the path
nodes, its visible-sky fractions (the sky fan's, and the specular lobe's) and the sky seen by
rays that leave the scene. Every frame after it traces the primary rays and the sun's shadow
rays (Embree packets) through the geometry as it is now, and forms the five signature terms
from those tables (:func:`radscene.render.node_mixing.mix_terms`, the kernel of the full
render). A new key frame is made when the observer moves.

What a frame gives up against the full render (``docs/simulation.md``, "Real-time mode"):

* the sky view is that of the key frame's surface in each pixel: an object that moves into a
  pixel reflects the sky with its own material but the visible-sky fractions of what the
  pixel saw in the key frame; the same for the specular lobe's (a pixel without a specular
  surface in the key frame lends the lobe its cosine fan's fractions);
* each pixel's path radiance and transmittance mix the path nodes of the key frame's hit;
* the sun, its atmosphere and the surface temperatures are those of the key frame;
* the reflected background is the key frame's where a pixel sees the key frame's object, and
  zero where it sees another;
* no surface–atmosphere coupling layers, no supersampling, no geolocation maps.

The parts of the reflected sky and background by the light's origin
(:data:`radscene.render.outputs.PART_LAYERS`) are written beside their layers, as the full
render does: the sky's emission reflected is formed with the thermal sky's tables only in
bands whose sky holds both parts (:class:`radscene.render.sky_split.SkySplit`), from the same
frozen fractions; the background's self-emitted part is the key frame's, as the layer is.

With the sky's visible fractions frozen, a key frame equals the full render of the same
instant (the same random numbers): to 1e-12 relative in the tests.
"""

from __future__ import annotations

import sys
import time as _time
from types import SimpleNamespace

import numba
import numpy as np
import xarray as xr

from radscene.errors import ConfigError
from radscene.render import background, illumination, kernels, node_mixing, terms
from radscene.render.band_setup import BandSetup, emission_pairs, mix_tables, path_setup
from radscene.render.integrator import TILE_SAMPLES
from radscene.render.outputs import (
    BACKGROUND_LONG_NAME,
    BACKGROUND_TERM,
    PART_LAYERS,
    PART_LONG_NAMES,
    TERM_LONG_NAMES,
    TERMS,
    THERMAL_BAND_START,
)
from radscene.render.sky_split import PART_COMMENTS
from radscene.render.sun_track import sun_track
from radscene.render.surface import fan_shifts, shadows, surface_state, textures

__all__ = ["RealtimeRenderer", "check_realtime", "SERIAL_PIXELS"]

#: Frames that trace at most this many pixels run their compiled kernels on the calling
#: thread alone: each parallel kernel waits for numba's workers to be scheduled, which on a
#: shared machine costs more than the work. Measured on the development machine (2 cores,
#: load 5): 7 400 pixels of 65 536 took 76 ms a frame on two threads, 17 ms on one.
SERIAL_PIXELS = 1 << 15


def check_realtime(scene) -> None:
    """Refuse what real-time frames do not render, naming it and what to do instead.

    Raises
    ------
    ConfigError
        Hyperspectral or scanning observers, supersampling, motion blur, BRDF-model
        materials, semi-transparent sheets or volumes.
    """
    problems = []
    for i, setup in enumerate(scene.observers):
        if getattr(setup, "spectral", None) is not None:
            problems.append(f"observers[{i}] ({setup.name}) records a spectral grid")
        if setup.kind in ("pushbroom", "whiskbroom"):
            problems.append(f"observers[{i}] ({setup.name}) is a {setup.kind} scanner")
        if setup.supersample != 1:
            problems.append(f"observers[{i}] ({setup.name}) has supersample {setup.supersample}")
    if scene.settings.motion_blur is not None:
        problems.append("render.motion_blur is set")
    if getattr(scene.settings, "spectral_grid", None) is not None:
        problems.append("render.spectral_grid is set")
    if scene.brdfs:
        problems.append(f"materials with a BRDF model: {', '.join(sorted(map(str, scene.brdfs)))}")
    if any(getattr(o, "transmissive", False) for o in scene.objects):
        problems.append("the scene has semi-transparent sheets")
    if scene.volumes:
        problems.append("the scene has volumes")
    if problems:
        raise ConfigError("real-time frames render frame cameras of diffuse and Phong surfaces "
                          "only; " + "; ".join(problems) + " (render without realtime)",
                          key="realtime")


class RealtimeRenderer:
    """Frames of the observers of a scene from tables kept between frames.

    Parameters
    ----------
    scene : radscene.scene.Scene
        Loaded; checked with :func:`check_realtime`. Its materials and surface temperatures
        are read at each key frame.
    tables : radscene.render.surface.SceneTables
        The ray tracer (moved between frames by the caller) and the per-face tables.
    """

    def __init__(self, scene, tables):
        check_realtime(scene)
        self.scene = scene
        self.tables = tables
        #: Trace again only the pixels an object moved since the last frame may have changed
        #: (True, the default); False: every pixel every frame (the same images, slower).
        self.incremental = True
        self._keys = {}

    def render(self, setup) -> xr.Dataset:
        """The frame of observer ``setup`` (a key frame first, and when its camera moved)."""
        key = self._keys.get(setup.name)
        if key is None or key.camera is not setup.camera:
            key = self._keys[setup.name] = self._key_frame(setup)
        return self._frame(key, setup)

    # -- the key frame ------------------------------------------------------------------------

    def _key_frame(self, setup):
        scene, tables = self.scene, self.tables
        started = _time.perf_counter()
        bands = [scene.band(name) for name in setup.bands]
        rays = setup.camera.rays(supersample=1)
        n_pix = rays.shape[0] * rays.shape[1]
        track = sun_track(scene, None)
        sun_dir = track.direction(None)
        hits = tables.tracer.intersect(rays.origins, rays.directions)
        hit = hits.hit
        geo = path_setup(scene, rays, hits, hit, track, None)
        nodes_all = geo.nodes_all
        bset = BandSetup(scene, bands, geo.path_nodes, geo.suns, track.reference)
        coef = bset.coefficients
        # per pixel: the path nodes of its key-frame hit (pixels that missed: the nearest hit's)
        pixel = rays.pixel[hit]
        nearest = _nearest_hit(hit.reshape(rays.shape)).ravel()
        rows = np.zeros(n_pix, dtype=np.int64)
        rows[pixel] = np.arange(len(pixel))
        rows = rows[nearest] if len(pixel) else rows
        index = _rows(nodes_all.index, rows, len(pixel))
        weight = _rows(nodes_all.weight, rows, len(pixel), fill=1.0)
        # emission of every (material, temperature) pair among the faces, once
        face_pair, emission = emission_pairs(bset, tables.face_material, tables.face_temperature)
        specular = np.any(coef.sun_specular != 0.0, axis=(1, 2)) | np.any(
            coef.sky_specular != 0.0, axis=(1, 2, 3))
        # the sky seen by rays that leave the scene, per pixel (zero looking down)
        sky_seen = np.zeros((len(bands), n_pix))
        sky_seen[:, rays.pixel] = terms.leaving_sky(rays.directions, bset.sky_nodes,
                                                    coef.sky_view).T
        key = SimpleNamespace(
            camera=setup.camera, bands=bands, rays=rays, shape=rays.shape, sun_dir=sun_dir,
            track=track, sun=track.nodes[track.reference], index=index, weight=weight,
            path_index=_rows(geo.path_index, rows, len(pixel)),
            path_weight=_rows(geo.path_weight, rows, len(pixel), fill=1.0),
            face_pair=face_pair, specular=specular, tables=mix_tables(coef, emission),
            sky_seen=sky_seen, exponent=tables.exponent, split=bset.sky_split, last=None)
        self._freeze_sky(key, bset, nodes_all, hits, hit, n_pix)
        key.seconds = _time.perf_counter() - started
        return key

    def _freeze_sky(self, key, bset, nodes_all, hits, hit, n_pix):
        """The key frame's visible-sky fractions per pixel, drawn tile by tile with the full
        render's random numbers, and their sums for each pixel's key-frame material; its
        reflected background (:mod:`radscene.render.background`) and objects seen."""
        scene, tables, settings = self.scene, self.tables, self.scene.settings
        reflect = background.for_render(
            scene, tables, bset, key.bands, 1,
            [band.response.center >= THERMAL_BAND_START for band in key.bands],
            (lambda obj, pos: textures(scene, obj, pos))
            if any(obj.textures for obj in scene.objects) else None)
        key.background = np.zeros((len(key.bands), n_pix)) if reflect is not None else None
        key.background_thermal = None if reflect is None else np.zeros_like(key.background)
        key.object = np.full(n_pix, -1, dtype=np.int64)
        rays = key.rays
        n_k = bset.coefficients.sky_view.shape[1]
        key.sky_fractions = np.zeros((n_pix, n_k))
        key.lobe_fractions = np.zeros((n_pix, n_k))
        key.material = np.full(n_pix, -1, dtype=np.int64)
        hit_rank = np.cumsum(hit) - 1
        hit_face = tables.face_offset[hits.object[hit]] + hits.primitive[hit]
        hit_material = tables.face_material[hit_face]
        total = len(rays.pixel)
        scratch = {}
        for start in range(0, total, TILE_SAMPLES):
            sl = slice(start, min(start + TILE_SAMPLES, total))
            st = surface_state(tables, rays, hits, hit, hit_rank, sl, key.sun_dir, hit_material,
                          np.zeros(len(hit_material)))
            if st is None:
                continue
            spec = key.specular[st.mat]
            n_spec = int(np.count_nonzero(spec))
            sky_shift, lobe_shift = fan_shifts(settings.seed, sl, st.hidx, spec)
            p = rays.pixel[st.hidx]
            key.material[p] = st.mat
            key.object[p] = st.obj
            fan = None if reflect is None else background.Fan(
                sky_shift, settings.sky_samples,
                np.empty((len(st.mat), settings.sky_samples), dtype=bool))
            sky = illumination.sky_fractions(tables.tracer, st.origin, st.nrm,
                                             settings.sky_samples, bset.sky_nodes, None,
                                             shift=sky_shift, scratch=scratch,
                                             blocked=None if fan is None else fan.blocked)
            if reflect is not None:  # at the surface, then through τ_a and Δρ, as the render
                values, emitted = reflect(st.origin, st.nrm, st.wo, st.mat, st.sun, sl.start,
                                          fan)
                tau_a = node_mixing.gather_band(bset.coefficients.transmittance,
                                                nodes_all.subset(st.rank))
                reflectance = textures(scene, st.obj, st.pos)["reflectance"][:, None]
                for part, layer in ((values, key.background), (emitted, key.background_thermal)):
                    part *= tau_a
                    part *= reflectance
                    layer[:, p] = part.T
            key.sky_fractions[p] = sky
            key.lobe_fractions[p] = sky  # what a surface that was not specular lends the lobe
            if n_spec:
                axis = 2.0 * st.cos_v[spec, None] * st.nrm[spec] - st.wo[spec]
                key.lobe_fractions[p[spec]] = illumination.lobe_sky_fractions(
                    tables.tracer, st.origin[spec], st.nrm[spec], axis,
                    tables.exponent[st.mat[spec]], settings.specular_samples, bset.sky_nodes,
                    None, shift=lobe_shift, scratch=scratch)
        seen = key.material >= 0
        key.sky_sums = np.zeros((n_pix, len(key.bands)))
        if seen.any():
            at = np.flatnonzero(seen)
            key.sky_sums[at] = node_mixing.mix_sky(key.tables["sky_diffuse"],
                                                   key.material[at], key.index[at],
                                                   key.weight[at], key.sky_fractions[at])
        key.sky_view = key.sky_fractions.sum(axis=1)
        key.sky_thermal_sums = _thermal_sky_sums(key, key.material, np.arange(n_pix))
        if key.background is not None:  # its solar part, as the full render forms it
            key.background_solar = key.background - key.background_thermal

    # -- a frame ------------------------------------------------------------------------------

    def _frame(self, key, setup) -> xr.Dataset:
        """The next frame: the last frame's images with the pixels that may have changed
        (:meth:`_changed`) traced and shaded again."""
        started = _time.perf_counter()
        tracer = self.tables.tracer
        ny, nx = key.shape
        n_pix, n_b = ny * nx, len(key.bands)
        last = key.last
        if last is None:
            dirty = np.arange(n_pix)
            out = SimpleNamespace(
                acc=np.zeros((len(TERMS), n_b, n_pix)), tau=np.full((n_b, n_pix), np.nan),
                background=None if key.background is None else np.zeros((n_b, n_pix)),
                parts={name: np.empty((n_b, n_pix)) for name in _part_names(key)}, older={},
                radiance=np.zeros((n_b, n_pix)), bt=np.full((n_b, n_pix), np.nan),
                maps={name: np.full(n_pix, fill, dtype=dtype)
                      for name, (dtype, fill) in MAPS.items()})
        else:
            dirty = self._changed(key, last) if self.incremental else np.arange(n_pix)
            out = SimpleNamespace(acc=last.acc.copy(), tau=last.tau.copy(),
                                  background=None if last.background is None
                                  else last.background.copy(),
                                  parts=_carried(last), older=last.parts,
                                  radiance=last.radiance.copy(), bt=last.bt.copy(),
                                  maps={k: v.copy() for k, v in last.maps.items()})
        if len(dirty):
            threads = numba.get_num_threads()
            if len(dirty) <= SERIAL_PIXELS:  # on this thread alone (see SERIAL_PIXELS)
                numba.set_num_threads(1)
            try:
                self._shade(key, dirty, out)
            finally:
                numba.set_num_threads(threads)
        out.dirty = dirty
        out.counts = tracer.move_count.copy()
        out.lo, out.hi = tracer.mesh_bounds
        out.half = tracer.half_size
        out.traced = len(dirty)
        key.last = out
        return self._dataset(key, setup, out, _time.perf_counter() - started)

    def _changed(self, key, last) -> np.ndarray:
        """The pixels whose primary or shadow rays may meet an object moved since the last
        frame: those where the camera sees the box of its old or new place swept away from
        the sun (a shadow may fall there), one pixel of margin. The sweep reaches down to the
        lowest surface the last frame saw where the sweep to the scene's floor is seen (a
        shadow falls only on a surface seen; those whose rays change are among the pixels
        anyway). Every pixel where that cannot be worked out (a camera without ``project``,
        a box behind a pinhole, a sun on the horizon) or when the tracer's clipping box grew."""
        tracer = self.tables.tracer
        ny, nx = key.shape
        everything = np.arange(ny * nx)
        moved = np.flatnonzero(tracer.move_count != last.counts)
        if not len(moved):
            return np.zeros(0, dtype=np.int64)
        if getattr(key.camera, "project", None) is None or not np.array_equal(
                tracer.half_size, last.half):
            # the clipping box grew (an object moved past it): every ray starts at another
            # float32 point, and a pixel kept would differ from one traced again by that
            # rounding (up to a shadow flipped at a grazing sun); the box grows with room to
            # spare (geometry.raytracer.BOX_GROWTH), so this is seldom
            return everything
        lo_now, hi_now = tracer.mesh_bounds
        lo = np.concatenate([last.lo[moved], lo_now[moved]])
        hi = np.concatenate([last.hi[moved], hi_now[moved]])
        if self.scene.settings.shadows and key.track.up:
            sun = key.sun_dir[0]
            if sun[2] <= 1e-6:
                return everything
            rects = _rects(key.camera, *_swept(lo, hi, sun, tracer.bounds[0][2]), ny, nx)
            if rects is None:
                return everything
            rays = key.rays
            seen = rays.origins[:, 2] + last.maps["range"] * rays.directions[:, 2]
            seen = np.where(np.isfinite(seen), seen, np.inf).reshape(ny, nx)
            floor = np.array([seen[a:b, c:d].min() if a < b and c < d else np.inf
                              for a, b, c, d in zip(*rects, strict=True)])
            lo, hi = _swept(lo, hi, sun, np.minimum(floor, lo[:, 2]))
        rects = _rects(key.camera, lo, hi, ny, nx)
        if rects is None:
            return everything
        mask = np.zeros((ny, nx), dtype=bool)
        for a, b, c, d in zip(*rects, strict=True):
            mask[a:b, c:d] = True
        return np.flatnonzero(mask)

    def _shade(self, key, dirty, out):
        """Trace and shade the pixels ``dirty`` (supersample 1: ray = pixel) into ``out``."""
        from radscene.radiometry import band_brightness_temperature

        scene, tables, settings = self.scene, self.tables, self.scene.settings
        rays = key.rays
        directions = rays.directions[dirty]
        hits = tables.tracer.intersect(rays.origins[dirty], directions)
        hit = hits.hit
        hidx = np.flatnonzero(hit)
        p = dirty[hidx]
        lit = shadows(tables, hits, hit, directions, key.sun_dir, settings.shadows,
                       key.track.up)
        nrm, wo, cos_v, cos_i, _origin = kernels.surface_state(
            hits.normal, directions, hits.position, hidx, tables.epsilon, key.sun_dir)
        obj = hits.object[hidx]
        face = tables.face_offset[obj] + hits.primitive[hidx]
        mat = tables.face_material[face]
        tex = textures(scene, obj, hits.position[hidx])
        spec = key.specular[mat]
        n_k = key.sky_fractions.shape[1]
        if spec.any():
            sun = np.broadcast_to(key.sun_dir, nrm.shape)
            mirror_sun = 2.0 * cos_i[:, None] * nrm - sun
            lobe = terms.phong_geometry(np.einsum("nc,nc->n", mirror_sun, wo),
                                        key.exponent[mat], cos_i, cos_v)
            lobe_fractions = np.zeros((len(hidx), n_k))
            lobe_fractions[spec] = key.lobe_fractions[p[spec]]
        else:
            lobe = np.zeros(len(hidx))
            lobe_fractions = np.zeros((0, n_k))
        # the reflected sky: the key frame's sums where the pixel keeps its material, else the
        # frozen fractions with the new material's table
        sky_sums = key.sky_sums[p]
        changed = np.flatnonzero(mat != key.material[p])
        if len(changed):
            at = p[changed]
            sky_sums[changed] = node_mixing.mix_sky(
                key.tables["sky_diffuse"], mat[changed], key.index[at], key.weight[at],
                key.sky_fractions[at])
        pair = np.zeros(out.radiance.shape[1], dtype=np.int64)
        pair[p] = key.face_pair[face]
        out.acc[:, :, dirty] = 0.0
        out.tau[:, dirty] = np.nan
        node_mixing.mix_terms(
            out.acc, out.tau, p, np.ones(len(p)), p, mat, pair, key.index, key.weight,
            cos_incidence=cos_i, lit=lit, reflectance=tex["reflectance"],
            emissivity=tex["emissivity"], lobe=lobe, specular=spec,
            sky_fractions=np.zeros((0, n_k)), lobe_fractions=lobe_fractions,
            sky_sums=sky_sums, path_index=key.path_index, path_weight=key.path_weight,
            **key.tables)
        miss = dirty[~hit]
        if len(miss):  # rays that leave the scene see the sky, or nothing
            out.acc[TERMS.index("path_radiance")][:, miss] = key.sky_seen[:, miss]
        total = out.acc[0][:, dirty]  # the terms summed in TERMS order, as the full render
        for t in range(1, len(TERMS)):
            total += out.acc[t][:, dirty]
        if out.background is not None:  # the key frame's, where the pixel sees its object
            same = p[obj == key.object[p]]
            out.background[:, dirty] = 0.0
            out.background[:, same] = key.background[:, same]
            total += out.background[:, dirty]
        out.radiance[:, dirty] = total
        self._shade_parts(key, out, dirty, hidx, obj, mat, spec, lobe_fractions,
                          tex["reflectance"])
        for b, band in enumerate(key.bands):
            if band.response.center >= THERMAL_BAND_START:
                out.bt[b, dirty] = band_brightness_temperature(total[b], band.response)
        values = {"object_id": obj, "material_id": mat, "range": hits.distance[hidx],
                  "cos_incidence": cos_i, "shadow_fraction": 1.0 - lit,
                  "surface_temperature": tables.face_temperature[face]}
        for name, (_, fill) in MAPS.items():
            out.maps[name][dirty] = fill
            out.maps[name][p] = values[name]

    def _shade_parts(self, key, out, dirty, hidx, obj, mat, spec, lobe_fractions,
                     reflectance):
        """The part layers (:data:`~radscene.render.outputs.PART_LAYERS`) at the pixels
        ``dirty``, whose hits are ``hidx`` among them (objects ``obj``, materials ``mat``,
        specular flags ``spec``, the lobe's sky fractions, Δρ ``reflectance``), once their
        layers are shaded: the reflected sky's from its layer and, in the bands whose sky holds
        both parts, the sky's emission reflected (:func:`_thermal_sky`); the background's the
        key frame's where the pixel sees the key frame's object, as the layer."""
        split = key.split
        p = dirty[hidx]
        rows = np.zeros((len(split.split), len(dirty)))
        if len(split.split) and len(p):  # the sky's emission reflected, where it holds both
            rows[:, hidx] = _thermal_sky(key, p, mat, spec, lobe_fractions, reflectance).T
        solar, thermal = _split_rows(out.acc[TERMS.index("sky_reflected")][:, dirty], rows,
                                     split)
        for name, values in zip(PART_LAYERS["sky_reflected"], (solar, thermal), strict=True):
            for row, value in zip(out.parts[name], values, strict=True):  # a band at a time:
                row[dirty] = value  # numpy indexes rows faster than (band, pixel) columns
        if key.background is not None:
            same = p[obj == key.object[p]]
            for name, kept in zip(PART_LAYERS[BACKGROUND_TERM],
                                  (key.background_solar, key.background_thermal), strict=True):
                for row, value in zip(out.parts[name], kept, strict=True):
                    row[dirty] = 0.0
                    row[same] = value[same]

    def _dataset(self, key, setup, out, seconds) -> xr.Dataset:
        ny, nx = key.shape
        n_b = len(key.bands)
        image = ("band", "y", "x")
        units = {"units": "W m-2 sr-1"}
        data = {"radiance": (image, out.radiance.reshape(n_b, ny, nx), {
            **units, "long_name": "at-aperture band radiance, sum of the signature terms"})}
        for t, name in enumerate(TERMS):
            data[name] = (image, out.acc[t].reshape(n_b, ny, nx),
                          {**units, "long_name": TERM_LONG_NAMES[name]})
        if out.background is not None:
            data[BACKGROUND_TERM] = (image, out.background.reshape(n_b, ny, nx), {
                **units, "long_name": BACKGROUND_LONG_NAME,
                "comment": "the key frame's, where the pixel sees the key frame's object; 0 "
                "elsewhere"})
        for name, values in out.parts.items():  # beside their layers, as the full render
            data[name] = (image, values.reshape(n_b, ny, nx), {
                **units, "long_name": PART_LONG_NAMES[name], "comment": PART_COMMENTS[name]})
        data["brightness_temperature"] = (image, out.bt.reshape(n_b, ny, nx), {
            "units": "K", "long_name": "band brightness temperature of the total radiance",
            "comment": f"bands centred at or beyond {THERMAL_BAND_START} um; NaN elsewhere"})
        data["path_transmittance"] = (image, out.tau.reshape(n_b, ny, nx), {
            "units": "1", "long_name": "response-weighted target-to-sensor transmittance"})
        for name, attrs in MAP_ATTRS.items():
            data[name] = (("y", "x"), out.maps[name].reshape(ny, nx), attrs)
        sky_view = np.where(key.material >= 0, key.sky_view, np.nan)
        data["sky_view_fraction"] = (("y", "x"), sky_view.reshape(ny, nx), {
            "units": "1", "long_name": "cosine-weighted fraction of the hemisphere that sees "
            "sky, of the key frame's surface"})
        coords = {"band": ("band", [b.name for b in key.bands]),
                  "wavelength_center": ("band", [float(b.response.center) for b in key.bands],
                                        {"units": "um"}),
                  "x": ("x", np.arange(nx), {"long_name": "pixel column"}),
                  "y": ("y", np.arange(ny), {"long_name": "pixel row"})}
        ds = xr.Dataset(data, coords=coords)
        ds.attrs = {"Conventions": "CF-1.10", "scene": self.scene.name, "observer": setup.name,
                    "render_mode": "realtime", "sun_zenith_deg": key.sun.zenith,
                    "sun_azimuth_deg": key.sun.azimuth, "render_seconds": round(seconds, 5),
                    "key_frame_seconds": round(key.seconds, 3), "pixels_traced": out.traced}
        return ds


#: The truth maps of a real-time frame: dtype and the value of pixels that see no surface.
MAPS = {"object_id": (np.int32, -1), "material_id": (np.int32, -1), "range": (float, np.nan),
        "cos_incidence": (float, np.nan), "shadow_fraction": (float, np.nan),
        "surface_temperature": (float, np.nan)}
MAP_ATTRS = {
    "object_id": {"long_name": "object index (-1: no object)"},
    "material_id": {"long_name": "material index (-1: no material)"},
    "range": {"units": "m", "long_name": "distance from the observer to the surface"},
    "cos_incidence": {"units": "1", "long_name": "cosine of the sun's angle of incidence "
                      "(negative: facing away)"},
    "shadow_fraction": {"units": "1", "long_name": "fraction of the pixel not directly sunlit "
                        "(cast or self shadow)"},
    "surface_temperature": {"units": "K", "standard_name": "surface_temperature",
                            "long_name": "surface temperature"},
}


def _thermal_sky_sums(key, material, pixels) -> np.ndarray:
    """The key frame's diffuse sums of the thermal sky for ``pixels`` seen as ``material``
    (-1: nothing), in the bands whose sky holds both parts: (len(pixels), n_split), zero
    where nothing is seen (:func:`~radscene.render.node_mixing.mix_sky`, the thermal tables
    of :class:`~radscene.render.sky_split.SkySplit`)."""
    out = np.zeros((len(pixels), len(key.split.split)))
    seen = np.flatnonzero(material >= 0)
    if len(seen) and out.shape[1]:
        at = pixels[seen]
        out[seen] = node_mixing.mix_sky(key.split.diffuse, material[seen], key.index[at],
                                        key.weight[at], key.sky_fractions[at])
    return out


def _thermal_sky(key, p, mat, spec, lobe_fractions, reflectance) -> np.ndarray:
    """The sky's emission reflected by the hits of pixels ``p`` (materials ``mat``, specular
    flags ``spec``, the lobe's sky fractions ``lobe_fractions`` of every hit, Δρ
    ``reflectance``) in the bands whose sky holds both parts: (len(p), n_split), the sums
    of the reflected sky with the thermal tables (as
    :meth:`~radscene.render.sky_split.SkySplit.tile_thermal`)."""
    out = key.sky_thermal_sums[p]
    changed = np.flatnonzero(mat != key.material[p])
    if len(changed):
        out[changed] = _thermal_sky_sums(key, mat[changed], p[changed])
    sel = np.flatnonzero(spec)
    if len(sel):
        at = p[sel]
        out[sel] += node_mixing.mix_sky(key.split.specular, mat[sel], key.index[at],
                                        key.weight[at], lobe_fractions[sel])
    out *= reflectance[:, None]
    return out


def _part_names(key) -> tuple[str, ...]:
    """The part layers of a key frame's frames: the reflected sky's, and the background's
    where the frames have the layer."""
    names = PART_LAYERS["sky_reflected"]
    return names + (PART_LAYERS[BACKGROUND_TERM] if key.background is not None else ())


def _carried(last) -> dict:
    """The part layers of the frame after ``last``, to be changed at its pixels traced again.

    A frame's images stay as they were made, so a frame cannot write into the last frame's
    arrays (the caller holds them while it asks for the next), but it may into those of the
    frame before (``last.older``) once nothing else holds them: brought up to date at the
    pixels ``last`` traced again, they are ``last``'s. Then a frame writes its pixels traced
    again and ``last``'s, not every pixel of four more layers; where the older arrays are held
    (a caller that keeps its frames) the last frame's are copied.
    """
    out = {}
    for name, array in last.parts.items():
        older = last.older.pop(name, None)
        # two references: this name and getrefcount's argument; a view of it (a Dataset
        # variable of that frame, kept) adds one
        if older is None or sys.getrefcount(older) > 2:
            out[name] = array.copy()
            continue
        for row, value in zip(older, array, strict=True):  # a band at a time (see _shade_parts)
            row[last.dirty] = value[last.dirty]
        out[name] = older
    return out


def _split_rows(layer, thermal_rows, split) -> tuple[np.ndarray, np.ndarray]:
    """(solar, thermal) parts (n_b, N) of the reflected sky ``layer`` (n_b, N), as
    :func:`~radscene.render.sky_split.part_layers` forms them: a band whose sky holds one part
    is all that part; the bands ``split.split`` have their thermal part in ``thermal_rows``
    (n_split, N) and the layer less it as the solar part."""
    solar, thermal = np.zeros_like(layer), np.zeros_like(layer)
    row = {int(b): i for i, b in enumerate(split.split)}
    for b in range(len(layer)):
        if b in row:
            thermal[b] = thermal_rows[row[b]]
            solar[b] = layer[b] - thermal[b]
        elif split.thermal[b] and not split.solar[b]:
            thermal[b] = layer[b]
        else:
            solar[b] = layer[b]
    return solar, thermal


def _swept(lo, hi, sun, floor):
    """Boxes ``lo``, ``hi`` (n, 3) [m] grown by their sweep away from the unit vector ``sun``
    down to ``floor`` (scalar or (n,)) [m]: where their shadows may fall."""
    reach = np.maximum(hi[:, 2] - floor, 0.0) / sun[2]
    return np.minimum(lo, lo - reach[:, None] * sun), np.maximum(hi, hi - reach[:, None] * sun)


def _rects(camera, lo, hi, ny, nx):
    """Per box (lo, hi) the pixel rectangle (row0, row1, col0, col1) that its projection
    covers, one pixel of margin, clipped to the image; None where a corner lies behind a
    pinhole."""
    corners = np.stack([np.where(np.array(c, bool), hi, lo) for c in np.ndindex(2, 2, 2)],
                       axis=1)  # (boxes, 8, 3)
    row, col, in_front = camera.project(corners)
    if not (in_front.all() or hasattr(camera, "plane_center")):  # orthographic: any point
        return None
    return (np.clip(np.floor(row.min(axis=1)).astype(np.int64) - 1, 0, ny),
            np.clip(np.ceil(row.max(axis=1)).astype(np.int64) + 1, 0, ny),
            np.clip(np.floor(col.min(axis=1)).astype(np.int64) - 1, 0, nx),
            np.clip(np.ceil(col.max(axis=1)).astype(np.int64) + 1, 0, nx))


def _nearest_hit(hit) -> np.ndarray:
    """Per pixel the flat index of the nearest pixel whose ray hit (itself where it hit)."""
    from scipy import ndimage

    if hit.all() or not hit.any():
        return np.arange(hit.size).reshape(hit.shape)
    _, (iy, ix) = ndimage.distance_transform_edt(~hit, return_indices=True)
    return iy * hit.shape[1] + ix


def _rows(values, rows, n_hits, fill=0.0):
    """``values`` (n_hits, k) per pixel through ``rows``; without hits one column of
    ``fill`` (a pixel on node 0 with weight ``fill``)."""
    if n_hits == 0:
        return np.full((len(rows), 1), fill, dtype=values.dtype)
    return np.ascontiguousarray(values[rows])
