"""The memory a scene will need, estimated from its file before anything is built.

A terrain grid, an observer's shape and supersampling and its bands set the peak memory of a
render. The figures below were measured on the renderer (peak resident memory, 2026-11-25):
a procedural terrain of 2.25 M cells took 638 MB to load (283 B a cell; its ray-tracing
structure comes on top); a 1024 × 1024 map of one band 540 MB, of eight bands 887 MB, 512 × 512
at supersample 2 with eight bands 654 MB — about 400 B per ray sample (rays, hits and their
secondary rays are held for the whole image) and 50 B per pixel and band (the layers), over a
base of about 300 MB (Python, numpy, the libraries). The estimate rounds each up.

:func:`check_memory` refuses a scene whose estimate exceeds the limit — ``render.max_memory``,
``radscene render/check --max-memory``, or else the machine's physical memory — with the
key that sets the size and the figures. A DEM file's grid is sized from its header (a .npy
file's, a GeoTIFF's) before a sample of it is read.

Two sizes are known only once the run is: a frame sequence (:func:`check_sequence_memory`:
every frame's layers are held until the last, about 200 B per pixel and 200 B per pixel and
band, measured on 64 × 64 frames of one and four bands) and a heat balance
(:func:`check_thermal_memory`: 150–205 B per element and time step, measured on 1 600 and
6 400 elements over 721 steps, the flux terms, shadows and incidence of every step; and the
conduction nodes and hemisphere rays of each element). :func:`radscene.pipeline.render_sequence`
and :func:`radscene.pipeline.solve_thermal` check them before their first step, ``radscene
check`` too, against the same limit (:func:`memory_limit`).
"""

from __future__ import annotations

import os
from pathlib import Path

from radscene.errors import ConfigError

__all__ = ["estimate", "available_memory", "check_memory", "parse_memory", "memory_limit",
           "check_sequence_memory", "check_thermal_memory", "check_cube_memory", "dem_file_cells"]

BASE_BYTES = 300e6
TERRAIN_BYTES_PER_CELL = 400.0
SAMPLE_BYTES = 450.0
PIXEL_BAND_BYTES = 60.0
#: A spectral observer's cube is rendered in passes of this much image memory at most
#: (:data:`radscene.render.hyperspectral.PASS_MEMORY`).
SPECTRAL_PASS_BYTES = 1.5e9
#: A hyperspectral channel: its response, weights and per-material factors (the responses
#: alone measured 700 B a channel for a grid of 200 000).
CHANNEL_BYTES = 2000.0
#: A frame of a sequence, held until the last one: per pixel, and per pixel and band.
FRAME_PIXEL_BYTES = 200.0
FRAME_PIXEL_BAND_BYTES = 200.0
#: A heat balance: per element and time step, per element and conduction node, per element
#: and hemisphere ray.
THERMAL_ELEMENT_STEP_BYTES = 200.0
THERMAL_ELEMENT_NODE_BYTES = 100.0
THERMAL_ELEMENT_RAY_BYTES = 100.0

_UNITS = {"b": 1.0, "kb": 1e3, "mb": 1e6, "gb": 1e9, "tb": 1e12,
          "kib": 1024.0, "mib": 1024.0 ** 2, "gib": 1024.0 ** 3, "tib": 1024.0 ** 4}


def parse_memory(value, key: str = "render.max_memory") -> float:
    """Bytes from a number of bytes or a string such as ``"8 GB"`` or ``"512MiB"``."""
    if isinstance(value, (int, float)) and not isinstance(value, bool):
        number, unit = float(value), "b"
    else:
        text = str(value).strip().lower().replace(" ", "")
        digits = text.rstrip("abcdefghijklmnopqrstuvwxyz")
        unit = text[len(digits):] or "b"
        try:
            number = float(digits)
        except ValueError:
            number = float("nan")
    if unit not in _UNITS or not number > 0:
        raise ConfigError(f"a memory size > 0 such as '8 GB' or '512 MiB'; got {value!r}",
                          key=key)
    return number * _UNITS[unit]


def available_memory() -> float:
    """The machine's physical memory [bytes] (what is free at this instant depends on what
    else runs, and a check that passes or fails with it would not be repeatable)."""
    try:
        return float(os.sysconf("SC_PHYS_PAGES") * os.sysconf("SC_PAGE_SIZE"))
    except (ValueError, OSError, AttributeError):
        return float("inf")


def _terrain_cells(spec, base_dir=None) -> tuple[float, str]:
    terrain = spec.terrain
    if terrain is None:
        return 0.0, ""
    if getattr(terrain, "type", None) in ("procedural", "flat"):
        nx = terrain.size[0] / terrain.spacing + 1
        ny = terrain.size[1] / terrain.spacing + 1
        return nx * ny, "terrain.spacing"
    if getattr(terrain, "type", None) == "sea":
        if terrain.far_field or terrain.wind_speed == 0:
            return 4.0, "terrain.resolution"
        nx = terrain.size[0] / terrain.resolution + 1
        ny = terrain.size[1] / terrain.resolution + 1
        return nx * ny, "terrain.resolution"
    elevation = getattr(terrain, "elevation", None)
    if elevation is not None:
        return float(sum(len(row) for row in elevation)), "terrain.elevation"
    if base_dir is not None and getattr(terrain, "file", None) is not None:
        path = Path(terrain.file)
        return dem_file_cells(path if path.is_absolute() else Path(base_dir) / path), "terrain.file"
    return 0.0, ""


def dem_file_cells(path) -> float:
    """The number of samples of a DEM file from its header, reading none of them: a .npy
    array's shape, a GeoTIFF's width × height (0 when the header cannot be read: the reader
    then says what is wrong with the file)."""
    path = Path(path)
    try:
        if path.suffix.lower() == ".npy":
            import numpy as np

            with open(path, "rb") as f:
                major, _ = np.lib.format.read_magic(f)
                read = (np.lib.format.read_array_header_1_0 if major == 1
                        else np.lib.format.read_array_header_2_0)
                shape = read(f)[0]
            return float(np.prod(shape, dtype=float))
        import rasterio

        with rasterio.open(path) as raster:
            return float(raster.width) * float(raster.height)
    except Exception:  # noqa: BLE001 - an unreadable header: the reader reports the file
        return 0.0


def estimate(spec, base_dir=None) -> dict:
    """Estimated peak bytes of rendering each observer of a validated scene spec.

    Returns
    -------
    dict
        ``terrain`` (bytes, key), and ``observers``: per observer (bytes, key, what).
    """
    cells, terrain_key = _terrain_cells(spec, base_dir)
    terrain = cells * TERRAIN_BYTES_PER_CELL
    n_bands = max(1, len(spec.bands or []))
    observers = []
    for i, obs in enumerate(spec.observers):
        grid = getattr(obs, "spectral", None)
        channels = 0.0 if grid is None else _channel_count(grid)
        if obs.shape is None:  # the sensor fixes it: only a spectral grid is estimated
            if channels * CHANNEL_BYTES > 0:
                observers.append((BASE_BYTES + terrain + channels * CHANNEL_BYTES,
                                  f"observers[{i}].spectral.step", f"{channels:.3g} channels"))
            continue
        pixels = float(obs.shape[0]) * float(obs.shape[1])
        samples = pixels * obs.supersample ** 2
        key = f"observers[{i}].shape"
        if grid is not None:
            image = min(SPECTRAL_PASS_BYTES, pixels * PIXEL_BAND_BYTES * 1e3)
            what = (f"{pixels:.3g} pixels × {obs.supersample}² samples, {channels:.3g} channels "
                    "in passes")
            if channels * CHANNEL_BYTES > samples * SAMPLE_BYTES + image:
                key = f"observers[{i}].spectral.step"
            image += channels * CHANNEL_BYTES
        else:
            image = pixels * n_bands * PIXEL_BAND_BYTES
            what = f"{pixels:.3g} pixels × {obs.supersample}² samples × {n_bands} bands"
        observers.append((BASE_BYTES + terrain + samples * SAMPLE_BYTES + image, key, what))
    return {"terrain": (BASE_BYTES + terrain, terrain_key), "observers": observers}


def _channel_count(grid) -> float:
    """Channels of a spectral grid spec: (max - min) / step + 1 [-]."""
    return float(max(0.0, (grid.max - grid.min) / grid.step) + 1.0)


def memory_limit(spec, limit=None) -> tuple[float, str]:
    """The limit a run's memory is checked against [bytes] and where it comes from: ``limit``
    (``--max-memory``), else ``render.max_memory``, else the machine's memory."""
    if limit is not None:
        return float(limit), "--max-memory"
    if getattr(spec.render, "max_memory", None) is not None:
        return parse_memory(spec.render.max_memory), "render.max_memory"
    return available_memory(), "this machine's memory"


def _refuse(need: float, limit: tuple[float, str], key: str, what: str, advice: str) -> None:
    if need > limit[0]:
        raise ConfigError(f"{what} needs about {need / 1e9:.1f} GB; the limit is "
                          f"{limit[0] / 1e9:.1f} GB ({limit[1]}): {advice}", key=key)


def check_sequence_memory(frames: int, observers, limit: tuple[float, str],
                          key: str = "time.step") -> float:
    """Refuse a sequence of ``frames`` frames of ``observers`` (each ``(shape, bands)``: its
    rendered (rows, columns) and its number of bands) whose held frames exceed ``limit``
    ((bytes, source), :func:`memory_limit`); returns the bytes estimated."""
    per_frame = sum(float(shape[0]) * float(shape[1]) * (FRAME_PIXEL_BYTES
                                                         + bands * FRAME_PIXEL_BAND_BYTES)
                    for shape, bands in observers)
    need = BASE_BYTES + float(frames) * per_frame
    _refuse(need, limit, key, f"the sequence of {frames:,} frames ({per_frame / 1e6:.3g} MB "
            "each, all held until the last)", "a longer step, a shorter span, fewer pixels or "
            "fewer observers")
    return need


def check_cube_memory(channels: int, pixels: int, limit: tuple[float, str], key: str,
                      bytes_per_value: int = 4) -> float:
    """Refuse a spectral cube of ``channels`` × ``pixels`` gathered in memory whose values
    exceed ``limit`` ((bytes, source)); returns the bytes estimated."""
    need = BASE_BYTES + float(channels) * float(pixels) * bytes_per_value
    _refuse(need, limit, key, f"the spectral cube of {channels:,} channels × {pixels:,} pixels "
            "in memory", "a coarser spectral step, fewer pixels, or radscene render (or "
            "radscene.pipeline.spectral_passes), which writes the cube pass by pass")
    return need


def check_thermal_memory(elements: int, steps: int, nodes: int, rays: int,
                         limit: tuple[float, str], key: str = "thermal.step") -> float:
    """Refuse a heat balance of ``elements`` surface elements over ``steps`` time steps, with
    ``nodes`` conduction nodes and ``rays`` hemisphere rays per element, whose arrays exceed
    ``limit`` ((bytes, source)); returns the bytes estimated."""
    need = BASE_BYTES + float(elements) * (float(steps) * THERMAL_ELEMENT_STEP_BYTES
                                           + nodes * THERMAL_ELEMENT_NODE_BYTES
                                           + rays * THERMAL_ELEMENT_RAY_BYTES)
    _refuse(need, limit, key, f"the heat balance of {elements:,} elements × {steps:,} time "
            f"steps × {nodes} nodes", "a longer thermal.step, a shorter span, a coarser "
            "thermal.resolution or fewer nodes")
    return need


def check_memory(spec, limit=None, base_dir=None) -> None:
    """Refuse a scene whose estimated render exceeds ``limit`` [bytes] (default:
    ``render.max_memory``, else the machine's memory, :func:`available_memory`); a DEM file's
    header is read from ``base_dir`` (relative names)."""
    limit, source = memory_limit(spec, limit)
    est = estimate(spec, base_dir)
    terrain, key = est["terrain"]
    gb = 1e9
    if key and terrain > limit:
        advice = ("a DEM resampled coarser or cropped" if key == "terrain.file"
                  else "a coarser spacing or a smaller area")
        raise ConfigError(f"the terrain grid needs about {terrain / gb:.1f} GB; the limit is "
                          f"{limit / gb:.1f} GB ({source}): {advice}", key=key)
    for need, key, what in est["observers"]:
        if need > limit:
            advice = ("a coarser spectral step (fewer channels) or fewer pixels"
                      if key.endswith("spectral.step")
                      else "fewer pixels, a lower supersample or fewer bands")
            raise ConfigError(f"rendering it needs about {need / gb:.1f} GB ({what}, with the "
                              f"terrain); the limit is {limit / gb:.1f} GB ({source}): "
                              f"{advice}", key=key)
