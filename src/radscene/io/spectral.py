"""Spectral cubes written as they are rendered: NetCDF-4 and ENVI, a pass of channels at a time.

The passes of :func:`radscene.render.hyperspectral.render_passes` go to disk one by one, so a
cube never has to fit in memory: the NetCDF variable ``radiance(wavelength, y, x)`` is
created at its full size (float32, one chunk per channel) and filled pass by pass, and the
ENVI image is band-sequential (BSQ), so each pass is appended to it. Both files are written
beside their destination under temporary names and moved into place only when complete.
"""

from __future__ import annotations

import contextlib
import os
from collections.abc import Iterable
from pathlib import Path

import numpy as np
import xarray as xr

from radscene.errors import ConfigError
from radscene.io.envi import header_text
from radscene.io.files import atomic_output
from radscene.io.netcdf import _encoding

__all__ = ["write_spectral", "envi_header"]


def envi_header(ds_attrs: dict, shape: tuple[int, int, int], wavelength, fwhm,
                description: str = "") -> str:
    """The text of an ENVI header for a BSQ float32 little-endian cube.

    Parameters
    ----------
    ds_attrs : dict
        Attributes of the cube's Dataset (scene and observer named in the description; each
        written as a field, :func:`radscene.io.envi.attribute_fields`).
    shape : (bands, lines, samples)
        Channels, rows, columns.
    wavelength, fwhm : array_like
        Channel centres and full widths at half maximum [um].
    description : str
        Appended to the description.

    Returns
    -------
    str
    """
    text = (f"radscene spectral radiance [W m-2 sr-1 um-1] of scene {ds_attrs.get('scene', '')!r}, "
            f"observer {ds_attrs.get('observer', '')!r}. {description}").strip()
    return header_text(shape, wavelength, fwhm, [f"{float(v):.6f} um" for v in wavelength],
                       text, "W m-2 sr-1 um-1", ds_attrs)


def write_spectral(passes: Iterable[xr.Dataset], path: str | os.PathLike, grid, *,
                   envi: str | os.PathLike | None = None, compress: bool = True) -> list[Path]:
    """Write the passes of a spectral render to NetCDF-4 (and ENVI) as they come.

    Parameters
    ----------
    passes : iterable of xarray.Dataset
        In grid order, each ``radiance(wavelength, y, x)`` [W m-2 sr-1 um-1] of some channels
        with ``wavelength`` and ``fwhm`` [um] and the band-free maps (taken from the first).
    path : path-like
        The NetCDF file.
    grid : radscene.radiometry.ChannelGrid
        The render's grid: every channel's centre ``wavelength`` and ``width`` (its FWHM) [um].
    envi : path-like, optional
        The ENVI image (``.img``); its header goes beside it with the suffix ``.hdr``.
    compress : bool
        gzip the NetCDF cube (level 1, shuffled).

    Returns
    -------
    list of pathlib.Path
        The files written (NetCDF, then the ENVI image and header).

    Raises
    ------
    ConfigError
        The passes do not fill the grid exactly.
    """
    import h5netcdf

    wavelength = np.asarray(grid.wavelength, dtype=float)
    fwhm = np.asarray(grid.width, dtype=float)
    n = wavelength.size
    path = Path(path)
    written = [path]
    with contextlib.ExitStack() as stack:
        nc_tmp = stack.enter_context(atomic_output(path))
        img_tmp = hdr_tmp = None
        if envi is not None:
            envi = Path(envi)
            img_tmp = stack.enter_context(atomic_output(envi))
            hdr_tmp = stack.enter_context(atomic_output(envi.with_suffix(".hdr")))
            written += [envi, envi.with_suffix(".hdr")]
        done, nc, img, attrs, shape = 0, None, None, None, None
        try:
            for part in passes:
                cube = part["radiance"]
                if nc is None:
                    attrs, shape = {**part.attrs, "spectral_mode": "hyperspectral"}, cube.shape[1:]
                    maps = part.drop_vars(["radiance", "wavelength", "fwhm"])
                    maps.attrs = attrs
                    maps.to_netcdf(nc_tmp, engine="h5netcdf",
                                   encoding=_encoding(maps, compress))
                    nc = h5netcdf.File(nc_tmp, "a")
                    var = _cube_variable(nc, cube, wavelength, fwhm, compress)
                    if img_tmp is not None:
                        img = open(img_tmp, "wb")  # noqa: SIM115 - closed below
                k = cube.shape[0]
                if done + k > n or not np.allclose(part["wavelength"].values,
                                                   wavelength[done:done + k], rtol=0, atol=1e-12):
                    raise ConfigError(f"pass of channels {done}-{done + k - 1} does not match "
                                      "the grid", key="passes")
                values = np.asarray(cube.values, dtype=np.float32)
                var[done:done + k] = values
                if img is not None:
                    img.write(values.astype("<f4", copy=False).tobytes(order="C"))
                done += k
            if done != n:
                raise ConfigError(f"the passes hold {done} of the grid's {n} channels",
                                  key="passes")
        finally:
            if nc is not None:
                nc.close()
            if img is not None:
                img.close()
        if hdr_tmp is not None:
            Path(hdr_tmp).write_text(envi_header(attrs, (n,) + tuple(shape), wavelength, fwhm))
    return written


def _cube_variable(nc, cube: xr.DataArray, wavelength, fwhm, compress: bool):
    """Create the wavelength axis, its coordinates and the empty float32 cube in ``nc``."""
    nc.dimensions["wavelength"] = wavelength.size
    for name, values, source in (("wavelength", wavelength, cube["wavelength"]),
                                 ("fwhm", fwhm, cube["fwhm"])):
        v = nc.create_variable(name, ("wavelength",), dtype="f8", data=values)
        v.attrs.update(source.attrs)
    options = {"compression": "gzip", "compression_opts": 1, "shuffle": True} if compress else {}
    var = nc.create_variable("radiance", ("wavelength",) + tuple(cube.dims[1:]), dtype="f4",
                             chunks=(1,) + tuple(cube.shape[1:]), **options)
    var.attrs.update({**cube.attrs, "coordinates": "fwhm"})
    return var
