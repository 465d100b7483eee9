"""Animations of a frame sequence, one per band: looping GIFs (Pillow, which matplotlib already
needs) and MP4 videos (H.264 through imageio and imageio-ffmpeg: ``pip install imageio imageio-ffmpeg``, or the
extra ``[video]``).

``render.video`` in a scene file chooses (:func:`video_formats`):

=======  =====================================================================================
value    writes
=======  =====================================================================================
auto     a GIF per band, and an MP4 too when imageio-ffmpeg is installed (the default)
gif      GIFs only
mp4      MP4s only (needs imageio-ffmpeg: an error before any frame is rendered otherwise)
both     both (idem)
none     neither
=======  =====================================================================================
"""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np
import xarray as xr

from radscene.errors import ConfigError, did_you_mean
from radscene.io.files import atomic_output
from radscene.io.quicklook import stretch_limits

__all__ = ["STRETCH_SAMPLES", "VIDEO_CHOICES", "band_animations", "band_videos", "mp4_available",
           "video_formats"]

VIDEO_CHOICES = ("auto", "gif", "mp4", "both", "none")

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
        A sequence (:func:`radscene.pipeline.simulation.render_sequence`), in memory or opened
        lazily: ``radiance(time, band, y, x)``.
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
    folder = Path(folder)
    written = []
    for band, grey in _grey_frames(ds):
        images = [Image.fromarray(g, mode="L") for g in grey]
        path = folder / f"{prefix}{band}.gif"
        with atomic_output(path, suffix=".gif") as tmp:
            images[0].save(tmp, format="GIF", save_all=True, append_images=images[1:],
                           duration=round(1000.0 / fps), loop=0)
        written.append(path)
    return written


#: The grey stretch of an animation is taken from at most this many values of a band (every
#: value of a shorter sequence; of a longer one, every frame's pixels on a regular stride).
STRETCH_SAMPLES = 1 << 24


def _grey_frames(ds: xr.Dataset):
    """Per band its frames as 8-bit grey ``(time, y, x)`` on one stretch (display only).

    The frames are read one at a time (a lazily opened file stays on disk): a first pass takes
    the stretch, the 1st–99th percentile of the band's finite values — all of them when the
    sequence has at most :data:`STRETCH_SAMPLES`, else every frame's pixels on a regular
    stride that keeps about that many — and a second makes the grey frames.
    Brightness temperature where the band has a finite one, radiance otherwise."""
    if "time" not in ds.dims:
        raise ConfigError("a sequence has a time dimension; this Dataset has none", key="ds")
    frames = ds.sizes["time"]
    for band in ds["band"].values:
        sel = ds.sel(band=band)
        name = "radiance"
        if "brightness_temperature" in sel:
            sample = _stretch_sample(sel["brightness_temperature"], frames)
            if np.isfinite(sample).any():
                name = "brightness_temperature"
        if name == "radiance":
            sample = _stretch_sample(sel["radiance"], frames)
        lo, hi = stretch_limits(sample)
        del sample
        var = sel[name]
        grey = np.empty((frames, *var.shape[1:]), dtype=np.uint8)
        for k in range(frames):
            image = np.asarray(var.isel(time=k).values, dtype=float)
            level = np.clip((np.nan_to_num(image, nan=lo) - lo) / (hi - lo), 0.0, 1.0)
            grey[k] = np.round(255 * level).astype(np.uint8)
        yield band, grey


def _stretch_sample(var: xr.DataArray, frames: int) -> np.ndarray:
    """The values of ``var`` (time, y, x) the stretch is taken from, read a frame at a time:
    all of them, or every frame's on a stride keeping about :data:`STRETCH_SAMPLES`."""
    pixels = int(np.prod(var.shape[1:]))
    stride = max(1, int(np.ceil(frames * pixels / STRETCH_SAMPLES)))
    parts = [np.asarray(var.isel(time=k).values, dtype=float).ravel()[::stride]
             for k in range(frames)]
    return np.concatenate(parts) if parts else np.empty(0)


def mp4_available() -> bool:
    """Whether MP4s can be written: imageio and imageio-ffmpeg importable."""
    import importlib.util

    return all(importlib.util.find_spec(m) is not None for m in ("imageio", "imageio_ffmpeg"))


def video_formats(choice: str = "auto", key: str = "render.video") -> tuple[str, ...]:
    """The animation formats a sequence writes for a ``render.video`` choice.

    Returns
    -------
    tuple of str
        Some of ``("gif", "mp4")``.

    Raises
    ------
    ConfigError
        An unknown choice, or mp4/both without imageio-ffmpeg (naming the extra to install).
    """
    if choice not in VIDEO_CHOICES:
        raise ConfigError(f"unknown choice {choice!r}; known: {', '.join(VIDEO_CHOICES)}"
                          f"{did_you_mean(choice, VIDEO_CHOICES)}", key=key)
    have_mp4 = mp4_available()
    if choice in ("mp4", "both") and not have_mp4:
        raise ConfigError(f"{choice} needs imageio and imageio-ffmpeg (pip install imageio imageio-ffmpeg); "
                          "or choose gif", key=key)
    return {"auto": ("gif", "mp4") if have_mp4 else ("gif",), "gif": ("gif",), "mp4": ("mp4",),
            "both": ("gif", "mp4"), "none": ()}[choice]


def band_videos(ds: xr.Dataset, folder: str | os.PathLike, prefix: str = "",
                fps: float = 10.0) -> list[Path]:
    """One MP4 (H.264, yuv420p) per band of a sequence, the frames of :func:`band_animations`.

    Odd image sizes are padded by repeating the last row or column (H.264 in yuv420p needs even
    ones); nothing is scaled.

    Parameters
    ----------
    ds : xarray.Dataset
        A sequence, in memory or opened lazily: ``radiance(time, band, y, x)``.
    folder : path-like
        Written as ``folder/<prefix><band>.mp4``.
    fps : float
        Playback frames per second [s-1], > 0.

    Returns
    -------
    list of pathlib.Path
    """
    fps = float(fps)
    if not (np.isfinite(fps) and fps > 0):
        raise ConfigError(f"must be > 0 frames per second, got {fps!r}", key="fps")
    if not mp4_available():
        raise ConfigError("MP4 needs imageio and imageio-ffmpeg (pip install imageio imageio-ffmpeg)", key="video")
    import imageio.v2 as imageio

    folder = Path(folder)
    written = []
    for band, grey in _grey_frames(ds):
        _, ny, nx = grey.shape
        grey = np.pad(grey, ((0, 0), (0, ny % 2), (0, nx % 2)), mode="edge")
        path = folder / f"{prefix}{band}.mp4"
        with atomic_output(path, suffix=".mp4") as tmp:
            with imageio.get_writer(tmp, format="FFMPEG", mode="I", fps=fps, codec="libx264",
                                    pixelformat="yuv420p", macro_block_size=1,
                                    ffmpeg_log_level="error") as writer:
                for frame in grey:
                    writer.append_data(frame)
        written.append(path)
    return written
