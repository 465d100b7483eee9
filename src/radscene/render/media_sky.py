"""The reflected sky of a render changed by its volumes and sheets.

:func:`for_render` gathers the volumes and sheets that a render's sky rays cross
(:class:`radscene.render.media.Media`); :func:`sky_change` turns the changed rays of a
tile's sky fans (:func:`radscene.render.media.sky_fan`) into the change of each hit's
reflected sky and the volumes' own radiance it reflects, and :func:`lobe_change` those of
its specular hits' Phong lobe fans (:func:`radscene.render.media.lobe_fan`) likewise
(``docs/physics.md``).
"""

from __future__ import annotations

import numpy as np

from radscene.atmosphere import sky_node_weights
from radscene.render import media, node_mixing, sheets
from radscene.render.band_setup import sun_irradiance
from radscene.render.brdf_tables import brdf_sky as brdf_sky_sum
from radscene.render.spectral import breakpoints
from radscene.render.surface import textures

__all__ = ["for_render", "sky_change", "sky_change_thermal", "lobe_change", "lobe_change_thermal",
           "lobe_hits", "MEDIA_CHUNK"]

#: Sky-fan rays whose sky-node weights are formed at once (P × sky nodes floats).
MEDIA_CHUNK = 1 << 13


def for_render(scene, tables, bands, sun_dir, sun_up, reference):
    """The volumes and sheets that the sky rays of a render cross (:class:`media.Media`), or
    None where the scene has neither. ``reference`` is the (sun, atmosphere) pair whose sun
    the volumes scatter, along the hits' mean sun direction ``sun_dir``."""
    has_sheets = bool(tables.sheet_object.any())
    if not scene.volumes and not has_sheets:
        return None
    sun = None
    if sun_up and any(v.albedo > 0.0 for v in scene.volumes):
        mean = np.reshape(sun_dir, (-1, 3)).mean(axis=0)
        sun = (mean / np.linalg.norm(mean), sun_irradiance(reference[1], reference[0]))
    sheet_tau = sheets.band_transmittance(scene.materials, bands) if has_sheets else None
    return media.Media(
        tuple(scene.volumes), list(bands), float(scene.location.altitude), sun,
        breakpoints(scene), tables if has_sheets else None, sheet_tau,
        (lambda obj, pos: textures(scene, obj, pos)["transmittance"]) if has_sheets else None)


def lobe_hits(bset, material, specular) -> np.ndarray:
    """Which hits' Phong lobes the media change through lobe fans of their own (N,) bool: the
    ``specular`` hits whose ``material`` (N,) has no BRDF model (a model's sky term, its lobe
    included, is its own table's: :func:`sky_change` changes it whole)."""
    mask = np.asarray(specular, dtype=bool)
    if bset.brdf is not None and bset.brdf.models and mask.any():
        mask = mask & ~np.isin(material, list(bset.brdf.models))
    return mask


def sky_change(change, bset, sky_diffuse, st, tex, nodes_all, reflection, transmittance):
    """The change of a tile's reflected sky by volumes and sheets, per hit (N, n_b), the
    volumes' own radiance reflected along the sky rays (N, n_b) and the part of it that is
    their emission (N, n_b) [W m-2 sr-1].

    Each changed ray r of hit i adds delta_r,b times its share of the reflected sky, the sky
    sum of the render's tables with the ray's own sky-node weights as fractions (so the sun's
    spectral factors, ρ and τ_a stay as in the sky term), divided by the fan's rays; and
    π f̄(ω_r, ω_o) L_v,r τ̄_a of the volumes' radiance, f̄ the band-mean BRDF of the
    reflected background (:mod:`radscene.render.background_tables`) — of a specular hit
    (``st.specular``) its diffuse part ρ̄_d / π, its lobe's rays being :func:`lobe_change`'s.
    """
    from radscene.render.background_tables import brdf

    n, n_b = len(st.mat), sky_diffuse.shape[2]
    d_sky, d_light, d_heat = np.zeros((n, n_b)), np.zeros((n, n_b)), np.zeros((n, n_b))
    if len(change.point) == 0:
        return d_sky, d_light, d_heat
    tau_a = node_mixing.gather_band(transmittance, nodes_all.subset(st.rank))  # (N, n_b)
    brdf_sky = None if bset.brdf is None else bset.brdf.sky
    for start in range(0, len(change.point), MEDIA_CHUNK):
        c = slice(start, start + MEDIA_CHUNK)
        point, d, share = _shares(change, c, bset, sky_diffuse, brdf_sky, st, nodes_all)
        mat = st.mat[point]
        light = change.light[c]
        factor = np.zeros_like(light)  # π f τ_a of each ray that brings light
        lit = np.flatnonzero(np.any(light > 0.0, axis=1))
        if len(lit):
            f = brdf(reflection, mat[lit], d[lit], st.wo[point[lit]], st.nrm[point[lit]])
            lobe = np.flatnonzero(lobe_hits(bset, mat[lit], st.specular[point[lit]]))
            if len(lobe):  # their Phong lobe has fans of its own (lobe_change): ρ_d / π here
                f[lobe] = reflection.diffuse[mat[lit][lobe]] / np.pi
            factor[lit] = np.pi * f * tau_a[point[lit]]
        _accumulate(point, change, c, share, factor, (d_sky, d_light, d_heat))
    scale = tex["reflectance"][:, None] / change.samples
    return d_sky * scale, d_light * scale, d_heat * scale


def _accumulate(point, change, c, share, factor, out):
    """Add each changed ray's sky change delta · share, its media's light · factor and the
    emission's part of it (``change.heat``) to the per-hit sums ``out`` at its ``point``."""
    d_sky, d_light, d_heat = out
    n = len(d_sky)
    light, heat = change.light[c] * factor, change.heat[c] * factor
    for b in range(d_sky.shape[1]):
        d_sky[:, b] += np.bincount(point, change.delta[c, b] * share[:, b], n)
        d_light[:, b] += np.bincount(point, light[:, b], n)
        d_heat[:, b] += np.bincount(point, heat[:, b], n)


def sky_change_thermal(change, bset, st, tex, nodes_all):
    """The thermal part of :func:`sky_change`'s change of the reflected sky, in the bands
    whose sky holds sunlight and emission (``bset.sky_split.split``): (N, n_split)
    [W m-2 sr-1], the same sums with the thermal sky's tables
    (:mod:`radscene.render.sky_split`)."""
    split = bset.sky_split
    n = len(st.mat)
    out = np.zeros((n, len(split.split)))
    brdf_sky = None if bset.brdf is None else bset.brdf.sky_thermal
    for start in range(0, len(change.point), MEDIA_CHUNK):
        c = slice(start, start + MEDIA_CHUNK)
        point, _, share = _shares(change, c, bset, split.diffuse, brdf_sky, st, nodes_all)
        for s, b in enumerate(split.split):
            out[:, s] += np.bincount(point, change.delta[c, b] * share[:, s], n)
    return out * (tex["reflectance"][:, None] / change.samples)


def lobe_change(change, bset, sky_specular, st, tex, nodes_all, reflection, transmittance):
    """The change of a tile's specularly reflected sky by volumes and sheets, per hit
    (N, n_b), the volumes' own radiance reflected along the lobe rays (N, n_b) and the part of
    it that is their emission (N, n_b) [W m-2 sr-1]; ``change`` holds the rays of the lobe fans of the tile's specular hits
    (``st.specular``, in order).

    Each lobe ray r, drawn from the lobe's own distribution, brings ρ_s L(ω_r) τ_a: a changed
    ray adds delta_r,b times the sky sum of the specular tables with its own sky-node weights,
    and ρ̄_s L_v,r τ̄_a of the volumes' radiance (ρ̄_s the band-mean specular reflectance of the
    reflected background's tables), each divided by the fan's rays.
    """
    n, n_b = len(st.mat), sky_specular.shape[2]
    d_sky, d_light, d_heat = np.zeros((n, n_b)), np.zeros((n, n_b)), np.zeros((n, n_b))
    if len(change.point) == 0:
        return d_sky, d_light, d_heat
    hit = np.flatnonzero(lobe_hits(bset, st.mat, st.specular))
    tau_a = node_mixing.gather_band(transmittance, nodes_all.subset(st.rank))  # (N, n_b)
    for start in range(0, len(change.point), MEDIA_CHUNK):
        c = slice(start, start + MEDIA_CHUNK)
        point, _, share = _shares(change, c, bset, sky_specular, None, st, nodes_all,
                                  hit[change.point[c]])
        factor = reflection.specular[st.mat[point]] * tau_a[point]
        _accumulate(point, change, c, share, factor, (d_sky, d_light, d_heat))
    scale = tex["reflectance"][:, None] / change.samples
    return d_sky * scale, d_light * scale, d_heat * scale


def lobe_change_thermal(change, bset, st, tex, nodes_all):
    """The thermal part of :func:`lobe_change`'s change of the reflected sky in the bands
    whose sky holds sunlight and emission: (N, n_split) [W m-2 sr-1] (as
    :func:`sky_change_thermal`, with the thermal sky's specular tables)."""
    split = bset.sky_split
    n = len(st.mat)
    out = np.zeros((n, len(split.split)))
    hit = np.flatnonzero(lobe_hits(bset, st.mat, st.specular))
    for start in range(0, len(change.point), MEDIA_CHUNK):
        c = slice(start, start + MEDIA_CHUNK)
        point, _, share = _shares(change, c, bset, split.specular, None, st, nodes_all,
                                  hit[change.point[c]])
        for s, b in enumerate(split.split):
            out[:, s] += np.bincount(point, change.delta[c, b] * share[:, s], n)
    return out * (tex["reflectance"][:, None] / change.samples)


def _shares(change, c, bset, sky_diffuse, brdf_sky, st, nodes_all, point=None):
    """The changed rays ``c`` of a tile's sky fans: their hits (P,), directions (P, 3) and
    shares of the reflected sky (P, bands of ``sky_diffuse``), the sky sum of ``sky_diffuse``
    (a material's BRDF model: of its table in ``brdf_sky``) with each ray's sky-node
    weights as fractions. ``point``, where given, is the rays' hits (default: the change's
    points)."""
    point = change.point[c] if point is None else point
    d = change.direction[c]
    zenith = np.degrees(np.arccos(np.clip(d[:, 2], -1.0, 1.0)))
    azimuth = np.degrees(np.arctan2(d[:, 0], d[:, 1]))
    hats = sky_node_weights(zenith, azimuth, *bset.sky_nodes)  # (P, K)
    nodes = nodes_all.subset(st.rank[point])
    mat = st.mat[point]
    share = node_mixing.mix_sky(sky_diffuse, mat, nodes.index, nodes.weight, hats)
    for m, table in (brdf_sky or {}).items():  # by reciprocity, ρ_dh at the view angle
        sel = np.flatnonzero(mat == m)
        if len(sel):
            share[sel] = brdf_sky_sum(table, st.cos_v[point[sel]], nodes.subset(sel), hats[sel])
    return point, d, share
