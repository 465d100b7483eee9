"""Shading of a tile's hits: the signature terms, and the passes that add to them.

For the hits of one tile of ray samples, :class:`TileShader` forms the five signature terms
(:func:`radscene.render.node_mixing.mix_terms`, the terms of :mod:`radscene.render.terms`
with their band coefficients mixed between path nodes), replaces them where the material has
a BRDF model (:func:`radscene.render.brdf_tables.brdf_terms`), changes the reflected sky by
the scene's volumes and sheets (:mod:`radscene.render.media_sky`), adds the reflected
background (:mod:`radscene.render.background`) and writes all of it, with the truth, into
the image's sums (:class:`radscene.render.tiles.TileSums`).
"""

from __future__ import annotations

import numpy as np

from radscene.render import background, key_frames, media_sky, node_mixing, terms
from radscene.render.brdf_tables import brdf_terms
from radscene.render.outputs import TERMS, THERMAL_BAND_START
from radscene.render.surface import textures

__all__ = ["TileShader"]


class TileShader:
    """Shades the tiles of one render (see the module's description).

    Parameters
    ----------
    scene, tables : the scene and its :class:`~radscene.render.surface.SceneTables`
    bset : :class:`~radscene.render.band_setup.BandSetup` — the render's band tables
    bands : list — the bands rendered
    rays, hits : the render's ray samples and their primary hits
    image : :class:`~radscene.render.tiles.TileSums` — where the tiles are written
    nodes : namespace — the hits' path-node mixing
        (:func:`~radscene.render.band_setup.path_setup`)
    mix_tables : dict — the band tables as ``mix_terms`` takes them
    emission_pair : (hits,) int — each hit's row of the emission table
    fused_sky : bool — the sky fans come folded into the diffuse sky sums
    medium : :class:`~radscene.render.media.Media` or None
    reflect : :class:`~radscene.render.background.Pass` or None
    per_pixel : int — ray samples per pixel
    cache : :class:`~radscene.render.frame_cache.FrameCache` or None — the observer's last
        frame, whose background paths' first rays are kept where nothing moved through them
    """

    def __init__(self, scene, tables, bset, bands, rays, hits, image, nodes, mix_tables,
                 emission_pair, fused_sky, medium, reflect, per_pixel, cache=None,
                 plan=None):
        self.scene, self.tables, self.bset, self.bands = scene, tables, bset, bands
        self.rays, self.hits, self.image, self.nodes = rays, hits, image, nodes
        self.mix_tables, self.emission_pair = mix_tables, emission_pair
        self.fused_sky, self.medium, self.reflect = fused_sky, medium, reflect
        self.per_pixel = per_pixel
        self.cache, self.plan = cache, plan  # the frame cache; the key frames' plan
        self.unit_weight = bool(np.all(rays.weight == 1.0))  # then weighting changes nothing
        self.media_tables = None  # the band-mean BRDFs that reflect the volumes' own radiance

    def __call__(self, st, job, sl):
        """Shade the hits of tile ``sl``: ``st`` their surface state
        (:func:`~radscene.render.surface.surface_state`), ``job`` the future of their
        secondary rays (:func:`~radscene.render.surface.secondary_rays`). Between key frames
        (:mod:`radscene.render.key_frames`) ``st`` holds the hits to shade, maybe none, and
        ``st.full`` every hit of the tile: the reflected background is that of all of them,
        or, where it is interpolated too, of the hits shaded (the pass still goes over every
        hit's first rays, so that its random numbers and its kept answers are those of a
        frame shaded in full)."""
        image, rays = self.image, self.rays
        plan = self.plan
        whole = st.full[0] if hasattr(st, "full") else st
        rows = st.full[1] if whole is not st and plan.background else slice(None)
        if len(st.hidx):
            tex = textures(self.scene, st.obj, st.pos)
            p = rays.pixel[st.hidx]
            wh = rays.weight[st.hidx]
            out, tau, lit, sky_view = self._terms(st, tex, job, p, wh)
            if self.medium is not None:  # the sky rays' change by volumes and sheets
                self._media(st, tex, out, p, wh, sky_view)
        if self.reflect is not None:  # at the surface, then through τ_a and Δρ
            active = None
            if whole is not st:  # the fans of the hits not shaded: their kept answers
                key_frames.whole_fan(self.cache, st, not isinstance(rows, slice))
                if isinstance(rows, slice):
                    tex_whole = textures(self.scene, whole.obj, whole.pos)
                else:  # the hits shaded: ``st``'s rows of ``whole``
                    tex_whole = tex if len(st.hidx) else {"reflectance": np.ones(0)}
                    active = np.zeros(len(whole.hidx), dtype=bool)
                    active[rows] = True
            else:
                tex_whole = tex
            kept = None if self.cache is None else self.cache.background(
                self.tables.tracer, whole, sl, self.reflect.samples)
            record = None if plan is None or plan.record is None else plan.record.bind(
                whole.hidx)
            values, emitted = self.reflect(whole.origin, whole.nrm, whole.wo, whole.mat,
                                           whole.sun, sl.start, getattr(whole, "fan", None),
                                           kept, record, active)
            values, emitted, hidx = values[rows], emitted[rows], whole.hidx[rows]
            tau_a = node_mixing.gather_band(self.bset.coefficients.transmittance,
                                            self.nodes.nodes_all.subset(whole.rank[rows]))
            for part in (values, emitted):
                part *= tau_a
                part *= tex_whole["reflectance"][:, None]
            image.add_background(rays.pixel[hidx], rays.weight[hidx], values.T, emitted.T)
        if not len(st.hidx):
            return
        truth_rows = (st.cos_i, 1.0 - lit, sky_view, st.temp, self.hits.distance[st.hidx], None)
        image.add(p, wh, out, tau, truth_rows, self.per_pixel, self.unit_weight)
        image.label(p, st.hidx, st.obj, st.mat, st.nrm, self.per_pixel)

    def _terms(self, st, tex, job, p, wh):
        """The tile's terms and transmittance, in the image (``direct``) or per hit; its lit
        flags and sky view."""
        nodes, bset = self.nodes, self.bset
        if np.any(st.specular):
            mirror_sun = 2.0 * st.cos_i[:, None] * st.nrm - st.sun
            cos_r = np.einsum("nc,nc->n", mirror_sun, st.wo)
            lobe = terms.phong_geometry(cos_r, self.tables.exponent[st.mat], st.cos_i, st.cos_v)
        else:  # every specular coefficient of these materials is zero
            lobe = np.zeros(len(st.hidx))
        lit, sky_out, lobe_f = job.result()
        if not self.fused_sky:
            sky_f, sky_sums, sky_view = sky_out, None, sky_out.sum(axis=1)
        else:
            sky_f, (sky_sums, sky_view) = None, sky_out
            sky_sums, fused_thermal = bset.sky_split.columns(sky_sums, len(self.bands))
        out, tau, out_pixel, out_weight = self.image.buffers(p, wh)
        node_mixing.mix_terms(
            out, tau, out_pixel, out_weight, st.rank, st.mat, self.emission_pair,
            nodes.nodes_all.index, nodes.nodes_all.weight, cos_incidence=st.cos_i, lit=lit,
            reflectance=tex["reflectance"], emissivity=tex["emissivity"], lobe=lobe,
            specular=st.specular, sky_fractions=sky_f, lobe_fractions=lobe_f,
            sky_sums=sky_sums, path_index=nodes.path_index, path_weight=nodes.path_weight,
            **self.mix_tables)
        if bset.brdf is not None:
            values = {name: out[t].T for t, name in enumerate(TERMS)}
            cos_g = np.einsum("nc,nc->n", st.wo, np.broadcast_to(st.sun, st.wo.shape))
            brdf_terms(bset, values, st.mat, st.temp, st.cos_i, st.cos_v, cos_g, lit, tex,
                       sky_f, nodes.nodes_all.subset(st.rank))
        if len(bset.sky_split.split):  # the sky's emission apart (sky_split.py)
            self.image.add_sky_thermal(p, wh, bset.sky_split.tile_thermal(
                st, tex["reflectance"], sky_f, lobe_f, None if sky_f is not None else
                fused_thermal, nodes.nodes_all.subset(st.rank), bset.brdf))
        return out, tau, lit, sky_view

    def _media(self, st, tex, out, p, wh, sky_view):
        """Add the change of the tile's reflected sky by volumes and sheets to ``out``, and
        the volumes' own radiance reflected along the sky rays to the image."""
        change = st.media.result()
        if self.media_tables is None:
            self.media_tables = (self.reflect.tables if self.reflect is not None
                                 else background.render_tables(
                                     self.scene, self.tables, self.bset,
                                     [band.response.center >= THERMAL_BAND_START
                                      for band in self.bands]))
        d_sky, d_light, d_heat = media_sky.sky_change(
            change, self.bset, self.mix_tables["sky_diffuse"], st, tex, self.nodes.nodes_all,
            self.media_tables, self.bset.coefficients.transmittance)
        lobe = None if getattr(st, "media_lobe", None) is None else st.media_lobe.result()
        if lobe is not None:  # the specular hits' lobe rays through the media
            for total, add in zip((d_sky, d_light, d_heat), media_sky.lobe_change(
                    lobe, self.bset, self.mix_tables["sky_specular"], st, tex,
                    self.nodes.nodes_all, self.media_tables,
                    self.bset.coefficients.transmittance), strict=True):
                total += add
        if self.image.direct:
            out[3][:, p] += (d_sky * wh[:, None]).T
        else:
            out[3] += d_sky.T
        if len(self.bset.sky_split.split):  # the thermal sky's share of the change
            thermal = media_sky.sky_change_thermal(change, self.bset, st, tex,
                                                   self.nodes.nodes_all)
            if lobe is not None:
                thermal += media_sky.lobe_change_thermal(lobe, self.bset, st, tex,
                                                         self.nodes.nodes_all)
            self.image.add_sky_thermal(p, wh, thermal.T)
        self.image.add_media(p, wh, d_light.T, sky_view[None, :] + change.view(len(st.hidx)).T,
                             d_heat.T)
