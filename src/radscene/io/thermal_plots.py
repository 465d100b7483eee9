"""Figures of a heat-balance solution (:func:`radscene.solve_thermal`): the diurnal curves of
each material and object, and maps of the terrain's surface temperature at chosen times."""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np
import xarray as xr

from radscene.io.quicklook import _save, colorbar_extend, stretch_limits, subplots

__all__ = ["diurnal_figure", "temperature_maps"]


def _local_hours(ds):
    return (ds.time.values - ds.time.values[0]) / np.timedelta64(1, "h")


def _area_mean(ds, mask):
    w = ds.area.where(mask, 0.0)
    return (ds.surface_temperature * w).sum("element") / w.sum()


def diurnal_figure(ds: xr.Dataset, path: str | os.PathLike) -> Path:
    """Area-weighted mean surface temperature of each material (upward-facing surfaces) and
    of each object (all its facets) against time, with the air temperature.

    Parameters
    ----------
    ds : xarray.Dataset
        A :func:`radscene.solve_thermal` result.
    path : path-like
        PNG to write.

    Returns
    -------
    pathlib.Path
    """
    hours = _local_hours(ds)
    fig, axes = subplots(1, 2, figsize=(13, 4.8), sharey=True)
    up = ds.normal_z > 0.7
    for name in np.unique(ds.material.values):
        mask = (ds.material == name) & up
        if bool(mask.any()):
            axes[0].plot(hours, _area_mean(ds, mask) - 273.15, label=str(name))
    for name in np.unique(ds.object.values):
        axes[1].plot(hours, _area_mean(ds, ds.object == name) - 273.15, label=str(name))
    start = np.datetime_as_string(ds.time.values[0], unit="m")
    for ax, title in zip(axes, ("materials (upward-facing surfaces)", "objects (every facet)"), strict=True):
        ax.plot(hours, ds.air_temperature - 273.15, "k--", lw=1, label="air")
        ax.set_xlabel(f"hours from {start} UTC")
        ax.set_title(title)
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7, ncol=3, loc="upper center", bbox_to_anchor=(0.5, -0.14),
                  frameon=False)
    axes[0].set_ylabel("surface temperature [°C]")
    return _save(fig, path)


def temperature_maps(ds: xr.Dataset, folder: str | os.PathLike, times=None, object_name="terrain") -> list[Path]:
    """Maps of the terrain elements' surface temperature at chosen times, one PNG each.

    Parameters
    ----------
    ds : xarray.Dataset
    folder : path-like
    times : sequence of int, optional
        Indices into ``ds.time``; default four times spread over the run and its end.
    object_name : str, optional

    Returns
    -------
    list of pathlib.Path
    """
    cells = ds.object == object_name
    if not bool(cells.any()):
        return []
    sub = ds.where(cells, drop=True)
    n = ds.sizes["time"]
    times = sorted({int(i) for i in (np.linspace(0, n - 1, 5)[1:] if times is None else times)})
    lo, hi = stretch_limits(sub.surface_temperature.values - 273.15)
    written = []
    for k in times:
        fig, ax = subplots(figsize=(6.2, 5.4))
        celsius = sub.surface_temperature.isel(time=k).values - 273.15
        art = ax.scatter(sub.x, sub.y, c=celsius, s=4, marker="s",
                         cmap="inferno", vmin=lo, vmax=hi, linewidths=0)
        fig.colorbar(art, ax=ax, label="surface temperature [°C]",
                     extend=colorbar_extend(celsius, lo, hi))
        ax.set_aspect("equal")
        ax.set_xlabel("x [m]")
        ax.set_ylabel("y [m]")
        when = np.datetime_as_string(ds.time.values[k], unit="m")
        ax.set_title(f"{object_name} at {when} UTC")
        written.append(_save(fig, Path(folder) / f"thermal_map_{when.replace(':', '')}.png"))
    return written
