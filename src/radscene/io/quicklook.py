"""Quicklook pictures of a render: one PNG per band, and figures of the signature terms and of
the truth maps, drawn for a report: colour bars that show where the stretch clips, units in
print form (µm, W m⁻² sr⁻¹), angles off the boresight on a perspective camera's axes, named
categories on the object and material maps, and no empty panels."""

from __future__ import annotations

import json
import math
import os
import re
import warnings
from pathlib import Path

import numpy as np
import xarray as xr
from matplotlib import colormaps
from matplotlib.colors import BoundaryNorm, ListedColormap
from matplotlib.figure import Figure
from matplotlib.patches import Patch
from matplotlib.ticker import MaxNLocator

from radscene.io.files import atomic_output

__all__ = ["band_quicklooks", "signal_quicklooks", "terms_figure", "truth_figure",
           "band_plot", "terms_plot", "term_layers", "truth_plot", "stretch_limits", "colorbar_extend",
           "unit_text", "observer_fov", "categories"]

_SUPERSCRIPT = str.maketrans("-0123456789", "⁻⁰¹²³⁴⁵⁶⁷⁸⁹")
#: Legend entries of a categorical map before the rest are summed up as "… n more".
MAX_LEGEND_ENTRIES = 14
#: Colour of the pixels of a categorical map without a category (-1: no object, no material).
NO_CATEGORY_COLOUR = "0.85"


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


def colorbar_extend(images, vmin: float, vmax: float) -> str:
    """The ``extend`` of a colour bar over ``[vmin, vmax]``: ``"min"``, ``"max"`` or ``"both"``
    where finite values of the images lie below or above the limits (clipped by the stretch),
    else ``"neither"``.

    >>> colorbar_extend(np.array([0.0, 1.0, 5.0]), 0.5, 5.0)
    'min'
    """
    below = above = False
    for image in images if isinstance(images, list | tuple) else [images]:
        values = np.asarray(image, dtype=float)
        values = values[np.isfinite(values)]
        if values.size:
            below |= bool(values.min() < vmin)
            above |= bool(values.max() > vmax)
    return {(True, True): "both", (True, False): "min", (False, True): "max"}.get(
        (below, above), "neither")


def unit_text(units: str | None) -> str:
    """A CF/UDUNITS unit string in print form: ``"W m-2 sr-1"`` → ``"W m⁻² sr⁻¹"``, ``"um"`` →
    ``"µm"``; ``"1"`` and ``""`` (dimensionless) → ``""``.

    >>> unit_text("W m-2 sr-1 um-1")
    'W m⁻² sr⁻¹ µm⁻¹'
    """
    if units is None or str(units).strip() in ("", "1", "-"):
        return ""
    out = []
    for token in str(units).split():
        match = re.fullmatch(r"([^\d\-]+)(-?\d+)", token)
        base, power = (match.group(1), match.group(2)) if match else (token, "")
        base = {"um": "µm", "micron": "µm", "degC": "°C", "deg": "°"}.get(base, base)
        out.append(base + power.translate(_SUPERSCRIPT))
    return " ".join(out)


def _bracketed(name: str, units: str | None) -> str:
    text = unit_text(units)
    return f"{name} [{text}]" if text else name


def subplots(*args, **kwargs):
    """A figure and its axes, as ``pyplot.subplots`` but outside pyplot: no global figure
    state and no backend switched, so importing radscene leaves a notebook's plotting alone.
    The layout is matplotlib's constrained layout unless ``layout`` says otherwise, so that
    labels, colour bars and legends do not overlap."""
    if "constrained_layout" not in kwargs:
        kwargs.setdefault("layout", "constrained")
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


# ----------------------------------------------------------------------------- angle axes


def observer_fov(ds) -> float | None:
    """The horizontal field of view [deg] of the perspective camera that made ``ds``, from its
    ``observer_geometry`` attribute (JSON, key ``fov_deg``) or a ``fov_deg`` attribute; None
    for other observers or when it is not recorded."""
    attrs = ds.attrs
    try:
        geometry = json.loads(attrs.get("observer_geometry", "{}"))
    except (TypeError, ValueError):
        geometry = {}
    geometry = geometry if isinstance(geometry, dict) else {}
    settings = geometry.get("settings") if isinstance(geometry.get("settings"), dict) else {}
    kind = attrs.get("observer_type", settings.get("type"))
    if kind not in (None, "perspective"):
        return None
    fov = attrs.get("fov_deg", geometry.get("fov_deg"))
    try:
        fov = float(fov)
    except (TypeError, ValueError):
        return None
    return fov if 0.0 < fov < 180.0 else None


def _angle_axes(ax, fov: float, shape) -> None:
    """Ticks in degrees off the boresight on an image drawn in pixel coordinates: a pinhole
    of horizontal field of view ``fov`` [deg] over ``shape`` (rows, columns), square pixels of
    pitch ``p = 2 tan(fov / 2) / columns`` on the tangent plane (radscene.platform.cameras)."""
    ny, nx = shape
    pitch = 2.0 * math.tan(math.radians(fov) / 2.0) / nx
    for size, axis, sign in ((nx, ax.xaxis, 1.0), (ny, ax.yaxis, -1.0)):
        half = math.degrees(math.atan(size * pitch / 2.0))
        angles = [a for a in MaxNLocator(nbins=7, steps=[1, 2, 2.5, 5, 10]).tick_values(
            -half, half) if abs(a) <= half + 1e-9]
        positions = [size / 2.0 - 0.5 + sign * math.tan(math.radians(a)) / pitch
                     for a in angles]
        axis.set_ticks(positions, [f"{a:g}°".replace("-", "\N{MINUS SIGN}") for a in angles])
    ax.set_xlabel("angle right of the boresight [°]")
    ax.set_ylabel("angle above the boresight [°]")


def _axes_for(ax, ds, extent, shape) -> None:
    if extent is not None:
        ax.set_xlabel("easting [m]")
        ax.set_ylabel("northing [m]")
        return
    fov = observer_fov(ds)
    if fov is not None:
        _angle_axes(ax, fov, shape)
    else:
        ax.set_xlabel("column [pixel]")
        ax.set_ylabel("row [pixel]")


# ----------------------------------------------------------------------------- band pictures


def _display_limits(image, low: float, high: float) -> tuple[float, float]:
    """:func:`stretch_limits`, widened to ±5 % (or ±0.05) about the value of an image that
    is constant, so that it is drawn mid-scale and its colour bar reads without an offset."""
    lo, hi = stretch_limits(image, low, high)
    if hi - lo <= 1e-6 * max(1.0, abs(lo)):
        pad = 0.05 * abs(lo) or 0.05
        return lo - pad, lo + pad
    return lo, hi


def _colorbar(fig, im, ax, image, **kwargs):
    lo, hi = im.get_clim()
    if "cax" not in kwargs:
        kwargs["ax"] = ax
    bar = fig.colorbar(im, extend=colorbar_extend(image, lo, hi), **kwargs)
    bar.formatter.set_useOffset(False)
    return bar


def _bar_axes(ax):
    """The axes of a colour bar right beside the map of ``ax`` (equal aspect), 80 % of its
    height: placed on the map as drawn, so that a map narrower than its grid cell keeps its
    bar next to it, where a bar of the cell would sit at the cell's edge, by the next panel.
    Its width is a twentieth of the map's longer side, about that of the grid cell, so that
    every panel's bar is as wide."""
    (x0, x1), (y0, y1) = ax.get_xlim(), ax.get_ylim()
    tall = abs(y1 - y0) / abs(x1 - x0) if x1 != x0 else 1.0
    width = 0.05 * max(1.0, tall)
    cax = ax.inset_axes([1.0 + 0.8 * width, 0.1, width, 0.8])
    cax.set_label("<colorbar>")
    return cax


def _stretched(fig, ax, image, cmap, label, extent=None):
    lo, hi = _display_limits(image, 1.0, 99.0)
    im = ax.imshow(image, cmap=cmap, vmin=lo, vmax=hi, extent=extent, interpolation="nearest")
    _colorbar(fig, im, ax, image, label=label, shrink=0.85)
    return im


def band_plot(ds: xr.Dataset, band) -> Figure | None:
    """The quicklook of one band: its total radiance (a thermal band's brightness temperature)
    at a 1–99 % stretch, on map axes [m], angles off the boresight, or pixels; None when the
    band has no finite pixel."""
    sel = ds.sel(band=band)
    bt = sel["brightness_temperature"].values
    use_bt = np.isfinite(bt).any()
    image = bt if use_bt else sel["radiance"].values
    if not np.isfinite(image).any():
        return None
    extent = _extent(ds)
    fig, ax = subplots(figsize=(6, 5))
    units = ds["radiance"].attrs.get("units", "W m-2 sr-1")
    label = "brightness temperature [K]" if use_bt else _bracketed("radiance", units)
    _stretched(fig, ax, image, "inferno" if use_bt else "gray", label, extent)
    wl = float(sel["wavelength_center"])
    ax.set_title(f"{ds.attrs.get('observer', '')}: {band} ({wl:.3g} µm)")
    _axes_for(ax, ds, extent, image.shape)
    return fig


def band_quicklooks(ds: xr.Dataset, folder: str | os.PathLike, prefix: str = "") -> list[Path]:
    """One PNG per band (:func:`band_plot`); a band without a finite pixel is left out with a
    warning.

    Returns
    -------
    list of pathlib.Path
        The files written.
    """
    folder = Path(folder)
    written = []
    for band in ds["band"].values:
        fig = band_plot(ds, band)
        if fig is None:
            warnings.warn(f"band {band!s}: no pixel has a finite radiance; no quicklook drawn",
                          stacklevel=2)
            continue
        written.append(_save(fig, folder / f"{prefix}{band}.png"))
    return written


def terms_figure(ds: xr.Dataset, path: str | os.PathLike) -> Path:
    """:func:`terms_plot` written to a PNG."""
    return _save(terms_plot(ds), path)


#: Panels in a row of the terms figure; a band with more layers wraps onto further rows.
TERMS_COLUMNS = 5


def term_layers(ds: xr.Dataset) -> tuple[list[str], dict[str, list[str]]]:
    """The layers the terms figure shows: every layer of ``ds`` that sums to its radiance
    (:data:`radscene.render.outputs.TERM_LAYERS`, in that order), the reflected sky and
    background as their solar and thermal parts where ``ds`` has them
    (:func:`radscene.render.outputs.finest_layers`), less those it leaves out.

    Returns
    -------
    shown : list of str
        The layer names drawn, in summing order.
    left_out : dict
        ``{"all zero": [...], "no finite value": [...]}``: the layers present in ``ds`` but
        not drawn, zero (or NaN) in every band with a finite radiance, or with no finite value
        at all; they add nothing to the radiance.
    """
    from radscene.render.outputs import finest_layers

    bands = [b for b in ds["band"].values if np.isfinite(ds["radiance"].sel(band=b).values).any()]
    shown, zero, empty = [], [], []
    for name in finest_layers(ds.data_vars):
        values = [ds[name].sel(band=b).values for b in bands]
        finite = [v[np.isfinite(v)] for v in values]
        if not any(f.size for f in finite):
            empty.append(name)
        elif not any(np.any(f != 0.0) for f in finite):
            zero.append(name)
        else:
            shown.append(name)
    return shown, {"all zero": zero, "no finite value": empty}


def terms_plot(ds: xr.Dataset) -> Figure:
    """Every layer that sums to the radiance, and the radiance, band by band.

    The layers are those of :func:`term_layers` (:data:`radscene.render.outputs.TERM_LAYERS`
    present in ``ds``: the signature terms, the reflected sky and background as their solar and
    thermal parts, the coupling layers, the sheet and volume layers), followed by the radiance they sum to, in rows of at most
    :data:`TERMS_COLUMNS` panels per band. Each band shares one colour scale (0.5–99.5 % of
    its radiance), so the size of each layer in its band can be read off; its colour bar shows
    where a layer passes the scale. The layers zero everywhere, or without a finite value,
    and the bands without a finite pixel are left out and named in the title.
    """
    shown, left_out = term_layers(ds)
    names = [*shown, "radiance"]
    bands = [b for b in ds["band"].values if np.isfinite(ds["radiance"].sel(band=b).values).any()]
    notes = [f"{why}, not shown: {', '.join(n.replace('_', ' ') for n in layers)}"
             for why, layers in left_out.items() if layers]
    missing = [str(b) for b in ds["band"].values if b not in bands]
    if missing:
        notes.append(f"no finite radiance, not shown: band {', band '.join(missing)}")
    units = unit_text(ds["radiance"].attrs.get("units", "W m-2 sr-1"))
    title = (f"radiance layers [{units}] — {ds.attrs.get('observer', '')}: each band's layers "
             "sum to its last panel, the radiance (number: image mean)")
    if notes:
        title += "\n" + "; ".join(notes)
    columns = min(len(names), TERMS_COLUMNS)
    per_band = math.ceil(len(names) / columns)
    n_rows = max(len(bands), 1) * per_band
    fig, axes = subplots(n_rows, columns, figsize=(2.4 * columns + 1.0, 2.1 * n_rows + 0.9),
                         squeeze=False)
    for i, band in enumerate(bands):
        block = axes[i * per_band:(i + 1) * per_band, :].ravel()
        lo, hi = stretch_limits(ds["radiance"].sel(band=band).values, 0.5, 99.5)
        vmin = 0.0 if lo >= 0 else lo
        images = [ds[name].sel(band=band).values for name in names]
        for j, (name, image) in enumerate(zip(names, images, strict=True)):
            ax = block[j]
            im = ax.imshow(image, cmap="magma", vmin=vmin, vmax=hi, interpolation="nearest")
            ax.set_xticks([])
            ax.set_yticks([])
            label = "radiance (sum)" if name == "radiance" else name.replace("_", " ")
            ax.set_title(label if len(bands) < 2 else f"{band}: {label}", fontsize=8)
            if j % columns == 0:
                ax.set_ylabel(str(band), fontsize=8)
            ax.text(0.02, 0.02, f"{np.nanmean(image):.3g}", transform=ax.transAxes, fontsize=6,
                    color="white", va="bottom",
                    bbox={"facecolor": "black", "alpha": 0.6, "pad": 1.0, "linewidth": 0})
        for ax in block[len(names):]:
            fig.delaxes(ax)
        bar = fig.colorbar(im, ax=block[:len(names)].tolist(), shrink=0.8, pad=0.01,
                           extend=colorbar_extend(images, vmin, hi))
        bar.ax.tick_params(labelsize=6)
    if not bands:
        for ax in axes.ravel():
            ax.set_axis_off()
        axes[0, 0].text(0.0, 0.5, "no band has a finite radiance", transform=axes[0, 0].transAxes)
    fig.suptitle(title, fontsize=9)
    return fig


# ----------------------------------------------------------------------------- truth maps


def categories(variable: xr.DataArray) -> dict[int, str]:
    """Category value → name of a flag variable (CF ``flag_values`` and ``flag_meanings``);
    values without a stated meaning are named by their number."""
    values = np.atleast_1d(np.asarray(variable.attrs.get("flag_values", []))).astype(int)
    meanings = str(variable.attrs.get("flag_meanings", "")).split()
    if len(meanings) != len(values):  # names with spaces cannot be told apart: numbers
        meanings = [str(v) for v in values]
    return dict(zip(values.tolist(), meanings, strict=True))


def _palette(n: int) -> list:
    colours = [*colormaps["tab20"].colors, *colormaps["tab20b"].colors, *colormaps["tab20c"].colors]
    if n > len(colours):
        colours = list(colormaps["turbo"](np.linspace(0.0, 1.0, n)))
    return colours[:n]


def _categorical(fig, ax, variable: xr.DataArray, title: str, extent=None,
                 legend_right: bool = False) -> None:
    """A map of categories in a discrete colour map, with a legend of the names present
    (below the map, or right of it when the map has axes of its own: ``legend_right``)."""
    ids = np.asarray(variable.values).astype(int)
    names = categories(variable)
    present = sorted(int(v) for v in np.unique(ids) if v >= 0)
    everything = sorted({v for v in names if v >= 0} | set(present))  # -1: no category
    colour_of = dict(zip(everything, _palette(len(everything)), strict=True))
    cmap = ListedColormap([colour_of[v] for v in present] or ["white"]).with_extremes(
        bad=NO_CATEGORY_COLOUR)
    rank = np.full(ids.shape, np.nan)
    for k, value in enumerate(present):
        rank[ids == value] = k
    norm = BoundaryNorm(np.arange(max(len(present), 1) + 1) - 0.5, max(len(present), 1))
    ax.imshow(rank, cmap=cmap, norm=norm, interpolation="nearest", extent=extent)
    handles = [Patch(facecolor=colour_of[v], edgecolor="0.3", linewidth=0.3,
                     label=names.get(v, str(v))) for v in present]
    if len(handles) > MAX_LEGEND_ENTRIES:
        more = len(handles) - MAX_LEGEND_ENTRIES + 1
        handles = handles[:MAX_LEGEND_ENTRIES - 1] + [
            Patch(facecolor="none", edgecolor="none", label=f"… {more} more")]
    if np.any(ids < 0):
        handles.append(Patch(facecolor=NO_CATEGORY_COLOUR, edgecolor="0.3", linewidth=0.3,
                             label="(none)"))
    if legend_right:
        ax.legend(handles=handles, loc="upper left", bbox_to_anchor=(1.02, 1.0), fontsize=6,
                  frameon=False, borderaxespad=0.0, handlelength=1.0)
    else:
        ax.legend(handles=handles, loc="upper center", bbox_to_anchor=(0.5, -0.02), fontsize=6,
                  frameon=False, borderaxespad=0.0, handlelength=1.0, ncol=3,
                  columnspacing=0.8)
    ax.set_title(title, fontsize=8)
    if not legend_right:
        ax.set_xticks([])
        ax.set_yticks([])


def truth_figure(ds: xr.Dataset, path: str | os.PathLike) -> Path:
    """:func:`truth_plot` written to a PNG."""
    return _save(truth_plot(ds), path)


def _truth_axes(ax, ds, extent, shape, left: bool, bottom: bool) -> None:
    """A truth panel's axes, those of the band PNGs (:func:`band_plot`): map axes [m] for a
    map product, angles off the boresight for a perspective camera, none otherwise; the
    axis labels on the figure's left column and bottom row only."""
    if extent is None and observer_fov(ds) is None:
        ax.set_xticks([])
        ax.set_yticks([])
        return
    _axes_for(ax, ds, extent, shape)
    ax.tick_params(labelsize=6)
    ax.xaxis.label.set_fontsize(7)
    ax.yaxis.label.set_fontsize(7)
    if not left:
        ax.set_ylabel("")
    if not bottom:
        ax.set_xlabel("")


def truth_plot(ds: xr.Dataset) -> Figure:
    """The geometric truth maps of a render in one figure: the object and material maps in
    named categories, the others with colour bars; maps without a finite value are left out
    and named in a note. The maps have the axes of the band PNGs: map axes [m] for a map
    product, angles off the boresight for a perspective camera."""
    layers = [("object_id", None), ("material_id", None), ("range", "viridis"),
              ("cos_incidence", "gray"), ("shadow_fraction", "gray_r"),
              ("sky_view_fraction", "gray"), ("surface_temperature", "inferno")]
    panels, skipped = [], []
    for name, cmap in layers:
        if name not in ds:
            continue
        values = ds[name].values
        has_data = (values >= 0).any() if name.endswith("_id") else np.isfinite(values).any()
        (panels if has_data or name.endswith("_id") else skipped).append((name, cmap))
    normal = ds["surface_normal"].sel(vector="up").values if "surface_normal" in ds else None
    if normal is not None and np.isfinite(normal).any():
        panels.append(("surface_normal", "gray"))
    elif normal is not None:
        skipped.append(("surface_normal", None))
    columns = 4
    rows = max(1, math.ceil(len(panels) / columns))
    fig, axes = subplots(rows, columns, figsize=(14, 3.3 * rows + 0.5), squeeze=False)
    extent = _extent(ds)
    with_axes = extent is not None or observer_fov(ds) is not None
    shape = (ds.sizes["y"], ds.sizes["x"])
    for k, (ax, (name, cmap)) in enumerate(zip(axes.ravel(), panels, strict=False)):
        left, bottom = k % columns == 0, k + columns >= len(panels)
        if name.endswith("_id"):
            _categorical(fig, ax, ds[name], name.replace("_", " "), extent, with_axes)
            _truth_axes(ax, ds, extent, shape, left, bottom)
            continue
        if name == "surface_normal":
            image, title = normal, "surface normal, up component"
        else:
            image = ds[name].values.astype(float)
            title = _bracketed(name.replace("_", " "), ds[name].attrs.get("units"))
        lo, hi = _display_limits(image, 0, 100)
        im = ax.imshow(image, cmap=cmap, vmin=lo, vmax=hi, interpolation="nearest",
                       extent=extent)
        ax.set_title(title, fontsize=8)
        _truth_axes(ax, ds, extent, shape, left, bottom)
        _colorbar(fig, im, ax, image, cax=_bar_axes(ax)).ax.tick_params(labelsize=6)
    for ax in axes.ravel()[len(panels):]:
        fig.delaxes(ax)
    title = f"truth maps — {ds.attrs.get('observer', '')}"
    if skipped:
        title += f"\nnot shown, no finite value: {', '.join(n for n, _ in skipped)}"
    fig.suptitle(title, fontsize=9)
    return fig


def signal_quicklooks(signal: xr.Dataset, folder: str | os.PathLike) -> list[Path]:
    """One PNG per band of a sensor's digital numbers (first frame), 1–99 % stretch; a band
    without a finite value is left out with a warning."""
    folder = Path(folder)
    written = []
    dn = signal["dn"]
    if "frame" in dn.dims:
        dn = dn.isel(frame=0)
    for band in dn["band"].values:
        image = dn.sel(band=band).values
        if not np.isfinite(image).any():
            warnings.warn(f"band {band!s}: no finite signal; no quicklook drawn", stacklevel=2)
            continue
        fig, ax = subplots(figsize=(6, 5))
        _stretched(fig, ax, image, "gray", "signal [DN]")
        ax.set_title(f"{signal.attrs.get('observer', '')}: {band}, sensor output")
        _axes_for(ax, signal, None, image.shape)
        written.append(_save(fig, folder / f"{band}.png"))
    return written
