"""Reader and writer of ENVI spectral libraries (``.sli`` binary + ``.hdr`` text header).

Format
------
The header is text: the line ``ENVI``, then ``key = value`` lines, where a value in braces may
run over several lines. For a spectral library ``file type = ENVI Spectral Library``,
``samples`` is the number of wavelengths, ``lines`` the number of spectra, ``bands = 1``; the
binary file holds ``lines x samples`` numbers of ``data type`` (1 uint8, 2 int16, 3 int32,
4 float32, 5 float64, 12 uint16, 13 uint32, 14 int64, 15 uint64) in ``byte order`` (0 little-,
1 big-endian) after ``header offset`` bytes. ``wavelength = {...}`` gives the band centres,
``spectra names = {...}`` the names.

Rules (each stated, none silent)
--------------------------------
* ``wavelength units`` ``Micrometers``/``um``/``microns`` are used as they are,
  ``Nanometers``/``nm`` divided by 1000. When the header has no units the wavelengths are taken
  as nanometres if their maximum exceeds 100, else as micrometres, and
  ``metadata["wavelength units"]`` records the assumption. Other units raise.
* ``reflectance scale factor`` (e.g. 10000), when present, divides the values.
* A value below 0 raises, naming the file, the spectrum and its wavelength (a binary file has no
  lines).
* The data file is the header's path without ``.hdr`` or with ``.sli`` (``spectra.hdr`` and
  ``spectra.sli.hdr`` conventions both work).

Reference
---------
ENVI header files, NV5 Geospatial documentation ("ENVI Header Format").
"""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np

from radscene.errors import ConfigError
from radscene.materials.libraries.base import LibrarySpectrum, SpectralLibrary

__all__ = ["read_envi", "read_envi_header", "write_envi_library", "sniff_envi", "ENVI_DATA_TYPES"]

#: ENVI ``data type`` codes and their numpy types.
ENVI_DATA_TYPES = {
    1: np.uint8,
    2: np.int16,
    3: np.int32,
    4: np.float32,
    5: np.float64,
    12: np.uint16,
    13: np.uint32,
    14: np.int64,
    15: np.uint64,
}


def sniff_envi(path: Path, first_lines: list[str]) -> bool:
    """True for ``.sli``/``.hdr`` paths or text starting with the line ``ENVI``."""
    if path.suffix.lower() in (".sli", ".hdr"):
        return True
    for line in first_lines:
        if line.strip():
            return line.lstrip("\ufeff").strip() == "ENVI"
    return False


def _paths(path: Path) -> tuple[Path, Path]:
    """(header, data) paths for a path to either."""
    if path.suffix.lower() == ".hdr":
        header = path
        stem = path.with_suffix("")
        candidates = [stem, stem.with_suffix(".sli")] if stem.suffix else [stem.with_suffix(".sli"), stem]
    else:
        candidates = [path]
        header = next(
            (h for h in (path.with_suffix(".hdr"), Path(str(path) + ".hdr")) if h.is_file()),
            path.with_suffix(".hdr"),
        )
    if not header.is_file():
        raise ConfigError(
            f"ENVI header not found: looked for {header.name} and {path.name}.hdr", key=str(path)
        )
    data = next((c for c in candidates if c.is_file() and c != header), None)
    if data is None:
        raise ConfigError(
            f"ENVI data file not found for header {header.name}; looked for "
            f"{', '.join(c.name for c in candidates)}",
            key=str(header),
        )
    return header, data


def read_envi_header(path) -> tuple[dict[str, str], dict[str, int]]:
    """Parse an ENVI header.

    Parameters
    ----------
    path : str or path-like
        The ``.hdr`` file.

    Returns
    -------
    fields : dict of str to str
        Lower-case keys; brace values without the braces.
    lines : dict of str to int
        The line (1-based) where each key starts, for messages.

    Raises
    ------
    ConfigError
        Naming the file and line: no ``ENVI`` first line, a line that is not ``key = value``, or
        an unclosed brace.
    """
    path = Path(path)
    try:
        text = path.read_text(encoding="utf-8", errors="replace")
    except OSError as exc:
        raise ConfigError(f"cannot read ENVI header: {exc.strerror or exc}", key=str(path)) from exc
    lines = text.splitlines()
    first = next((i for i, ln in enumerate(lines) if ln.strip()), None)
    if first is None or lines[first].lstrip("\ufeff").strip() != "ENVI":
        raise ConfigError(
            "not an ENVI header: the first line must be 'ENVI'", key=f"{path}:{(first or 0) + 1}"
        )
    fields: dict[str, str] = {}
    where: dict[str, int] = {}
    i = first + 1
    while i < len(lines):
        line = lines[i].strip()
        lineno = i + 1
        i += 1
        if not line or line.startswith(";"):
            continue
        if "=" not in line:
            raise ConfigError("header line is not 'key = value'", key=f"{path}:{lineno}")
        key, value = line.split("=", 1)
        key = key.strip().lower()
        value = value.strip()
        if value.startswith("{"):
            while "}" not in value:
                if i >= len(lines):
                    raise ConfigError(f"value of {key!r} opens '{{' but never closes it", key=f"{path}:{lineno}")
                value += " " + lines[i].strip()
                i += 1
            value = value[1 : value.rindex("}")].strip()
        fields[key] = value
        where[key] = lineno
    return fields, where


def _int_field(fields, where, key, path, default=None) -> int:
    if key not in fields:
        if default is not None:
            return default
        raise ConfigError(f"ENVI header has no '{key}'", key=str(path))
    try:
        return int(fields[key])
    except ValueError:
        raise ConfigError(f"'{key}' must be an integer", key=f"{path}:{where[key]}") from None


def _list(value: str) -> list[str]:
    return [v.strip() for v in value.split(",")] if value.strip() else []


def _read_arrays(path):
    """(wavelength [um], values (n, samples) [-], names, data path, units note); read-only."""
    header_path, data_path = _paths(Path(path))
    fields, where = read_envi_header(header_path)
    hp = str(header_path)
    samples = _int_field(fields, where, "samples", hp)
    n_spectra = _int_field(fields, where, "lines", hp)
    bands = _int_field(fields, where, "bands", hp, default=1)
    offset = _int_field(fields, where, "header offset", hp, default=0)
    dtype_code = _int_field(fields, where, "data type", hp)
    order = _int_field(fields, where, "byte order", hp, default=0)
    if bands != 1:
        raise ConfigError(
            f"bands = {bands}: an ENVI spectral library has bands = 1 (this looks like an image)",
            key=f"{hp}:{where.get('bands', 1)}",
        )
    if "library" not in fields.get("file type", "spectral library").lower():
        raise ConfigError(
            "file type is not 'ENVI Spectral Library'",
            key=f"{hp}:{where['file type']}",
        )
    if dtype_code not in ENVI_DATA_TYPES:
        raise ConfigError(
            f"data type {dtype_code} not supported; accepted: {sorted(ENVI_DATA_TYPES)}",
            key=f"{hp}:{where['data type']}",
        )
    if order not in (0, 1):
        raise ConfigError(f"byte order must be 0 or 1; got {order}", key=f"{hp}:{where['byte order']}")
    dtype = np.dtype(ENVI_DATA_TYPES[dtype_code]).newbyteorder("<" if order == 0 else ">")
    expected = offset + samples * n_spectra * dtype.itemsize
    size = data_path.stat().st_size
    if size != expected:
        raise ConfigError(
            f"data file {data_path.name} has {size} bytes; the header ({n_spectra} spectra x "
            f"{samples} samples of {dtype.itemsize} bytes + offset {offset}) needs {expected}",
            key=str(data_path),
        )
    data = np.fromfile(data_path, dtype=dtype, count=samples * n_spectra, offset=offset)
    data = data.reshape(n_spectra, samples).astype(float)
    if "wavelength" not in fields:
        raise ConfigError("ENVI header has no 'wavelength' list", key=hp)
    try:
        wl = np.array([float(v) for v in _list(fields["wavelength"])])
    except ValueError:
        raise ConfigError("wavelength list holds non-numbers", key=f"{hp}:{where['wavelength']}") from None
    if wl.size != samples:
        raise ConfigError(
            f"wavelength list has {wl.size} values; samples = {samples}",
            key=f"{hp}:{where['wavelength']}",
        )
    units = fields.get("wavelength units", "").strip()
    u = units.lower()
    if not units:
        scale = 1e-3 if wl.max() > 100.0 else 1.0
        units_note = (
            "assumed nanometers (no 'wavelength units' in header; maximum > 100)"
            if scale == 1e-3
            else "assumed micrometers (no 'wavelength units' in header; maximum <= 100)"
        )
    elif u in ("micrometers", "micrometres", "microns", "micron", "um", "µm"):
        scale, units_note = 1.0, units
    elif u in ("nanometers", "nanometres", "nm"):
        scale, units_note = 1e-3, units
    else:
        raise ConfigError(
            f"wavelength units {units!r} not supported; accepted: Micrometers, Nanometers",
            key=f"{hp}:{where['wavelength units']}",
        )
    wl = wl * scale
    factor = 1.0
    if "reflectance scale factor" in fields:
        try:
            factor = float(fields["reflectance scale factor"])
        except ValueError:
            factor = float("nan")
        if not (factor > 0 and np.isfinite(factor)):
            raise ConfigError(
                "reflectance scale factor must be a number > 0",
                key=f"{hp}:{where['reflectance scale factor']}",
            )
        data = data / factor
    names = _list(fields.get("spectra names", ""))
    if names and len(names) != n_spectra:
        raise ConfigError(
            f"spectra names lists {len(names)} names; lines = {n_spectra}",
            key=f"{hp}:{where['spectra names']}",
        )
    if not names:
        names = [f"spectrum_{i + 1}" for i in range(n_spectra)]
    order_idx = np.argsort(wl, kind="stable")
    wl = wl[order_idx]
    data = data[:, order_idx]
    bad = np.argwhere(~np.isfinite(data) | (data < 0.0))
    if bad.size:
        r, c = (int(v) for v in bad[0])
        raise ConfigError(
            f"spectrum {names[r]!r} (index {r}): reflectance {data[r, c]:g} at {wl[c]:g} µm is "
            "negative or not finite",
            key=str(data_path),
        )
    wl.setflags(write=False)
    data.setflags(write=False)
    return wl, data, names, data_path, units_note, fields.get("file type", "")


def read_envi(path) -> SpectralLibrary:
    """Read an ENVI spectral library.

    Parameters
    ----------
    path : str or path-like
        The ``.sli`` data file or its ``.hdr`` header.

    Returns
    -------
    SpectralLibrary
        One :class:`LibrarySpectrum` per library line, wavelength in um, values [-] (after the
        reflectance scale factor); ``metadata`` holds ``"format": "envi"``, the ``index``,
        ``wavelength units`` and ``file type``.

    Raises
    ------
    ConfigError
        Naming the file (and header line): missing header or data, not a spectral library
        (``bands`` != 1), an unknown data type or byte order, a data file of the wrong size, a
        wavelength list of the wrong length, unknown units, or a negative value.
    """
    wl, data, names, data_path, units_note, file_type = _read_arrays(path)
    common = {
        "format": "envi",
        "file type": file_type,
        "wavelength units": units_note,
    }
    spectra = [
        LibrarySpectrum(
            name=names[r],
            wavelength=wl,
            values=data[r],
            quantity="reflectance",
            source=f"{data_path}[{r}]",
            metadata={**common, "index": str(r)},
        )
        for r in range(len(names))
    ]
    return SpectralLibrary(spectra, name=str(data_path))


def write_envi_library(
    path,
    wavelength,
    spectra,
    names=None,
    *,
    data_type: int = 4,
    byte_order: int = 0,
    wavelength_units: str = "Micrometers",
    reflectance_scale_factor: float | None = None,
    description: str = "",
) -> tuple[Path, Path]:
    """Write an ENVI spectral library (``path`` with ``.sli``, plus ``.hdr``).

    Parameters
    ----------
    path : str or path-like
        Data file; ``.sli`` is added when it has no suffix.
    wavelength : array_like
        Band centres, shape (samples,), in ``wavelength_units``.
    spectra : array_like
        Values, shape (n_spectra, samples), already multiplied by the scale factor if any.
    names : sequence of str, optional
        Spectrum names (no commas or braces).
    data_type : int, optional
        ENVI data type code (see :data:`ENVI_DATA_TYPES`); default 4 (float32).
    byte_order : {0, 1}, optional
        0 little-endian (default), 1 big-endian.
    wavelength_units : str, optional
        ``"Micrometers"`` (default) or ``"Nanometers"``.
    reflectance_scale_factor : float, optional
        Written to the header when given.
    description : str, optional
        Header description.

    Returns
    -------
    (pathlib.Path, pathlib.Path)
        Data and header paths.
    """
    path = Path(path)
    if not path.suffix:
        path = path.with_suffix(".sli")
    values = np.atleast_2d(np.asarray(spectra))
    wl = np.asarray(wavelength, dtype=float)
    if values.shape[1] != wl.size:
        raise ConfigError(
            f"spectra have {values.shape[1]} samples but wavelength has {wl.size}", key=str(path)
        )
    if data_type not in ENVI_DATA_TYPES:
        raise ConfigError(f"data_type must be one of {sorted(ENVI_DATA_TYPES)}", key="data_type")
    names = list(names) if names is not None else [f"spectrum_{i + 1}" for i in range(len(values))]
    if len(names) != len(values) or any(re.search(r"[,{}]", n) for n in names):
        raise ConfigError("names: one per spectrum, without commas or braces", key="names")
    dtype = np.dtype(ENVI_DATA_TYPES[data_type]).newbyteorder("<" if byte_order == 0 else ">")
    values.astype(dtype).tofile(path)
    header = path.with_suffix(".hdr")
    text = [
        "ENVI",
        f"description = {{{description}}}",
        f"samples = {wl.size}",
        f"lines = {len(values)}",
        "bands = 1",
        "header offset = 0",
        "file type = ENVI Spectral Library",
        f"data type = {data_type}",
        "interleave = bsq",
        f"byte order = {byte_order}",
        f"wavelength units = {wavelength_units}",
    ]
    if reflectance_scale_factor is not None:
        text.append(f"reflectance scale factor = {reflectance_scale_factor:g}")
    text.append("spectra names = {" + ", ".join(names) + "}")
    text.append("wavelength = {" + ", ".join(f"{w:.6g}" for w in wl) + "}")
    header.write_text("\n".join(text) + "\n", encoding="utf-8")
    return path, header
