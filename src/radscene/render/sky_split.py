"""The reflected sky and background split by where their light comes from.

Seed 001's eq. 1 keeps apart, in the light a surface reflects, the sky's scattered sunlight
(B, E_ds/π) and the sky's own emission (E, E_de/π), and in the light of the surroundings their
reflected sunlight (G, L_bs) and their self-emitted radiance (H, L_be). The renderer's
``sky_reflected`` (B + E) and ``background_reflected`` (G + H) are each split into two layers
(:data:`radscene.render.outputs.PART_LAYERS`):

.. math::
    L_{sky} = L_{sky,solar} + L_{sky,thermal}, \\qquad L_{bg} = L_{bg,solar} + L_{bg,thermal}.

The sky's parts come from the atmosphere engine's own split
(:meth:`radscene.atmosphere.Atmosphere.sky_parts`). In most bands one part is exactly zero (the
visible: the air emits nothing; the LWIR of the database and 6S: no sunlight in the tables):
there the other part is the whole layer and nothing more is computed. Only in bands where
both are nonzero (:attr:`SkySplit.split`) is the thermal part contracted with the hits' sky
fractions a second time — the same sums as ``sky_reflected``'s with the thermal sky's band
tables (:meth:`SkySplit.tile_thermal`) — and the solar part is the layer less it. The background
pass carries its vertices' emission, their thermal sky and the air's emission apart
(:mod:`radscene.render.background`); its solar part is the layer less that.

Volumes and sheets on the sky rays dim each part as their own
(:func:`radscene.render.media_sky.sky_change_thermal`). The volumes' own radiance reflected
along the sky rays and met on the background's paths goes into each part by its origin, in
every band: their emission into the thermal part, the sun they scatter into the solar one
(:meth:`radscene.render.tiles.TileSums.finish`, :func:`radscene.render.background._segment`).
"""

from __future__ import annotations

import numpy as np

from radscene.render import node_mixing
from radscene.render.spectral import sky_table

__all__ = ["SkySplit", "part_layers", "PART_LAYERS", "PART_NAMES", "PART_COMMENTS"]

#: The layers split by the light's origin, and their (solar, thermal) parts.
PART_LAYERS = {
    "sky_reflected": ("sky_reflected_solar", "sky_reflected_thermal"),
    "background_reflected": ("background_reflected_solar", "background_reflected_thermal"),
}
#: Every part layer, in :data:`PART_LAYERS` order.
PART_NAMES = tuple(name for parts in PART_LAYERS.values() for name in parts)

#: The ``comment`` attribute of each part layer: its share of its layer.
PART_COMMENTS = {
    "sky_reflected_solar": "seed 001 eq. 1 term B: the sky's scattered sunlight reflected (and "
                           "the sun that volumes scatter into the sky rays); "
                           "sky_reflected = sky_reflected_solar + sky_reflected_thermal",
    "sky_reflected_thermal": "seed 001 eq. 1 term E: the sky's own emission reflected (and the "
                             "emission of volumes on the sky rays); "
                             "sky_reflected = sky_reflected_solar + sky_reflected_thermal",
    "background_reflected_solar": "seed 001 eq. 1 term G: the surroundings' sunlight (their sun "
                                  "and sky's scattered sunlight) reflected; background_reflected"
                                  " = background_reflected_solar + background_reflected_thermal",
    "background_reflected_thermal": "seed 001 eq. 1 term H: the surroundings' self-emitted "
                                    "radiance (their emission, their sky's emission, the air's "
                                    "and volumes' on the paths) "
                                    "reflected; background_reflected = background_reflected_solar"
                                    " + background_reflected_thermal",
}


class SkySplit:
    """Which bands' skies hold sunlight, emission or both, and the thermal sky's band tables
    of the bands that hold both.

    Filled band by band while :class:`~radscene.render.band_setup.BandSetup` builds its sky
    tables (:meth:`add`).

    Attributes
    ----------
    solar, thermal : (n_b,) bool — the band's sky holds scattered sunlight, emission
    split : (n_split,) int — the bands that hold both
    view : (n_b, n_k) — ∫ S L_sky,thermal,k dλ of the reference sun node [W m-2 sr-1]
    diffuse, specular : (n_m, n_j, n_split, n_k) — ∫ S ρ L_sky,thermal,k τ_a dλ of the split
        bands, in :func:`~radscene.render.node_mixing.mix_sky`'s layout [W m-2 sr-1]
    """

    def __init__(self, n_m, n_b, n_j, n_k):
        self.solar = np.zeros(n_b, dtype=bool)
        self.thermal = np.zeros(n_b, dtype=bool)
        self.view = np.zeros((n_b, n_k))
        self._tables = {}  # band → (diffuse, specular) (n_m, n_j, n_k), where it emits
        self._shape = (n_m, n_j, n_k)
        self.split = np.zeros(0, dtype=np.int64)
        self.diffuse = self.specular = np.zeros((n_m, n_j, 0, n_k))

    def add(self, band, block, parts, rho, tau, view_weights=None):
        """Record band ``band``'s sky under one sun node: ``parts`` (solar, thermal) its
        spectra (k, q) as the sky table takes them, ``rho`` the weighted diffuse and
        specular reflectances (m, q) and ``tau`` the path transmittance (j, q) of its sky
        tables (:func:`~radscene.render.spectral.sky_table`), ``block`` this sun node's slice
        of the node axis; ``view_weights``, the band's quadrature weights [um], where it is
        the reference sun node (whose sky :attr:`view` holds)."""
        solar, thermal = parts
        self.solar[band] |= bool(np.any(solar != 0.0))
        if not np.any(thermal != 0.0):
            return
        self.thermal[band] = True
        if view_weights is not None:
            self.view[band] = thermal @ view_weights
        tables = self._tables.setdefault(band, tuple(np.zeros(self._shape) for _ in range(2)))
        for table, weighted in zip(tables, rho, strict=True):
            table[:, block] = sky_table(weighted, thermal, tau)

    def finish(self):
        """Keep the thermal tables of the bands that hold both parts, in the kernels'
        layout; let go of the others."""
        self.split = np.flatnonzero(self.solar & self.thermal)
        if len(self.split):
            self.diffuse, self.specular = (np.ascontiguousarray(np.stack(
                [self._tables[b][i] for b in self.split], axis=2)) for i in range(2))
        self._tables = {}

    def fused_table(self, sky_diffuse):
        """The diffuse sky table (n_m, n_j, n_b, n_k) with the split bands' thermal tables
        after its bands: folded with the sky fans on the worker thread, it gives the
        thermal sums as extra columns (:meth:`columns`)."""
        if not len(self.split):
            return sky_diffuse
        return np.ascontiguousarray(np.concatenate([sky_diffuse, self.diffuse], axis=2))

    def columns(self, sums, n_b):
        """A fused sky sum (N, n_b + n_split) as (the sky's (N, n_b), the thermal's
        (N, n_split) or None)."""
        if sums.shape[1] == n_b:
            return sums, None
        return np.ascontiguousarray(sums[:, :n_b]), sums[:, n_b:]

    def tile_thermal(self, st, reflectance, sky_f, lobe_f, fused, nodes, brdf=None):
        """The split bands' thermal reflected sky of a tile's hits, (n_split, N)
        [W m-2 sr-1]: the sky term's sums (:func:`~radscene.render.terms.sky_reflected`)
        with the thermal tables.

        ``st`` is the tile's surface state (``mat``, ``specular``, ``cos_v``),
        ``reflectance`` Δρ (N,), ``sky_f`` and ``lobe_f`` the sky fractions F and G (F None
        where ``fused``, the thermal diffuse sums (N, n_split), came with the sky fans),
        ``nodes`` the hits' path nodes; ``brdf`` the render's
        :class:`~radscene.render.brdf_tables.BrdfTables` or None.
        """
        if fused is not None:
            out = np.array(fused, dtype=float)
        else:
            out = node_mixing.mix_sky(self.diffuse, st.mat, nodes.index, nodes.weight, sky_f)
        sel = np.flatnonzero(st.specular)
        if len(sel):
            sub = nodes.subset(sel)
            out[sel] += node_mixing.mix_sky(self.specular, st.mat[sel], sub.index, sub.weight,
                                            lobe_f[sel])
        if brdf is not None:
            from radscene.render.brdf_tables import brdf_sky

            for m in brdf.models:
                sel = np.flatnonzero(st.mat == m)
                if len(sel):
                    out[sel] = brdf_sky(brdf.sky_thermal[m], st.cos_v[sel], nodes.subset(sel),
                                        sky_f[sel])
        out *= reflectance[:, None]
        return out.T


def part_layers(layer, thermal_part, solar, thermal, split):
    """A layer's (solar, thermal) parts (n_b, ...): ``thermal_part`` is its thermal part
    where computed (rows of the ``split`` bands, or of every band: ``split`` None); a band whose
    sky holds only sunlight (``solar`` and not ``thermal``, (n_b,) bool) is all solar, one
    with only emission all thermal. Bands of one part are copied, not subtracted."""
    thermal_layer = np.zeros(layer.shape)  # pages of zeros, written only where needed
    if split is None:
        thermal_layer[...] = thermal_part
        return layer - thermal_layer, thermal_layer
    only = np.asarray(thermal) & ~np.asarray(solar)
    solar_layer = np.zeros(layer.shape)
    for b in range(len(layer)):
        (thermal_layer if only[b] else solar_layer)[b] = layer[b]
    if len(split):
        thermal_layer[split] = thermal_part
        solar_layer[split] -= thermal_part
    return solar_layer, thermal_layer
