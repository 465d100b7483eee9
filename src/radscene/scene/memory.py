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

So is every image a scene names (:func:`image_files`: the terrain's and the objects' textures,
the terrain's material and temperature maps), by :func:`image_header` (a PNG's or JPEG's
width and height as Pillow reads them without decoding a pixel, a .npy file's shape and dtype,
a GeoTIFF's width, height, bands and dtype): its reading is refused, naming the image's key,
when it would exceed the limit. Reading 4000 × 4000 images took (peak resident memory,
2026-11-25): as a texture, 17 B a texel grey (25 B with a contrast), 36 B RGB, 48 B RGBA,
palette or JPEG, 17 B from a .npy array of one band whatever its dtype, 64 B from one of four
float64 bands; as a temperature or material map, 9–20 B a pixel of one band, 24 B an RGBA or
palette PNG's, 73–80 B a GeoTIFF's of four float64 bands (each band is read). The estimate
takes 32 B a texel plus twice the bytes of the decoded values (:data:`IMAGE_TEXEL_BYTES`,
:data:`IMAGE_VALUE_COPIES`). A texture's multipliers are held for the whole render, 8 B a
texel (:data:`TEXTURE_TEXEL_BYTES`), and count in every observer's estimate.

A volume's density grid (:func:`grid_files`: ``volumes[i].profile.file``, a .npy array or
a NetCDF variable) is sized the same way by :func:`grid_header` (the .npy header's shape and
dtype, the NetCDF variable's shape and stored and decoded dtypes, none of its values read):
the loader turns it into float64 and checks it, and the render holds it. Peak resident
memory over a 200 × 200 × 200 grid (8 M nodes) against a 2 × 2 × 2 one, the scene otherwise
the same (2026-11-25): to load it, 11.6 B a node from a float32 .npy, 12.4 B from a float32
NetCDF variable, 9.6 B from an int16 .npy, 8.7 B from a float64 or uint8 one; through the load
and a render, 9.2 B a node from float32, 7.5 B from float64, int16 or uint8 (the render marches
rays through the grid and copies none of it). The estimate takes, to read it, 9 B a node (the float64 grid
and the checks' one-byte masks, :data:`GRID_NODE_BYTES`) plus the bytes of every other array
the reader makes on the way (the stored values, and the decoded ones where they differ; none
when they are float64 already); it is held for the whole render, 8 B a node
(:data:`GRID_HELD_BYTES`), and counts in every observer's estimate.

Two sizes are known only once the run is: a frame sequence (:func:`check_sequence_memory`)
and a heat balance (:func:`check_thermal_memory`: 150–205 B per element and time step,
measured on 1 600 and 6 400 elements over 721 steps, the flux terms, shadows and incidence of
every step; and the conduction nodes and hemisphere rays of each element). A frame's layers
take about 200 B per pixel and 200 B per pixel and band (measured on 64 × 64 frames of one and
four bands). A sequence held in memory (:func:`radscene.pipeline.render_sequence` without
``output``) keeps every frame until the last: the frames times that. One written to disk as it
is rendered (``render_sequence(..., output=...)``, ``radscene render``) holds one frame of every
observer (two, :data:`STREAMED_FRAMES`, counting those being written and rendered) and the
frame caches of incremental frames, 167 B a ray sample (measured on the demo,
docs/benchmarks.md; :data:`FRAME_CACHE_SAMPLE_BYTES`), beside its largest render (the
observers' estimates above), whatever the number of frames: peak resident memory of
``radscene render`` of a 256 × 256 map of two bands, 2026-11-26: 399 MB for 3 frames, 407 MB
for 12, 414 MB for 48 (held in memory: 476, 827 and 2 215 MB); of the demo, 1.83 GB for 3
frames and 1.92 GB for 100 (held in memory they would need about 60 GB). Its files take
at most :data:`DISK_PIXEL_BYTES` a pixel and :data:`DISK_PIXEL_BAND_BYTES` a pixel and band a
frame (float32 layers, float64 geolocation, before compression), checked against the space free
in the output folder (:func:`check_sequence_disk`, :func:`free_disk_space`).
:func:`radscene.pipeline.render_sequence` and :func:`radscene.pipeline.solve_thermal` check
them before their first step, ``radscene check`` too (a sequence as ``radscene render`` writes
it, into the default folder ``out``), against the same limit (:func:`memory_limit`).
"""

from __future__ import annotations

import math
import os
import shutil
from pathlib import Path

from radscene.errors import ConfigError

__all__ = ["estimate", "available_memory", "check_memory", "parse_memory", "memory_limit",
           "check_sequence_memory", "check_sequence_disk", "free_disk_space", "check_thermal_memory", "check_cube_memory", "dem_file_cells",
           "image_files", "image_header", "grid_files", "grid_header"]

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
#: Frames of every observer a sequence written to disk frame by frame holds at once, beside
#: its largest render: the images of one frame, and their float32 copies and the next
#: frame's images while they are written and rendered. The demo's 100 frames peaked at
#: 1.92 GB resident (3 frames: 1.83 GB) against 2.1 GB estimated (2026-11-26).
STREAMED_FRAMES = 2.0
#: The frame cache of incremental frames (:mod:`radscene.render.frame_cache`): per ray sample
#: (measured 167 B on the demo, docs/benchmarks.md).
FRAME_CACHE_SAMPLE_BYTES = 170.0
#: A frame on disk at most: per pixel, and per pixel and band — half the bytes of the frame in
#: memory (its layers float32 instead of float64), before compression, which only lowers it.
#: The demo's frames took 242 B (map) and 227 B (oblique) a pixel of their 8 bands, gzip level
#: 1, against 900 B estimated (2026-11-26).
DISK_PIXEL_BYTES = 100.0
DISK_PIXEL_BAND_BYTES = 100.0
#: A heat balance: per element and time step (the terms, the forcing, the beam's and the sky's
#: absorptance, the layers' temperatures), per element and conduction node, per element and
#: hemisphere ray.
THERMAL_ELEMENT_STEP_BYTES = 240.0
THERMAL_ELEMENT_NODE_BYTES = 100.0
#: ``thermal.profiles``: per element, time step and node (float32, recorded and written).
THERMAL_PROFILE_NODE_STEP_BYTES = 8.0
THERMAL_ELEMENT_RAY_BYTES = 100.0
#: An image a scene names, while it is read: per texel, and a multiple of the bytes of its
#: decoded values (PNG/JPEG: 4 B a channel, a palette as four channels; .npy and GeoTIFF: its
#: dtype, every band). Measured on 4000 × 4000 images (peak resident memory, 2026-11-25):
#: 17–48 B a texel for a texture of one to four 8-bit channels, 64 B from four float64 bands;
#: 9–25 B a pixel for a temperature or material map of one 8-bit channel to four, 80 B from
#: four float64 bands.
IMAGE_TEXEL_BYTES = 32.0
IMAGE_VALUE_COPIES = 2.0
#: A texture's multipliers, held for the whole render (float64; measured 8.0 B a texel,
#: 2026-11-25).
TEXTURE_TEXEL_BYTES = 8.0
#: A volume's density grid while it is read: per node, the float64 grid and the one-byte masks
#: of its checks, on top of the bytes of the arrays read on the way (:func:`grid_header`).
#: Measured on a 200³ grid (peak resident memory, 2026-11-25): 8.7 B a node from a float64
#: .npy, 11.6 B from float32, 12.4 B from a float32 NetCDF variable.
GRID_NODE_BYTES = 9.0
#: A density grid held for the whole render (float64; measured 7.5-9.2 B a node through a
#: load and a render, 2026-11-25).
GRID_HELD_BYTES = 8.0

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


def _npy_header(path: Path) -> tuple[tuple, object]:
    """The shape and dtype a .npy file's header declares (none of its values is read)."""
    import numpy as np

    with open(path, "rb") as f:
        major, _ = np.lib.format.read_magic(f)
        read = (np.lib.format.read_array_header_1_0 if major == 1
                else np.lib.format.read_array_header_2_0)
        shape, _, dtype = read(f)
    return tuple(shape), dtype


def dem_file_cells(path) -> float:
    """The number of samples of a DEM file from its header, reading none of them: a .npy
    array's shape, a GeoTIFF's width × height (0 when the header cannot be read: the reader
    then says what is wrong with the file)."""
    path = Path(path)
    try:
        if path.suffix.lower() == ".npy":
            shape, _ = _npy_header(path)
            return float(math.prod(float(n) for n in shape))
        import rasterio

        with rasterio.open(path) as raster:
            return float(raster.width) * float(raster.height)
    except Exception:  # noqa: BLE001 - an unreadable header: the reader reports the file
        return 0.0


def image_header(path) -> tuple[int, int, float] | None:
    """An image file's size from its header, reading none of its pixels.

    Parameters
    ----------
    path : str or path-like
        A .npy array (rows, columns[, bands]), a GeoTIFF (``.tif``, ``.tiff``) or any image
        Pillow opens (PNG, JPEG, ...).

    Returns
    -------
    tuple of (int, int, float) or None
        ``(rows, columns, value_bytes)``: the image's height and width [pixels] and the bytes
        of its values as the readers decode them (a .npy array's or a GeoTIFF's dtype, every
        band; PNG/JPEG as 4 B a channel, a palette as four channels, as a texture's reader
        decodes them: a material map's levels, read as they are, take fewer). None when the
        header cannot be read: the reader then says what is wrong with the file.
    """
    path = Path(path)
    suffix = path.suffix.lower()
    try:
        if suffix == ".npy":
            shape, dtype = _npy_header(path)
            rows = int(shape[0]) if len(shape) > 0 else 1
            columns = int(shape[1]) if len(shape) > 1 else 1
            return rows, columns, math.prod(float(n) for n in shape) * float(dtype.itemsize)
        if suffix in (".tif", ".tiff"):
            import numpy as np
            import rasterio

            with rasterio.open(path) as raster:
                itemsize = max(np.dtype(d).itemsize for d in raster.dtypes)
                return (int(raster.height), int(raster.width),
                        float(raster.height) * float(raster.width) * raster.count * itemsize)
        from PIL import Image

        from radscene.materials.imagefile import pil_unlimited

        with pil_unlimited(), Image.open(path) as image:
            columns, rows = image.size
            channels = 4 if image.mode in ("P", "PA") else len(image.getbands())
        return int(rows), int(columns), float(rows) * float(columns) * channels * 4.0
    except Exception:  # noqa: BLE001 - an unreadable header: the reader reports the file
        return None


def image_files(spec, base_dir) -> list[tuple[str, Path, bool]]:
    """The image files a validated scene spec names, with the keys that name them.

    Parameters
    ----------
    spec : radscene.scene.schema.SceneSpec
    base_dir : str or path-like or None
        Folder of relative file names; None: no image is listed (none can be found).

    Returns
    -------
    list of (str, pathlib.Path, bool)
        ``(key, path, held)``: ``terrain.textures.<kind>.file``,
        ``objects[i].textures.<kind>.file`` (held: a texture is kept for the whole render),
        ``terrain.material_map.file`` and ``terrain.temperature_map`` (resampled onto the
        terrain's grid, then dropped).
    """
    if base_dir is None:
        return []

    def where(name) -> Path:
        path = Path(name)
        return path if path.is_absolute() else Path(base_dir) / path

    out = []

    def textures(tset, key):
        for kind in ("reflectance", "emissivity", "transmittance"):
            texture = getattr(tset, kind, None)
            if getattr(texture, "file", None) is not None:
                out.append((f"{key}.textures.{kind}.file", where(texture.file), True))

    terrain = spec.terrain
    if terrain is not None:
        textures(getattr(terrain, "textures", None), "terrain")
        material_map = getattr(terrain, "material_map", None)
        if getattr(material_map, "file", None) is not None:
            out.append(("terrain.material_map.file", where(material_map.file), False))
        if getattr(terrain, "temperature_map", None) is not None:
            out.append(("terrain.temperature_map", where(terrain.temperature_map), False))
    for i, obj in enumerate(spec.objects):
        textures(obj.textures, f"objects[{i}]")
    return out


def grid_files(spec, base_dir) -> list[tuple[str, Path, str]]:
    """The density grids a validated scene spec names, with the keys that name them.

    Parameters
    ----------
    spec : radscene.scene.schema.SceneSpec
    base_dir : str or path-like or None
        Folder of relative file names; None: no grid is listed (none can be found).

    Returns
    -------
    list of (str, pathlib.Path, str)
        ``(key, path, variable)``: ``volumes[i].profile.file``, the file, and the NetCDF
        variable the grid is read from (``profile.variable``; unused for a .npy array).
    """
    if base_dir is None:
        return []
    out = []
    for i, volume in enumerate(getattr(spec, "volumes", None) or []):
        profile = volume.profile
        if profile.type == "grid" and profile.file is not None:
            path = Path(profile.file)
            out.append((f"volumes[{i}].profile.file",
                        path if path.is_absolute() else Path(base_dir) / path, profile.variable))
    return out


def grid_header(path, variable: str = "density") -> tuple[tuple[int, ...], float] | None:
    """A density grid's shape from its file's header, reading none of its values.

    Parameters
    ----------
    path : str or path-like
        A .npy array, or a NetCDF file (any other suffix).
    variable : str
        The NetCDF variable.

    Returns
    -------
    tuple of (tuple of int, float) or None
        ``(shape, read_bytes)``: the grid's shape [nodes] and the bytes a node of the arrays
        the reader makes before its float64 grid: the values as stored (a .npy array's
        dtype, a NetCDF variable's) and, where decoding (a scale factor) gives another dtype,
        as decoded; the last of them is the grid itself when it is float64. None when the
        header cannot be read or does not hold the variable: the reader then says what is
        wrong with the file.
    """
    import numpy as np

    path = Path(path)
    try:
        if path.suffix.lower() == ".npy":
            shape, dtype = _npy_header(path)
            steps = [np.dtype(dtype)]
        else:
            import xarray as xr

            with xr.open_dataset(path) as ds:
                if variable not in ds.variables:
                    return None
                var = ds[variable]  # lazily: only its header is read
                shape = var.shape
                steps = [np.dtype(var.encoding.get("dtype", var.dtype))]
                if np.dtype(var.dtype) != steps[0]:
                    steps.append(np.dtype(var.dtype))
        if steps[-1] == np.dtype(np.float64):
            steps.pop()  # read as it is: the grid itself, no copy
        return tuple(int(n) for n in shape), float(sum(d.itemsize for d in steps))
    except Exception:  # noqa: BLE001 - an unreadable header: the reader reports the file
        return None


def _joined(parts) -> str:
    """``a``, ``a and b``, ``a, b and c``."""
    parts = list(parts)
    return ", ".join(parts[:-1]) + " and " + parts[-1] if len(parts) > 1 else "".join(parts)


def estimate(spec, base_dir=None) -> dict:
    """Estimated peak bytes of rendering each observer of a validated scene spec.

    Parameters
    ----------
    spec : radscene.scene.schema.SceneSpec
    base_dir : str or path-like, optional
        Folder of the scene's relative file names: a DEM file, the images
        (:func:`image_files`) and the density grids (:func:`grid_files`) are sized from
        their headers only when it is given.

    Returns
    -------
    dict
        ``terrain`` (bytes, key); ``images``: per image file (bytes to read it, with the
        terrain; key; what); ``textures``: the bytes of the textures' multipliers, held for
        the whole render; ``grids``: per density grid (bytes to read it, with the terrain,
        the textures and the grids read before it; key; what); ``grids_held``: the bytes of
        the grids, held for the whole render; ``observers``: per observer (bytes, key, what),
        the terrain, the textures and the grids included.
    """
    cells, terrain_key = _terrain_cells(spec, base_dir)
    terrain = cells * TERRAIN_BYTES_PER_CELL
    images, held = [], 0.0
    for key, path, keep in image_files(spec, base_dir):
        header = image_header(path)
        if header is None:
            continue
        rows, columns, values = header
        texels = float(rows) * float(columns)
        images.append((BASE_BYTES + terrain + texels * IMAGE_TEXEL_BYTES
                       + IMAGE_VALUE_COPIES * values, key,
                       f"the image {path.name} ({columns:,} × {rows:,} pixels)"))
        if keep:
            held += texels * TEXTURE_TEXEL_BYTES
    grids, grids_held = [], 0.0
    for key, path, variable in grid_files(spec, base_dir):
        header = grid_header(path, variable)
        if header is None:
            continue
        shape, read = header
        nodes = math.prod(float(n) for n in shape)
        grids.append((BASE_BYTES + terrain + held + grids_held + nodes * (GRID_NODE_BYTES + read),
                      key, f"the density grid {path.name} "
                           f"({' × '.join(f'{n:,}' for n in shape)} nodes)"))
        grids_held += nodes * GRID_HELD_BYTES
    # the textures and the grids are held alongside the terrain for every render
    terrain += held + grids_held
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
            resolving = getattr(getattr(spec, "render", None), "spectral_grid", None)
            if resolving is not None:  # the grid's channel passes beside the band render
                image += min(SPECTRAL_PASS_BYTES, pixels * PIXEL_BAND_BYTES * 1e3)
                image += _channel_count(resolving) * CHANNEL_BYTES
                what += ", and the channels of render.spectral_grid in passes"
        observers.append((BASE_BYTES + terrain + samples * SAMPLE_BYTES + image, key, what))
    return {"terrain": (BASE_BYTES + cells * TERRAIN_BYTES_PER_CELL, terrain_key),
            "images": images, "textures": held, "grids": grids, "grids_held": grids_held,
            "observers": observers}


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


def _frame_bytes(observers, pixel: float, pixel_band: float) -> float:
    """A frame's bytes of ``observers`` (each ``(shape, bands[, samples])``) at ``pixel`` B a
    pixel and ``pixel_band`` B a pixel and band."""
    return sum(float(shape[0]) * float(shape[1]) * (pixel + bands * pixel_band)
               for shape, bands, *_ in observers)


def check_sequence_memory(frames: int, observers, limit: tuple[float, str],
                          key: str = "time.step", streamed: bool = False,
                          render: float = BASE_BYTES, ahead: bool = False) -> float:
    """Refuse a sequence of ``frames`` frames of ``observers`` whose memory exceeds ``limit``
    ((bytes, source), :func:`memory_limit`); returns the bytes estimated.

    Parameters
    ----------
    frames : int
    observers : sequence of tuple
        Per observer ``(shape, bands)`` or ``(shape, bands, samples)``: its rendered (rows,
        columns), its number of bands and the ray samples its frame cache keeps (rows ×
        columns × supersample²; 0 without a cache).
    limit : (float, str)
    key : str
    streamed : bool
        False: every frame is held until the last, ``frames`` × the frame's bytes.
        True: each frame is written to disk as it is rendered (``render_sequence(...,
        output=...)``, ``radscene render``): the largest render (``render``), and beside it
        :data:`STREAMED_FRAMES` frames of every observer (the last one's images while they
        are written, the next one's as its observers are rendered) and the frame caches
        (:data:`FRAME_CACHE_SAMPLE_BYTES` a sample), whatever the number of frames.
    render : float
        With ``streamed``: the largest render's estimate, the base included (:func:`estimate`)
        [bytes].
    ahead : bool
        Key frames are rendered ahead (:mod:`radscene.pipeline.look_ahead`): one frame more
        is held, the next key frame's.
    """
    per_frame = _frame_bytes(observers, FRAME_PIXEL_BYTES, FRAME_PIXEL_BAND_BYTES)
    if not streamed:
        need = BASE_BYTES + (float(frames) + ahead) * per_frame
        _refuse(need, limit, key, f"the sequence of {frames:,} frames ({per_frame / 1e6:.3g} MB "
                "each, all held until the last)", "a longer step, a shorter span, fewer pixels "
                "or fewer observers")
        return need
    cache = FRAME_CACHE_SAMPLE_BYTES * sum(
        float(o[2]) if len(o) > 2 else float(o[0][0]) * float(o[0][1]) for o in observers)
    need = max(render, BASE_BYTES) + (STREAMED_FRAMES + ahead) * per_frame + cache
    _refuse(need, limit, key, f"the sequence of {frames:,} frames written as they come "
            f"({per_frame / 1e6:.3g} MB a frame, {cache / 1e6:.3g} MB of frame caches, beside "
            "its largest render)", "fewer pixels, a lower supersample or fewer observers")
    return need


def free_disk_space(folder) -> float:
    """The bytes free for this user on the file system of ``folder`` (or of its nearest
    existing parent, when it does not exist yet); infinite when it cannot be told."""
    path = Path(folder).absolute()
    for candidate in (path, *path.parents):
        if candidate.is_dir():
            try:
                return float(shutil.disk_usage(candidate).free)
            except OSError:
                return float("inf")
    return float("inf")


def check_sequence_disk(frames: int, observers, folder, key: str = "time.step") -> float:
    """Refuse a sequence of ``frames`` frames of ``observers`` (as for
    :func:`check_sequence_memory`) streamed into ``folder`` when its files would not fit in
    the space free there (:func:`free_disk_space`); returns the bytes estimated.

    A frame takes at most :data:`DISK_PIXEL_BYTES` a pixel and :data:`DISK_PIXEL_BAND_BYTES`
    a pixel and band (its layers as float32, the geolocation as float64, before compression,
    which only lowers it); the files grow in place, so nothing more is needed at the end.

    Raises
    ------
    ConfigError
        Naming ``key``, with the bytes needed and free.
    """
    per_frame = _frame_bytes(observers, DISK_PIXEL_BYTES, DISK_PIXEL_BAND_BYTES)
    need = float(frames) * per_frame
    free = free_disk_space(folder)
    if need > free:
        raise ConfigError(f"the sequence of {frames:,} frames needs up to {need / 1e9:,.1f} GB of "
                          f"disk ({per_frame / 1e6:.3g} MB a frame before compression); {folder} "
                          f"has {free / 1e9:,.1f} GB free: a folder on a larger disk, a longer "
                          "step, a shorter span, fewer pixels or fewer observers", key=key)
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
                         limit: tuple[float, str], key: str = "thermal.step", profiles: bool = False) -> float:
    """Refuse a heat balance of ``elements`` surface elements over ``steps`` time steps, with
    ``nodes`` conduction nodes and ``rays`` hemisphere rays per element (and, with
    ``profiles``, every node's temperature at every step), whose arrays exceed ``limit``
    ((bytes, source)); returns the bytes estimated."""
    per_step = THERMAL_ELEMENT_STEP_BYTES + (THERMAL_PROFILE_NODE_STEP_BYTES * nodes if profiles else 0.0)
    need = BASE_BYTES + float(elements) * (float(steps) * per_step
                                           + nodes * THERMAL_ELEMENT_NODE_BYTES
                                           + rays * THERMAL_ELEMENT_RAY_BYTES)
    _refuse(need, limit, key, f"the heat balance of {elements:,} elements × {steps:,} time "
            f"steps × {nodes} nodes", "a longer thermal.step, a shorter span, a coarser "
            "thermal.resolution or fewer nodes")
    return need


def check_memory(spec, limit=None, base_dir=None) -> None:
    """Refuse a scene whose estimated render exceeds ``limit`` [bytes] (default:
    ``render.max_memory``, else the machine's memory, :func:`available_memory`): its terrain
    grid, then each image it names, then each density grid, then each observer. A DEM file's,
    the images' and the density grids' headers are read from ``base_dir`` (relative
    names)."""
    limit, source = memory_limit(spec, limit)
    est = estimate(spec, base_dir)
    terrain, key = est["terrain"]
    gb = 1e9
    if key and terrain > limit:
        advice = ("a DEM resampled coarser or cropped" if key == "terrain.file"
                  else "a coarser spacing or a smaller area")
        raise ConfigError(f"the terrain grid needs about {terrain / gb:.1f} GB; the limit is "
                          f"{limit / gb:.1f} GB ({source}): {advice}", key=key)
    with_terrain = ", with the terrain" if terrain > BASE_BYTES else ""
    for need, key, what in est["images"]:
        if need > limit:
            raise ConfigError(f"{what} needs about {need / gb:.1f} GB to read{with_terrain}; "
                              f"the limit is {limit / gb:.1f} GB ({source}): an image resampled "
                              "coarser or cropped", key=key)
    held = [name for name, size in (("the terrain", terrain > BASE_BYTES),
                                    ("textures", est["textures"])) if size]
    for j, (need, key, what) in enumerate(est["grids"]):
        if need > limit:
            parts = held + ["the density grids before it"] * (j > 0)
            with_held = f", with {_joined(parts)}" if parts else ""
            raise ConfigError(f"{what} needs about {need / gb:.1f} GB to read{with_held}; the "
                              f"limit is {limit / gb:.1f} GB ({source}): a grid resampled "
                              "coarser or cropped", key=key)
    for need, key, what in est["observers"]:
        if need > limit:
            advice = ("a coarser spectral step (fewer channels) or fewer pixels"
                      if key.endswith("spectral.step")
                      else "fewer pixels, a lower supersample or fewer bands")
            parts = ["the terrain"] + ["textures"] * bool(est["textures"]) + [
                "density grids"] * bool(est["grids_held"])
            raise ConfigError(f"rendering it needs about {need / gb:.1f} GB ({what}, with "
                              f"{_joined(parts)}); the limit is {limit / gb:.1f} GB "
                              f"({source}): {advice}", key=key)
