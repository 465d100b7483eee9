"""Animated GIFs of a frame sequence, one per band (Pillow, which matplotlib already needs)."""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np
import xarray as xr

from radscene.errors import ConfigError
from radscene.io.files import atomic_output
from radscene.io.quicklook import stretch_limits

__all__ = ["band_animations"]

#: GIF frame durations are whole hundredths of a second; browsers play shorter ones slowly [s].
GIF_MIN_FRAME = 0.02


def band_animations(ds: xr.Dataset, folder: str | os.PathLike, prefix: str = "",
                    fps: float = 10.0) -> list[Path]:
    """One looping GIF per band of a sequence's total radiance (thermal bands: brightness
    temperature), grey levels on one stretch for all frames (1st–99th percentile), so that
    changes between frames show.

    Parameters
    ----------
    ds : xarray.Dataset
        A sequence (:func:`radscene.pipeline.simulation.render_sequence`): ``radiance(time, band, y, x)``.
    folder : path-like
        Written as ``folder/<prefix><band>.gif``.
    fps : float
        Playback frames per second [s-1], > 0 and at most 1 / 0.02 s.

    Returns
    -------
    list of pathlib.Path
    """
    from PIL import Image

    fps = float(fps)
    if not (np.isfinite(fps) and 0 < fps <= 1.0 / GIF_MIN_FRAME):
        raise ConfigError(f"must lie in (0, {1.0 / GIF_MIN_FRAME:g}] frames per second (GIF durations "
                          f"are whole hundredths of a second), got {fps!r}", key="fps")
    if "time" not in ds.dims:
        raise ConfigError("a sequence has a time dimension; this Dataset has none", key="ds")
    folder = Path(folder)
    written = []
    for band in ds["band"].values:
        sel = ds.sel(band=band)
        bt = sel["brightness_temperature"].values if "brightness_temperature" in sel else None
        stack = bt if bt is not None and np.isfinite(bt).any() else sel["radiance"].values
        lo, hi = stretch_limits(stack)
        grey = np.clip((np.nan_to_num(stack, nan=lo) - lo) / (hi - lo), 0.0, 1.0)  # display only
        images = [Image.fromarray(np.round(255 * g).astype(np.uint8), mode="L") for g in grey]
        path = folder / f"{prefix}{band}.gif"
        with atomic_output(path, suffix=".gif") as tmp:
            images[0].save(tmp, format="GIF", save_all=True, append_images=images[1:],
                           duration=round(1000.0 / fps), loop=0)
        written.append(path)
    return written
