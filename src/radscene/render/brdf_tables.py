"""Band tables and signature terms of the materials that have a BRDF model.

For such a material the reflected sun is f(ω_sun, ω_view, λ_b) cos θ_i ∫ S E_sun τ_so τ_a dλ,
with the BRDF evaluated at the band's centre wavelength λ_b (exact for BRDFs whose shape
does not change across the band, as for band-wise RPV or Ross-Li parameters); the reflected
sky is Σ_k F_k ∫ S ρ_dh(θ_v, λ) L_sky,k τ_a dλ (by reciprocity, exact for a sky that is
uniform over the visible hemisphere); the emission is ∫ S ε(θ_v, λ) B(λ, T) τ_a dλ with the
directional emissivity ε = 1 − ρ_dh − τ_dh (Kirchhoff). ρ_dh and ε are evaluated at
``BRDF_WAVELENGTHS`` wavelengths evenly spread over each band and ``VIEW_COSINES`` view
angles, and interpolated linearly between them.

:class:`BrdfTables` holds the band tables (built with the render's other band tables,
:class:`radscene.render.band_setup.BandSetup`); :func:`brdf_terms` replaces the Phong terms
of a tile's samples whose material has a BRDF model.
"""

from __future__ import annotations

import numpy as np

from radscene.atmosphere import SkyGeometry
from radscene.render.node_mixing import gather_band, sky_sum
from radscene.render.spectral import emission_coefficients, sun_toa

__all__ = ["BrdfTables", "brdf_terms", "brdf_sky", "view_weights", "VIEW_COSINES",
           "BRDF_WAVELENGTHS"]

#: Cosines of the view zenith at which BRDF materials' directional emissivity and albedo are
#: tabulated per band; between them the renderer interpolates linearly, beyond them it holds
#: the end values.
VIEW_COSINES = np.linspace(0.02, 1.0, 15)
#: Wavelengths per band at which BRDF albedo and emissivity are evaluated, then interpolated.
BRDF_WAVELENGTHS = 12


class BrdfTables:
    """Band tables of the materials that have a BRDF model (see the module's description).

    ``quadrature`` holds each band's (nodes [um], weights [um]); ``suns`` pairs each sun
    node with the atmosphere set up for it, the tables' node axis running over sun node ×
    path node of ``path_nodes``; ``sky_scale`` the sky table's factors per band and sun node
    (:class:`radscene.render.band_setup.BandSetup`); ``split`` the bands whose sky holds
    both sunlight and emission, whose thermal sky tables ``sky_thermal`` keeps apart
    (:mod:`radscene.render.sky_split`).
    """

    def __init__(self, scene, bands, quadrature, path_nodes, suns, target_alt, sky_zenith,
                 sky_azimuth, sky_scale=(), split=()):
        mu = VIEW_COSINES
        wi = np.stack([np.sqrt(1.0 - mu**2), np.zeros_like(mu), mu], axis=-1)
        n_b, n_j, n_s = len(bands), path_nodes.size, len(suns)
        self.models = dict(scene.brdfs)
        self.centre = np.array([float(b.response.center) for b in bands])
        self.sun = np.zeros((n_b, n_s * n_j))
        self.emissivity_tau = {m: [] for m in self.models}
        self.sky = {m: np.zeros((mu.size, n_b, n_s * n_j, np.size(sky_zenith)))
                    for m in self.models}
        split = [int(b) for b in split]
        self.sky_thermal = {m: np.zeros((mu.size, len(split), n_s * n_j, np.size(sky_zenith)))
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
                    toa = sun_toa(atm, sun, nodes)
                    e_sun = atm.sun(target_alt, sun.zenith, nodes, toa).irradiance
                    self.sun[b, block] = tau @ (weights * e_sun)
                sky_geom = SkyGeometry(scene.location.altitude, sun.zenith, sun.azimuth)
                parts = atm.sky_parts(sky_zenith, sky_azimuth, nodes, sky_geom)  # (k, q) each
                sky, thermal = parts.solar + parts.thermal, parts.thermal
                if sky_scale and sky_scale[b]:
                    sky, thermal = sky * sky_scale[b][s], thermal * sky_scale[b][s]
                for m in self.models:
                    self.sky[m][:, b, block] = np.einsum("q,vq,kq,jq->vjk", weights, rho[m],
                                                         sky, tau)
                    if b in split:
                        self.sky_thermal[m][:, split.index(b), block] = np.einsum(
                            "q,vq,kq,jq->vjk", weights, rho[m], thermal, tau)
            tau = np.tile(tau, (n_s, 1))  # the same line of sight under every sun node
            for m in self.models:
                self.emissivity_tau[m].append(eps[m][:, None, :] * tau[None, :, :])


def _interp_rows(x, rows, new_x):
    """Linear interpolation of each row of ``rows`` (sampled at ``x``) onto ``new_x``."""
    rows = np.broadcast_to(np.atleast_2d(rows), (np.atleast_2d(rows).shape[0], np.size(x)))
    return np.stack([np.interp(new_x, x, row) for row in rows])


def view_weights(cos_view):
    """Linear weights of view cosines on VIEW_COSINES: (lower index, upper weight)."""
    mu = np.clip(cos_view, VIEW_COSINES[0], VIEW_COSINES[-1])
    lower = np.clip(np.searchsorted(VIEW_COSINES, mu, side="right") - 1, 0, VIEW_COSINES.size - 2)
    frac = (mu - VIEW_COSINES[lower]) / (VIEW_COSINES[lower + 1] - VIEW_COSINES[lower])
    return lower, frac


def brdf_terms(bset, values, mat, temp, cos_i, cos_v, cos_g, lit, tex, sky_f, nodes):
    """Replace the terms of samples whose material has a BRDF model (see :class:`BrdfTables`).

    ``bset`` is the render's band setup, ``values`` the tile's terms by name, (N, n_b) each
    [W m-2 sr-1], written in place; per sample ``mat``, ``temp`` [K], the cosines of
    incidence, view and phase ``cos_i``, ``cos_v``, ``cos_g``, ``lit``, the textures ``tex``,
    the sky fractions ``sky_f`` (N, n_k) and the path ``nodes``.
    """
    tables = bset.brdf
    for m, model in tables.models.items():
        sel = mat == m
        if not np.any(sel):
            continue
        sub = nodes.subset(np.flatnonzero(sel))
        f = model.kernel(cos_i[sel, None], cos_v[sel, None], cos_g[sel, None],
                         tables.centre[None, :])  # (n, b)
        geometry = np.maximum(cos_i[sel], 0.0) * lit[sel] * tex["reflectance"][sel]
        values["sun_diffuse"][sel] = f * geometry[:, None] * gather_band(tables.sun, sub)
        values["sun_specular"][sel] = 0.0
        lower, frac = view_weights(cos_v[sel])
        sky = brdf_sky(tables.sky[m], cos_v[sel], sub, sky_f[sel])
        emission = np.zeros((int(sel.sum()), len(bset.quadrature)))
        for v_index, v_weight in ((lower, 1.0 - frac), (lower + 1, frac)):
            for b, (q_nodes, q_weights) in enumerate(bset.quadrature):
                coef = emission_coefficients(tables.emissivity_tau[m][b], q_nodes, q_weights,
                                             v_index, temp[sel])  # (n, j)
                emission[:, b] += v_weight * (np.take_along_axis(coef, sub.index, axis=1)
                                              * sub.weight).sum(1)
        values["sky_reflected"][sel] = sky * tex["reflectance"][sel, None]
        values["thermal_emission"][sel] = emission * tex["emissivity"][sel, None]


def brdf_sky(table, cos_view, nodes, sky_fractions):
    """The reflected sky of samples of a BRDF material (N, n_b) [W m-2 sr-1], without Δρ:
    Σ_j w_j Σ_k table[v, :, j, k] F_k, the view cosines ``cos_view`` (N,) interpolated
    between the table's rows v (:data:`VIEW_COSINES`); ``table`` is (n_v, n_b, n_j, n_k)."""
    lower, frac = view_weights(cos_view)
    sky = 0.0
    for v_index, v_weight in ((lower, 1.0 - frac), (lower + 1, frac)):
        sky = sky + v_weight[:, None] * sky_sum(table, v_index, nodes, sky_fractions)
    return sky
