"""GeoTIFF of georeferenced products, in the scene's local map projection or any other.

Two kinds of products:

* **Map products** on a regular ``(y, x)`` grid of the scene frame (a nadir orthographic
  render, whose ``x``/``y`` coordinates are easting/northing in metres): the frame's CRS is the
  ellipsoidal orthographic projection centred at the scene origin
  (:meth:`radscene.platform.geolocation.LocalFrame.crs`), whose easting/northing are the
  frame's x/y. :func:`write_geotiff` writes them in that CRS or reprojects them (rioxarray /
  GDAL warp) to any map projection, e.g. ``dst_crs="utm"`` (the UTM zone of the product).
* **Image-geometry products** (a perspective frame, a pushbroom or whiskbroom image) with the
  per-pixel latitude and longitude of :func:`radscene.platform.geolocation.geolocation_truth`:
  :func:`write_geotiff_gcps` writes them with a grid of ground control points (EPSG:4326),
  and reprojects them through those points to a map projection when ``dst_crs`` is given.

Files are written atomically (a temporary file in the target folder, then a rename);
variables keep their ``units`` and ``long_name`` as GDAL metadata, bands their names as
descriptions.

Example::

    ds = radscene.render(scene, "map")
    write_geotiff(ds["radiance"], "map.tif", crs=LocalFrame(lat, lon, alt))
    write_geotiff(ds["radiance"], "map_utm.tif", crs=frame, dst_crs="utm", resolution=30.0)
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from radscene.errors import ConfigError, did_you_mean
from radscene.io.files import atomic_output

__all__ = ["write_geotiff", "write_geotiff_gcps", "read_geotiff", "RESAMPLING"]

#: Resampling methods accepted for reprojection (names of rasterio.enums.Resampling).
RESAMPLING = ("nearest", "bilinear", "cubic", "average", "lanczos")


def _crs(crs, key="crs"):
    from pyproj import CRS
    from pyproj.exceptions import CRSError

    if hasattr(crs, "crs") and callable(crs.crs):  # a LocalFrame
        return crs.crs()
    try:
        return CRS.from_user_input(crs)
    except CRSError as exc:
        raise ConfigError(f"not a coordinate reference system: {exc}", key=key) from None


def _resampling(name):
    from rasterio.enums import Resampling

    if name not in RESAMPLING:
        raise ConfigError(f"unknown resampling {name!r}; known: {', '.join(RESAMPLING)}"
                          f"{did_you_mean(name, RESAMPLING)}",
                          key="resampling")
    return getattr(Resampling, name)


def _prepare(data, x, y):
    import rioxarray  # noqa: F401  (registers the .rio accessor)
    import xarray as xr

    if not isinstance(data, xr.DataArray):
        raise ConfigError(f"must be an xarray.DataArray; got {type(data).__name__} (pick a "
                          "variable of a Dataset)", key="data")
    if y not in data.dims or x not in data.dims:
        raise ConfigError(f"must have the dimensions {y!r} and {x!r}; got {data.dims}",
                          key="data")
    extra = [d for d in data.dims if d not in (x, y)]
    if len(extra) > 1:
        raise ConfigError(f"at most one dimension besides {y!r} and {x!r} (the bands); got "
                          f"{extra}", key="data")
    da = data.transpose(*extra, y, x)
    if extra:
        names = [str(v) for v in da[extra[0]].values]
        da = da.assign_attrs(long_name=tuple(names)) if len(names) > 1 else da
    return da, extra


def _atomic(path, write):
    path = Path(path)
    with atomic_output(path, suffix=".tif") as tmp:
        write(tmp)
    return path


def _regular(values, key):
    v = np.asarray(values, dtype=float)
    if v.size >= 2:
        step = np.diff(v)
        if not np.allclose(step, step[0], rtol=1e-9, atol=0.0) or step[0] == 0:
            raise ConfigError("coordinates must be equally spaced (a map grid); for image "
                              "geometry use write_geotiff_gcps", key=key)


def _tags(data, extra):
    tags = {k: str(v) for k, v in data.attrs.items()
            if k in ("units", "long_name", "standard_name") and not isinstance(v, tuple)}
    if extra:
        tags["band_names"] = ",".join(str(v) for v in data[extra[0]].values)
    return tags


def write_geotiff(data, path, crs, *, x: str = "x", y: str = "y", dst_crs=None,
                  resolution=None, resampling: str = "bilinear", nodata=np.nan,
                  compress: str = "deflate") -> Path:
    """Write a map product (regular x/y grid) to a GeoTIFF, optionally reprojected.

    Parameters
    ----------
    data : xarray.DataArray
        ``(y, x)`` or ``(band, y, x)`` (any name for the band dimension), with equally spaced
        ``x``/``y`` coordinates at the pixel centres in the units of ``crs`` [m].
    path : str or path-like
        Destination; its folder is created.
    crs : LocalFrame, pyproj.CRS, EPSG code or PROJ string
        The CRS of ``x``/``y``; a :class:`~radscene.platform.geolocation.LocalFrame` stands
        for its own CRS (the scene frame's x/y).
    x, y : str
        Names of the coordinate dimensions.
    dst_crs : CRS-like or "utm", optional
        Reproject to this CRS first; ``"utm"`` picks the UTM zone of the product's centre.
    resolution : float or (float, float), optional
        Pixel size of the reprojected grid [units of dst_crs]; default GDAL's choice.
    resampling : str
        One of :data:`RESAMPLING`.
    nodata : float
        Value of pixels without data.
    compress : str
        GeoTIFF compression.

    Returns
    -------
    pathlib.Path
    """
    da, extra = _prepare(data, x, y)
    _regular(da[x].values, x)
    _regular(da[y].values, y)
    da = da.astype("float32") if da.dtype.kind == "f" else da
    da = da.rio.set_spatial_dims(x_dim=x, y_dim=y).rio.write_crs(_crs(crs))
    da = da.rio.write_nodata(nodata, encoded=False)
    if dst_crs is not None:
        target = da.rio.estimate_utm_crs() if str(dst_crs).lower() == "utm" \
            else _crs(dst_crs, "dst_crs")
        kwargs = {} if resolution is None else {"resolution": resolution}
        da = da.rio.reproject(target, resampling=_resampling(resampling), nodata=nodata,
                              **kwargs)
    tags = _tags(data, extra)
    return _atomic(path, lambda tmp: da.rio.to_raster(tmp, driver="GTiff", compress=compress,
                                                     tags=tags))


def write_geotiff_gcps(data, latitude, longitude, path, *, height=None, step=None,
                       dst_crs=None, resolution=None, resampling: str = "bilinear",
                       nodata=np.nan, x: str = "x", y: str = "y",
                       compress: str = "deflate") -> Path:
    """Write an image-geometry product georeferenced by ground control points.

    Parameters
    ----------
    data : xarray.DataArray
        ``(y, x)`` or ``(band, y, x)`` in image geometry.
    latitude, longitude : array_like
        ``(ny, nx)`` geodetic position of every pixel centre [deg] (WGS84), e.g. from
        :func:`radscene.platform.geolocation.geolocation_truth`.
    path : str or path-like
        Destination.
    height : array_like, optional
        ``(ny, nx)`` ellipsoidal height [m] of the GCPs.
    step : int, optional
        GCP spacing [px]; default so that about 16 x 16 GCPs cover the image (corners
        included).
    dst_crs : CRS-like or "utm", optional
        Warp through the GCPs to this map projection (GDAL's GCP transformer) instead of
        writing the image geometry.
    resolution, resampling, nodata, x, y, compress
        As :func:`write_geotiff`.

    Returns
    -------
    pathlib.Path
    """
    from rasterio.control import GroundControlPoint

    da, extra = _prepare(data, x, y)
    ny, nx = da.sizes[y], da.sizes[x]
    lat = np.asarray(latitude, dtype=float)
    lon = np.asarray(longitude, dtype=float)
    z = np.zeros((ny, nx)) if height is None else np.asarray(height, dtype=float)
    for name, arr in (("latitude", lat), ("longitude", lon), ("height", z)):
        if arr.shape != (ny, nx):
            raise ConfigError(f"must have the image's shape ({ny}, {nx}); got {arr.shape}",
                              key=name)
    if step is None:
        step = max(1, int(np.ceil(max(ny, nx) / 15)))
    if isinstance(step, bool) or not isinstance(step, int | np.integer) or step < 1:
        raise ConfigError(f"must be an integer >= 1; got {step!r}", key="step")
    rows = np.unique(np.r_[np.arange(0, ny, step), ny - 1])
    cols = np.unique(np.r_[np.arange(0, nx, step), nx - 1])
    gcps = [GroundControlPoint(row=r + 0.5, col=c + 0.5, x=float(lon[r, c]),
                               y=float(lat[r, c]), z=float(z[r, c]))
            for r in rows for c in cols if np.isfinite(lat[r, c]) and np.isfinite(lon[r, c])]
    if len(gcps) < 3:
        raise ConfigError("fewer than 3 pixels have a finite latitude and longitude",
                          key="latitude")
    da = da.astype("float32") if da.dtype.kind == "f" else da
    da = da.drop_vars([c for c in (x, y) if c in da.coords])
    da = da.rio.set_spatial_dims(x_dim=x, y_dim=y)
    da = da.rio.write_gcps(gcps, "EPSG:4326").rio.write_nodata(nodata, encoded=False)
    if dst_crs is not None:
        if str(dst_crs).lower() == "utm":
            from pyproj.aoi import AreaOfInterest
            from pyproj.database import query_utm_crs_info

            info = query_utm_crs_info("WGS 84", AreaOfInterest(
                float(np.nanmean(lon)), float(np.nanmean(lat)), float(np.nanmean(lon)),
                float(np.nanmean(lat))))
            target = _crs(f"EPSG:{info[0].code}")
        else:
            target = _crs(dst_crs, "dst_crs")
        kwargs = {} if resolution is None else {"resolution": resolution}
        da = da.rio.reproject(target, resampling=_resampling(resampling), nodata=nodata,
                              **kwargs)
    tags = _tags(data, extra)

    def write(tmp):
        import warnings

        from rasterio.errors import NotGeoreferencedWarning

        with warnings.catch_warnings():  # image geometry: the GCPs carry the georeference
            warnings.simplefilter("ignore", NotGeoreferencedWarning)
            da.rio.to_raster(tmp, driver="GTiff", compress=compress, tags=tags)

    return _atomic(path, write)


def read_geotiff(path):
    """Read a GeoTIFF back as an ``xarray.DataArray`` ``(band, y, x)`` with its CRS."""
    import rioxarray

    path = Path(path)
    if not path.is_file():
        raise ConfigError("no such file", key=str(path))
    return rioxarray.open_rasterio(path, masked=True)
