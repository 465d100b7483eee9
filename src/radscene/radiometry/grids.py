"""Spectral grids and resampling of spectra between them.

Spectra are arrays with wavelength [um] on the last axis. Resampling never extrapolates:
a target wavelength outside the source table is an error.
"""

from __future__ import annotations

import math

import numpy as np

from radscene.errors import ConfigError, did_you_mean

__all__ = ["wavelength_grid", "resample", "RESAMPLE_METHODS"]

#: Resampling methods accepted by :func:`resample`.
RESAMPLE_METHODS = ("linear", "average")


def wavelength_grid(start, stop, step) -> np.ndarray:
    """Evenly spaced wavelengths from `start` to `stop` inclusive.

    Parameters
    ----------
    start : float
        First wavelength [um], > 0.
    stop : float
        Last wavelength [um], >= `start`. Included when (stop - start) / step is an
        integer to 1e-9; otherwise the grid ends at the last sample below `stop`.
    step : float
        Spacing [um], > 0.

    Returns
    -------
    numpy.ndarray
        Wavelengths [um], shape (n,), ``start + step * arange(n)``.

    Examples
    --------
    >>> wavelength_grid(8.0, 12.0, 1.0)
    array([ 8.,  9., 10., 11., 12.])
    """
    for name, v in (("start", start), ("stop", stop), ("step", step)):
        if not (isinstance(v, (int, float, np.number)) and math.isfinite(v)):
            raise ConfigError(f"must be a finite number [µm]; got {v!r}", key=name)
    if start <= 0:
        raise ConfigError(f"must be > 0 µm; got {start!r}", key="start")
    if step <= 0:
        raise ConfigError(f"must be > 0 µm; got {step!r}", key="step")
    if stop < start:
        raise ConfigError(f"must be >= start = {start!r} µm; got {stop!r}", key="stop")
    n = int(math.floor((stop - start) / step + 1e-9)) + 1
    grid = start + step * np.arange(n)
    if abs(grid[-1] - stop) <= 1e-9 * step:
        grid[-1] = stop
    return grid


def _check_table(wavelength, values):
    wl = np.asarray(wavelength, dtype=float)
    vals = np.asarray(values, dtype=float)
    if wl.ndim != 1 or wl.size < 2 or not np.all(np.diff(wl) > 0):
        raise ConfigError(
            "must be a 1-D, strictly increasing array of at least 2 wavelengths [µm]",
            key="wavelength",
        )
    if vals.ndim == 0 or vals.shape[-1] != wl.size:
        raise ConfigError(
            f"last axis must have the length of wavelength ({wl.size}); got shape {vals.shape}",
            key="values",
        )
    return wl, vals


def _interp_last_axis(wl, vals, x):
    """Linear interpolation of vals (..., n) sampled at wl onto x (inside [wl0, wl-1])."""
    i = np.clip(np.searchsorted(wl, x, side="right") - 1, 0, wl.size - 2)
    frac = (x - wl[i]) / (wl[i + 1] - wl[i])
    return vals[..., i] * (1.0 - frac) + vals[..., i + 1] * frac


def resample(wavelength, values, new_wavelength, method: str = "linear"):
    """Resample a spectrum onto new wavelengths.

    Parameters
    ----------
    wavelength : array_like
        Source wavelengths [um], shape (n,), strictly increasing.
    values : array_like
        Spectrum, shape (..., n), wavelength on the last axis; any unit.
    new_wavelength : array_like
        Target wavelengths [um], shape (m,), inside [wavelength[0], wavelength[-1]]
        (strictly increasing, m >= 2, for ``"average"``).
    method : {"linear", "average"}
        ``"linear"``: the piecewise-linear source spectrum evaluated at the targets.
        ``"average"``: the mean of the piecewise-linear source spectrum over each target's
        cell, for down-sampling. Cells are bounded by the midpoints between targets; the
        two end cells extend half a spacing outward, cut at the source range.

    Returns
    -------
    numpy.ndarray
        Resampled spectrum, shape (..., m), the unit of `values`.

    Raises
    ------
    ConfigError
        Unknown method, a target outside the source range, or malformed arrays.

    Examples
    --------
    >>> resample([1.0, 2.0, 3.0], [0.0, 1.0, 0.0], [1.5, 2.5])
    array([0.5, 0.5])
    """
    if method not in RESAMPLE_METHODS:
        raise ConfigError(
            f"unknown resampling method {method!r}; known: {', '.join(RESAMPLE_METHODS)}"
            f"{did_you_mean(method, RESAMPLE_METHODS)}",
            key="method",
        )
    wl, vals = _check_table(wavelength, values)
    new = np.asarray(new_wavelength, dtype=float)
    if new.ndim != 1 or new.size == 0 or np.any(np.isnan(new)):
        raise ConfigError("must be a non-empty 1-D array of wavelengths [µm]", key="new_wavelength")
    if new.min() < wl[0] or new.max() > wl[-1]:
        raise ConfigError(
            f"{new.min():g}-{new.max():g} µm is outside the source range "
            f"{wl[0]:g}-{wl[-1]:g} µm (no extrapolation)",
            key="new_wavelength",
        )
    if method == "linear":
        return _interp_last_axis(wl, vals, new)
    if new.size < 2 or not np.all(np.diff(new) > 0):
        raise ConfigError(
            "method 'average' needs at least 2 strictly increasing wavelengths",
            key="new_wavelength",
        )
    mid = 0.5 * (new[1:] + new[:-1])
    first = max(new[0] - 0.5 * (new[1] - new[0]), wl[0])
    last = min(new[-1] + 0.5 * (new[-1] - new[-2]), wl[-1])
    edges = np.concatenate(([first], mid, [last]))
    # Cumulative trapezoid integral of the piecewise-linear spectrum, exact at any edge.
    cumulative = np.concatenate(
        (
            np.zeros(vals.shape[:-1] + (1,)),
            np.cumsum(0.5 * (vals[..., 1:] + vals[..., :-1]) * np.diff(wl), axis=-1),
        ),
        axis=-1,
    )
    i = np.clip(np.searchsorted(wl, edges, side="right") - 1, 0, wl.size - 2)
    at_edges = _interp_last_axis(wl, vals, edges)
    integral = cumulative[..., i] + 0.5 * (vals[..., i] + at_edges) * (edges - wl[i])
    return np.diff(integral, axis=-1) / np.diff(edges)
