"""The whole pipeline for one observer: render the at-aperture radiance, then the sensor."""

from __future__ import annotations

import xarray as xr

from radscene.render import render

__all__ = ["simulate"]


def simulate(scene, observer: str | None = None, *, progress=None
             ) -> tuple[xr.Dataset, xr.Dataset | None]:
    """Render an observer and, when it has a sensor, record the signal.

    Parameters
    ----------
    scene : radscene.scene.Scene
    observer : str, optional
        Observer name; the first by default.
    progress : callable, optional
        As for :func:`radscene.render`.

    Returns
    -------
    radiance : xarray.Dataset
        The render (``radiance(band, y, x)`` [W m-2 sr-1], terms, truth).
    signal : xarray.Dataset or None
        The sensor's output (``dn(frame, band, y, x)`` [DN] and its truth), or None when the
        observer has no sensor.
    """
    setup = scene.observers[0] if observer is None else scene.observer(observer)
    images = render(scene, setup.name, progress=progress)
    if setup.sensor is None:
        return images, None
    responses = {b.name: b.response for b in scene.bands if b.name in setup.bands}
    signal = setup.sensor.apply(images, frames=setup.frames, seed=scene.settings.seed,
                                responses=responses)
    signal.attrs.update({"scene": scene.name, "observer": setup.name})
    return images, signal
