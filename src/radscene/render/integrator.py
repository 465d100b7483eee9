"""Render one observer of a scene: rays → hits → signature terms → band radiance Dataset.

The work is done in tiles of ray samples (no Python loop over pixels): each tile is traced in
one batch, its secondary rays (shadow, sky, lobe) in a few more, and its terms are gathered
from the per-material band coefficients. Pixel values are weighted sums of their sub-samples.
The secondary rays of the next tiles are traced on a worker thread while the calling thread
evaluates the terms of the current one; the results do not depend on that overlap.

Geometry is per ray sample (docs/physics.md, "Per-ray geometry"): each sample mixes the band
coefficients of the atmosphere's path nodes around its own view zenith, altitudes and — for the
path radiance — its line of sight's azimuth relative to the sun; a scanner's samples see the
sun of their own acquisition time (:mod:`radscene.render.sun_track`).

This module only orchestrates the passes over the tiles; each lives in a module of its own:
the scene tables, a tile's hit state, its shadow and secondary rays in
:mod:`~radscene.render.surface`; the path nodes and the band tables of every term in
:mod:`~radscene.render.band_setup`; a tile's terms, with the BRDF, media and background
passes, in :mod:`~radscene.render.shading`; the per-pixel sums in
:mod:`~radscene.render.tiles`; the coupling layers in :mod:`~radscene.render.coupling_pass`;
the layers' names and the Dataset in :mod:`~radscene.render.outputs`, the truth maps in
:mod:`~radscene.render.truth`.
"""

from __future__ import annotations

import time as _time
from collections.abc import Callable
from concurrent.futures import ThreadPoolExecutor

import numpy as np
import xarray as xr

from radscene.render import background, media, media_sky, sheets, truth, volumes
from radscene.render.band_setup import (
    EMISSION_TEMPERATURE_STEP,
    BandSetup,
    configured_atmosphere,
    emission_pairs,
    mix_tables,
    path_setup,
    sun_irradiance,
)
from radscene.render.coupling_pass import coupling_layers, coupling_pass
from radscene.render.frame_cache import FrameCache
from radscene.render.outputs import (
    BACKGROUND_LONG_NAME,
    BACKGROUND_TERM,
    CONSTANT_ANGLES,
    COUPLING_LONG_NAMES,
    COUPLING_TERMS,
    GEOLOCATION_COORDS,
    TERM_LONG_NAMES,
    TERMS,
    THERMAL_BAND_START,
    cf_conventions,
    dataset,
    pixel_coordinates,
    sky_view_transmitted,
)
from radscene.render.shading import TileShader
from radscene.render.spectral import breakpoints
from radscene.render.sun_track import sun_track
from radscene.render.surface import (
    SceneTables,
    fan_shifts,
    hit_temperature,
    scene_tables,
    secondary_rays,
    shadows,
    surface_state,
    textures,
)
from radscene.render.tiles import TileSums, tile_slices, touch_pages

__all__ = ["render", "render_all", "scene_tables", "cf_conventions", "TERMS", "TERM_LONG_NAMES",
           "BACKGROUND_TERM", "BACKGROUND_LONG_NAME", "COUPLING_TERMS", "COUPLING_LONG_NAMES",
           "THERMAL_BAND_START", "GEOLOCATION_COORDS", "CONSTANT_ANGLES", "TILE_SAMPLES"]

#: Ray samples per tile.
TILE_SAMPLES = 1 << 17
#: Tiles whose secondary rays are queued on the worker thread while this one shades.
TILES_AHEAD = 2


def render(scene, observer: str | None = None, *, progress: Callable[[int, int], None] | None = None,
           bands=None, specular=None, tables: SceneTables | None = None, rays=None,
           cache: FrameCache | None = None) -> xr.Dataset:
    """Render one observer of a scene.

    Parameters
    ----------
    scene : radscene.scene.Scene
        A loaded scene (:func:`radscene.load_scene`).
    observer : str, optional
        Name of the observer; the first one by default.
    progress : callable, optional
        Called as ``progress(samples_done, samples_total)`` after each tile.
    bands : list, optional
        Bands to render instead of the observer's: objects with ``name`` and ``response``
        (the channels of :mod:`radscene.render.hyperspectral`).
    specular : array_like of bool, optional
        Per material, whether its samples trace specular lobes; default: those with a
        nonzero specular coefficient in some band (with ``render.spectral_grid``: somewhere
        on the grid). Renders of one observer split over several band sets pass the same
        flags, so that they draw the same random numbers.
    tables : SceneTables, optional
        The scene's tables (:func:`scene_tables`), when several renders of one scene share
        them; built by default.
    rays : RayBundle, optional
        The rays to trace instead of the observer's own (one ``supersample`` grid), e.g. a
        part of its image or its rays at other times.
    cache : FrameCache, optional
        The rays of the observer's last frame (a sequence's): traced again only where
        something moved through them (:mod:`radscene.render.frame_cache`).

    Returns
    -------
    xarray.Dataset
        ``radiance(band, y, x)`` [W m-2 sr-1], one variable per signature term (same dims),
        and the truth maps; see ``docs/outputs.md``.
    """
    grid = scene.settings.spectral_grid
    setup = scene.observers[0] if observer is None else scene.observer(observer)
    if bands is None and grid is not None and getattr(setup, "spectral", None) is None:
        # the non-linear layers resolved on the grid (render/resolved.py)
        from radscene.radiometry import channel_grid
        from radscene.render.resolved import render_resolved

        tables = tables or scene_tables(scene)
        grid = channel_grid(grid.min, grid.max, grid.step, key="render.spectral_grid")
        own = [scene.band(name) for name in setup.bands]

        def band_render(band_list, flags, report):  # the frame cache serves the bands alone
            return _render(scene, observer, report, band_list, flags, tables, rays,
                           cache if band_list is own else None, depth=0)

        return render_resolved(band_render, scene, setup, grid, own, specular=specular,
                               progress=progress)
    return _render(scene, observer, progress, bands, specular, tables, rays, cache, depth=0)


def _render(scene, observer, progress, bands, specular, tables, rays, cache, depth):
    """:func:`render`; ``depth`` is how many sheets the rays crossed (0 for the observer's,
    1 and more for the rays beyond the sheets of an outer pass)."""
    setup = scene.observers[0] if observer is None else scene.observer(observer)
    if bands is None and getattr(setup, "spectral", None) is not None:
        from radscene.errors import ConfigError

        raise ConfigError(f"observer {setup.name!r} records a spectral grid: render it with "
                          "radscene.render_hyperspectral", key="observer")
    tables = tables or scene_tables(scene)
    bands = [scene.band(name) for name in setup.bands] if bands is None else list(bands)
    sun = tables.sun
    settings = scene.settings
    given_rays = rays is not None
    if not given_rays:
        rays = setup.camera.rays(supersample=setup.supersample)
    started = _time.perf_counter()
    # the sun at each ray's time (scanners), or the scene's
    track = sun_track(scene, rays.time, getattr(setup.camera, "epoch", None))

    frame_cache = cache
    if cache is not None and (given_rays or not FrameCache.usable(scene, tables, track, rays)):
        cache.reset()
        frame_cache = None
    # first pass: primary hits, for the path nodes of the whole image
    hits = (tables.tracer.intersect(rays.origins, rays.directions) if frame_cache is None
            else frame_cache.primary(tables.tracer, rays))
    hit = hits.hit
    hit_time = rays.time[hit] if track.moving else None
    sun_dir = track.direction(hit_time)  # per hit, or one row for all
    # The shadow rays of every hit are traced on a worker thread while this one prepares the
    # tables; the shadow, sky and lobe rays of the later tiles go to the same thread.
    worker = ThreadPoolExecutor(max_workers=1)
    try:
        shadow_pass = worker.submit(shadows, tables, hits, hit, rays.directions, sun_dir,
                                    settings.shadows, track.up)
        ds = _render_rest(scene, setup, tables, bands, sun, track, hit_time, sun_dir,
                          settings, rays, hits, hit, shadow_pass, worker, started, progress,
                          specular, frame_cache)
    except BaseException:
        if frame_cache is not None:  # a frame left half done keeps nothing
            frame_cache.reset()
        raise
    finally:
        worker.shutdown(wait=True, cancel_futures=True)
    layers = TERMS + (BACKGROUND_TERM,) + COUPLING_TERMS
    if tables.sheet_object.any():  # partial shadows, and the light from behind the sheets
        def behind(bundle):
            return _render(scene, setup.name, None, bands, specular, tables, bundle, None,
                           depth + 1)
        ds = sheets.apply(ds, tables, sheets.band_transmittance(scene.materials, bands), bands,
                          rays, hits, layers, sun_dir, track.up, settings.shadows,
                          lambda obj, pos: textures(scene, obj, pos)["transmittance"], behind,
                          depth)
        layers += ("transmitted",)
    if scene.volumes:  # the light from behind through them, and their own
        atm = configured_atmosphere(scene, sun, None)
        ds = volumes.apply(ds, scene, bands, rays, hits, sun_dir, track.up, atm, layers,
                           sun_irradiance(atm, sun), breakpoints(scene))
    return ds


def _render_rest(scene, setup, tables, bands, sun, track, hit_time, sun_dir, settings, rays,
                 hits, hit, shadow_pass, worker, started, progress, specular=None,
                 cache=None) -> xr.Dataset:
    """:func:`render` after the primary rays: the path nodes, the band tables and the tiles.

    ``sun`` is the scene's sun (the Dataset's attributes), ``track`` the sun at the rays'
    times, ``sun_dir`` the unit vector towards the sun of each hit (one row: of every hit),
    ``shadow_pass`` the future of :func:`~radscene.render.surface.shadows` on ``worker``,
    ``cache`` the observer's :class:`~radscene.render.frame_cache.FrameCache` or None.
    """
    n_pix = rays.shape[0] * rays.shape[1]
    geo = path_setup(scene, rays, hits, hit, track, hit_time)
    keys = None if cache is None else cache.keys
    if keys is None:
        plan = None
        bset = BandSetup(scene, bands, geo.path_nodes, geo.suns, track.reference)
    else:  # a key frame, or one between key frames (radscene.render.key_frames)
        plan = keys.plan(cache, rays, hits, shadow_pass, geo.path_nodes, lambda: BandSetup(
            scene, bands, geo.path_nodes, geo.suns, track.reference),
            background=settings.background_bounces == 1 and not scene.volumes
            and not tables.sheet_object.any())
        bset = plan.bset
    coef = bset.coefficients
    # the sub-sample nearest each pixel centre labels ids and normals
    central = truth.central_subsample(rays)
    labelled = central & hit  # positions and view directions are known from the primary rays
    hit_rank = np.cumsum(hit) - 1  # index of each hit sample among hits
    per_pixel = setup.supersample**2
    tiles = tile_slices(len(rays.pixel), per_pixel, TILE_SAMPLES)
    hit_face = tables.face_offset[hits.object[hit]] + hits.primitive[hit]
    hit_material = tables.face_material[hit_face]
    hit_temp = hit_temperature(tables, hits, hit, hit_face)
    specular_material = np.any(coef.sun_specular != 0.0, axis=(1, 2)) | np.any(
        coef.sky_specular != 0.0, axis=(1, 2, 3)) if specular is None else np.asarray(
        specular, dtype=bool)
    # volumes and sheets on the sky and background rays (None: the scene has neither)
    medium = media_sky.for_render(scene, tables, bands, sun_dir, track.up,
                                  geo.suns[track.reference])
    sky_diffuse = np.ascontiguousarray(coef.sky_diffuse.transpose(0, 2, 1, 3), dtype=float)
    # without BRDF models nothing but the diffuse sky sum needs the sky fractions: the
    # sky fan is folded straight into it on the worker thread
    fused_sky = None if bset.brdf is not None else (
        bset.sky_split.fused_table(sky_diffuse), geo.nodes_all.index, geo.nodes_all.weight)
    # The shadow, sky and lobe rays of the next tiles are traced on a worker thread while this
    # thread evaluates the terms of tile i (Embree and the numba kernels release the GIL). The
    # random rotations are drawn here, per ray sample of each tile (surface.fan_shifts).
    scratch = {}
    reflecting = settings.background_bounces > 0  # the background pass will run

    def launch(sl):
        state = surface_state(tables, rays, hits, hit, hit_rank, sl, sun_dir, hit_material,
                              hit_temp)
        if state is not None:
            state.specular = specular_material[state.mat]
            shifts = fan_shifts(settings.seed, sl, state.hidx, state.specular)
        if plan is not None:  # between key frames: only the hits of the pixels to shade
            state, shifts = keys.launch(plan, sl, state, None if state is None else shifts,
                                        settings, tables.exponent)
        if state is None:
            return None
        # the sky fan's blocked directions, for the reflected background's first bounce
        state.fan = background.Fan(shifts[0], settings.sky_samples, np.empty(
            (len(state.mat), settings.sky_samples), dtype=bool)) if reflecting else None
        job = worker.submit(secondary_rays, tables, state, settings, bset.sky_nodes, shifts,
                            scratch, fused_sky, shadow_pass, cache)
        # the sky rays through volumes and sheets: the same fan, traced again (media.py)
        state.media = None if medium is None else worker.submit(
            media.sky_fan, tables, medium, state.origin, state.nrm, settings.sky_samples,
            shifts[0])
        state.media_lobe = None
        if medium is not None and shifts[1] is not None:  # and the specular lobes' fans
            lobe = state.specular[state.specular]  # the rows of the lobe fans' rotations
            lobe = lobe & media_sky.lobe_hits(bset, state.mat[state.specular], lobe)
            sel = np.flatnonzero(state.specular)[lobe]
            if len(sel):
                axis = 2.0 * state.cos_v[sel, None] * state.nrm[sel] - state.wo[sel]
                state.media_lobe = worker.submit(
                    media.lobe_fan, tables, medium, state.origin[sel], state.nrm[sel], axis,
                    tables.exponent[state.mat[sel]], settings.specular_samples,
                    shifts[1][lobe])
        return state, job

    pending = {k: launch(tiles[k]) for k in range(min(TILES_AHEAD, len(tiles)))}
    # the other tables while the first tiles' rays are traced
    emission_pair, emission_tables = emission_pairs(
        bset, hit_material, hit_temp,
        None if tables.face_corner_temperature is None else EMISSION_TEMPERATURE_STEP)
    # one sample per pixel and no BRDF model: the terms go straight into the outputs
    direct = per_pixel == 1 and bset.brdf is None and len(rays.pixel) == n_pix
    # the coupling layers: their pages are first touched tile by tile below, while the worker
    # traces (at 1 M pixels and 8 bands that first touch, 192 MB, was most of the coupling pass)
    layers = coupling_layers(bset, labelled, len(bands), n_pix)
    # the reflected background: its own pass over each tile's hits (None: off)
    reflect = background.for_render(
        scene, tables, bset, bands, per_pixel,
        [band.response.center >= THERMAL_BAND_START for band in bands],
        (lambda obj, pos: textures(scene, obj, pos))
        if any(obj.textures for obj in scene.objects) else None, medium)
    image = TileSums(bands, n_pix, central, direct, medium is not None, reflect is not None)
    shade = TileShader(scene, tables, bset, bands, rays, hits, image, geo,
                       mix_tables(coef, emission_tables, sky_diffuse), emission_pair,
                       fused_sky is not None, medium, reflect, per_pixel, cache, plan)
    geolocation = pixel_coords = None
    for i, sl in enumerate(tiles):
        if i + TILES_AHEAD < len(tiles):
            pending[i + TILES_AHEAD] = launch(tiles[i + TILES_AHEAD])
        if geolocation is None:  # while the first tiles' rays are traced
            geolocation = truth.geolocation(scene, hits, rays, labelled, track,
                                            None if cache is None else cache.kept)
            pixel_coords = pixel_coordinates(setup, rays.shape)
        current = pending.pop(i)
        if layers is not None:
            touch_pages(layers, i, len(tiles))
        miss = ~hit[sl]  # rays that leave the scene see the sky (upwards) or nothing
        if plan is not None and plan.between:
            miss &= plan.active[sl]
        if np.any(miss):
            image.leaving(rays.pixel[sl][miss], rays.weight[sl][miss],
                          rays.directions[sl][miss], bset.sky_nodes, coef.sky_view)
        if current is not None:  # the tile has hits
            shade(*current, sl)
        image.totals(rays.pixel[sl])
        if progress is not None:
            progress(sl.stop, len(rays.pixel))
    if plan is not None:  # the pixels not shaded, extrapolated; or the key frame kept
        keys.finish(plan, image)
    # the layers are added to the total radiance (where it is formed per tile) as they are made
    coupled = coupling_pass(scene, bset, image.acc, image.truth["hit_weight"], rays, hits,
                            labelled, hit_rank, geo.nodes_all, geo.obs_alt, geo.tgt_alt,
                            geo.view_zenith, image.radiance, layers)
    return _assemble(scene, setup, bands, sun, track, rays, hits, labelled, image, coupled,
                     started, worker, geolocation, pixel_coords, bset.sky_split)


def _assemble(scene, setup, bands, sun, track, rays, hits, labelled, image, coupled, started,
              worker, geolocation, pixel_coords, split) -> xr.Dataset:
    """The render's Dataset from the tiles' sums ``image`` and the ``coupled`` layers;
    ``worker`` may take the brightness temperatures, ``geolocation`` and ``pixel_coords``
    are those made during the tiles (None: not yet made), ``split`` the band setup's
    :class:`~radscene.render.sky_split.SkySplit`."""
    from radscene.radiometry import band_brightness_temperature

    if image.brightness is not None:
        for b in image.thermal:
            if any(np.any(layer[b]) for layer in coupled.values()):
                image.brightness[b] = band_brightness_temperature(image.radiance[b],
                                                                  bands[b].response)
    image.sums.update(coupled)
    image.finish(split)  # the volumes' light and the layers' parts (sky_split.py)
    elapsed = _time.perf_counter() - started
    ds = dataset(scene, setup, bands, rays.shape, image.sums, image.transmittance, image.truth,
                 image.object_id, image.material_id, image.normal_map, sun, elapsed,
                 pool=worker, brightness=image.brightness, pixel_coords=pixel_coords,
                 radiance=image.radiance)
    if geolocation is None:  # no samples
        geolocation = truth.geolocation(scene, hits, rays, labelled, track)
    if image.sky_open is not None:
        ds["sky_view_transmitted"] = sky_view_transmitted(image.sky_open,
                                                          image.truth["hit_weight"], rays.shape)
    return cf_conventions(ds.assign(geolocation), scene)


def render_all(scene, progress=None) -> dict[str, xr.Dataset]:
    """Render every observer of a scene; returns ``{observer name: Dataset}``."""
    tables = scene_tables(scene)
    return {
        obs.name: render(scene, obs.name, progress=progress, tables=tables)
        for obs in scene.observers
    }
