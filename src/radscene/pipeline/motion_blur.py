"""Motion blur: a frame's image as the mean over its exposure of renders at sub-frame instants.

A detector integrates the radiance reaching it during its exposure ``E``; a frame whose objects
move is the time mean

.. math::

    \\bar L(x) = \\frac{1}{E} \\int_{t - E/2}^{t + E/2} L(x, t') \\, dt'
              \\approx \\frac{1}{n} \\sum_{k=0}^{n-1} L\\left(x, t + E \\left(\\frac{k + 1/2}{n}
              - \\frac{1}{2}\\right)\\right),

the midpoint rule on ``n`` equal sub-intervals of the exposure centred on the frame's instant
``t``: deterministic, and one sample is the instant itself (the unblurred frame). A feature
moving at speed ``v`` is spread over ``v E``: ``n`` copies ``v E / n`` apart, which blend into a
streak when ``v E / n`` is at most a pixel.

:class:`radscene.pipeline.Simulation` places what moves (trajectories, spins, parts, scanners)
at each sub-instant; this module holds the sampling and the averaging.
"""

from __future__ import annotations

import numpy as np
import xarray as xr

from radscene.errors import ConfigError

__all__ = ["exposure_offsets", "mean_frame", "observer_exposure"]


def exposure_offsets(samples: int, exposure: float) -> np.ndarray:
    """The sub-frame instants relative to the frame's: the centres of ``samples`` equal parts
    of an exposure centred on it [s].

    Parameters
    ----------
    samples : int
        ``n`` >= 1.
    exposure : float
        ``E`` [s] > 0.

    Returns
    -------
    numpy.ndarray
        ``(n,)`` [s]: ``E ((k + 1/2) / n - 1/2)``, ``k = 0 ... n-1``; ``[0.0]`` for ``n = 1``.

    Examples
    --------
    >>> exposure_offsets(4, 0.008).round(6).tolist()
    [-0.003, -0.001, 0.001, 0.003]
    """
    if isinstance(samples, bool) or not isinstance(samples, (int, np.integer)) or samples < 1:
        raise ConfigError(f"must be an integer >= 1, got {samples!r}", key="render.motion_blur.samples")
    if not np.isfinite(exposure) or exposure <= 0:
        raise ConfigError(f"must be a positive finite duration, got {exposure!r}",
                          key="render.motion_blur.exposure")
    k = np.arange(samples, dtype=float)
    return exposure * ((k + 0.5) / samples - 0.5)


def observer_exposure(setup, exposure: float | None) -> float:
    """The exposure of an observer [s]: ``exposure`` when given, else its sensor's integration
    time (one for all the bands it records).

    Raises
    ------
    ConfigError
        Naming ``render.motion_blur.exposure``: no exposure and no sensor, or a sensor whose
        bands integrate for different times.
    """
    if exposure is not None:
        return float(exposure)
    if setup.sensor is None:
        raise ConfigError(f"observer {setup.name!r} has no sensor, so no integration time: give "
                          "the exposure, e.g. '10 ms'", key="render.motion_blur.exposure")
    bands = setup.bands or []
    times = {float(setup.sensor.channel(b).detector.integration_time) for b in bands} or {
        float(setup.sensor.base.detector.integration_time)}
    if len(times) > 1:
        listed = ", ".join(f"{t * 1e3:g} ms" for t in sorted(times))
        raise ConfigError(f"the bands of observer {setup.name!r} integrate for different times "
                          f"({listed}): give one exposure", key="render.motion_blur.exposure")
    return times.pop()


def mean_frame(layers: list[xr.Dataset], bands=None, truth: int | None = None) -> xr.Dataset:
    """The blurred image of a frame from its renders at the sub-frame instants.

    Parameters
    ----------
    layers : list of xarray.Dataset
        The renders (:func:`radscene.render`), one per sub-instant, in time order.
    bands : list, optional
        The rendered bands (objects with ``response``), to recompute ``brightness_temperature``
        from the mean radiance; without them it is that of the truth layer.
    truth : int, optional
        The layer whose truth maps (ids, normals, range, geolocation ...) the image keeps;
        default ``len(layers) // 2``: the frame's own instant for an odd count.

    Returns
    -------
    xarray.Dataset
        The truth layer with every floating-point variable along ``band`` or ``wavelength``
        (radiance, the terms, the transmittances, a spectral cube) replaced by its mean over the layers [its unit], and the brightness
        temperature of the mean radiance [K]. One layer is returned as it is.
    """
    if len(layers) == 1:
        return layers[0]
    truth = len(layers) // 2 if truth is None else truth
    out = layers[truth].copy()
    for name, var in out.data_vars.items():
        if not {"band", "wavelength"} & set(var.dims) or not np.issubdtype(var.dtype, np.floating) \
                or name == "brightness_temperature":
            continue
        total = np.zeros(var.shape, dtype=float)
        for ds in layers:
            total += ds[name].values
        out[name] = var.copy(data=total / len(layers))
    if bands is not None and "brightness_temperature" in out:
        from radscene.radiometry import band_brightness_temperature
        from radscene.render.integrator import THERMAL_BAND_START

        bt = np.full(out["brightness_temperature"].shape, np.nan)
        for b, band in enumerate(bands):
            if band.response.center >= THERMAL_BAND_START:
                bt[b] = band_brightness_temperature(out["radiance"].values[b], band.response)
        out["brightness_temperature"] = out["brightness_temperature"].copy(data=bt)
    out.attrs["motion_blur_samples"] = len(layers)
    return out
