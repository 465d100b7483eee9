"""Quicklook pictures of a render: one PNG per band, and a figure of the signature terms."""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np
import xarray as xr
from matplotlib.figure import Figure

from radscene.io.files import atomic_output

__all__ = ["band_quicklooks", "signal_quicklooks", "terms_figure", "truth_figure",
           "stretch_limits"]


def stretch_limits(image, low: float = 1.0, high: float = 99.0) -> tuple[float, float]:
    """Percentile display limits of the finite values of an image."""
    values = np.asarray(image, dtype=float)
    values = values[np.isfinite(values)]
    if values.size == 0:
        return 0.0, 1.0
    lo, hi = np.percentile(values, [low, high])
    if hi <= lo:
        hi = lo + (abs(lo) * 1e-6 or 1e-12)
    return float(lo), float(hi)


def subplots(*args, **kwargs):
    """A figure and its axes, as ``pyplot.subplots`` but outside pyplot: no global figure
    state and no backend switched, so importing radscene leaves a notebook's plotting alone."""
    figure_keys = ("figsize", "dpi", "layout", "constrained_layout")
    fig = Figure(**{k: kwargs.pop(k) for k in figure_keys if k in kwargs})
    return fig, fig.subplots(*args, **kwargs)


def _save(fig, path: Path) -> Path:
    path = Path(path)
    with atomic_output(path, suffix=".png") as tmp:
        fig.savefig(tmp, dpi=110, bbox_inches="tight", format="png")
    return path


def _extent(ds):
    if ds["x"].attrs.get("units") == "m":
        x, y = ds["x"].values, ds["y"].values
        dx = (x[1] - x[0]) if x.size > 1 else 1.0
        dy = (y[1] - y[0]) if y.size > 1 else -1.0
        return [x[0] - dx / 2, x[-1] + dx / 2, y[-1] + dy / 2, y[0] - dy / 2]
    return None


def band_quicklooks(ds: xr.Dataset, folder: str | os.PathLike, prefix: str = "") -> list[Path]:
    """One PNG per band of the total radiance (thermal bands also as brightness temperature).

    Returns
    -------
    list of pathlib.Path
        The files written.
    """
    folder = Path(folder)
    written = []
    extent = _extent(ds)
    for band in ds["band"].values:
        sel = ds.sel(band=band)
        bt = sel["brightness_temperature"].values
        use_bt = np.isfinite(bt).any()
        image = bt if use_bt else sel["radiance"].values
        lo, hi = stretch_limits(image)
        fig, ax = subplots(figsize=(6, 5))
        im = ax.imshow(image, cmap="inferno" if use_bt else "gray", vmin=lo, vmax=hi,
                       extent=extent, interpolation="nearest")
        label = "brightness temperature [K]" if use_bt else "radiance [W m-2 sr-1]"
        fig.colorbar(im, ax=ax, label=label, shrink=0.85)
        wl = float(sel["wavelength_center"])
        ax.set_title(f"{ds.attrs.get('observer', '')}: {band} ({wl:.3g} um)")
        if extent is not None:
            ax.set_xlabel("easting [m]")
            ax.set_ylabel("northing [m]")
        written.append(_save(fig, folder / f"{prefix}{band}.png"))
    return written


def terms_figure(ds: xr.Dataset, path: str | os.PathLike) -> Path:
    """A grid of images: one row per band, one column per signature term and the total.

    Each row shares one colour scale, so the size of each term in its band can be read off.
    """
    from radscene.render import TERMS

    names = list(TERMS) + ["radiance"]
    n_b = ds.sizes["band"]
    fig, axes = subplots(n_b, len(names), figsize=(2.2 * len(names), 2.0 * n_b + 0.6),
                             squeeze=False)
    for i, band in enumerate(ds["band"].values):
        lo, hi = stretch_limits(ds["radiance"].sel(band=band).values, 0.5, 99.5)
        hi = max(hi, lo + 1e-12)
        for j, name in enumerate(names):
            ax = axes[i, j]
            image = ds[name].sel(band=band).values
            im = ax.imshow(image, cmap="magma", vmin=0.0 if lo >= 0 else lo, vmax=hi,
                           interpolation="nearest")
            ax.set_xticks([])
            ax.set_yticks([])
            if i == 0:
                ax.set_title(name.replace("_", " "), fontsize=8)
            if j == 0:
                ax.set_ylabel(str(band), fontsize=8)
            mean = np.nanmean(image)
            ax.text(0.02, 0.02, f"{mean:.3g}", transform=ax.transAxes, fontsize=6,
                    color="white", va="bottom")
        fig.colorbar(im, ax=axes[i, :].tolist(), shrink=0.8, pad=0.01).ax.tick_params(labelsize=6)
    fig.suptitle(f"signature terms [W m-2 sr-1] — {ds.attrs.get('observer', '')} "
                 "(number: image mean)", fontsize=9)
    return _save(fig, path)


def truth_figure(ds: xr.Dataset, path: str | os.PathLike) -> Path:
    """The geometric truth maps of a render in one figure."""
    layers = [("object_id", "tab20"), ("material_id", "tab20"), ("range", "viridis"),
              ("cos_incidence", "gray"), ("shadow_fraction", "gray_r"),
              ("sky_view_fraction", "gray"), ("surface_temperature", "inferno")]
    fig, axes = subplots(2, 4, figsize=(12, 6))
    for ax, (name, cmap) in zip(axes.ravel(), layers, strict=False):
        image = ds[name].values.astype(float)
        if name.endswith("_id"):
            image = np.where(image < 0, np.nan, image)
        lo, hi = stretch_limits(image, 0, 100)
        im = ax.imshow(image, cmap=cmap, vmin=lo, vmax=hi, interpolation="nearest")
        ax.set_title(f"{name} [{ds[name].attrs.get('units', '-')}]", fontsize=8)
        ax.set_xticks([])
        ax.set_yticks([])
        fig.colorbar(im, ax=ax, shrink=0.75).ax.tick_params(labelsize=6)
    normal_up = ds["surface_normal"].sel(vector="up").values
    ax = axes.ravel()[-1]
    im = ax.imshow(normal_up, cmap="gray", interpolation="nearest")
    ax.set_title("surface normal, up component", fontsize=8)
    ax.set_xticks([])
    ax.set_yticks([])
    fig.colorbar(im, ax=ax, shrink=0.75).ax.tick_params(labelsize=6)
    fig.suptitle(f"truth maps — {ds.attrs.get('observer', '')}", fontsize=9)
    return _save(fig, path)


def signal_quicklooks(signal: xr.Dataset, folder: str | os.PathLike) -> list[Path]:
    """One PNG per band of a sensor's digital numbers (first frame), 1–99 % stretch."""
    folder = Path(folder)
    written = []
    dn = signal["dn"]
    if "frame" in dn.dims:
        dn = dn.isel(frame=0)
    for band in dn["band"].values:
        image = dn.sel(band=band).values
        lo, hi = stretch_limits(image)
        fig, ax = subplots(figsize=(6, 5))
        im = ax.imshow(image, cmap="gray", vmin=lo, vmax=hi, interpolation="nearest")
        fig.colorbar(im, ax=ax, label="signal [DN]", shrink=0.85)
        ax.set_title(f"{signal.attrs.get('observer', '')}: {band}, sensor output")
        written.append(_save(fig, folder / f"{band}.png"))
    return written
