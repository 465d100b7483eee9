"""ENVI images (BSQ, float32 little-endian) of band renders, and the header text they share with
spectral cubes (:mod:`radscene.io.spectral`).

A band render's ``radiance(band, y, x)`` [W m-2 sr-1] becomes ``NAME.img`` + ``NAME.hdr`` with
``wavelength`` = the bands' centres, ``fwhm`` = their equivalent widths
(∫ S dλ, the response's peak taken as 1) and ``wavelength units = Micrometers``, the band
names, the units in the description and in ``data units``, and the Dataset's global
attributes (its provenance) each as a header field whose value is a JSON string on one line
(``json.loads`` gives the attribute back exactly). ENVI readers — the ``spectral`` package,
GDAL, ENVI, QGIS — read it as a spectral image.
"""

from __future__ import annotations

import json
import os
from pathlib import Path

import numpy as np

from radscene.errors import ConfigError
from radscene.io.files import atomic_output

__all__ = ["write_envi", "header_text", "attribute_fields"]


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


def header_text(shape: tuple[int, int, int], wavelength, fwhm, band_names, description: str,
                units: str, attrs: dict | None = None) -> str:
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
    """
    import xarray as xr

    if not isinstance(data, xr.DataArray) or data.dims != ("band", "y", "x"):
        raise ConfigError("must be a DataArray (band, y, x), e.g. a render's radiance; got "
                          f"{getattr(data, 'dims', type(data).__name__)}", key="data")
    missing = [c for c in ("wavelength_center", "equivalent_width") if c not in data.coords]
    if missing:
        raise ConfigError(f"needs the band coordinates {', '.join(missing)} [um]", key="data")
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
                       description, units, attrs)
    with atomic_output(path) as img_tmp, atomic_output(header) as hdr_tmp:
        np.asarray(data.values, dtype="<f4").tofile(img_tmp)
        Path(hdr_tmp).write_text(text)
    return [path, header]
