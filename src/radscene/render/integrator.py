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
from dataclasses import fields
from types import SimpleNamespace

import numpy as np
import xarray as xr

from radscene.atmosphere import CouplingSpectra, SkyGeometry, sky_node_weights
from radscene.atmosphere.nodes import fold_relative_azimuth
from radscene.render import (
    background,
    illumination,
    media,
    node_mixing,
    sheets,
    terms,
    truth,
    volumes,
)
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
from radscene.render.spectral import (
    BandCoefficients,
    band_quadrature,
    breakpoints,
    emission_coefficients,
    solar_spectrum,
)
from radscene.render.sun_track import combine_nodes, sun_geometry, sun_track

__all__ = ["render", "render_all", "scene_tables", "cf_conventions", "TERMS", "TERM_LONG_NAMES",
           "BACKGROUND_TERM", "BACKGROUND_LONG_NAME", "COUPLING_TERMS", "COUPLING_LONG_NAMES",
           "THERMAL_BAND_START", "GEOLOCATION_COORDS", "CONSTANT_ANGLES", "TILE_SAMPLES"]

#: Ray samples per tile.
TILE_SAMPLES = 1 << 17
#: Step to which temperatures interpolated across faces are grouped for the emission [K]: at
#: most half of it, 0.5 mK, off (a band radiance off by 6e-5 relative at 3 um and 200 K; more at
#: shorter wavelengths, where a surface near 300 K emits next to nothing).
EMISSION_TEMPERATURE_STEP = 1e-3


class _SceneTables:
    """Per-scene data shared by all observers: the ray tracer and per-face lookups (``tracer``:
    one already built of the objects' meshes, kept)."""

    def __init__(self, scene, tracer=None):
        from radscene.geometry import RayTracer

        self.scene = scene
        self.tracer = RayTracer([obj.mesh for obj in scene.objects]) if tracer is None else tracer
        sizes = [len(obj.face_material) for obj in scene.objects]
        self.face_offset = np.concatenate([[0], np.cumsum(sizes)[:-1]]).astype(np.int64)
        self.face_material = np.concatenate([obj.face_material for obj in scene.objects])
        self.face_temperature = np.concatenate([obj.face_temperature for obj in scene.objects])
        corners = [getattr(obj, "face_corner_temperature", None) for obj in scene.objects]
        self.face_corner_temperature = None if all(c is None for c in corners) else np.concatenate(
            [np.repeat(np.asarray(obj.face_temperature, float)[:, None], 3, axis=1) if c is None else np.asarray(c, float)
             for obj, c in zip(scene.objects, corners, strict=True)])
        # semi-transparent sheets: shadow rays pass them (render/sheets.py)
        self.sheet_object, self.shadow_tracer, self.sheet_tracer = sheets.tracers(
            scene.objects, self.tracer)
        lo, hi = self.tracer.bounds
        self.epsilon = 1e-4 + 2e-6 * float(np.linalg.norm(np.asarray(hi) - np.asarray(lo)))
        self.sun = sun_geometry(scene)
        self.exponent = np.array([m.specular_exponent for m in scene.materials], dtype=float)


class _BandSetup:
    """Quadrature and coefficient tables for the bands of one render.

    ``suns`` pairs each sun node with the atmosphere set up for it (one pair for a frame);
    the tables' node axis runs over sun node × path node, ``s · n_j + j``, and the path
    radiance's also over the relative-azimuth nodes of ``path_nodes``. The sky table's grid
    and the sky that rays leaving the scene see are those of the reference sun node.
    """

    def __init__(self, scene, bands, path_nodes, suns, reference=0):
        from radscene.sun import toa_solar_irradiance

        atm_ref = suns[reference][1]
        points = breakpoints(scene)
        zen_nodes = np.asarray(atm_ref.sky_zenith_nodes(), dtype=float)
        az_nodes = np.asarray(atm_ref.sky_azimuth_nodes(), dtype=float)
        sky_zenith, sky_azimuth = (g.ravel() for g in np.meshgrid(zen_nodes, az_nodes,
                                                                  indexing="ij"))
        target_alt = float(np.mean(path_nodes.target_altitude))
        n_j, n_a, n_s = path_nodes.size, path_nodes.azimuth_size, len(suns)
        n_m, n_b, n_k = len(scene.materials), len(bands), sky_zenith.size
        shape = (n_m, n_b, n_s * n_j)
        c = BandCoefficients(
            sun_diffuse=np.zeros(shape), sun_specular=np.zeros(shape),
            sky_diffuse=np.zeros(shape + (n_k,)), sky_specular=np.zeros(shape + (n_k,)),
            path=np.zeros((n_a, n_b, n_s * n_j)), transmittance=np.zeros((n_b, n_s * n_j)),
            sky_view=np.zeros((n_b, n_k)),
        )
        self.quadrature = []
        self.emissivity_tau = []
        taus = []  # the direct transmittance at the nodes, per band
        couplings = []  # the engine's coupling spectra at the nodes, per band
        self.sky_scale = []  # per band and sun node: the node table's factors (_sky_scale)
        self.sun_spectra = []  # per band: E_sun τ_so of the reference sun node at the nodes
        hemisphere = _hemisphere_weights(zen_nodes, az_nodes) if atm_ref.couples else None
        for b, band in enumerate(bands):
            nodes, weights = band_quadrature(band.response, points)
            atm_ref.check_wavelength(nodes, key=f"bands[{band.name}]")
            self.quadrature.append((nodes, weights))
            comps = [m.components(nodes) for m in scene.materials]
            rho_d = np.array([cc["diffuse_reflectance"] for cc in comps])  # (m, q)
            rho_s = np.array([cc["specular_reflectance"] for cc in comps])
            eps = np.array([cc["emissivity"] for cc in comps])
            scales, parts = [], []
            for s, (sun, atm) in enumerate(suns):
                block = slice(s * n_j, (s + 1) * n_j)
                if sun.zenith < 90.0:
                    toa = toa_solar_irradiance(nodes, sun.distance, solar_spectrum(atm))
                    e_sun = atm.sun(target_alt, sun.zenith, nodes, toa).irradiance  # (q,)
                else:
                    e_sun = np.zeros_like(nodes)
                tau, radiance = _path_spectra(atm, path_nodes, sun, nodes)  # (j, q), (a, j, q)
                sky_geom = SkyGeometry(scene.location.altitude, sun.zenith, sun.azimuth)
                sky = atm.sky(sky_zenith, sky_azimuth, nodes, sky_geom)  # (k·l, q)
                if atm_ref.couples:
                    cp = atm.coupling(path_nodes.observer_altitude,
                                      path_nodes.target_altitude, path_nodes.view_zenith, nodes)
                    parts.append(cp)
                    scales.append(_sky_scale(atm, sky, hemisphere, cp))
                    sky = sky * scales[-1]
                wt = weights * e_sun
                c.sun_diffuse[:, b, block] = np.einsum("q,mq,jq->mj", wt, rho_d / np.pi, tau)
                c.sun_specular[:, b, block] = np.einsum("q,mq,jq->mj", wt, rho_s, tau)
                c.sky_diffuse[:, b, block, :] = np.einsum("q,mq,kq,jq->mjk", weights, rho_d, sky,
                                                          tau)
                c.sky_specular[:, b, block, :] = np.einsum("q,mq,kq,jq->mjk", weights, rho_s,
                                                           sky, tau)
                c.path[:, b, block] = radiance @ weights
                c.transmittance[b, block] = tau @ weights / weights.sum()
                if s == reference:
                    c.sky_view[b] = sky @ weights
                    self.sun_spectra.append(e_sun)
            tau = np.tile(tau, (n_s, 1))  # the same line of sight under every sun node
            self.emissivity_tau.append(eps[:, None, :] * tau[None, :, :])
            taus.append(tau)
            self.sky_scale.append(scales)
            if parts:
                couplings.append(CouplingSpectra(*(np.concatenate(
                    [getattr(p, f.name) for p in parts]) for f in fields(CouplingSpectra))))
        self.coefficients = c
        self.coupling = (_CouplingTables(self.quadrature, taus, couplings, n_s * n_j)
                         if atm_ref.couples and scene.settings.coupling else None)
        self.sky_nodes = (zen_nodes, az_nodes)
        self.brdf = _BrdfTables(scene, bands, self.quadrature, path_nodes, suns, target_alt,
                                sky_zenith, sky_azimuth, self.sky_scale
                                ) if scene.brdfs else None


def _path_spectra(atm, path_nodes, sun, wavelength):
    """Direct transmittance (n_j, q) and path radiance (n_a, n_j, q) at the path nodes, the
    latter at each relative-azimuth node, ``view_azimuth`` = the sun's + the node's."""
    args = (path_nodes.observer_altitude, path_nodes.target_altitude, path_nodes.view_zenith,
            wavelength)
    if path_nodes.relative_azimuth is None:
        path = atm.path(*args)
        return path.transmittance, path.radiance[None]
    radiance = []
    for phi in path_nodes.relative_azimuth:
        path = atm.path(*args, view_azimuth=(sun.azimuth + float(phi)) % 360.0)
        radiance.append(path.radiance)
    return path.transmittance, np.stack(radiance)


def _hemisphere_weights(zen_nodes, az_nodes) -> np.ndarray:
    """∫ h_k(ω) cos θ dω over the hemisphere for each node k of the sky table [sr], with h_k
    the bilinear interpolation weights the renderer uses (1° × 2° midpoint rule)."""
    z = np.arange(0.5, 90.0, 1.0)
    a = np.arange(1.0, 360.0, 2.0)
    zz, aa = (g.ravel() for g in np.meshgrid(z, a, indexing="ij"))
    dw = np.cos(np.radians(zz)) * np.sin(np.radians(zz)) * np.radians(1.0) * np.radians(2.0)
    return dw @ sky_node_weights(zz, aa, zen_nodes, az_nodes)


def _sky_scale(atm, sky, hemisphere, cp) -> np.ndarray:
    """Per wavelength, the factor that makes the interpolated sky table's irradiance on a
    horizontal surface equal the engine's own diffuse irradiance (q,).

    Between its zenith nodes the table's linear interpolation cuts the aureole around the
    sun (an 11 % loss with maritime aerosol and the sun at 30°); the engine's hemispheric
    integral is E_dif + E_0 S ρ_b / (1 − S ρ_b), with ρ_b its own surroundings' albedo.
    """
    e_dir = cp.direct_irradiance.mean(axis=0)
    e_dif = cp.diffuse_irradiance.mean(axis=0)
    rb = float(getattr(atm, "surface_albedo", 0.0) or 0.0) * cp.spherical_albedo.mean(axis=0)
    target = e_dif + (e_dir + e_dif) * rb / (1.0 - rb)
    table = hemisphere @ sky
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where((table > 0.0) & (target > 0.0), target / table, 1.0)


class _CouplingTables:
    """Band values of the surface–atmosphere coupling (:mod:`radscene.render.coupling`).

    Spectral factors are weighted by the band response times the irradiance of a horizontal
    surface E_0 = E_dir + E_dif (the spectrum of the light a gray surface sends up; the
    response alone where there is none): per path node j the direct and diffuse upward
    transmittances ``tau[b, j]`` and ``t_d[b, j]``; per band the spherical albedo ``s``, the
    molecular share of t_d ``share``, and the band irradiances ``e0`` and ``e_dif``
    [W m-2].
    """

    def __init__(self, quadrature, taus, couplings, n_nodes):
        n_b, n_j = len(quadrature), n_nodes
        self.tau, self.t_d = np.zeros((n_b, n_j)), np.zeros((n_b, n_j))
        self.s, self.share = np.zeros(n_b), np.zeros(n_b)
        self.e0, self.e_dif = np.zeros(n_b), np.zeros(n_b)
        for b, (_, weights) in enumerate(quadrature):
            cp, tau = couplings[b], taus[b]  # (j, q) each
            e0 = (cp.direct_irradiance + cp.diffuse_irradiance).mean(axis=0)  # (q,)
            w = weights * e0
            if not w.sum() > 0.0:
                w = weights
            w = w / w.sum()
            self.tau[b], self.t_d[b] = tau @ w, cp.diffuse_transmittance @ w
            self.s[b] = float(np.mean(cp.spherical_albedo @ w))
            self.share[b] = float(np.mean(cp.rayleigh_share @ w))
            self.e0[b] = float(e0 @ weights)
            self.e_dif[b] = float(cp.diffuse_irradiance.mean(axis=0) @ weights)

    @property
    def active(self) -> bool:
        """Whether anything couples (a scattering atmosphere in some band)."""
        return bool(np.any(self.t_d > 0.0) or np.any(self.s > 0.0))


#: Cosines of the view zenith at which BRDF materials' directional emissivity and albedo are
#: tabulated per band; between them the renderer interpolates linearly, beyond them it holds
#: the end values.
VIEW_COSINES = np.linspace(0.02, 1.0, 15)
#: Wavelengths per band at which BRDF albedo and emissivity are evaluated, then interpolated.
BRDF_WAVELENGTHS = 12


class _BrdfTables:
    """Band tables of the materials that have a BRDF model.

    For such a material the reflected sun is f(ω_sun, ω_view, λ_b) cos θ_i ∫ S E_sun τ_so τ_a dλ,
    with the BRDF evaluated at the band's centre wavelength λ_b (exact for BRDFs whose shape
    does not change across the band, as for band-wise RPV or Ross-Li parameters); the reflected
    sky is Σ_k F_k ∫ S ρ_dh(θ_v, λ) L_sky,k τ_a dλ (by reciprocity, exact for a sky that is
    uniform over the visible hemisphere); the emission is ∫ S ε(θ_v, λ) B(λ, T) τ_a dλ with the
    directional emissivity ε = 1 − ρ_dh − τ_dh (Kirchhoff). ρ_dh and ε are evaluated at
    ``BRDF_WAVELENGTHS`` wavelengths evenly spread over each band and ``VIEW_COSINES`` view
    angles, and interpolated linearly between them.
    """

    def __init__(self, scene, bands, quadrature, path_nodes, suns, target_alt, sky_zenith,
                 sky_azimuth, sky_scale=()):
        from radscene.sun import toa_solar_irradiance

        mu = VIEW_COSINES
        wi = np.stack([np.sqrt(1.0 - mu**2), np.zeros_like(mu), mu], axis=-1)
        n_b, n_j, n_s = len(bands), path_nodes.size, len(suns)
        self.models = dict(scene.brdfs)
        self.centre = np.array([float(b.response.center) for b in bands])
        self.sun = np.zeros((n_b, n_s * n_j))
        self.emissivity_tau = {m: [] for m in self.models}
        self.sky = {m: np.zeros((mu.size, n_b, n_s * n_j, np.size(sky_zenith)))
                    for m in self.models}
        for b, (nodes, weights) in enumerate(quadrature):
            coarse = np.linspace(nodes.min(), nodes.max(), BRDF_WAVELENGTHS)
            # the hemispherical integrals are costly: evaluate them on a coarse grid
            eps = {m: _interp_rows(coarse, model.emissivity(wi[:, None, :], coarse[None, :]),
                                   nodes) for m, model in self.models.items()}
            rho = {m: _interp_rows(coarse, model.albedo(wi[:, None, :], coarse[None, :]), nodes)
                   for m, model in self.models.items()}
            for s, (sun, atm) in enumerate(suns):
                block = slice(s * n_j, (s + 1) * n_j)
                tau = atm.path(path_nodes.observer_altitude, path_nodes.target_altitude,
                               path_nodes.view_zenith, nodes).transmittance  # (j, q)
                if sun.zenith < 90.0:
                    toa = toa_solar_irradiance(nodes, sun.distance, solar_spectrum(atm))
                    e_sun = atm.sun(target_alt, sun.zenith, nodes, toa).irradiance
                    self.sun[b, block] = tau @ (weights * e_sun)
                sky_geom = SkyGeometry(scene.location.altitude, sun.zenith, sun.azimuth)
                sky = atm.sky(sky_zenith, sky_azimuth, nodes, sky_geom)  # (k, q)
                if sky_scale and sky_scale[b]:
                    sky = sky * sky_scale[b][s]
                for m in self.models:
                    self.sky[m][:, b, block] = np.einsum("q,vq,kq,jq->vjk", weights, rho[m],
                                                         sky, tau)
            tau = np.tile(tau, (n_s, 1))  # the same line of sight under every sun node
            for m in self.models:
                self.emissivity_tau[m].append(eps[m][:, None, :] * tau[None, :, :])


def _interp_rows(x, rows, new_x):
    """Linear interpolation of each row of ``rows`` (sampled at ``x``) onto ``new_x``."""
    rows = np.broadcast_to(np.atleast_2d(rows), (np.atleast_2d(rows).shape[0], np.size(x)))
    return np.stack([np.interp(new_x, x, row) for row in rows])


def _view_weights(cos_view):
    """Linear weights of view cosines on VIEW_COSINES: (lower index, upper weight)."""
    mu = np.clip(cos_view, VIEW_COSINES[0], VIEW_COSINES[-1])
    lower = np.clip(np.searchsorted(VIEW_COSINES, mu, side="right") - 1, 0, VIEW_COSINES.size - 2)
    frac = (mu - VIEW_COSINES[lower]) / (VIEW_COSINES[lower + 1] - VIEW_COSINES[lower])
    return lower, frac


def _brdf_terms(bset, values, mat, temp, cos_i, cos_v, cos_g, lit, tex, sky_f, nodes):
    """Replace the terms of samples whose material has a BRDF model (see _BrdfTables)."""
    tables = bset.brdf
    for m, model in tables.models.items():
        sel = mat == m
        if not np.any(sel):
            continue
        sub = nodes.subset(np.flatnonzero(sel))
        f = model.kernel(cos_i[sel, None], cos_v[sel, None], cos_g[sel, None],
                         tables.centre[None, :])  # (n, b)
        geometry = np.maximum(cos_i[sel], 0.0) * lit[sel] * tex["reflectance"][sel]
        values["sun_diffuse"][sel] = f * geometry[:, None] * _gather_band(tables.sun, sub)
        values["sun_specular"][sel] = 0.0
        lower, frac = _view_weights(cos_v[sel])
        sky = 0.0
        emission = np.zeros((int(sel.sum()), len(bset.quadrature)))
        for v_index, v_weight in ((lower, 1.0 - frac), (lower + 1, frac)):
            # Σ_j w_j Σ_k sky[v, :, j, k] F_k, the view cosine as the table's row
            sky = sky + v_weight[:, None] * _sky_sum(tables.sky[m], v_index, sub, sky_f[sel])
            for b, (q_nodes, q_weights) in enumerate(bset.quadrature):
                coef = emission_coefficients(tables.emissivity_tau[m][b], q_nodes, q_weights,
                                             v_index, temp[sel])  # (n, j)
                emission[:, b] += v_weight * (np.take_along_axis(coef, sub.index, axis=1)
                                              * sub.weight).sum(1)
        values["sky_reflected"][sel] = sky * tex["reflectance"][sel, None]
        values["thermal_emission"][sel] = emission * tex["emissivity"][sel, None]


def _gather_band(table, nodes):
    """Σ_j w_j table[:, idx_j] for each sample: (N, n_b); ``table`` is (n_b, n_j)."""
    return node_mixing.mix_rows(table.T[None], np.zeros(len(nodes.index), dtype=np.int64),
                                nodes.index, nodes.weight)


def _sky_sum(table, row, nodes, fractions):
    """Σ_j w_j Σ_k table[row, :, idx_j, k] F_k for each sample: (N, n_b).

    ``table`` is (n_rows, n_b, n_j, n_k) (rows: materials, or view cosines of a BRDF table),
    ``row`` and ``fractions`` (N,) and (N, n_k): terms.sky_reflected's sum without forming
    the (N, n_b, n_k) table of each sample.
    """
    return node_mixing.mix_sky(table.transpose(0, 2, 1, 3), row, nodes.index, nodes.weight,
                               fractions)


def render(scene, observer: str | None = None, *, progress: Callable[[int, int], None] | None = None,
           bands=None, specular=None, _tables: _SceneTables | None = None, _rays=None,
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
        shadows = worker.submit(_shadows, tables, hits, hit, rays.directions, sun_dir,
                                settings.shadows, track.up)
        ds = _render_rest(scene, setup, tables, bands, sun, track, hit_time, sun_dir,
                          settings, rays, hits, hit, shadows, worker, started, progress,
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
                          lambda obj, pos: _textures(scene, obj, pos)["transmittance"], behind,
                          _depth)
        layers += ("transmitted",)
    if scene.volumes:  # the light from behind through them, and their own
        atm = _configured_atmosphere(scene, sun, None)
        ds = volumes.apply(ds, scene, bands, rays, hits, sun_dir, track.up, atm, layers,
                           _sun_irradiance(atm, sun), breakpoints(scene))
    return ds


def _render_rest(scene, setup, tables, bands, sun, track, hit_time, sun_dir, settings, rays,
                 hits, hit, shadows, worker, started, progress, specular=None) -> xr.Dataset:
    """:func:`render` after the primary rays: the path nodes, the band tables and the tiles.

    ``sun`` is the scene's sun (the Dataset's attributes), ``track`` the sun at the rays'
    times, ``sun_dir`` the unit vector towards the sun of each hit (one row: of every hit).
    """
    from radscene.radiometry import band_brightness_temperature

    ny, nx = rays.shape
    n_pix = ny * nx
    n_b = len(bands)
    alt0 = scene.location.altitude
    obs_alt = rays.origins[hit, 2] + alt0
    tgt_alt = hits.position[hit, 2] + alt0
    to_observer = -rays.directions[hit]
    view_zenith = np.degrees(np.arccos(np.clip(to_observer[:, 2], -1.0, 1.0)))
    view_azimuth = np.degrees(np.arctan2(to_observer[:, 0], to_observer[:, 1])) % 360.0
    relative_azimuth = fold_relative_azimuth(view_azimuth, track.angles(hit_time)[1])
    mean_azimuth = _mean_view_azimuth(rays.directions, hit)
    suns = [(s, _configured_atmosphere(scene, s, mean_azimuth)) for s in track.nodes]
    atm = suns[track.reference][1]
    path_nodes = atm.path_nodes(obs_alt, tgt_alt, view_zenith,
                                relative_azimuth=relative_azimuth)
    # each hit's mixing: path node × sun node (the sun nodes around the hit's time)
    path_nodes_all = combine_nodes(path_nodes, *track.node_weights(hit_time))
    path_index, path_weight = path_nodes_all.azimuth_mixing()
    bset = _BandSetup(scene, bands, path_nodes, suns, track.reference)
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
    tile = max(per_pixel, (TILE_SAMPLES // per_pixel) * per_pixel)  # whole pixels per tile
    tiles = [slice(start, min(start + tile, total)) for start in range(0, total, tile)]
    hit_face = tables.face_offset[hits.object[hit]] + hits.primitive[hit]
    hit_material = tables.face_material[hit_face]
    hit_temperature = _hit_temperature(tables, hits, hit, hit_face)
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
    medium = _media(scene, tables, bands, sun_dir, track.up, suns[track.reference])
    sky_open = np.zeros((n_b, n_pix)) if medium is not None else None
    media_light = np.zeros((n_b, n_pix)) if medium is not None else None

    def launch(sl):
        state = _surface(tables, rays, hits, hit, hit_rank, sl, sun_dir, hit_material,
                         hit_temperature)
        if state is None:
            return None
        state.specular = specular_material[state.mat]
        n_specular = int(np.count_nonzero(state.specular))
        shifts = (rng.random((len(state.mat), 2)),
                  rng.random((n_specular, 2)) if n_specular else None)
        job = worker.submit(_secondary_rays, tables, state, settings, sky_nodes, shifts,
                            scratch, fused_sky, shadows)
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
    emission_pair, emission_tables = _emission_pairs(
        bset, hit_material, hit_temperature,
        None if tables.face_corner_temperature is None else EMISSION_TEMPERATURE_STEP)
    mix_tables = {  # (row, path node, band[, sky node]), as node_mixing.mix_terms takes them
        "sun_diffuse": coef.sun_diffuse.transpose(0, 2, 1),
        "sun_specular": coef.sun_specular.transpose(0, 2, 1),
        "emission": np.stack(emission_tables, axis=-1),
        "sky_specular": coef.sky_specular.transpose(0, 2, 1, 3),
        "path": coef.path.transpose(0, 2, 1), "transmittance": coef.transmittance.T[None]}
    mix_tables = {k: np.ascontiguousarray(v, dtype=float) for k, v in mix_tables.items()}
    mix_tables["sky_diffuse"] = sky_diffuse
    # with one sample per pixel a tile's pixels are final once its terms are written: their
    # brightness temperatures are computed here, while the next tiles' rays are traced
    thermal = [b for b, band in enumerate(bands)
               if band.response.center >= THERMAL_BAND_START]
    bt_map = np.full((n_b, n_pix), np.nan) if direct and thermal else None
    radiance = np.empty((n_b, n_pix)) if direct else None
    pixel_coords = None
    # the coupling layers: their pages are first touched tile by tile below, while the worker
    # traces (at 1 M pixels and 8 bands that first touch, 192 MB, was most of the coupling pass)
    layers = _coupling_layers(bset, labelled, n_b, n_pix)
    # the reflected background: its own pass over each tile's hits (None: off)
    reflect = background.for_render(
        scene, tables, bset, bands, per_pixel,
        [band.response.center >= THERMAL_BAND_START for band in bands],
        (lambda obj, pos: _textures(scene, obj, pos))
        if any(obj.textures for obj in scene.objects) else None, medium)
    sums[BACKGROUND_TERM] = bg = np.zeros((n_b, n_pix))

    def tile_totals(sl):
        """The tile's total radiance (the terms summed in TERMS order, as _dataset would)
        and brightness temperatures, while later tiles are traced."""
        if radiance is None:
            return
        at = _as_slice(rays.pixel[sl])
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
            _touch_pages(layers, i, len(tiles))
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
        tex = _textures(scene, obj, pos)
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
            sky_sums=sky_sums, path_index=path_index, path_weight=path_weight, **mix_tables)
        if bset.brdf is not None:
            values = {name: out[t].T for t, name in enumerate(TERMS)}
            cos_g = np.einsum("nc,nc->n", wo, np.broadcast_to(st.sun, wo.shape))
            _brdf_terms(bset, values, mat, temp, cos_i, cos_v, cos_g, lit, tex, sky_f,
                        path_nodes_all.subset(rank))
        if medium is not None:  # the sky rays' change by volumes and sheets
            change = st.media.result()
            if media_tables is None:
                media_tables = reflect.tables if reflect is not None else _reflection_tables(
                    scene, tables, bset, bands)
            d_sky, d_light = _media_sky(change, bset, sky_diffuse, st, tex, path_nodes_all,
                                        media_tables, coef.transmittance)
            if direct:
                out[3][:, p] += (d_sky * wh[:, None]).T
            else:
                out[3] += d_sky.T
            pixels, totals = _pixel_sums(p, wh, np.vstack([
                d_light.T, sky_view[None, :] + change.view(n_hits).T]))
            media_light[:, pixels] += totals[:n_b]
            sky_open[:, pixels] += totals[n_b:]
        if reflect is not None:  # at the surface, then through τ_a and Δρ
            values = reflect(st.origin, nrm, wo, mat, st.sun, sl.start)
            values *= _gather_band(coef.transmittance, path_nodes_all.subset(rank))
            values *= tex["reflectance"][:, None]
            pixels, totals = _pixel_sums(p, wh, values.T)
            bg[:, pixels] += totals
        truth_rows = (cos_i, 1.0 - lit, sky_view, temp, hits.distance[hidx], None)
        if per_pixel == 1:  # one sample per pixel: no sums, only weighted copies
            at = _as_slice(p)  # a tile of whole rows: plain slices
            if not direct:
                acc[:, :, at] = out if unit_weight else out * wh
                transmittance[:, at] = tau if unit_weight else tau * wh
            for key, row in zip(truth.TRUTH_SUMS, truth_rows, strict=True):
                truth_sum[key][at] = wh if row is None else row if unit_weight else row * wh
        else:
            n_rows = len(TERMS) * n_b
            rows = np.concatenate([out.reshape(n_rows, n_hits), tau, np.vstack(
                [np.ones(n_hits) if row is None else row for row in truth_rows])])
            pixels, totals = _pixel_sums(p, wh, rows)
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
    coupled = _coupling_pass(scene, bset, acc, truth_sum["hit_weight"], rays, hits, labelled,
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


def _media(scene, tables, bands, sun_dir, sun_up, reference):
    """The volumes and sheets that the sky rays of a render cross (:class:`media.Media`), or
    None where the scene has neither. ``reference`` is the (sun, atmosphere) pair whose sun
    the volumes scatter, along the hits' mean sun direction ``sun_dir``."""
    has_sheets = bool(tables.sheet_object.any())
    if not scene.volumes and not has_sheets:
        return None
    sun = None
    if sun_up and any(v.albedo > 0.0 for v in scene.volumes):
        mean = np.reshape(sun_dir, (-1, 3)).mean(axis=0)
        sun = (mean / np.linalg.norm(mean), _sun_irradiance(reference[1], reference[0]))
    sheet_tau = sheets.band_transmittance(scene.materials, bands) if has_sheets else None
    return media.Media(
        tuple(scene.volumes), list(bands), float(scene.location.altitude), sun,
        breakpoints(scene), tables if has_sheets else None, sheet_tau,
        (lambda obj, pos: _textures(scene, obj, pos)["transmittance"]) if has_sheets else None)


def _reflection_tables(scene, tables, bset, bands):
    """The reflected background's band tables (band-mean BRDFs) without its pass."""
    return background.band_tables(
        scene.materials, scene.brdfs, bset.quadrature, bset.sun_spectra,
        bset.coefficients.sky_view, bset.sky_nodes,
        [band.response.center >= THERMAL_BAND_START for band in bands], tables.face_offset,
        tables.face_material, tables.face_temperature)


#: Sky-fan rays whose sky-node weights are formed at once (P × sky nodes floats).
MEDIA_CHUNK = 1 << 13


def _media_sky(change, bset, sky_diffuse, st, tex, nodes_all, reflection, transmittance):
    """The change of a tile's reflected sky by volumes and sheets, per hit (N, n_b), and the
    volumes' own radiance reflected along the sky rays (N, n_b) [W m-2 sr-1].

    Each changed ray r of hit i adds delta_r,b times its share of the reflected sky, the sky
    sum of the render's tables with the ray's own sky-node weights as fractions (so the sun's
    spectral factors, ρ and τ_a stay as in the sky term), divided by the fan's rays; and
    π f̄(ω_r, ω_o) L_v,r τ̄_a of the volumes' radiance, f̄ the band-mean BRDF of the
    reflected background (:mod:`radscene.render.background_tables`).
    """
    from radscene.render.background_tables import brdf

    n, n_b = len(st.mat), sky_diffuse.shape[2]
    d_sky, d_light = np.zeros((n, n_b)), np.zeros((n, n_b))
    if len(change.point) == 0:
        return d_sky, d_light
    tau_a = _gather_band(transmittance, nodes_all.subset(st.rank))  # (N, n_b)
    for start in range(0, len(change.point), MEDIA_CHUNK):
        c = slice(start, start + MEDIA_CHUNK)
        point, d = change.point[c], change.direction[c]
        zenith = np.degrees(np.arccos(np.clip(d[:, 2], -1.0, 1.0)))
        azimuth = np.degrees(np.arctan2(d[:, 0], d[:, 1]))
        hats = sky_node_weights(zenith, azimuth, *bset.sky_nodes)  # (P, K)
        nodes = nodes_all.subset(st.rank[point])
        mat = st.mat[point]
        share = node_mixing.mix_sky(sky_diffuse, mat, nodes.index, nodes.weight, hats)
        if bset.brdf is not None:  # by reciprocity, ρ_dh at the view angle (_brdf_terms)
            for m in bset.brdf.models:
                sel = np.flatnonzero(mat == m)
                if len(sel) == 0:
                    continue
                lower, frac = _view_weights(st.cos_v[point[sel]])
                sub = nodes.subset(sel)
                share[sel] = sum(
                    v_weight[:, None] * _sky_sum(bset.brdf.sky[m], v_index, sub, hats[sel])
                    for v_index, v_weight in ((lower, 1.0 - frac), (lower + 1, frac)))
        light = change.light[c]
        own = np.zeros_like(light)
        lit = np.flatnonzero(np.any(light > 0.0, axis=1))
        if len(lit):
            f = brdf(reflection, mat[lit], d[lit], st.wo[point[lit]], st.nrm[point[lit]])
            own[lit] = np.pi * f * light[lit] * tau_a[point[lit]]
        for b in range(n_b):
            d_sky[:, b] += np.bincount(point, change.delta[c, b] * share[:, b], n)
            d_light[:, b] += np.bincount(point, own[:, b], n)
    scale = tex["reflectance"][:, None] / change.samples
    return d_sky * scale, d_light * scale


def _adjacency_on(scene, height) -> bool:
    """Whether the render applies the PSF: the scene's setting, or ``auto``: for observers
    more than :data:`~radscene.render.coupling.BOUNDARY_LAYER_HEIGHT` above the ground."""
    from radscene.render.coupling import BOUNDARY_LAYER_HEIGHT

    setting = scene.settings.adjacency
    return height > BOUNDARY_LAYER_HEIGHT if setting == "auto" else bool(setting)


def _coupling_layers(bset, labelled, n_b, n_pix):
    """Zeroed (layer, band, pixel) outputs of the coupling pass where the render couples (the
    engine scatters and some pixel has a labelled hit), else None."""
    tables = bset.coupling
    if tables is None or not tables.active or not np.any(labelled):
        return None
    return np.zeros((len(COUPLING_TERMS), n_b, n_pix))


def _touch_pages(array, part, parts):
    """Write a zero into every memory page of the ``part``-th of ``parts`` equal spans of
    ``array`` (a zeroed array): the pages' first touch, done where the thread would wait."""
    flat = array.reshape(-1)
    lo, hi = flat.size * part // parts, flat.size * (part + 1) // parts
    flat[lo:hi:max(1, 4096 // flat.itemsize)] = 0.0


def _coupling_pass(scene, bset, acc, coverage, rays, hits, labelled, hit_rank, path_nodes,
                   obs_alt, tgt_alt, view_zenith, total=None, layers=None) -> dict:
    """The coupling layers (band, pixel) of a render: zero where nothing couples; added to
    ``total`` (band, pixel), the total radiance, where given; written into ``layers`` (from
    :func:`_coupling_layers`) where given."""
    from radscene.render import coupling

    n_b, n_pix = acc.shape[1], acc.shape[2]
    tables = bset.coupling
    if tables is None or not tables.active or not np.any(labelled):
        return {name: np.zeros((n_b, n_pix)) for name in COUPLING_TERMS}
    slot = {name: i for i, name in enumerate(TERMS)}
    sample = np.flatnonzero(labelled)  # one hit per pixel: its position and path nodes
    pix = rays.pixel[sample]
    at = _as_slice(pix)  # every pixel in order (the usual case): views, not copies
    terms = [acc[slot[name]][:, at] for name in ("sun_diffuse", "sun_specular",
                                                 "sky_reflected", "thermal_emission")]
    transmittances = coupling.NodeTransmittances(tables.tau, tables.t_d, path_nodes.index,
                                                 path_nodes.weight, hit_rank[sample])
    psf = None
    height = float(np.mean(obs_alt) - np.mean(tgt_alt))
    if _adjacency_on(scene, height):
        pos = hits.position[_as_slice(sample)]
        cos_view = float(np.cos(np.radians(np.mean(view_zenith))))
        psf = (pos[:, 0], pos[:, 1], height / 1000.0, cos_view, tables.share)
    if layers is None:
        layers = np.zeros((len(COUPLING_TERMS), n_b, n_pix))
    out = dict(zip(COUPLING_TERMS, layers, strict=True))
    coupling.image_layers(*terms, coverage[at], transmittances, tables.s, tables.e0,
                          tables.e_dif, out, pix, psf, total)
    return out


def scene_tables(scene, tracer=None) -> _SceneTables:
    """The ray tracer and per-face tables of a scene, built once and kept with the scene;
    given a ``tracer`` (of the objects' meshes as they are), built anew around it."""
    cached = scene.render_cache.get("tables")
    if cached is None or tracer is not None:
        cached = scene.render_cache["tables"] = _SceneTables(scene, tracer)
    return cached


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


def _mean_view_azimuth(directions, hit):
    """The mean azimuth [deg] of the lines of sight from the hits, ``hit``, back along the
    rays' ``directions``; None without hits."""
    if not np.any(hit):
        return None
    pick = slice(None) if hit.all() else hit
    east = -directions[pick, 0].mean()
    north = -directions[pick, 1].mean()
    return float(np.degrees(np.arctan2(east, north)) % 360)


def _configured_atmosphere(scene, sun, azimuth):
    """The scene's atmosphere set up for a sun and a view azimuth [deg] (the lines of sight's
    mean: the engine's default where a query takes none)."""
    day = scene.time.timetuple().tm_yday if scene.time is not None else None
    return scene.atmosphere.with_sun(sun.zenith, sun.azimuth, day_of_year=day,
                                     view_azimuth=azimuth, earth_sun_distance=sun.distance)


def _sun_irradiance(atm, sun):
    """``irradiance(wavelength, altitude)``: E_sun τ_so normal to the beam [W m-2 um-1] of the
    scene's sun through ``atm``, zero below the horizon."""
    from radscene.sun import toa_solar_irradiance

    def irradiance(wavelength, altitude):
        if sun.zenith >= 90.0:
            return np.zeros_like(wavelength)
        toa = toa_solar_irradiance(wavelength, sun.distance, solar_spectrum(atm))
        return atm.sun(altitude, sun.zenith, wavelength, toa).irradiance
    return irradiance


def _pixel_sums(pixel, weight, rows):
    """Weighted sums of sample columns per pixel: (unique pixels, (n_rows, n_unique)).

    ``rows`` is (n_rows, N), one row per quantity. Rays come ordered pixel by pixel (each
    pixel's sub-samples together), so the samples of a pixel form one contiguous run that
    ``np.add.reduceat`` sums; with one sample per pixel there is nothing to sum.
    """
    weighted = rows * weight[None, :]
    if len(pixel) > 1 and np.any(pixel[1:] < pixel[:-1]):  # not ordered: sort first
        order = np.argsort(pixel, kind="stable")
        pixel, weighted = pixel[order], weighted[:, order]
    starts = np.flatnonzero(np.r_[True, pixel[1:] != pixel[:-1]])
    if len(starts) == len(pixel):
        return pixel, weighted
    return pixel[starts], np.add.reduceat(weighted, starts, axis=1)


def _hit_temperature(tables, hits, hit, hit_face):
    """The surface temperature at each hit [K]: its face's, or interpolated barycentrically
    between the face's corner temperatures where the scene gives them."""
    if tables.face_corner_temperature is None:
        return tables.face_temperature[hit_face]
    corner = tables.face_corner_temperature[hit_face]
    u = hits.u[hit].astype(float)
    v = hits.v[hit].astype(float)
    return (1.0 - u - v) * corner[:, 0] + u * corner[:, 1] + v * corner[:, 2]


def _emission_pairs(bset, material, temperature, step=None):
    """∫ S ε B(T) τ_a,j dλ once per (material, temperature) pair among the hits of a render.

    ``step`` [K]: temperatures interpolated across faces (one per hit) are grouped to this
    step for the emission (not for the truth map); None: each distinct temperature its own.
    Returns the pair of each hit (N,) and one (n_pairs, n_j) table per band.
    """
    if step is not None:
        temperature = np.round(np.asarray(temperature) / step) * step
    t_unique, t_inverse = np.unique(temperature, return_inverse=True)
    pairs, index = np.unique(material.astype(np.int64) * t_unique.size + t_inverse.ravel(),
                             return_inverse=True)
    pair_material, pair_t = np.divmod(pairs, max(t_unique.size, 1))
    tables = [emission_coefficients(bset.emissivity_tau[b], q_nodes, q_weights, pair_material,
                                    t_unique[pair_t])
              for b, (q_nodes, q_weights) in enumerate(bset.quadrature)]
    return index.ravel(), tables


def _surface(tables, rays, hits, hit, hit_rank, sl, sun_dir, hit_material, hit_temperature):
    """The state at the hits of one tile of samples, or None where the tile has none.

    ``sun_dir`` is the unit vector towards the sun of every hit (in hit order), or one row
    for all; the state's ``sun`` is that of the tile's hits (or the one row).
    """
    from radscene.render import kernels

    h = hit[sl]
    if not np.any(h):
        return None
    hidx = np.nonzero(h)[0] + sl.start
    rank = hit_rank[hidx]
    sun = sun_dir if len(sun_dir) == 1 else sun_dir[rank]
    nrm, wo, cos_v, cos_i, origin = kernels.surface_state(
        hits.normal, rays.directions, hits.position, hidx, tables.epsilon, sun)
    return SimpleNamespace(
        hidx=hidx, rank=rank, obj=hits.object[hidx], mat=hit_material[rank],
        temp=hit_temperature[rank], pos=hits.position[hidx], nrm=nrm, wo=wo, cos_v=cos_v,
        cos_i=cos_i, origin=origin, sun=sun)


def _shadows(tables, hits, hit, directions, sun_dir, trace, sun_up=True) -> np.ndarray:
    """1.0 for each hit (in hit order) where the sun is above its face (the normal turned to
    face the viewer) and, with ``trace``, seen from it; else 0.0. ``sun_dir`` is the unit
    vector towards the sun of each hit, or one row for all; ``sun_up`` False: it is below
    the horizon for every hit."""
    from radscene.render import kernels

    sel = slice(None) if hit.all() else hit
    pos, nrm, view = hits.position[sel], hits.normal[sel], directions[sel]
    sun_dir = np.reshape(sun_dir, (-1, 3))
    lit = np.zeros(len(pos))
    if not sun_up or len(pos) == 0:
        return lit
    tracer = tables.shadow_tracer
    todo = slice(None)  # the hits left to the checked query below: all of them, or
    if tracer.packets is not None:  # one pass, packets of eight neighbouring hits
        _traced, outside = kernels.packet_shadows(tracer.packets, np.ascontiguousarray(pos),
                                                  np.ascontiguousarray(nrm),
                                                  np.ascontiguousarray(view),
                                                  tracer.center, tracer.half_size,
                                                  tables.epsilon, sun_dir, trace, lit)
        if not outside:
            return lit
        todo = np.flatnonzero(lit < 0.0)  # those whose origin lies outside the scene's box
    pos, nrm, view = pos[todo], nrm[todo], view[todo]
    sun = np.broadcast_to(sun_dir if len(sun_dir) == 1 else sun_dir[todo], pos.shape)
    nrm = np.where((np.einsum("nc,nc->n", nrm, view) > 0.0)[:, None], -nrm, nrm)
    facing = np.einsum("nc,nc->n", nrm, sun) > 0.0
    out = np.zeros(len(pos))
    if trace:
        out[facing] = illumination.cast_shadow(tracer, pos[facing] + tables.epsilon
                                               * nrm[facing], sun[facing])
    else:
        out[facing] = 1.0
    lit[todo] = out
    return lit


def _secondary_rays(tables, st, settings, sky_nodes, shifts, scratch, sky, shadows):
    """Lit flags, sky and lobe rays of one tile's hits: (lit, sky, lobe fractions).

    ``shifts`` are the sky and lobe fans' rotations, drawn by the caller; ``scratch`` holds
    the fans' ray buffers between tiles. ``sky`` is None, or (table, index, weight): then the
    sky fan is folded straight into the reflected-sky band sums and the second item is
    (sums (N, n_b), sky view (N,)) instead of the fractions (N, K). The lobe fractions have
    no rows where the tile has no specular hit. ``shadows`` is the future of :func:`_shadows`
    for every hit of the render (run earlier on the same thread).
    """
    lit = shadows.result()[st.rank]
    if sky is None:
        sky_out = illumination.sky_fractions(tables.tracer, st.origin, st.nrm,
                                             settings.sky_samples, sky_nodes, None,
                                             shift=shifts[0], scratch=scratch)
    else:
        table, index, weight = sky
        sky_out = illumination.sky_sums(tables.tracer, st.origin, st.nrm, settings.sky_samples,
                                        sky_nodes, None, rank=st.rank, material=st.mat,
                                        index=index, weight=weight, table=table,
                                        shift=shifts[0], scratch=scratch)
    n_k = len(sky_nodes[0]) * len(sky_nodes[1])
    if shifts[1] is None:
        return lit, sky_out, np.zeros((0, n_k))
    lobe_f = np.zeros((len(st.mat), n_k))
    sel = st.specular
    axis = 2.0 * st.cos_v[sel, None] * st.nrm[sel] - st.wo[sel]
    lobe_f[sel] = illumination.lobe_sky_fractions(
        tables.tracer, st.origin[sel], st.nrm[sel], axis, tables.exponent[st.mat[sel]],
        settings.specular_samples, sky_nodes, None, shift=shifts[1], scratch=scratch)
    return lit, sky_out, lobe_f


def _as_slice(index):
    """``index`` as a slice where it is a run of consecutive integers, else itself."""
    if len(index) and index[-1] - index[0] == len(index) - 1 and np.all(np.diff(index) == 1):
        return slice(int(index[0]), int(index[-1]) + 1)
    return index


def _textures(scene, obj, pos) -> dict[str, np.ndarray]:
    out = {k: np.ones(len(obj)) for k in ("reflectance", "emissivity", "transmittance")}
    for o, sobj in enumerate(scene.objects):
        if not sobj.textures:
            continue
        sel = obj == o
        if not np.any(sel):
            continue
        for kind, texture in sobj.textures.items():
            out[kind][sel] = texture.sample(pos[sel, 0], pos[sel, 1])
    return out

