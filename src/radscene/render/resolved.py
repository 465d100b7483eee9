"""Band renders whose non-linear layers are resolved on a spectral grid (``render.spectral_grid``).

Every signature term is linear in the band response and band mode integrates it exactly
(``docs/hyperspectral.md``, "What equals what"). Some layers are not: the surface–atmosphere
coupling combines band means of the spherical albedo and the transmittances non-linearly, the
reflected background reflects the neighbours' band radiance with band-mean reflectances, and
volumes and sheets dim what lies behind them with band-mean transmittances. For those, band mode
and a hyperspectral cube integrated with the band's response differ (by up to 1e-3 of the
radiance in the tests).

With a grid, a band render also renders the grid's channels that its bands' responses reach —
the hyperspectral mode's channels (triangles on the grid), with the same rays, the same random
numbers and the same specular flags — and replaces each of those layers of band b by

    Σ_c S_b(λ_c) L_c      (L_c the channel's band radiance [W m-2 sr-1]),

what :func:`radscene.render.hyperspectral.band_radiance` makes of a cube on the grid (for a
response that is not linear between the centres, scaled to the band's own integral:
:func:`grid_weights`). The
linear layers keep their own exact band integrals; for a response linear between the grid's
centres and zero outside it, those equal the cube's integral too, so that the band render and
the integrated cube agree layer by layer (``tests/system/test_hyperspectral.py``). Without
volumes, sheets and BRDF models the resolved layers are :data:`NONLINEAR`; with them, every
layer (:func:`resolved_layers`).
"""

from __future__ import annotations

import numpy as np

from radscene.errors import ConfigError
from radscene.render.outputs import PART_NAMES, TERM_LAYERS

__all__ = ["NONLINEAR", "resolved_layers", "grid_weights", "render_resolved"]

#: The layers that band means make non-linear in the band response (scenes without volumes
#: and sheets).
NONLINEAR = ("multiple_reflection", "diffuse_transmitted", "adjacency", "background_reflected",
             "background_reflected_solar", "background_reflected_thermal")

KEY = "render.spectral_grid"


def resolved_layers(scene) -> tuple[str, ...]:
    """The layers a render of ``scene`` resolves on its grid: :data:`NONLINEAR`, or every layer
    that sums to the radiance and every part layer where the scene has volumes or sheets (their
    band-mean transmittances dim every layer behind them) or materials with a BRDF model (their
    kernel is taken at the band's centre)."""
    if (scene.volumes or getattr(scene, "brdfs", None)
            or any(getattr(o, "transmissive", False) for o in scene.objects)):
        return tuple(TERM_LAYERS) + tuple(PART_NAMES)
    return NONLINEAR


def grid_weights(grid, bands) -> np.ndarray:
    """Each band's weights of the grid's channels (n_b, n_c) [-]: S_b(λ_c) scaled by
    ∫ S_b dλ / Σ_c S_b(λ_c) fwhm_c, so that a spectrally flat layer keeps the band's own
    integral. For a response linear between the grid's centres and zero outside the grid the
    scale is 1 (to rounding) and the weights are those of
    :func:`radscene.render.hyperspectral.band_radiance`; for another (a rectangle, a
    Gaussian) they follow its interpolant on the grid, scaled.

    Raises
    ------
    ConfigError
        A band whose response reaches beyond the grid's first or last centre (the cube cannot
        integrate it), or that is zero at every centre (narrower than the grid's step).
    """
    lo, hi = float(grid.wavelength[0]), float(grid.wavelength[-1])
    out = []
    for band in bands:
        b_lo, b_hi = band.response.support
        try:
            trapezoid = grid.band_weights(band.response)  # S_b(λ_c) fwhm_c
        except ConfigError:
            raise ConfigError(f"band {band.name!r} ({b_lo:g}-{b_hi:g} µm) reaches beyond the grid "
                              f"({lo:g}-{hi:g} µm): widen the grid to hold every band",
                              key=KEY) from None
        s = trapezoid / grid.width
        interpolant = float(trapezoid.sum())
        if not interpolant > 0.0:
            raise ConfigError(f"band {band.name!r} ({b_lo:g}-{b_hi:g} µm) is zero at every centre "
                              f"of the grid (step {grid.step:g} µm): use a finer grid", key=KEY)
        out.append(s * (band.response.equivalent_width() / interpolant))
    return np.array(out)


def render_resolved(render, scene, setup, grid, bands, *, specular=None, progress=None,
                    memory=None):
    """A band render with its non-linear layers resolved on ``grid``.

    Parameters
    ----------
    render : callable
        ``render(bands, specular, progress)`` → the band render of those bands (the
        integrator's, with the observer's rays and tables).
    scene : radscene.scene.Scene
    setup : the observer's setup (its camera's shape and supersampling size the passes)
    grid : radscene.radiometry.ChannelGrid
    bands : list — the observer's bands
    specular : array_like of bool, optional
        Per material; default: a specular reflectance above zero somewhere on the grid (the
        flags a cube on the grid uses, so that both draw the same random numbers).
    progress : callable, optional
        ``progress(done, total)`` over the band render and the channels' passes.
    memory : float, optional
        Bytes a channel pass may hold (:func:`radscene.render.hyperspectral.pass_size`).

    Returns
    -------
    xarray.Dataset
        The band render with the layers of :func:`resolved_layers` replaced, ``radiance``
        their sum again and the thermal bands' ``brightness_temperature`` from it; the
        attribute ``spectral_grid`` names the grid.
    """
    from radscene.radiometry import band_brightness_temperature
    from radscene.render.hyperspectral import PASS_MEMORY, _specular_flags, channels, pass_size
    from radscene.render.outputs import THERMAL_BAND_START

    weights = grid_weights(grid, bands)
    if specular is None:
        specular = _specular_flags(scene, grid)
    needed = np.flatnonzero(np.any(weights != 0.0, axis=0))
    samples = int(np.prod(setup.camera.shape)) * setup.supersample**2
    per_pass = pass_size(grid, samples, PASS_MEMORY if memory is None else memory)
    starts = list(range(0, len(needed), per_pass))
    steps = 1 + len(starts)

    def stage(n):
        def report(done, total):
            if progress is not None:
                progress(n * total + done, steps * total)
        return report

    ds = render(bands, specular, stage(0))
    names = [name for name in resolved_layers(scene) if name in ds.data_vars]
    for name in names:  # accumulated in place: the band means are not kept
        ds[name].values[...] = 0.0
    every = channels(grid)
    for n, start in enumerate(starts, start=1):
        part = needed[start:start + per_pass]
        cube = render([every[c] for c in part], specular, stage(n))
        w = weights[:, part]
        for name in names:
            ds[name].values[...] += np.einsum("bc,cyx->byx", w, cube[name].values)
        del cube
    total = sum(ds[name].values for name in TERM_LAYERS if name in ds.data_vars)
    ds["radiance"].values[...] = total
    for b, band in enumerate(bands):
        if band.response.center >= THERMAL_BAND_START:
            ds["brightness_temperature"].values[b] = band_brightness_temperature(
                total[b], band.response)
    ds.attrs["spectral_grid"] = (f"non-linear layers resolved on channels {grid.wavelength[0]:g}"
                                 f"-{grid.wavelength[-1]:g} um every {grid.step:g} um: "
                                 + ", ".join(names))
    return ds
