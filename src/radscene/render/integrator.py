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
"""

from __future__ import annotations

import time as _time
from collections.abc import Callable
from concurrent.futures import ThreadPoolExecutor

import numpy as np
import xarray as xr

from radscene.atmosphere import sky_node_weights
from radscene.render import (
    background,
    media,
    media_sky,
    node_mixing,
    sheets,
    terms,
    truth,
    volumes,
)
from radscene.render.band_setup import (
    EMISSION_TEMPERATURE_STEP,
    BandSetup,
    configured_atmosphere,
    emission_pairs,
    mix_tables,
    path_setup,
    sun_irradiance,
)
from radscene.render.brdf_tables import brdf_terms
from radscene.render.coupling_pass import coupling_layers, coupling_pass
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
from radscene.render.spectral import breakpoints
from radscene.render.sun_track import sun_track
from radscene.render.surface import (
    SceneTables,
    hit_temperature,
    scene_tables,
    secondary_rays,
    shadows,
    surface_state,
    textures,
)
from radscene.render.tiles import as_slice, pixel_sums, tile_slices, touch_pages

__all__ = ["render", "render_all", "scene_tables", "cf_conventions", "TERMS", "TERM_LONG_NAMES",
           "BACKGROUND_TERM", "BACKGROUND_LONG_NAME", "COUPLING_TERMS", "COUPLING_LONG_NAMES",
           "THERMAL_BAND_START", "GEOLOCATION_COORDS", "CONSTANT_ANGLES", "TILE_SAMPLES"]

#: Ray samples per tile.
TILE_SAMPLES = 1 << 17


def render(scene, observer: str | None = None, *, progress: Callable[[int, int], None] | None = None,
           bands=None, specular=None, _tables: SceneTables | None = None, _rays=None,
           _depth: int = 0) -> xr.Dataset:
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
        nonzero specular coefficient in some band. Renders of one observer split over
        several band sets pass the same flags, so that they draw the same random numbers.

    Returns
    -------
    xarray.Dataset
        ``radiance(band, y, x)`` [W m-2 sr-1], one variable per signature term (same dims),
        and the truth maps; see ``docs/outputs.md``.
    """
    setup = scene.observers[0] if observer is None else scene.observer(observer)
    if bands is None and getattr(setup, "spectral", None) is not None:
        from radscene.errors import ConfigError

        raise ConfigError(f"observer {setup.name!r} records a spectral grid: render it with "
                          "radscene.render_hyperspectral", key="observer")
    tables = _tables or scene_tables(scene)
    bands = [scene.band(name) for name in setup.bands] if bands is None else list(bands)
    sun = tables.sun
    settings = scene.settings
    # _rays, _depth: the rays beyond the sheets of an outer pass, and how many it crossed
    rays = setup.camera.rays(supersample=setup.supersample) if _rays is None else _rays
    started = _time.perf_counter()
    # the sun at each ray's time (scanners), or the scene's
    track = sun_track(scene, rays.time, getattr(setup.camera, "epoch", None))

    # first pass: primary hits, for the path nodes of the whole image
    hits = tables.tracer.intersect(rays.origins, rays.directions)
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
                          specular)
    finally:
        worker.shutdown(wait=True, cancel_futures=True)
    layers = TERMS + (BACKGROUND_TERM,) + COUPLING_TERMS
    if tables.sheet_object.any():  # partial shadows, and the light from behind the sheets
        def behind(bundle):
            return render(scene, setup.name, bands=bands, specular=specular, _tables=tables,
                          _rays=bundle, _depth=_depth + 1)
        ds = sheets.apply(ds, tables, sheets.band_transmittance(scene.materials, bands), bands,
                          rays, hits, layers, sun_dir, track.up, settings.shadows,
                          lambda obj, pos: textures(scene, obj, pos)["transmittance"], behind,
                          _depth)
        layers += ("transmitted",)
    if scene.volumes:  # the light from behind through them, and their own
        atm = configured_atmosphere(scene, sun, None)
        ds = volumes.apply(ds, scene, bands, rays, hits, sun_dir, track.up, atm, layers,
                           sun_irradiance(atm, sun), breakpoints(scene))
    return ds


def _render_rest(scene, setup, tables, bands, sun, track, hit_time, sun_dir, settings, rays,
                 hits, hit, shadow_pass, worker, started, progress, specular=None) -> xr.Dataset:
    """:func:`render` after the primary rays: the path nodes, the band tables and the tiles.

    ``sun`` is the scene's sun (the Dataset's attributes), ``track`` the sun at the rays'
    times, ``sun_dir`` the unit vector towards the sun of each hit (one row: of every hit).
    """
    from radscene.radiometry import band_brightness_temperature

    ny, nx = rays.shape
    n_pix = ny * nx
    n_b = len(bands)
    geo = path_setup(scene, rays, hits, hit, track, hit_time)
    obs_alt, tgt_alt, view_zenith = geo.obs_alt, geo.tgt_alt, geo.view_zenith
    suns, path_nodes_all = geo.suns, geo.nodes_all
    path_index, path_weight = geo.path_index, geo.path_weight
    bset = BandSetup(scene, bands, geo.path_nodes, suns, track.reference)
    coef = bset.coefficients
    sky_nodes = bset.sky_nodes

    # the terms (term, band, pixel) and the transmittance: node_mixing.mix_terms writes them
    acc = np.zeros((len(TERMS), n_b, n_pix))
    sums = dict(zip(TERMS, acc, strict=True))
    transmittance = np.zeros((n_b, n_pix))
    truth_sum = {k: np.zeros(n_pix) for k in truth.TRUTH_SUMS}
    # the sub-sample nearest each pixel centre labels ids and normals
    central = truth.central_subsample(rays)
    object_id = np.full(n_pix, -1, dtype=np.int32)
    material_id = np.full(n_pix, -1, dtype=np.int32)
    normal_map = np.full((3, n_pix), np.nan)

    hit_rank = np.cumsum(hit) - 1  # index of each hit sample among hits
    rng = np.random.default_rng(settings.seed)
    total = len(rays.pixel)
    per_pixel = setup.supersample**2
    tiles = tile_slices(total, per_pixel, TILE_SAMPLES)
    hit_face = tables.face_offset[hits.object[hit]] + hits.primitive[hit]
    hit_material = tables.face_material[hit_face]
    hit_temp = hit_temperature(tables, hits, hit, hit_face)
    specular_material = np.any(coef.sun_specular != 0.0, axis=(1, 2)) | np.any(
        coef.sky_specular != 0.0, axis=(1, 2, 3)) if specular is None else np.asarray(
        specular, dtype=bool)
    # The shadow, sky and lobe rays of the next tiles are traced on a worker thread while this
    # thread evaluates the terms of tile i (Embree and the numba kernels release the GIL). The
    # random rotations are drawn here, tile by tile, in the order of a serial render.
    scratch = {}
    media_tables = None  # the band-mean BRDFs that reflect the volumes' own radiance
    unit_weight = bool(np.all(rays.weight == 1.0))  # then weighting changes nothing: skip it
    geolocation = None
    labelled = central & hit  # positions and view directions are known from the primary rays

    # volumes and sheets on the sky and background rays (None: the scene has neither)
    medium = media_sky.for_render(scene, tables, bands, sun_dir, track.up,
                                  suns[track.reference])
    sky_open = np.zeros((n_b, n_pix)) if medium is not None else None
    media_light = np.zeros((n_b, n_pix)) if medium is not None else None

    def launch(sl):
        state = surface_state(tables, rays, hits, hit, hit_rank, sl, sun_dir, hit_material,
                              hit_temp)
        if state is None:
            return None
        state.specular = specular_material[state.mat]
        n_specular = int(np.count_nonzero(state.specular))
        shifts = (rng.random((len(state.mat), 2)),
                  rng.random((n_specular, 2)) if n_specular else None)
        job = worker.submit(secondary_rays, tables, state, settings, sky_nodes, shifts,
                            scratch, fused_sky, shadow_pass)
        # the sky rays through volumes and sheets: the same fan, traced again (media.py)
        state.media = None if medium is None else worker.submit(
            media.sky_fan, tables, medium, state.origin, state.nrm, settings.sky_samples,
            shifts[0])
        return state, job

    sky_diffuse = np.ascontiguousarray(coef.sky_diffuse.transpose(0, 2, 1, 3), dtype=float)
    # one sample per pixel and no BRDF model: the terms go straight into the outputs
    direct = per_pixel == 1 and bset.brdf is None and len(rays.pixel) == n_pix
    # without BRDF models nothing but the diffuse sky sum needs the sky fractions: the
    # sky fan is folded straight into it on the worker thread
    fused_sky = None if bset.brdf is not None else (
        sky_diffuse, path_nodes_all.index, path_nodes_all.weight)
    ahead = 2  # tiles whose rays are queued while this thread works
    pending = {k: launch(tiles[k]) for k in range(min(ahead, len(tiles)))}
    # the other tables while the first tiles' rays are traced
    emission_pair, emission_tables = emission_pairs(
        bset, hit_material, hit_temp,
        None if tables.face_corner_temperature is None else EMISSION_TEMPERATURE_STEP)
    mixing = mix_tables(coef, emission_tables, sky_diffuse)
    # with one sample per pixel a tile's pixels are final once its terms are written: their
    # brightness temperatures are computed here, while the next tiles' rays are traced
    thermal = [b for b, band in enumerate(bands)
               if band.response.center >= THERMAL_BAND_START]
    bt_map = np.full((n_b, n_pix), np.nan) if direct and thermal else None
    radiance = np.empty((n_b, n_pix)) if direct else None
    pixel_coords = None
    # the coupling layers: their pages are first touched tile by tile below, while the worker
    # traces (at 1 M pixels and 8 bands that first touch, 192 MB, was most of the coupling pass)
    layers = coupling_layers(bset, labelled, n_b, n_pix)
    # the reflected background: its own pass over each tile's hits (None: off)
    reflect = background.for_render(
        scene, tables, bset, bands, per_pixel,
        [band.response.center >= THERMAL_BAND_START for band in bands],
        (lambda obj, pos: textures(scene, obj, pos))
        if any(obj.textures for obj in scene.objects) else None, medium)
    sums[BACKGROUND_TERM] = bg = np.zeros((n_b, n_pix))

    def tile_totals(sl):
        """The tile's total radiance (the terms summed in TERMS order, as _dataset would)
        and brightness temperatures, while later tiles are traced."""
        if radiance is None:
            return
        at = as_slice(rays.pixel[sl])
        total = radiance[:, at]
        np.copyto(total, acc[0, :, at])
        for t in range(1, len(TERMS)):
            total += acc[t, :, at]
        if reflect is not None:
            total += bg[:, at]
        if media_light is not None:
            total += media_light[:, at]
        if bt_map is not None:
            for b in thermal:
                bt_map[b, at] = band_brightness_temperature(total[b], bands[b].response)
    for i, sl in enumerate(tiles):
        if i + ahead < len(tiles):
            pending[i + ahead] = launch(tiles[i + ahead])
        if geolocation is None:  # while the first tiles' rays are traced
            geolocation = truth.geolocation(scene, hits, rays, labelled, track)
            pixel_coords = pixel_coordinates(setup, rays.shape)
        current = pending.pop(i)
        if layers is not None:
            touch_pages(layers, i, len(tiles))
        pix = rays.pixel[sl]
        w = rays.weight[sl]
        d = rays.directions[sl]
        h = hit[sl]
        # --- rays that leave the scene see the sky (upwards) or nothing (downwards) ----
        miss = ~h
        if np.any(miss):
            dz = d[miss, 2]
            zen = np.degrees(np.arccos(np.clip(dz, -1.0, 1.0)))
            azi = np.degrees(np.arctan2(d[miss, 0], d[miss, 1]))
            weights = sky_node_weights(zen, azi, *sky_nodes)
            sky_seen = (weights @ coef.sky_view.T) * (dz > 0)[:, None]
            for b in range(n_b):
                sums["path_radiance"][b] += np.bincount(pix[miss], w[miss] * sky_seen[:, b],
                                                        n_pix)
        if current is None:  # no hits in this tile
            tile_totals(sl)
            _report(progress, sl.stop, total)
            continue
        st, job = current
        hidx, rank, obj, mat, temp = st.hidx, st.rank, st.obj, st.mat, st.temp
        pos, nrm, wo, cos_v, cos_i = st.pos, st.nrm, st.wo, st.cos_v, st.cos_i
        tex = textures(scene, obj, pos)
        n_hits = len(hidx)
        if np.any(st.specular):
            mirror_sun = 2.0 * cos_i[:, None] * nrm - st.sun
            cos_r = np.einsum("nc,nc->n", mirror_sun, wo)
            lobe = terms.phong_geometry(cos_r, tables.exponent[mat], cos_i, cos_v)
        else:  # every specular coefficient of these materials is zero
            lobe = np.zeros(n_hits)
        p = rays.pixel[hidx]
        wh = rays.weight[hidx]
        lit, sky_out, lobe_f = job.result()
        if fused_sky is None:
            sky_f, sky_sums, sky_view = sky_out, None, sky_out.sum(axis=1)
        else:
            sky_f, (sky_sums, sky_view) = None, sky_out
        # --- terms (terms.py's, with the coefficients mixed between path nodes) ---------
        if direct:
            out, tau, out_pixel, out_weight = acc, transmittance, p, wh
        else:  # per hit, then weighted and summed per pixel below
            out, tau = np.empty((len(TERMS), n_b, n_hits)), np.empty((n_b, n_hits))
            out_pixel, out_weight = np.arange(n_hits), np.ones(n_hits)
        node_mixing.mix_terms(
            out, tau, out_pixel, out_weight, rank, mat, emission_pair, path_nodes_all.index,
            path_nodes_all.weight, cos_incidence=cos_i, lit=lit,
            reflectance=tex["reflectance"], emissivity=tex["emissivity"], lobe=lobe,
            specular=st.specular, sky_fractions=sky_f, lobe_fractions=lobe_f,
            sky_sums=sky_sums, path_index=path_index, path_weight=path_weight, **mixing)
        if bset.brdf is not None:
            values = {name: out[t].T for t, name in enumerate(TERMS)}
            cos_g = np.einsum("nc,nc->n", wo, np.broadcast_to(st.sun, wo.shape))
            brdf_terms(bset, values, mat, temp, cos_i, cos_v, cos_g, lit, tex, sky_f,
                        path_nodes_all.subset(rank))
        if medium is not None:  # the sky rays' change by volumes and sheets
            change = st.media.result()
            if media_tables is None:
                media_tables = reflect.tables if reflect is not None else (
                    background.render_tables(
                        scene, tables, bset,
                        [band.response.center >= THERMAL_BAND_START for band in bands]))
            d_sky, d_light = media_sky.sky_change(change, bset, sky_diffuse, st, tex, path_nodes_all,
                                        media_tables, coef.transmittance)
            if direct:
                out[3][:, p] += (d_sky * wh[:, None]).T
            else:
                out[3] += d_sky.T
            pixels, totals = pixel_sums(p, wh, np.vstack([
                d_light.T, sky_view[None, :] + change.view(n_hits).T]))
            media_light[:, pixels] += totals[:n_b]
            sky_open[:, pixels] += totals[n_b:]
        if reflect is not None:  # at the surface, then through τ_a and Δρ
            values = reflect(st.origin, nrm, wo, mat, st.sun, sl.start)
            values *= node_mixing.gather_band(coef.transmittance, path_nodes_all.subset(rank))
            values *= tex["reflectance"][:, None]
            pixels, totals = pixel_sums(p, wh, values.T)
            bg[:, pixels] += totals
        truth_rows = (cos_i, 1.0 - lit, sky_view, temp, hits.distance[hidx], None)
        if per_pixel == 1:  # one sample per pixel: no sums, only weighted copies
            at = as_slice(p)  # a tile of whole rows: plain slices
            if not direct:
                acc[:, :, at] = out if unit_weight else out * wh
                transmittance[:, at] = tau if unit_weight else tau * wh
            for key, row in zip(truth.TRUTH_SUMS, truth_rows, strict=True):
                truth_sum[key][at] = wh if row is None else row if unit_weight else row * wh
        else:
            n_rows = len(TERMS) * n_b
            rows = np.concatenate([out.reshape(n_rows, n_hits), tau, np.vstack(
                [np.ones(n_hits) if row is None else row for row in truth_rows])])
            pixels, totals = pixel_sums(p, wh, rows)
            acc[:, :, pixels] += totals[:n_rows].reshape(len(TERMS), n_b, -1)
            transmittance[:, pixels] += totals[n_rows:n_rows + n_b]
            for c, key in enumerate(truth.TRUTH_SUMS):
                truth_sum[key][pixels] += totals[n_rows + n_b + c]
        if per_pixel == 1:  # every sample is its pixel's central one
            object_id[at], material_id[at], normal_map[:, at] = obj, mat, nrm.T
        else:
            c = central[hidx]
            object_id[p[c]] = obj[c]
            material_id[p[c]] = mat[c]
            normal_map[:, p[c]] = nrm[c].T
        tile_totals(sl)
        _report(progress, sl.stop, total)
    # the layers are added to the total radiance (where it is formed per tile) as they are made
    coupled = coupling_pass(scene, bset, acc, truth_sum["hit_weight"], rays, hits, labelled,
                             hit_rank, path_nodes_all, obs_alt, tgt_alt, view_zenith, radiance,
                             layers)
    if bt_map is not None:
        for b in thermal:
            if any(np.any(layer[b]) for layer in coupled.values()):
                bt_map[b] = band_brightness_temperature(radiance[b], bands[b].response)
    sums.update(coupled)
    if media_light is not None:  # after the coupling pass: it is not light from the sky
        sums["sky_reflected"] += media_light
    elapsed = _time.perf_counter() - started
    ds = dataset(scene, setup, bands, rays.shape, sums, transmittance, truth_sum,
                  object_id, material_id, normal_map, sun, elapsed, pool=worker,
                  brightness=bt_map, pixel_coords=pixel_coords, radiance=radiance)
    if geolocation is None:  # no samples
        geolocation = truth.geolocation(scene, hits, rays, labelled, track)
    if sky_open is not None:
        ds["sky_view_transmitted"] = sky_view_transmitted(sky_open, truth_sum["hit_weight"],
                                                          rays.shape)
    return cf_conventions(ds.assign(geolocation), scene)


def render_all(scene, progress=None) -> dict[str, xr.Dataset]:
    """Render every observer of a scene; returns ``{observer name: Dataset}``."""
    tables = scene_tables(scene)
    return {
        obs.name: render(scene, obs.name, progress=progress, _tables=tables)
        for obs in scene.observers
    }


# ---------------------------------------------------------------------------------------------


def _report(progress, done, total):
    if progress is not None:
        progress(done, total)

