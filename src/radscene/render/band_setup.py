"""The band tables of one render: every spectral factor integrated once per band.

The spectral–spatial separation (ARCHITECTURE.md, "Speed comes from separating the spectrum
from space"): :func:`path_setup` finds the atmosphere's path nodes around the hits' lines of
sight and the sun nodes around their times; :class:`BandSetup` integrates each term's
spectral factor once per material × band × path node × sky node
(:class:`radscene.render.spectral.BandCoefficients`), with the coupling
(:class:`radscene.render.coupling_pass.CouplingTables`) and BRDF
(:class:`radscene.render.brdf_tables.BrdfTables`) tables beside them; :func:`emission_pairs`
the emission once per (material, temperature) pair among the hits.
"""

from __future__ import annotations

from dataclasses import fields
from types import SimpleNamespace

import numpy as np

from radscene.atmosphere import CouplingSpectra, SkyGeometry, sky_node_weights
from radscene.atmosphere.nodes import fold_relative_azimuth
from radscene.render.background_tables import air_extinction
from radscene.render.brdf_tables import BrdfTables
from radscene.render.coupling_pass import CouplingTables
from radscene.render.sky_split import SkySplit
from radscene.render.spectral import (
    BandCoefficients,
    band_quadrature,
    breakpoints,
    emission_coefficients,
    sky_table,
    sun_toa,
)
from radscene.render.sun_track import combine_nodes

__all__ = ["BandSetup", "path_setup", "emission_pairs", "mix_tables", "configured_atmosphere",
           "sun_irradiance", "mean_view_azimuth", "EMISSION_TEMPERATURE_STEP"]

#: Step to which temperatures interpolated across faces are grouped for the emission [K]: at
#: most half of it, 0.5 mK, off (a band radiance off by 6e-5 relative at 3 um and 200 K; more at
#: shorter wavelengths, where a surface near 300 K emits next to nothing).
EMISSION_TEMPERATURE_STEP = 1e-3


class BandSetup:
    """Quadrature and coefficient tables for the bands of one render.

    ``suns`` pairs each sun node with the atmosphere set up for it (one pair for a frame);
    the tables' node axis runs over sun node × path node, ``s · n_j + j``, and the path
    radiance's also over the relative-azimuth nodes of ``path_nodes``. The sky table's grid
    and the sky that rays leaving the scene see are those of the reference sun node.
    """

    def __init__(self, scene, bands, path_nodes, suns, reference=0):
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
        #: the sky's sunlight and emission apart (:mod:`radscene.render.sky_split`)
        self.sky_split = SkySplit(n_m, n_b, n_s * n_j, n_k)
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
                    toa = sun_toa(atm, sun, nodes)
                    e_sun = atm.sun(target_alt, sun.zenith, nodes, toa).irradiance  # (q,)
                else:
                    e_sun = np.zeros_like(nodes)
                tau, radiance = _path_spectra(atm, path_nodes, sun, nodes)  # (j, q), (a, j, q)
                sky_geom = SkyGeometry(scene.location.altitude, sun.zenith, sun.azimuth)
                split = atm.sky_parts(sky_zenith, sky_azimuth, nodes, sky_geom)
                sky, thermal = split.solar + split.thermal, split.thermal  # (k·l, q)
                if atm_ref.couples:
                    cp = atm.coupling(path_nodes.observer_altitude,
                                      path_nodes.target_altitude, path_nodes.view_zenith, nodes)
                    parts.append(cp)
                    scales.append(_sky_scale(atm, sky, hemisphere, cp))
                    sky, thermal = sky * scales[-1], thermal * scales[-1]
                wt = weights * e_sun
                c.sun_diffuse[:, b, block] = np.einsum("q,mq,jq->mj", wt, rho_d / np.pi, tau)
                c.sun_specular[:, b, block] = np.einsum("q,mq,jq->mj", wt, rho_s, tau)
                c.sky_diffuse[:, b, block, :] = sky_table(weights * rho_d, sky, tau)
                c.sky_specular[:, b, block, :] = sky_table(weights * rho_s, sky, tau)
                self.sky_split.add(b, block, (split.solar, thermal),
                                   (weights * rho_d, weights * rho_s), tau,
                                   weights if s == reference else None)
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
        self.sky_split.finish()
        self.coupling = (CouplingTables(self.quadrature, taus, couplings, n_s * n_j)
                         if atm_ref.couples and scene.settings.coupling else None)
        self.sky_nodes = (zen_nodes, az_nodes)
        self._air = (atm_ref, float(scene.location.altitude))
        self.brdf = BrdfTables(scene, bands, self.quadrature, path_nodes, suns, target_alt,
                               sky_zenith, sky_azimuth, self.sky_scale, self.sky_split.split
                               ) if scene.brdfs else None

    @property
    def air_extinction(self) -> np.ndarray:
        """The air's band extinction coefficient at the ground, (n_b,) [m-1], for the
        background's paths between surfaces (:func:`~radscene.render.background_tables.
        air_extinction`); worked out when first asked for."""
        if not hasattr(self, "_air_extinction"):
            self._air_extinction = air_extinction(*self._air, self.quadrature)
        return self._air_extinction


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


def path_setup(scene, rays, hits, hit, track, hit_time):
    """The atmosphere's nodes for the hits of a render.

    ``track`` is the sun at the rays' times, ``hit_time`` the hits' times (None: one sun).
    Returns a namespace: the hits' observer and target altitudes ``obs_alt``, ``tgt_alt``
    [m] and ``view_zenith`` [deg]; ``suns``, each sun node with the atmosphere set up for
    it; the ``path_nodes`` of the reference sun's atmosphere; ``nodes_all``, each hit's
    mixing of path node × sun node; its relative-azimuth mixing ``path_index``,
    ``path_weight``.
    """
    alt0 = scene.location.altitude
    obs_alt = rays.origins[hit, 2] + alt0
    tgt_alt = hits.position[hit, 2] + alt0
    to_observer = -rays.directions[hit]
    view_zenith = np.degrees(np.arccos(np.clip(to_observer[:, 2], -1.0, 1.0)))
    view_azimuth = np.degrees(np.arctan2(to_observer[:, 0], to_observer[:, 1])) % 360.0
    relative_azimuth = fold_relative_azimuth(view_azimuth, track.angles(hit_time)[1])
    mean_azimuth = mean_view_azimuth(rays.directions, hit)
    suns = [(s, configured_atmosphere(scene, s, mean_azimuth)) for s in track.nodes]
    atm = suns[track.reference][1]
    path_nodes = atm.path_nodes(obs_alt, tgt_alt, view_zenith,
                                relative_azimuth=relative_azimuth)
    # each hit's mixing: path node × sun node (the sun nodes around the hit's time)
    nodes_all = combine_nodes(path_nodes, *track.node_weights(hit_time))
    path_index, path_weight = nodes_all.azimuth_mixing()
    return SimpleNamespace(obs_alt=obs_alt, tgt_alt=tgt_alt, view_zenith=view_zenith,
                           suns=suns, path_nodes=path_nodes, nodes_all=nodes_all,
                           path_index=path_index, path_weight=path_weight)


def mix_tables(coef, emission_tables, sky_diffuse=None) -> dict:
    """The band tables as :func:`radscene.render.node_mixing.mix_terms` takes them: (row,
    path node, band[, sky node]), contiguous float64. ``coef`` are the render's
    :class:`~radscene.render.spectral.BandCoefficients`, ``emission_tables`` one (row, n_j)
    table per band; ``sky_diffuse``, where given, the diffuse sky table already in that
    form."""
    if sky_diffuse is None:
        sky_diffuse = np.ascontiguousarray(coef.sky_diffuse.transpose(0, 2, 1, 3), dtype=float)
    tables = {
        "sun_diffuse": coef.sun_diffuse.transpose(0, 2, 1),
        "sun_specular": coef.sun_specular.transpose(0, 2, 1),
        "emission": np.stack(emission_tables, axis=-1),
        "sky_specular": coef.sky_specular.transpose(0, 2, 1, 3),
        "path": coef.path.transpose(0, 2, 1), "transmittance": coef.transmittance.T[None]}
    tables = {k: np.ascontiguousarray(v, dtype=float) for k, v in tables.items()}
    tables["sky_diffuse"] = sky_diffuse
    return tables


def emission_pairs(bset, material, temperature, step=None):
    """∫ S ε B(T) τ_a,j dλ once per (material, temperature) pair among the hits of a render.

    ``step`` [K]: temperatures interpolated across faces (one per hit) are grouped to this
    step for the emission (not for the truth map); None: each distinct temperature its own.
    Returns the pair of each hit (N,) and one (n_pairs, n_j) table per band.
    """
    material = np.asarray(material).astype(np.int64)
    temperature = np.asarray(temperature, dtype=float)
    if step is not None and np.isfinite(temperature).all():
        # whole steps: one sort of integers finds the pairs
        level = np.round(temperature / step).astype(np.int64)
        low = int(level.min()) if level.size else 0
        span = int(level.max()) - low + 1 if level.size else 1
        pairs, index = _distinct(material * span + (level - low))
        pair_material, pair_level = np.divmod(pairs, span)
        pair_temperature = (pair_level + low) * step
    else:
        if step is not None:
            temperature = np.round(temperature / step) * step
        t_unique, t_inverse = np.unique(temperature, return_inverse=True)
        pairs, index = np.unique(material * t_unique.size + t_inverse.ravel(),
                                 return_inverse=True)
        pair_material, pair_t = np.divmod(pairs, max(t_unique.size, 1))
        pair_temperature = t_unique[pair_t]
    tables = [emission_coefficients(bset.emissivity_tau[b], q_nodes, q_weights, pair_material,
                                    pair_temperature, distinct=True)
              for b, (q_nodes, q_weights) in enumerate(bset.quadrature)]
    return index.ravel(), tables


#: The most keys :func:`_distinct` marks in a table rather than sorts.
DISTINCT_TABLE = 1 << 24


def _distinct(key):
    """``np.unique(key, return_inverse=True)`` of non-negative int64 keys: by a table of the
    keys present where their range is at most :data:`DISTINCT_TABLE` (no sort), else sorted."""
    if not key.size or int(key.max()) >= DISTINCT_TABLE:
        return np.unique(key, return_inverse=True)
    present = np.zeros(int(key.max()) + 1, dtype=bool)
    present[key] = True
    distinct = np.flatnonzero(present)
    rank = np.cumsum(present) - 1
    return distinct, rank[key]


def mean_view_azimuth(directions, hit):
    """The mean azimuth [deg] of the lines of sight from the hits, ``hit``, back along the
    rays' ``directions``; None without hits."""
    if not np.any(hit):
        return None
    pick = slice(None) if hit.all() else hit
    east = -directions[pick, 0].mean()
    north = -directions[pick, 1].mean()
    return float(np.degrees(np.arctan2(east, north)) % 360)


def configured_atmosphere(scene, sun, azimuth):
    """The scene's atmosphere set up for a sun and a view azimuth [deg] (the lines of sight's
    mean: the engine's default where a query takes none)."""
    day = scene.time.timetuple().tm_yday if scene.time is not None else None
    return scene.atmosphere.with_sun(sun.zenith, sun.azimuth, day_of_year=day,
                                     view_azimuth=azimuth, earth_sun_distance=sun.distance)


def sun_irradiance(atm, sun):
    """``irradiance(wavelength, altitude)``: E_sun τ_so normal to the beam [W m-2 um-1] of the
    scene's sun through ``atm``, zero below the horizon."""
    def irradiance(wavelength, altitude):
        if sun.zenith >= 90.0:
            return np.zeros_like(wavelength)
        toa = sun_toa(atm, sun, wavelength)
        return atm.sun(altitude, sun.zenith, wavelength, toa).irradiance
    return irradiance
