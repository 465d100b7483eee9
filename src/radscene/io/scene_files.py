"""The files a scene names, carried inside its outputs, so that an output re-renders alone.

A rendered output records every file its scene names (the provenance attribute
``scene_files``: key, absolute path, size, SHA-256). :func:`embed` also stores their bytes in
the output — a NetCDF group ``scene_files`` (or a Zarr subgroup), one ``uint8`` variable per
file with its key, name and SHA-256 — when they are :data:`EMBED_LIMIT` bytes or fewer in
all. xarray opens the root group only, so a reader of the image never sees them.
``radscene render --from OUT.nc`` takes a file from there when it is gone from its recorded
place or its bytes changed there (:func:`extract`), so the output can be sent to a colleague
alone. The global attribute ``scene_files_embedded`` says which was done.
"""

from __future__ import annotations

import hashlib
import json
from pathlib import Path

import numpy as np

__all__ = ["EMBED_LIMIT", "GROUP", "embed", "embedded", "extract"]

#: The most bytes of named files an output carries; above it they are only recorded.
EMBED_LIMIT = 64 * 1024 * 1024
#: The group (NetCDF) or subgroup (Zarr) that holds them.
GROUP = "scene_files"


def _entries(attrs) -> list[dict]:
    try:
        return list(json.loads(attrs.get("scene_files", "[]")))
    except (TypeError, ValueError):
        return []


def _note(entries: list[dict], total: int) -> str:
    if not entries:
        return "none: the scene names no file"
    if total > EMBED_LIMIT:
        return (f"no: {total / 2**20:.1f} MiB of named files, above the "
                f"{EMBED_LIMIT / 2**20:.0f} MiB carried; recorded by path and SHA-256 only")
    return f"yes: {len(entries)} file(s), {total} bytes, in the group {GROUP!r}"


def embed(target, attrs, zarr: bool = False) -> None:
    """Store the files of ``attrs["scene_files"]`` in the written output ``target`` (a NetCDF
    file, or a Zarr store with ``zarr``), within :data:`EMBED_LIMIT`, and note what was done
    in its ``scene_files_embedded`` attribute. Outputs without provenance are left alone."""
    if "scene_files" not in attrs:
        return
    entries = _entries(attrs)
    present = [e for e in entries if Path(e["path"]).is_file()]
    total = sum(Path(e["path"]).stat().st_size for e in present)
    note = _note(present, total)
    carry = present if present and total <= EMBED_LIMIT else []
    if zarr:
        import zarr as zarr_module

        root = zarr_module.open_group(str(target), mode="a", zarr_format=2)
        root.attrs["scene_files_embedded"] = note
        if carry:
            group = root.require_group(GROUP)
            for i, entry in enumerate(carry):
                data = np.frombuffer(Path(entry["path"]).read_bytes(), dtype=np.uint8)
                array = group.create_array(f"file_{i}", shape=data.shape, dtype="u1",
                                           attributes=_attributes(entry))
                array[:] = data
        return
    import h5netcdf

    with h5netcdf.File(str(target), "a") as nc:
        nc.attrs["scene_files_embedded"] = note
        if carry:
            group = nc.create_group(GROUP)
            for i, entry in enumerate(carry):
                data = np.frombuffer(Path(entry["path"]).read_bytes(), dtype=np.uint8)
                group.dimensions[f"bytes_{i}"] = data.size
                var = group.create_variable(f"file_{i}", (f"bytes_{i}",), dtype="u1", data=data,
                                            compression="gzip", compression_opts=1)
                var.attrs.update(_attributes(entry))


def _attributes(entry: dict) -> dict:
    return {"key": entry["key"], "name": Path(entry["path"]).name, "path": entry["path"],
            "sha256": entry["sha256"]}


def embedded(path) -> dict[str, tuple[dict, bytes]]:
    """The files an output carries: scene key → (attributes, bytes); empty when none."""
    path = Path(path)
    out = {}
    if path.is_dir():
        import zarr as zarr_module

        root = zarr_module.open_group(str(path), mode="r", zarr_format=2)
        if GROUP not in root:
            return {}
        for _name, array in root[GROUP].arrays():
            attrs = dict(array.attrs)
            out[attrs["key"]] = (attrs, np.asarray(array[:], dtype=np.uint8).tobytes())
        return out
    import h5netcdf

    with h5netcdf.File(str(path), "r") as nc:
        if GROUP not in nc.groups:
            return {}
        for var in nc.groups[GROUP].variables.values():
            attrs = dict(var.attrs)
            out[str(attrs["key"])] = (attrs, np.asarray(var[:], dtype=np.uint8).tobytes())
    return out


def extract(path, keys, folder) -> dict[str, Path]:
    """Write the carried files of the scene ``keys`` from the output ``path`` into ``folder``
    (each in a subfolder named by its key, so that equal names do not collide), each checked
    against its SHA-256. Returns key → the written file; a key the output does not carry is
    left out."""
    held = embedded(path)
    out = {}
    for key in keys:
        if key not in held:
            continue
        attrs, data = held[key]
        if hashlib.sha256(data).hexdigest() != attrs["sha256"]:
            continue  # damaged: as if not carried
        target = Path(folder) / _safe(key) / str(attrs["name"])
        target.parent.mkdir(parents=True, exist_ok=True)
        target.write_bytes(data)
        out[key] = target.resolve()
    return out


def _safe(key: str) -> str:
    return "".join(c if c.isalnum() or c in "-_." else "_" for c in key)
