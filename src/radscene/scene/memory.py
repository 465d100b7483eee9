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
key that sets the size and the figures.
"""

from __future__ import annotations

import os

from radscene.errors import ConfigError

__all__ = ["estimate", "available_memory", "check_memory", "parse_memory"]

BASE_BYTES = 300e6
TERRAIN_BYTES_PER_CELL = 400.0
SAMPLE_BYTES = 450.0
PIXEL_BAND_BYTES = 60.0
#: A spectral observer's cube is rendered in passes of this much image memory at most
#: (:data:`radscene.render.hyperspectral.PASS_MEMORY`).
SPECTRAL_PASS_BYTES = 1.5e9

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


def _terrain_cells(spec) -> tuple[float, str]:
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
    return 0.0, ""  # a DEM file: its size is known once read


def estimate(spec) -> dict:
    """Estimated peak bytes of rendering each observer of a validated scene spec.

    Returns
    -------
    dict
        ``terrain`` (bytes, key), and ``observers``: per observer (bytes, key, what).
    """
    cells, terrain_key = _terrain_cells(spec)
    terrain = cells * TERRAIN_BYTES_PER_CELL
    n_bands = max(1, len(spec.bands or []))
    observers = []
    for i, obs in enumerate(spec.observers):
        if obs.shape is None:  # the sensor fixes it; not estimated
            continue
        pixels = float(obs.shape[0]) * float(obs.shape[1])
        samples = pixels * obs.supersample ** 2
        if getattr(obs, "spectral", None) is not None:
            image = min(SPECTRAL_PASS_BYTES, pixels * PIXEL_BAND_BYTES * 1e3)
            what = f"{pixels:.3g} pixels × {obs.supersample}² samples, spectral passes"
        else:
            image = pixels * n_bands * PIXEL_BAND_BYTES
            what = f"{pixels:.3g} pixels × {obs.supersample}² samples × {n_bands} bands"
        observers.append((BASE_BYTES + terrain + samples * SAMPLE_BYTES + image,
                          f"observers[{i}].shape", what))
    return {"terrain": (BASE_BYTES + terrain, terrain_key), "observers": observers}


def check_memory(spec, limit=None) -> None:
    """Refuse a scene whose estimated render exceeds ``limit`` [bytes] (default:
    ``render.max_memory``, else the machine's memory, :func:`available_memory`)."""
    source = "--max-memory"
    if limit is None and getattr(spec.render, "max_memory", None) is not None:
        limit, source = parse_memory(spec.render.max_memory), "render.max_memory"
    if limit is None:
        limit, source = available_memory(), "this machine's memory"
    est = estimate(spec)
    terrain, key = est["terrain"]
    gb = 1e9
    if key and terrain > limit:
        raise ConfigError(f"the terrain grid needs about {terrain / gb:.1f} GB; the limit is "
                          f"{limit / gb:.1f} GB ({source}): a coarser spacing or a smaller "
                          "area", key=key)
    for need, key, what in est["observers"]:
        if need > limit:
            raise ConfigError(f"rendering it needs about {need / gb:.1f} GB ({what}, with the "
                              f"terrain); the limit is {limit / gb:.1f} GB ({source}): fewer "
                              "pixels, a lower supersample or fewer bands", key=key)
