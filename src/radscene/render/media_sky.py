"""The reflected sky of a render changed by its volumes and sheets.

:func:`for_render` gathers the volumes and sheets that a render's sky rays cross
(:class:`radscene.render.media.Media`); :func:`sky_change` turns the changed rays of a
tile's sky fans (:func:`radscene.render.media.sky_fan`) into the change of each hit's
reflected sky and the volumes' own radiance it reflects (``docs/physics.md``).
"""

from __future__ import annotations

import numpy as np

from radscene.atmosphere import sky_node_weights
from radscene.render import media, node_mixing, sheets
from radscene.render.band_setup import sun_irradiance
from radscene.render.brdf_tables import view_weights
from radscene.render.spectral import breakpoints
from radscene.render.surface import textures

__all__ = ["for_render", "sky_change", "MEDIA_CHUNK"]

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


def sky_change(change, bset, sky_diffuse, st, tex, nodes_all, reflection, transmittance):
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
    tau_a = node_mixing.gather_band(transmittance, nodes_all.subset(st.rank))  # (N, n_b)
    for start in range(0, len(change.point), MEDIA_CHUNK):
        c = slice(start, start + MEDIA_CHUNK)
        point, d = change.point[c], change.direction[c]
        zenith = np.degrees(np.arccos(np.clip(d[:, 2], -1.0, 1.0)))
        azimuth = np.degrees(np.arctan2(d[:, 0], d[:, 1]))
        hats = sky_node_weights(zenith, azimuth, *bset.sky_nodes)  # (P, K)
        nodes = nodes_all.subset(st.rank[point])
        mat = st.mat[point]
        share = node_mixing.mix_sky(sky_diffuse, mat, nodes.index, nodes.weight, hats)
        if bset.brdf is not None:  # by reciprocity, ρ_dh at the view angle (brdf_terms)
            for m in bset.brdf.models:
                sel = np.flatnonzero(mat == m)
                if len(sel) == 0:
                    continue
                lower, frac = view_weights(st.cos_v[point[sel]])
                sub = nodes.subset(sel)
                share[sel] = sum(
                    v_weight[:, None] * node_mixing.sky_sum(bset.brdf.sky[m], v_index, sub,
                                                            hats[sel])
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
