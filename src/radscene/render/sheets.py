"""Semi-transparent sheets (camouflage nets, foliage layers): light through a surface.

An object marked ``transmissive`` keeps its own terms (reflection, and emission with
ε = 1 − ρ − τ) and lets through, in the direction of travel, the share Δτ τ(λ) of the light
from behind it (seed 000's transmitted term, the sheet's diffuse transmittance applied along
the line of sight):

.. math::

    L_{transmitted} = Δτ \\, τ(λ) \\, τ_a \\, L_{behind}

L_behind is rendered by a second pass of the integrator whose rays start just beyond the
sheet along the same directions (weighted by the ray's weight times Δτ), so whatever lies
behind — another sheet, a volume, the sky — is rendered as in the first pass; τ_a is the
pixel's band transmittance from the sheet to the sensor. Passes nest to
:data:`MAX_DEPTH` sheets; beyond, the light from behind is left out.

Shadows: the shadow rays of the render do not see sheets; the sun terms of each hit are
multiplied instead by the product of Δτ τ of the sheets its sun ray crosses
(:func:`sun_transmittance`), so the shadow a sheet casts is partial.

Band values of τ are response-weighted means ∫ S τ dλ / ∫ S dλ (exact for sheets grey
across the band).
"""

from __future__ import annotations

import numpy as np

__all__ = ["MAX_DEPTH", "MAX_CROSSINGS", "tracers", "band_transmittance", "sun_transmittance",
           "continuation", "apply"]

#: Sheets a line of sight passes through, one integrator pass each.
MAX_DEPTH = 4
#: Sheets a sun ray passes through (beyond, the sun counts as blocked).
MAX_CROSSINGS = 8


def tracers(objects, tracer):
    """Per object whether it is a sheet (n_objects,), and the tracers of the shadow rays (the
    other objects) and of the sheets alone: ``tracer`` for both where there is no sheet."""
    sheet = np.array([bool(getattr(o, "transmissive", False)) for o in objects])
    if not sheet.any():
        return sheet, tracer, tracer
    from radscene.geometry import Mesh, RayTracer

    def only(keep):  # a mesh without faces is never hit, and keeps the object indices
        return RayTracer([o.mesh if k else Mesh(np.zeros((0, 3)), np.zeros((0, 3), int))
                          for o, k in zip(objects, keep, strict=True)])
    return sheet, only(~sheet), only(sheet)


def band_transmittance(materials, bands, hold: bool = False) -> np.ndarray:
    """Response-weighted band means of each material's transmittance (n_m, n_b) [-].

    With ``hold`` a tabulated transmittance is taken at its end values beyond its table: the
    heat balance's broadband weightings (a 300 K blackbody over 4-50 um) reach past the
    library's 0.4-20 um. Without it, a band beyond the table raises, as a spectrum does.
    """
    from radscene.materials.spectrum import Spectrum
    from radscene.render.spectral import band_quadrature

    out = np.zeros((len(materials), len(bands)))
    for m, material in enumerate(materials):
        spectrum = material.transmittance
        if hold and spectrum.wavelength is not None and spectrum.extend != "edge":
            spectrum = Spectrum(spectrum.wavelength, spectrum.values, name=spectrum.name,
                                source=spectrum.source, extend="edge")
        for b, band in enumerate(bands):
            knots = () if spectrum.wavelength is None else spectrum.wavelength
            nodes, weights = band_quadrature(band.response, knots)
            out[m, b] = float(np.asarray(spectrum(nodes), float) @ weights / weights.sum())
    return out


def sun_transmittance(tables, tau_band, points, normals, sun_dir, texture) -> np.ndarray:
    """The product of Δτ τ_b of the sheets crossed by the sun rays from ``points`` (N, 3)
    (offset along ``normals`` (N, 3) turned to the sun): (N, n_b) [-].

    ``tau_band`` (n_m, n_b) from :func:`band_transmittance`; ``texture(obj, pos)`` → Δτ (N,).
    """
    n = len(points)
    sun = np.broadcast_to(np.reshape(sun_dir, (-1, 3)), (n, 3))
    side = np.where((np.einsum("nc,nc->n", normals, sun) < 0.0)[:, None], -normals, normals)
    origin = points + tables.epsilon * side
    out = np.ones((n, tau_band.shape[1]))
    alive = np.arange(n)
    for _ in range(MAX_CROSSINGS):
        if len(alive) == 0:
            break
        crossed = tables.sheet_tracer.intersect(origin[alive], sun[alive])
        on = crossed.hit
        alive, pos, obj = alive[on], crossed.position[on], crossed.object[on]
        face = tables.face_offset[obj] + crossed.primitive[on]
        out[alive] *= tau_band[tables.face_material[face]] * texture(obj, pos)[:, None]
        origin[alive] = pos + tables.epsilon * sun[alive]
    if len(alive):
        out[alive] = 0.0
    return out


def continuation(tables, rays, hits, texture):
    """The rays that continue beyond the sheets the primary rays hit, or None.

    Returns (RayBundle of the continued rays, their index among ``rays``); each weight is
    the ray's times the sheet's Δτ.
    """
    from radscene.platform.cameras import RayBundle

    hit = hits.hit
    on = np.zeros(len(rays), dtype=bool)
    on[hit] = tables.sheet_object[hits.object[hit]]
    index = np.flatnonzero(on)
    if len(index) == 0:
        return None, index
    d = rays.directions[index]
    bundle = RayBundle(
        origins=hits.position[index] + tables.epsilon * d, directions=d,
        pixel=rays.pixel[index],
        weight=rays.weight[index] * texture(hits.object[index], hits.position[index]),
        shape=rays.shape, subsample=rays.subsample[index],
        time=None if rays.time is None else rays.time[index])
    return bundle, index


def apply(ds, tables, tau_band, bands, rays, hits, layers, sun_dir, sun_up, shadows, texture,
          render_behind, depth):
    """The sheet pass on a rendered Dataset ``ds``: partial shadows on its sun layers, and the
    light from behind its sheets in ``transmitted``; returns it with ``radiance`` and the
    brightness temperatures formed again.

    ``render_behind(bundle)`` renders a RayBundle into a Dataset (the next pass);
    ``layers`` are the names of the layers that sum to the radiance.
    """
    from radscene.radiometry import band_brightness_temperature

    ny, nx = rays.shape
    n_pix, n_b = ny * nx, len(bands)
    pix, w = rays.pixel, rays.weight
    hit = hits.hit

    def per_pixel(rows, p, ww):
        return np.stack([np.bincount(p, ww * rows[:, b], n_pix) for b in range(n_b)])

    if sun_up and shadows and np.any(hit):
        normals = hits.normal[hit]
        t_sun = sun_transmittance(tables, tau_band, hits.position[hit], normals,
                                  np.reshape(sun_dir, (-1, 3)), texture)
        hit_w = np.bincount(pix[hit], w[hit], n_pix)
        seen = hit_w > 0.0
        factor = np.ones((n_b, n_pix))
        factor[:, seen] = per_pixel(t_sun, pix[hit], w[hit])[:, seen] / hit_w[seen]
        for name in ("sun_diffuse", "sun_specular"):
            ds[name].values[...] *= factor.reshape(n_b, ny, nx)
        lit = 1.0 - ds["shadow_fraction"].values
        ds["shadow_fraction"].values[...] = 1.0 - lit * factor.mean(axis=0).reshape(ny, nx)
    transmitted = np.zeros((n_b, n_pix))
    bundle, index = continuation(tables, rays, hits, texture)
    if bundle is not None and depth < MAX_DEPTH:
        behind = render_behind(bundle)["radiance"].values.reshape(n_b, n_pix)
        face = tables.face_offset[hits.object[index]] + hits.primitive[index]
        tau = tau_band[tables.face_material[face]]  # (n, n_b)
        wt = bundle.weight
        norm = np.bincount(bundle.pixel, wt, n_pix)
        sheet = norm > 0.0
        tau_pixel = np.zeros((n_b, n_pix))
        tau_pixel[:, sheet] = per_pixel(tau, bundle.pixel, wt)[:, sheet] / norm[sheet]
        tau_a = ds["path_transmittance"].values.reshape(n_b, n_pix)
        transmitted[:, sheet] = tau_pixel[:, sheet] * tau_a[:, sheet] * behind[:, sheet]
    total = ds["radiance"].values
    total[...] = 0.0
    for name in layers:
        total += ds[name].values
    total += transmitted.reshape(n_b, ny, nx)
    ds["transmitted"] = (("band", "y", "x"), transmitted.reshape(n_b, ny, nx), {
        "units": "W m-2 sr-1", "long_name": "radiance from behind semi-transparent sheets and "
        "volumes, attenuated by their transmittance"})
    bt = ds["brightness_temperature"].values
    for b, band in enumerate(bands):
        if np.any(np.isfinite(bt[b])):
            bt[b] = band_brightness_temperature(total[b], band.response)
    return ds
