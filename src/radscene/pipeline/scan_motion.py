"""Scanners over a moving scene: every pixel sees the scene at its own acquisition time.

A pushbroom records one line at a time, a whiskbroom one sample at a time
(:mod:`radscene.platform.scanners`): an object that moves during the scan lands in each line
where it stood when that line was recorded, so it comes out displaced, sheared, stretched or
compressed as in real scanner images. The renderer traces every ray through one placement of
the geometry, so the pixels are grouped by time: the pixels of a group are rendered together
(:func:`radscene.render.integrator.render` of their rays) with what moves — objects on
trajectories, spinning parts, a sea's waves — placed at the group's time by the ray tracer's
refit (:meth:`radscene.geometry.RayTracer.move`, :meth:`~radscene.geometry.RayTracer.update`),
and the groups' pixels make up the image.

Groups. A pixel's time is the weighted mean of its rays' times. Along the scan the motion is
measured in pixels: with what moves placed at ``K`` instants ``t_k`` spanning the scan
(every distinct pixel time when there are at most :data:`MOTION_SAMPLES`), the step
``p_k = max |v(t_{k+1}) - v(t_k)| / f_k`` over the vertices ``v`` of the moving meshes, with
``f_k = tan(ifov) min |v - s(t)|`` the footprint of a detector at the nearest moving vertex
(``s`` the sensor's position, the smaller of the two instants'). With the cumulative motion
:math:`P(t)` (piecewise linear through :math:`P(t_k) = \\sum_{j<k} p_j`) a pixel at time
:math:`t` belongs to group :math:`\\lfloor P(t) / \\epsilon \\rfloor`, :math:`\\epsilon` =
:data:`TOLERANCE` pixel, and the group is rendered at the middle of its pixels' times: no
moving vertex stands :math:`\\epsilon` pixel or more from where it was at a pixel's own time
(to the sampling of :math:`P`, :math:`P` being monotonic and each step bounding the motion
between its instants). A line of a pushbroom is never split; with nothing
moving during the scan there is one group, the render as it was.

What a group does not see: the other groups' pixels. With the adjacency PSF on
(``render.adjacency``) a pixel's surroundings are those of its group's pixels only; the other
terms of a pixel depend on its own rays alone.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
import xarray as xr

__all__ = ["MOTION_SAMPLES", "TOLERANCE", "compose", "motion_groups", "pixel_times"]

#: Less than this is the motion of any moving vertex between a pixel's time and its group's
#: [pixel].
TOLERANCE = 0.25
#: Instants at which the motion along a scan is measured, at most.
MOTION_SAMPLES = 129


def pixel_times(rays) -> np.ndarray:
    """The acquisition time of each pixel: the weighted mean of its rays' times.

    Parameters
    ----------
    rays : radscene.platform.cameras.RayBundle
        With ``time`` [s].

    Returns
    -------
    numpy.ndarray
        ``(ny * nx,)`` [s]; NaN for a pixel without rays.
    """
    size = rays.shape[0] * rays.shape[1]
    weight = np.bincount(rays.pixel, rays.weight, size)
    total = np.bincount(rays.pixel, rays.weight * rays.time, size)
    with np.errstate(invalid="ignore", divide="ignore"):
        return np.where(weight > 0, total / np.where(weight > 0, weight, 1.0), np.nan)


def motion_groups(times, vertices: Callable[[float], np.ndarray], sensor: Callable[[float], np.ndarray],
                  ifov: float, tolerance: float = TOLERANCE,
                  samples: int = MOTION_SAMPLES) -> tuple[np.ndarray, np.ndarray]:
    """Group pixels by time so that within a group what moves moves less than ``tolerance``.

    Parameters
    ----------
    times : array_like
        ``(n,)`` each pixel's time [s]; NaN: a pixel without rays (group -1).
    vertices : callable(t) -> (m, 3)
        The vertices of every moving mesh at time ``t`` [s], in one order [m].
    sensor : callable(t) -> (3,)
        The sensor's position at ``t`` [m].
    ifov : float
        A detector's angle [deg].
    tolerance : float
        The span of motion a group may hold [pixel], > 0.
    samples : int
        The most instants at which the motion is measured.

    Returns
    -------
    group : numpy.ndarray
        ``(n,)`` int: each pixel's group, 0 ... G-1 in time order (-1 for a pixel without rays).
    group_times : numpy.ndarray
        ``(G,)`` [s]: the middle of each group's pixel times.

    Examples
    --------
    A point at 7 m/s seen 1000 m away by 1 mrad detectors (1 m): 0.07 pixel from one pixel to
    the next, 0.01 s apart; groups of at most 0.25 pixel of motion.

    >>> group, at = motion_groups(np.arange(10) * 0.01, lambda t: np.array([[7.0 * t, 0, 0]]),
    ...                           lambda t: np.array([0.0, 0.0, 1000.0]), np.degrees(1e-3))
    >>> group.tolist(), at.round(3).tolist()
    ([0, 0, 0, 0, 1, 1, 1, 1, 2, 2], [0.015, 0.055, 0.085])
    """
    times = np.asarray(times, dtype=float)
    group = np.full(times.shape, -1, dtype=np.int64)
    seen = np.isfinite(times)
    distinct = np.unique(times[seen])
    if distinct.size == 0:
        return group, np.empty(0)
    if distinct.size <= samples:
        at = distinct
    else:
        at = np.linspace(distinct[0], distinct[-1], samples)
    pitch = np.tan(np.radians(ifov))
    steps = np.zeros(at.size)
    previous = footprint = None
    for k, t in enumerate(at):
        v = np.asarray(vertices(float(t)), dtype=float)
        here = pitch * float(np.min(np.linalg.norm(v - np.asarray(sensor(float(t)), float), axis=1)))
        if previous is not None:
            moved = float(np.max(np.linalg.norm(v - previous, axis=1)))
            steps[k] = moved / max(min(footprint, here), np.finfo(float).tiny)
        previous, footprint = v, here
    motion = np.cumsum(steps)  # P(t_k) [pixel]
    label = np.floor(np.interp(times[seen], at, motion) / tolerance).astype(np.int64)
    _, group[seen] = np.unique(label, return_inverse=True)
    n = int(group.max()) + 1
    first = np.full(n, np.inf)
    last = np.full(n, -np.inf)
    np.minimum.at(first, group[seen], times[seen])
    np.maximum.at(last, group[seen], times[seen])
    return group, 0.5 * (first + last)


def compose(parts: list[xr.Dataset], masks: list[np.ndarray]) -> xr.Dataset:
    """One image from renders of parts of it: each pixel from the part that rendered it.

    Parameters
    ----------
    parts : list of xarray.Dataset
        Renders of the same observer, each of some of its pixels (the others empty).
    masks : list of numpy.ndarray
        ``(ny, nx)`` bool: the pixels each part rendered; together every pixel once.

    Returns
    -------
    xarray.Dataset
        The first part with every variable and coordinate over ``(y, x)`` taken pixel by pixel
        from its part; an angle map that one part holds as a single value (the renderer's
        scalar for a constant map) is spread over that part's pixels, and stays a single value
        when every part holds the same; ``render_seconds`` summed; ``scan_time_groups`` the
        number of parts.
    """
    from radscene.render.integrator import CONSTANT_ANGLES

    if len(parts) == 1:
        out = parts[0]
        out.attrs["scan_time_groups"] = 1
        return out
    out = parts[0].copy(deep=True)
    shape = masks[0].shape
    for name in list(out.variables):
        var = out[name]
        if name in CONSTANT_ANGLES:
            values = [p[name] for p in parts if name in p]
            if all(v.ndim <= 1 and "y" not in v.dims for v in values) and all(
                    np.array_equal(v.values, values[0].values, equal_nan=True) for v in values):
                continue  # one value over the whole image
            ref = next((v for v in values if {"y", "x"} <= set(v.dims)), None)
            dims = ref.dims if ref is not None else ("y", "x")
            data = np.full(ref.shape if ref is not None else shape, np.nan)
            for part, mask in zip(parts, masks, strict=True):
                piece = part[name]
                data[..., mask] = (piece.values[..., mask] if {"y", "x"} <= set(piece.dims)
                                   else np.asarray(piece.values, float).reshape(-1)[0])
            out[name] = xr.Variable(dims, data, attrs=(ref if ref is not None else var).attrs)
            continue
        if not {"y", "x"} <= set(var.dims) or name in ("y", "x"):
            continue
        order = (*[d for d in var.dims if d not in ("y", "x")], "y", "x")
        data = var.transpose(*order).values.copy()
        for part, mask in zip(parts[1:], masks[1:], strict=True):
            data[..., mask] = part[name].transpose(*order).values[..., mask]
        merged = xr.Variable(order, data, attrs=var.attrs).transpose(*var.dims)
        if name in out.coords:
            out.coords[name] = merged
        else:
            out[name] = merged
    out.attrs["render_seconds"] = round(sum(float(p.attrs.get("render_seconds", 0.0)) for p in parts), 3)
    out.attrs["scan_time_groups"] = len(parts)
    return out
