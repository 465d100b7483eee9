"""Spectral cubes written as they are rendered: NetCDF-4 or Zarr, and ENVI, a pass of channels
at a time.

The passes of :func:`radscene.render.hyperspectral.render_passes` go to disk one by one, so a
cube never has to fit in memory: the variable ``radiance(wavelength, y, x)`` of the NetCDF file
(or of the Zarr store, the format of :func:`radscene.io.write_zarr`) — and, for passes rendered
with ``terms``, each term layer ``<term>(wavelength, y, x)`` beside it — is created at its full
size (float32, one chunk per channel) and filled pass by pass, and the ENVI image (radiance
only) is band-sequential (BSQ), so each pass is appended to it. Every file (or store) is written beside its destination
under a temporary name and moved into place only when complete.
"""

from __future__ import annotations

import contextlib
import os
from collections.abc import Iterable, Sequence
from pathlib import Path

import numpy as np
import xarray as xr

from radscene.errors import ConfigError
from radscene.io.cf import with_cf_coordinates
from radscene.io.envi import header_text, map_fields, pixel_size
from radscene.io.files import atomic_output
from radscene.io.netcdf import _encoding

__all__ = ["write_spectral", "envi_header"]


def envi_header(ds_attrs: dict, shape: tuple[int, int, int], wavelength, fwhm,
                description: str = "", georeference: Sequence[str] = ()) -> str:
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
    georeference : sequence of str
        ``map info`` and ``coordinate system string`` of a map product
        (:func:`radscene.io.envi.map_fields`).

    Returns
    -------
    str
    """
    text = (f"radscene spectral radiance [W m-2 sr-1 um-1] of scene {ds_attrs.get('scene', '')!r}, "
            f"observer {ds_attrs.get('observer', '')!r}. {description}").strip()
    return header_text(shape, wavelength, fwhm, [f"{float(v):.6f} um" for v in wavelength],
                       text, "W m-2 sr-1 um-1", ds_attrs, georeference)


def write_spectral(passes: Iterable[xr.Dataset], path: str | os.PathLike, grid, *,
                   envi: str | os.PathLike | None = None, compress: bool = True,
                   terms: bool | None = None) -> list[Path]:
    """Write the passes of a spectral render to NetCDF-4 or Zarr (and ENVI) as they come.

    Parameters
    ----------
    passes : iterable of xarray.Dataset
        In grid order, each ``radiance(wavelength, y, x)`` [W m-2 sr-1 um-1] of some channels
        with ``wavelength`` and ``fwhm`` [um] and the band-free maps (taken from the first);
        rendered with ``terms``, also each term layer ``<term>(wavelength, y, x)``.
    path : path-like
        The NetCDF file; a name ending in ``.zarr`` writes a Zarr store instead (format 2,
        consolidated, as :func:`radscene.io.write_zarr`; needs the package zarr).
    grid : radscene.radiometry.ChannelGrid
        The render's grid: every channel's centre ``wavelength`` and ``width`` (its FWHM) [um].
    envi : path-like, optional
        The ENVI image (``.img``); its header goes beside it with the suffix ``.hdr``.
    compress : bool
        Compress the cube: gzip (level 1, shuffled) in NetCDF, zstd in Zarr.
    terms : bool, optional
        Write the passes' term layers, each a float32 variable chunked as ``radiance``
        (:func:`radscene.render.hyperspectral.spectral_variables`): by default those the
        passes carry; False for the radiance alone; True requires them. The ENVI image holds
        the radiance alone either way.

    Returns
    -------
    list of pathlib.Path
        The files written (the NetCDF file or Zarr store, then the ENVI image and header).

    Raises
    ------
    ConfigError
        The passes do not fill the grid exactly, or lack the term layers ``terms=True``
        asks for, or a pass's variables differ from the first's.
    """
    from radscene.render.hyperspectral import spectral_variables

    wavelength = np.asarray(grid.wavelength, dtype=float)
    fwhm = np.asarray(grid.width, dtype=float)
    n = wavelength.size
    path = Path(path)
    if path.suffix.lower() == ".zarr":
        from radscene.io.zarr_store import cube_store as cube_output
    else:
        cube_output = _netcdf_cube
    written = [path]
    with contextlib.ExitStack() as stack:
        start_cube = stack.enter_context(cube_output(path, wavelength, fwhm, compress))
        img_tmp = hdr_tmp = None
        if envi is not None:
            envi = Path(envi)
            img_tmp = stack.enter_context(atomic_output(envi))
            hdr_tmp = stack.enter_context(atomic_output(envi.with_suffix(".hdr")))
            written += [envi, envi.with_suffix(".hdr")]
        done, out, img, attrs, shape, georeference = 0, None, None, None, None, []
        for part in passes:
            cube = part["radiance"]
            if out is None:
                names = _variables(spectral_variables(part), terms)
                attrs, shape = {**part.attrs, "spectral_mode": "hyperspectral"}, cube.shape[1:]
                maps = part.drop_vars(spectral_variables(part) + ["wavelength", "fwhm"])
                maps.attrs = attrs
                if hdr_tmp is not None:
                    georeference = map_fields(cube, pixel_size(attrs))
                out = start_cube(maps, {name: part[name] for name in names})
                if img_tmp is not None:
                    img = stack.enter_context(open(img_tmp, "wb"))
            k = cube.shape[0]
            if done + k > n or not np.allclose(part["wavelength"].values,
                                               wavelength[done:done + k], rtol=0, atol=1e-12):
                raise ConfigError(f"pass of channels {done}-{done + k - 1} does not match "
                                  "the grid", key="passes")
            if missing := [name for name in out if name not in part.data_vars]:
                raise ConfigError(f"pass of channels {done}-{done + k - 1} lacks "
                                  f"{', '.join(missing)}, which the first pass has",
                                  key="passes")
            for name, var in out.items():
                values = np.asarray(part[name].values, dtype=np.float32)
                var[done:done + k] = values
                if img is not None and name == "radiance":
                    img.write(values.astype("<f4", copy=False).tobytes(order="C"))
                del values
            done += k
        if done != n:
            raise ConfigError(f"the passes hold {done} of the grid's {n} channels",
                              key="passes")
        if img is not None:
            img.close()
        if hdr_tmp is not None:
            Path(hdr_tmp).write_text(envi_header(attrs, (n,) + tuple(shape), wavelength, fwhm,
                                                 georeference=georeference))
    return written


def _variables(names: list[str], terms: bool | None) -> list[str]:
    """Of the first pass's spectral variables ``names`` (``radiance`` first), those to write."""
    if terms is None:
        return names
    if isinstance(terms, bool | np.bool_) and not terms:
        return ["radiance"]
    if not isinstance(terms, bool | np.bool_):
        raise ConfigError(f"must be true, false or None; got {terms!r}", key="terms")
    if len(names) == 1:
        raise ConfigError("the passes carry no term layers: render them with terms=True "
                          "(observers[i].spectral.terms)", key="terms")
    return names


def grid_mapping(maps: xr.Dataset) -> str | None:
    """The grid-mapping variable of the maps of a map product (``crs``), else None."""
    return next((v.encoding["grid_mapping"] for v in maps.data_vars.values()
                 if "grid_mapping" in v.encoding), None)


def cube_coordinates(maps: xr.Dataset, cube: xr.DataArray) -> str:
    """A cube variable's ``coordinates``: ``fwhm``, the maps' auxiliary coordinates over its
    pixels (``latitude``, ``longitude``, ``height``) and the grid mapping of a map product."""
    pixels = set(cube.dims[1:])
    names = [str(n) for n, c in maps.coords.items()
             if n not in maps.dims and c.dims and set(c.dims) <= pixels]
    mapping = grid_mapping(maps)
    return " ".join(["fwhm", *names, *([mapping] if mapping else [])])


@contextlib.contextmanager
def _netcdf_cube(path: Path, wavelength, fwhm, compress: bool):
    """Yield ``start(maps, cubes)``, which writes the maps into a temporary NetCDF file beside
    ``path`` and returns the empty cube variables to fill, by name (those of ``cubes``, the
    first pass's spectral variables, ``radiance`` first); on success the file takes
    ``path``'s place."""
    import h5netcdf

    nc = None

    def start(maps: xr.Dataset, cubes: dict[str, xr.DataArray]):
        nonlocal nc
        maps = with_cf_coordinates(maps)
        maps.to_netcdf(tmp, engine="h5netcdf", encoding=_encoding(maps, compress))
        nc = h5netcdf.File(tmp, "a")
        _wavelength_axis(nc, cubes["radiance"], wavelength, fwhm)
        return {name: _cube_variable(nc, name, cube, compress, grid_mapping(maps),
                                     cube_coordinates(maps, cube))
                for name, cube in cubes.items()}

    with atomic_output(path) as tmp:
        try:
            yield start
        finally:
            if nc is not None:
                nc.close()


def _wavelength_axis(nc, cube: xr.DataArray, wavelength, fwhm) -> None:
    """Create the wavelength axis and its coordinates in ``nc``."""
    nc.dimensions["wavelength"] = wavelength.size
    for name, values, source in (("wavelength", wavelength, cube["wavelength"]),
                                 ("fwhm", fwhm, cube["fwhm"])):
        v = nc.create_variable(name, ("wavelength",), dtype="f8", data=values)
        v.attrs.update(source.attrs)


def _cube_variable(nc, name: str, cube: xr.DataArray, compress: bool, mapping: str | None,
                   coordinates: str):
    """Create the empty float32 cube variable ``name`` in ``nc``, one chunk per channel."""
    options = {"compression": "gzip", "compression_opts": 1, "shuffle": True} if compress else {}
    var = nc.create_variable(name, ("wavelength",) + tuple(cube.dims[1:]), dtype="f4",
                             chunks=(1,) + tuple(cube.shape[1:]), **options)
    var.attrs.update({**cube.attrs, "coordinates": coordinates})
    if mapping is not None:
        var.attrs["grid_mapping"] = mapping
    return var
