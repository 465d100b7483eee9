"""NetCDF output, written atomically: a temporary file in the target folder, then a rename."""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np
import xarray as xr

from radscene.io import scene_files
from radscene.io.cf import with_cf_coordinates, with_grid_mapping_coordinates
from radscene.io.files import atomic_output

__all__ = ["write_netcdf", "read_netcdf", "with_cf_coordinates", "with_grid_mapping_coordinates"]


def _encoding(ds: xr.Dataset, compress: bool) -> dict:
    enc = {}
    for name, var in ds.data_vars.items():
        e = {k: var.encoding[k] for k in ("grid_mapping",) if k in var.encoding}
        if var.encoding.get("radscene_packed"):  # packed (CF) by its writer, as it asks
            e.update({k: var.encoding[k] for k in ("dtype", "scale_factor", "add_offset",
                                                    "_FillValue", "chunksizes")
                      if k in var.encoding})
        elif var.dtype.kind == "f" and var.ndim >= 2:
            e["dtype"] = "float32"
        if compress and var.ndim >= 2:
            e.update({"compression": "gzip", "compression_opts": 1, "shuffle": True})
        if e:
            enc[name] = e
    return enc


def write_netcdf(ds: xr.Dataset, path: str | os.PathLike, compress: bool = True) -> Path:
    """Write a Dataset to NetCDF-4 (h5netcdf) without ever leaving a half-written file.

    Floating-point image layers are stored as float32 (seven significant digits) and
    gzip-compressed; scalars and coordinates keep their precision.

    Parameters
    ----------
    ds : xarray.Dataset
    path : path-like
        Destination; its folder is created when missing.
    compress : bool
        Compress the image layers.

    Returns
    -------
    pathlib.Path
        The written file.
    """
    path = Path(path)
    ds = with_cf_coordinates(ds)
    with atomic_output(path) as tmp:
        ds.to_netcdf(tmp, engine="h5netcdf", encoding=_encoding(ds, compress))
        scene_files.embed(tmp, ds.attrs)
    return path


def read_netcdf(path: str | os.PathLike) -> xr.Dataset:
    """Open a radscene NetCDF file (loaded into memory, file closed)."""
    with xr.open_dataset(path, engine="h5netcdf") as ds:
        out = ds.load()
    for name in ("object_id", "material_id"):
        if name in out and out[name].dtype.kind == "f":
            out[name] = out[name].fillna(-1).astype(np.int32)
    return out
