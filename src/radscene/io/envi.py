"""ENVI images (BSQ, float32 little-endian) of band renders, and the header text they share with
spectral cubes (:mod:`radscene.io.spectral`).

A band render's ``radiance(band, y, x)`` [W m-2 sr-1] becomes ``NAME.img`` + ``NAME.hdr`` with
``wavelength`` = the bands' centres, ``fwhm`` = their equivalent widths
(∫ S dλ, the response's peak taken as 1) and ``wavelength units = Micrometers``, the band
names, the units in the description and in ``data units``, and the Dataset's global
attributes (its provenance) each as a header field whose value is a JSON string on one line
(``json.loads`` gives the attribute back exactly). ENVI readers — the ``spectral`` package,
GDAL, ENVI, QGIS — read it as a spectral image.

A map product (a nadir orthographic observer: ``x``/``y`` eastings and northings [m] with the
``crs`` grid mapping) is georeferenced as GDAL and ENVI expect (:func:`map_fields`): ``map info
= {projection, 1, 1, easting, northing, x size, y size, [zone, North|South,] [WGS-84,]
units=Meters}``, the tie point (1, 1) being the outer corner of the first pixel, as in the
Cloud-Optimised GeoTIFFs' geotransform, and ``coordinate system string`` the CRS as ESRI WKT
(the form ENVI writes and reads). Other views (perspective cameras, scanners) have no map grid
and no such fields.
"""

from __future__ import annotations

import json
import os
from collections.abc import Sequence
from pathlib import Path

import numpy as np

from radscene.errors import ConfigError
from radscene.io.files import atomic_output

__all__ = ["write_envi", "header_text", "attribute_fields", "map_fields", "pixel_size"]


def _braces(values, fmt="{:.6f}") -> str:
    return "{" + ", ".join(fmt.format(float(v)) for v in values) + "}"


def _plain(text) -> str:
    """Text safe inside an ENVI ``{...}`` list: no braces, no commas."""
    return str(text).replace("{", "(").replace("}", ")").replace(",", ";")


def attribute_fields(attrs: dict) -> list[str]:
    """Header lines ``key = "json string"`` for the text and number attributes of ``attrs``.

    The value is the JSON encoding of the attribute as text, with braces escaped (``\\u007b``,
    ``\\u007d``) so no ENVI reader takes it for a list: ``json.loads`` of the value gives the
    attribute's text back unchanged.
    """
    lines = []
    for key, value in attrs.items():
        if not isinstance(value, str | int | float | np.integer | np.floating):
            continue
        text = json.dumps(str(value), ensure_ascii=True)
        text = text.replace("{", "\\u007b").replace("}", "\\u007d")
        lines.append(f"{str(key).lower()} = {text}")
    return lines


def _projection_name(crs) -> str:
    """ENVI's name of the projection of a pyproj CRS."""
    if crs.utm_zone:
        return "UTM"
    operation = crs.coordinate_operation
    return operation.method_name if operation is not None else "Arbitrary"


def pixel_size(attrs: dict) -> float | None:
    """The ground sample distance [m] a render's attributes record (``observer_geometry``),
    or None."""
    try:
        value = json.loads(attrs.get("observer_geometry", "{}")).get("gsd_m")
    except (TypeError, ValueError, AttributeError):
        return None
    return float(value) if isinstance(value, int | float) else None


def map_fields(data, pixel_size: float | None = None) -> list[str]:
    """The header lines that georeference a map product: ``map info`` and ``coordinate system
    string``.

    Parameters
    ----------
    data : xarray.DataArray or xarray.Dataset
        A map product's layer or pass: ``x``/``y`` [m] at the pixel centres, equally spaced,
        north up, with a CRS (the ``crs`` grid mapping).
    pixel_size : float, optional
        The pixel size [m] of a grid of one pixel, which its coordinates do not give (a
        render's: :func:`pixel_size` of its attributes).

    Returns
    -------
    list of str
        The two lines; none for data without map coordinates or a CRS (a perspective view).

    Raises
    ------
    ConfigError
        Map coordinates with a CRS that are not equally spaced, not north up (rows from
        north to south, columns from west to east), or a single pixel without
        ``pixel_size``.
    """
    import rioxarray  # noqa: F401  (the .rio accessor)
    from pyproj import CRS
    from pyproj.enums import WktVersion

    from radscene.io.geotiff import _regular

    if "x" not in data.coords or "y" not in data.coords or data["x"].attrs.get("units") != "m":
        return []
    found = data.rio.crs
    if found is None and "crs" in data.coords:  # the grid mapping, not named in the encoding
        found = data.rio.write_grid_mapping("crs").rio.crs
    if found is None:
        return []
    x, y = (np.asarray(data[name].values, dtype=float) for name in ("x", "y"))
    _regular(x, "x")
    _regular(y, "y")
    steps = [(v[-1] - v[0]) / (v.size - 1) if v.size > 1 else None for v in (x, -y)]
    if steps == [None, None]:
        if pixel_size is None:
            raise ConfigError("map info needs the pixel size, which a grid of one pixel does "
                              "not give; give pixel_size", key="data")
        steps = [float(pixel_size)] * 2
    dx, dy = (step if step is not None else other  # one row or column: square pixels
              for step, other in zip(steps, steps[::-1], strict=True))
    if dx <= 0 or dy <= 0:
        raise ConfigError("map info needs a north-up grid (x increasing, y decreasing); got "
                          f"steps of {dx:g} m in x and {-dy:g} m in y", key="data")
    crs = CRS.from_user_input(found.to_wkt())
    corner = (x[0] - dx / 2, y[0] + dy / 2)  # the outer corner of the first pixel
    fields = [_projection_name(crs), "1", "1"] + [f"{v:.12g}" for v in (*corner, dx, dy)]
    if crs.utm_zone:
        fields += [crs.utm_zone[:-1], "North" if crs.utm_zone.endswith("N") else "South"]
    if crs.datum is not None and crs.datum.name in ("World Geodetic System 1984",
                                                    "World Geodetic System 1984 ensemble"):
        fields.append("WGS-84")
    unit = crs.axis_info[0].unit_name if crs.axis_info else ""
    fields.append("units=Meters" if unit == "metre" else "")
    wkt = crs.to_wkt(WktVersion.WKT1_ESRI)
    return ["map info = {" + ", ".join(f for f in fields if f) + "}",
            "coordinate system string = {" + wkt + "}"]


def header_text(shape: tuple[int, int, int], wavelength, fwhm, band_names, description: str,
                units: str, attrs: dict | None = None,
                georeference: Sequence[str] = ()) -> str:
    """The text of an ENVI header for a BSQ float32 little-endian image.

    Parameters
    ----------
    shape : (bands, lines, samples)
        Bands, rows, columns.
    wavelength, fwhm : array_like
        Band centres and widths [um].
    band_names : sequence of str
    description : str
    units : str
        Units of the values, e.g. ``W m-2 sr-1``.
    attrs : dict, optional
        Attributes written as fields (:func:`attribute_fields`).
    georeference : sequence of str
        The lines of :func:`map_fields` (none for an image without a map grid).

    Returns
    -------
    str
    """
    n, ny, nx = shape
    return "\n".join([
        "ENVI",
        "description = {" + str(description).replace("{", "(").replace("}", ")") + "}",
        f"samples = {nx}",
        f"lines = {ny}",
        f"bands = {n}",
        "header offset = 0",
        "file type = ENVI Standard",
        "data type = 4",
        "interleave = bsq",
        "byte order = 0",
        *georeference,
        "wavelength units = Micrometers",
        "wavelength = " + _braces(wavelength),
        "fwhm = " + _braces(fwhm),
        "band names = {" + ", ".join(_plain(b) for b in band_names) + "}",
        f"data units = {units}",
        *attribute_fields(attrs or {}),
        "",
    ])


def write_envi(data, path: str | os.PathLike, attrs: dict | None = None) -> list[Path]:
    """Write band radiance ``(band, y, x)`` as an ENVI image ``path`` and its header.

    Parameters
    ----------
    data : xarray.DataArray
        ``(band, y, x)`` with the coordinates ``wavelength_center`` and ``equivalent_width``
        [um] on ``band`` (a render's ``radiance`` [W m-2 sr-1]).
    path : path-like
        The image (``.img``); the header goes beside it with the suffix ``.hdr``. Both are
        written atomically.
    attrs : dict, optional
        The Dataset's global attributes (provenance), written into the header.

    Returns
    -------
    list of pathlib.Path
        The image and the header.

    Raises
    ------
    ConfigError
        ``data`` is not ``(band, y, x)``, lacks the band coordinates, or is a map product
        whose grid :func:`map_fields` cannot describe.
    """
    import xarray as xr

    if not isinstance(data, xr.DataArray) or data.dims != ("band", "y", "x"):
        raise ConfigError("must be a DataArray (band, y, x), e.g. a render's radiance; got "
                          f"{getattr(data, 'dims', type(data).__name__)}", key="data")
    missing = [c for c in ("wavelength_center", "equivalent_width") if c not in data.coords]
    if missing:
        raise ConfigError(f"needs the band coordinates {', '.join(missing)} [µm]", key="data")
    path = Path(path)
    header = path.with_suffix(".hdr")
    attrs = dict(attrs or {})
    units = str(data.attrs.get("units", ""))
    description = (f"radscene band radiance [{units}] of scene {attrs.get('scene', '')!r} "
                   f"observer {attrs.get('observer', '')!r}: the integral of the band response "
                   "times the spectral radiance; divide by fwhm (the equivalent width) for the "
                   "band-mean spectral radiance [W m-2 sr-1 um-1]")
    text = header_text(data.shape, data["wavelength_center"].values,
                       data["equivalent_width"].values, [str(b) for b in data["band"].values],
                       description, units, attrs,
                       georeference=map_fields(data, pixel_size(attrs)))
    with atomic_output(path) as img_tmp, atomic_output(header) as hdr_tmp:
        np.asarray(data.values, dtype="<f4").tofile(img_tmp)
        Path(hdr_tmp).write_text(text)
    return [path, header]
