"""The surface–atmosphere coupling pass of a render: its band tables and its image layers.

After the tiles, :func:`coupling_pass` forms the layers ``multiple_reflection``,
``diffuse_transmitted`` and ``adjacency`` of every pixel from the render's terms
(:func:`radscene.render.coupling.image_layers`); :class:`CouplingTables` holds the band
values of the engine's coupling spectra that it needs, integrated once per render.
"""

from __future__ import annotations

import numpy as np

from radscene.render import coupling
from radscene.render.outputs import COUPLING_TERMS, TERMS
from radscene.render.tiles import as_slice

__all__ = ["CouplingTables", "adjacency_on", "coupling_layers", "coupling_pass"]


class CouplingTables:
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


def adjacency_on(scene, height) -> bool:
    """Whether the render applies the PSF: the scene's setting, or ``auto``: for observers
    more than :data:`~radscene.render.coupling.BOUNDARY_LAYER_HEIGHT` above the ground
    (``height`` [m])."""
    setting = scene.settings.adjacency
    return height > coupling.BOUNDARY_LAYER_HEIGHT if setting == "auto" else bool(setting)


def coupling_layers(bset, labelled, n_b, n_pix):
    """Zeroed (layer, band, pixel) outputs of the coupling pass where the render couples (the
    engine scatters and some pixel has a labelled hit), else None."""
    tables = bset.coupling
    if tables is None or not tables.active or not np.any(labelled):
        return None
    return np.zeros((len(COUPLING_TERMS), n_b, n_pix))


def coupling_pass(scene, bset, acc, coverage, rays, hits, labelled, hit_rank, path_nodes,
                  obs_alt, tgt_alt, view_zenith, total=None, layers=None) -> dict:
    """The coupling layers (band, pixel) of a render: zero where nothing couples; added to
    ``total`` (band, pixel), the total radiance, where given; written into ``layers`` (from
    :func:`coupling_layers`) where given.

    ``acc`` holds the render's terms (term, band, pixel) [W m-2 sr-1], ``coverage`` the
    weight of each pixel's surface samples; ``labelled`` flags the one hit of each pixel
    whose position and path nodes stand for it; ``obs_alt``, ``tgt_alt`` [m] and
    ``view_zenith`` [deg] are the hits' (the observer's height above them sets the PSF).
    """
    n_b, n_pix = acc.shape[1], acc.shape[2]
    tables = bset.coupling
    if tables is None or not tables.active or not np.any(labelled):
        return {name: np.zeros((n_b, n_pix)) for name in COUPLING_TERMS}
    slot = {name: i for i, name in enumerate(TERMS)}
    sample = np.flatnonzero(labelled)  # one hit per pixel: its position and path nodes
    pix = rays.pixel[sample]
    at = as_slice(pix)  # every pixel in order (the usual case): views, not copies
    terms = [acc[slot[name]][:, at] for name in ("sun_diffuse", "sun_specular",
                                                 "sky_reflected", "thermal_emission")]
    transmittances = coupling.NodeTransmittances(tables.tau, tables.t_d, path_nodes.index,
                                                 path_nodes.weight, hit_rank[sample])
    psf = None
    height = float(np.mean(obs_alt) - np.mean(tgt_alt))
    if adjacency_on(scene, height):
        pos = hits.position[as_slice(sample)]
        cos_view = float(np.cos(np.radians(np.mean(view_zenith))))
        psf = (pos[:, 0], pos[:, 1], height / 1000.0, cos_view, tables.share)
    if layers is None:
        layers = np.zeros((len(COUPLING_TERMS), n_b, n_pix))
    out = dict(zip(COUPLING_TERMS, layers, strict=True))
    coupling.image_layers(*terms, coverage[at], transmittances, tables.s, tables.e0,
                          tables.e_dif, out, pix, psf, total)
    return out
