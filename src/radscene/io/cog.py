"""Cloud-Optimised GeoTIFFs of a map product's layers, for GIS.

A map product (a nadir orthographic render, whose ``x``/``y`` are easting/northing [m] in the
scene frame, with the ``crs`` grid mapping) is written one layer per file, in the scene
frame's CRS, by GDAL's COG driver (through rioxarray and rasterio): tiled 512 × 512, deflate
compression with the predictor that suits the data type, and overviews down to a tile's size
(averaged for continuous layers, nearest for IDs), so a GIS can pan and zoom a remote file by
HTTP range requests. Band descriptions are the band names; ``units``, ``long_name`` and the
Dataset's global attributes (its provenance included) go into the file's metadata, the units
also per band. Floating-point layers are float32 with NaN as nodata; ``object_id`` and
``material_id`` are int32 with nodata −1.

Which layers are written is chosen by a level (:data:`LEVELS`):

=============  ==================================================================================
level          layers
=============  ==================================================================================
``none``       —
``radiance``   ``radiance`` (all bands) and ``brightness_temperature`` (the thermal bands)
``maps``       those and the truth maps: ``surface_temperature``, ``object_id``, ``material_id``,
               ``range``, ``shadow_fraction``, ``sky_view_fraction``, ``cos_incidence``
``all``        those, every per-term radiance layer (``sun_diffuse``, ...) and
               ``path_transmittance``
=============  ==================================================================================
"""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np
import xarray as xr

from radscene.errors import ConfigError, did_you_mean
from radscene.io.geotiff import _atomic, _crs, _prepare, _regular
from radscene.render.outputs import PART_NAMES
from radscene.render.outputs import TERM_LAYERS as _RADIANCE_LAYERS

__all__ = ["write_cog", "write_map_cogs", "map_layers", "layer_names", "is_map_product", "LEVELS",
           "TRUTH_LAYERS", "TERM_LAYERS"]

#: The levels of :func:`map_layers`, fewest layers first.
LEVELS = ("none", "radiance", "maps", "all")
#: The single-layer truth maps of level ``maps``.
TRUTH_LAYERS = ("surface_temperature", "object_id", "material_id", "range", "shadow_fraction",
                "sky_view_fraction", "cos_incidence")
#: The band layers level ``all`` adds, where a render has them: every layer that sums to the
#: radiance (:data:`radscene.render.outputs.TERM_LAYERS`), the parts of the reflected sky and
#: background (:data:`radscene.render.outputs.PART_NAMES`) and the transmittances.
TERM_LAYERS = _RADIANCE_LAYERS + PART_NAMES + ("path_transmittance", "volume_transmittance")


def layer_names(level: str) -> tuple[str, ...]:
    """Every layer name a level may write (those a render lacks are skipped)."""
    if level not in LEVELS:
        raise ConfigError(f"unknown GeoTIFF level {level!r}; known: {', '.join(LEVELS)}"
                          f"{did_you_mean(level, LEVELS)}",
                          key="--geotiff")
    rank = LEVELS.index(level)
    return (("radiance", "brightness_temperature") * (rank >= 1) + TRUTH_LAYERS * (rank >= 2)
            + TERM_LAYERS * (rank >= 3))


def is_map_product(ds: xr.Dataset) -> bool:
    """Whether ``ds`` is a map product: ``x``/``y`` in metres of a map grid."""
    return "x" in ds.coords and ds["x"].attrs.get("units") == "m"


def _thermal(ds: xr.Dataset) -> xr.DataArray:
    from radscene.render.integrator import THERMAL_BAND_START

    return ds["wavelength_center"] >= THERMAL_BAND_START


def map_layers(ds: xr.Dataset, level: str = "maps") -> dict[str, xr.DataArray]:
    """The layers of ``ds`` a level writes, by file stem.

    Parameters
    ----------
    ds : xarray.Dataset
        A render (:func:`radscene.render`).
    level : str
        One of :data:`LEVELS`.

    Returns
    -------
    dict of str to xarray.DataArray
        ``(band, y, x)`` or ``(y, x)`` layers; ``brightness_temperature`` only with its thermal
        bands (absent without any).
    """
    layers = {}
    for name in layer_names(level):
        if name not in ds:
            continue
        if name == "brightness_temperature":
            if bool(_thermal(ds).any()):
                layers[name] = ds[name].sel(band=_thermal(ds))
        else:
            layers[name] = ds[name]
    return layers


def _scalar_attrs(attrs: dict) -> dict:
    """Attributes as TIFF metadata: text and numbers only."""
    out = {}
    for key, value in attrs.items():
        if isinstance(value, str | int | float | np.integer | np.floating):
            out[key] = str(value)
    return out


def write_cog(data: xr.DataArray, path: str | os.PathLike, crs=None, *, nodata=None,
              attrs: dict | None = None, x: str = "x", y: str = "y",
              compress: str = "deflate") -> Path:
    """Write a map layer to a Cloud-Optimised GeoTIFF.

    Parameters
    ----------
    data : xarray.DataArray
        ``(y, x)`` or ``(band, y, x)`` on equally spaced ``x``/``y`` [units of the CRS].
    path : path-like
        Destination; its folder is created; written atomically.
    crs : LocalFrame, pyproj.CRS, EPSG code or PROJ string, optional
        The CRS of ``x``/``y``; default the one ``data`` carries (its ``crs`` grid mapping).
    nodata : float or int, optional
        Default NaN for floating-point data, −1 for integers.
    attrs : dict, optional
        More metadata for the file (e.g. the Dataset's global attributes).
    x, y : str
        Names of the coordinate dimensions.
    compress : str
        Compression of the tiles.

    Returns
    -------
    pathlib.Path
    """
    import rioxarray  # noqa: F401  (the .rio accessor)

    da, extra = _prepare(data, x, y)
    _regular(da[x].values, x)
    _regular(da[y].values, y)
    integer = da.dtype.kind in "iub"
    target = _crs(crs) if crs is not None else da.rio.crs
    if target is None:
        raise ConfigError("the layer carries no CRS (no grid mapping); give crs", key="crs")
    da = da.astype("int32") if integer else da.astype("float32")
    if nodata is None:
        nodata = -1 if integer else np.nan
    da = da.rio.set_spatial_dims(x_dim=x, y_dim=y).rio.write_crs(target)
    da = da.rio.write_nodata(nodata, encoded=False)
    if extra:  # band descriptions: the band names
        da = da.assign_attrs(long_name=tuple(str(v) for v in da[extra[0]].values))
    else:  # a single layer: the variable's name
        da = da.assign_attrs(long_name=str(data.name or data.attrs.get("long_name", "")))
    tags = _scalar_attrs(attrs or {})
    tags.update({k: str(v) for k, v in data.attrs.items()
                 if k in ("units", "long_name", "standard_name", "flag_meanings")
                 and isinstance(v, str)})
    if extra:
        tags["band_names"] = ",".join(str(v) for v in data[extra[0]].values)
    if "units" in data.attrs:
        tags["band_tags"] = [{"units": str(data.attrs["units"])}] * (
            da.sizes[extra[0]] if extra else 1)
    options = {"driver": "COG", "compress": compress, "predictor": "YES", "blocksize": 512,
               "overviews": "AUTO", "overview_resampling": "nearest" if integer else "average",
               "bigtiff": "IF_SAFER", "tags": tags}
    return _atomic(path, lambda tmp: da.rio.to_raster(tmp, **options))


def write_map_cogs(ds: xr.Dataset, prefix: str | os.PathLike, level: str = "maps",
                   crs=None) -> list[Path]:
    """Write the layers of ``level`` (:func:`map_layers`) of a map product as COGs.

    Parameters
    ----------
    ds : xarray.Dataset
        A map product (:func:`is_map_product`).
    prefix : path-like
        Each layer goes to ``{prefix}_{layer}.tif``, e.g. ``out/map`` →
        ``out/map_radiance.tif``, ``out/map_surface_temperature.tif``.
    level : str
        One of :data:`LEVELS`.
    crs : CRS-like, optional
        The CRS of the product's x/y; default its own grid mapping.

    Returns
    -------
    list of pathlib.Path
        The files written, in the order of :func:`map_layers`.
    """
    if not is_map_product(ds):
        raise ConfigError("not a map product (x/y are not map coordinates in metres): only "
                          "a nadir orthographic observer's render has a map grid", key="ds")
    prefix = Path(prefix)
    return [write_cog(layer, prefix.with_name(f"{prefix.name}_{name}.tif"), crs,
                      attrs=ds.attrs)
            for name, layer in map_layers(ds, level).items()]
