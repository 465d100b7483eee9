"""Zarr output, written atomically: a temporary store beside the destination, then a rename.

A store holds what the NetCDF file holds — the same variables, coordinates (``latitude`` and
``longitude`` auxiliary, the ``crs`` grid mapping of a map product), attributes (provenance
included) and float32 image layers — in the Zarr format 2 with consolidated metadata, the
version every Zarr reader knows (zarr-python 2 and 3, xarray, GDAL, the JavaScript and Julia
readers); the format 3 has no specified type yet for the fixed-length strings of the ``band``
coordinate, nor for consolidated metadata. Image layers are chunked one band at a time in
tiles of up to :data:`TILE` × :data:`TILE` pixels, compressed with zstd.

Needs the optional dependency ``zarr`` (``pip install zarr``).
"""

from __future__ import annotations

import contextlib
import os
from pathlib import Path

import numpy as np
import xarray as xr

from radscene.errors import ConfigError
from radscene.io import scene_files
from radscene.io.cf import with_cf_coordinates
from radscene.io.files import atomic_output_dir

__all__ = ["write_zarr", "read_zarr", "cube_store", "TILE"]

#: Largest chunk of an image layer along y and x [px].
TILE = 1024


def _zarr():
    try:
        import zarr
    except ImportError:
        raise ConfigError("writing Zarr needs the package zarr: pip install zarr",
                          key="--output") from None
    return zarr


def _codec():
    from numcodecs import Blosc

    return Blosc(cname="zstd", clevel=3, shuffle=Blosc.SHUFFLE)


def _encoding(ds: xr.Dataset, compress: bool) -> dict:
    codec = _codec()
    enc = {}
    for name, var in ds.data_vars.items():
        e = {k: var.encoding[k] for k in ("grid_mapping",) if k in var.encoding}
        if var.dtype.kind == "f" and var.ndim >= 2:
            e["dtype"] = "float32"
        if var.ndim >= 2:
            e["chunks"] = tuple(min(size, TILE) if dim in ("y", "x") else 1
                                for dim, size in var.sizes.items())
            e["compressors"] = (codec,) if compress else ()
        if e:
            enc[name] = e
    return enc


def write_zarr(ds: xr.Dataset, path: str | os.PathLike, compress: bool = True) -> Path:
    """Write a Dataset to a Zarr store (format 2, consolidated) without ever leaving half a store.

    As :func:`radscene.io.write_netcdf`: floating-point image layers are stored as float32,
    scalars and coordinates keep their precision, and the attributes go along unchanged.

    Parameters
    ----------
    ds : xarray.Dataset
    path : path-like
        The store, a folder (by convention named ``*.zarr``); its parent is created when
        missing, and an earlier store there is replaced.
    compress : bool
        Compress the image layers (zstd).

    Returns
    -------
    pathlib.Path
        The written store.

    Examples
    --------
    >>> ds = radscene.render(scene, "map")                         # doctest: +SKIP
    >>> radscene.write_zarr(ds, "out/map.zarr")                     # doctest: +SKIP
    >>> xr.open_zarr("out/map.zarr").rio.crs                        # doctest: +SKIP
    """
    zarr = _zarr()
    path = Path(path)
    ds = with_cf_coordinates(ds)
    with atomic_output_dir(path) as tmp:
        ds.to_zarr(tmp, mode="w", zarr_format=2, consolidated=False,
                   encoding=_encoding(ds, compress))
        scene_files.embed(tmp, ds.attrs, zarr=True)
        zarr.consolidate_metadata(tmp, zarr_format=2)
    return path


@contextlib.contextmanager
def cube_store(path: str | os.PathLike, wavelength, fwhm, compress: bool = True):
    """A spectral cube's Zarr store, filled a pass of channels at a time (for
    :func:`radscene.io.write_spectral`).

    Yields ``start(maps, cubes)``: given the band-free maps (a Dataset, with the attributes of
    the store) and the first pass's spectral variables ``cubes`` by name (``radiance(wavelength,
    y, x)`` with ``wavelength`` and ``fwhm`` first, then any term layers), it writes the maps,
    the ``wavelength`` axis and its ``fwhm`` [um] into a temporary store beside ``path`` and
    returns, by name, the empty float32 array of every channel of each (chunks of one channel,
    NaN until written) for the passes to fill by slices.
    When the block ends without error the metadata is consolidated and the store takes
    ``path``'s place; otherwise the temporary store is removed.

    Parameters
    ----------
    path : path-like
        The store (``*.zarr``).
    wavelength, fwhm : array_like
        Every channel's centre and full width at half maximum [um].
    compress : bool
        Compress the cube and the maps (zstd).
    """
    from radscene.io.spectral import cube_coordinates, grid_mapping

    zarr = _zarr()
    wavelength = np.asarray(wavelength, dtype=float)
    fwhm = np.asarray(fwhm, dtype=float)

    def start(maps: xr.Dataset, cubes: dict[str, xr.DataArray]):
        maps = with_cf_coordinates(maps)
        maps.to_zarr(tmp, mode="w", zarr_format=2, consolidated=False,
                     encoding=_encoding(maps, compress))
        group = zarr.open_group(tmp, mode="a", zarr_format=2)
        for name, values in (("wavelength", wavelength), ("fwhm", fwhm)):
            axis = group.create_array(name, shape=values.shape, dtype="f8", fill_value=None,
                                      attributes={**cubes["radiance"][name].attrs,
                                                  "_ARRAY_DIMENSIONS": ["wavelength"]})
            axis[:] = values
        mapping = grid_mapping(maps)
        arrays = {}
        for name, cube in cubes.items():
            dims = ("wavelength",) + tuple(cube.dims[1:])
            attrs = {**cube.attrs, "coordinates": cube_coordinates(maps, cube),
                     "_ARRAY_DIMENSIONS": list(dims)}
            if mapping is not None:
                attrs["grid_mapping"] = mapping
            shape = (wavelength.size,) + tuple(cube.shape[1:])
            chunks = (1,) + tuple(min(size, TILE) for size in cube.shape[1:])
            arrays[name] = group.create_array(name, shape=shape, chunks=chunks, dtype="f4",
                                              fill_value=np.nan, attributes=attrs,
                                              compressors=(_codec(),) if compress else None)
        return arrays

    with atomic_output_dir(path) as tmp:
        yield start
        zarr.consolidate_metadata(tmp, zarr_format=2)


def read_zarr(path: str | os.PathLike) -> xr.Dataset:
    """Open a radscene Zarr store (loaded into memory) as :func:`radscene.io.read_netcdf` opens
    a NetCDF file: auxiliary coordinates decoded, the ``crs`` grid mapping among them, IDs as
    int32 with −1 for none."""
    _zarr()
    path = Path(path)
    if not path.is_dir():
        raise ConfigError(f"no such Zarr store: {path}", key="path")
    with xr.open_zarr(path) as ds:
        out = ds.load()
    for name in ("object_id", "material_id"):
        if name in out and out[name].dtype.kind == "f":
            out[name] = out[name].fillna(-1).astype(np.int32)
    return out
