"""Reader of ECOSTRESS and ASTER spectral-library text files (JPL).

Format
------
One spectrum per file: a header of ``Key: value`` lines (``Name``, ``Type``, ``Class``,
``Subclass``, ``Sample No.``, ``Measurement``, ``X Units``, ``Y Units``, ``Number of X Values``,
...; a value may continue on following lines), then data rows of two numbers, wavelength and
value, usually in *decreasing* wavelength::

    Name: Construction Concrete
    Type: Manmade
    Class: Concrete
    ...
    X Units: Wavelength (micrometers)
    Y Units: Reflectance (percent)
    Number of X Values: 3

    14.0112   8.57
    ...

Rules (each stated, none silent)
--------------------------------
* ``X Units`` must name micrometres/microns, nanometres, or wavenumber in cm⁻¹ (converted to
  um as 10⁴/ν); ``Y Units`` must start with ``Reflectance``, ``Emissivity`` or
  ``Transmittance`` and say ``percent`` (values divided by 100) or ``fraction``/nothing (used
  as written). Anything else raises, naming the file and the line.
* Rows are sorted into increasing wavelength. Rows at exactly the same wavelength (instrument
  joins) are merged into their mean; the merge is recorded in ``metadata["merged_rows"]``.
* ``Number of X Values``, when given, must equal the number of data rows (a truncated file
  raises).
* A negative or non-finite value raises, naming the file and line.

References
----------
S. K. Meerdink, S. J. Hook, D. A. Roberts, E. A. Abbott, "The ECOSTRESS spectral library version
1.0", Remote Sens. Environ. 230, 111196 (2019), doi:10.1016/j.rse.2019.05.015.
A. M. Baldridge, S. J. Hook, C. I. Grove, G. Rivera, "The ASTER spectral library version 2.0",
Remote Sens. Environ. 113, 711-715 (2009), doi:10.1016/j.rse.2008.11.007.
"""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np

from radscene.errors import ConfigError
from radscene.materials.libraries.base import LibrarySpectrum

__all__ = ["read_ecostress", "sniff_ecostress"]

_KEY_RE = re.compile(r"^\s*([A-Za-z][A-Za-z0-9 .()/#_-]*?)\s*:\s?(.*)$")
_NUM_RE = re.compile(r"^[+-]?(\d+\.?\d*|\.\d+)([eE][+-]?\d+)?$")


def sniff_ecostress(first_lines: list[str]) -> bool:
    """True when the text starts like an ECOSTRESS/ASTER file (first non-blank line ``Name:``)."""
    for line in first_lines:
        if line.strip():
            return line.lstrip("\ufeff").strip().lower().startswith("name:")
    return False


def _x_scale(units: str, where: str):
    u = units.lower()
    if "wavenumber" in u or "cm-1" in u or "cm^-1" in u or "1/cm" in u:
        return "wavenumber"
    if "nanomet" in u or re.search(r"\bnm\b", u):
        return 1e-3
    if "micromet" in u or "micron" in u or re.search(r"\bum\b|µm", u):
        return 1.0
    raise ConfigError(
        "X Units not understood; accepted: micrometers/microns, nanometers, "
        "wavenumber (cm-1)",
        key=where,
    )


def _y_units(units: str, where: str) -> tuple[str, float]:
    u = units.strip().lower()
    quantity = next((q for q in ("reflectance", "emissivity", "transmittance") if u.startswith(q)), None)
    if quantity is None:
        raise ConfigError(
            "Y Units not understood; accepted: Reflectance, Emissivity or "
            "Transmittance, in percent or as a fraction",
            key=where,
        )
    if "percent" in u or "%" in u:
        return quantity, 0.01
    if "fraction" in u or u == quantity or "(" not in u:
        return quantity, 1.0
    raise ConfigError(
        f"Y Units {units!r}: scale not understood; accepted: (percent), (percentage), "
        "(fraction) or none",
        key=where,
    )


def read_ecostress(path) -> LibrarySpectrum:
    """Read one ECOSTRESS or ASTER spectral-library text file.

    Parameters
    ----------
    path : str or path-like
        The ``*.spectrum.txt`` (ECOSTRESS) or ASTER ``*.txt`` file.

    Returns
    -------
    LibrarySpectrum
        Wavelength increasing [um]; values as fractions [-]; ``quantity`` from ``Y Units``;
        ``metadata`` holds every header field (keys lower-case, e.g. ``"class"``,
        ``"sample no."``) plus ``"format": "ecostress"``.

    Raises
    ------
    ConfigError
        Naming the file and line: unreadable file, a header that is not ECOSTRESS/ASTER,
        unknown units, a non-numeric data row, a row count that differs from
        ``Number of X Values``, or a negative value.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> p = pathlib.Path(tempfile.mkdtemp()) / "grass.spectrum.txt"
    >>> _ = p.write_text("Name: Grass\\nX Units: Wavelength (micrometers)\\n"
    ...                  "Y Units: Reflectance (percent)\\n\\n2.0 30.0\\n0.5 10.0\\n")
    >>> s = read_ecostress(p)
    >>> s.wavelength.tolist(), s.values.tolist()
    ([0.5, 2.0], [0.1, 0.3])
    """
    path = Path(path)
    try:
        text = path.read_text(encoding="utf-8", errors="replace")
    except OSError as exc:
        raise ConfigError(f"cannot read spectral library file: {exc.strerror or exc}", key=str(path)) from exc
    lines = text.splitlines()
    if not sniff_ecostress(lines[:5]):
        raise ConfigError(
            "not an ECOSTRESS/ASTER spectrum: the first line must be 'Name: ...'",
            key=f"{path}:1",
        )
    header: dict[str, str] = {}
    header_line: dict[str, int] = {}
    rows: list[tuple[float, float]] = []
    row_lines: list[int] = []
    last_key = None
    for lineno, raw in enumerate(lines, start=1):
        line = raw.lstrip("\ufeff").strip()
        if not line:
            continue
        tokens = line.split()
        if len(tokens) >= 2 and all(_NUM_RE.match(t) for t in tokens[:2]) and header:
            if len(tokens) != 2:
                raise ConfigError(
                    f"data row has {len(tokens)} columns; an ECOSTRESS/ASTER row has 2 "
                    "(wavelength, value)",
                    key=f"{path}:{lineno}",
                )
            rows.append((float(tokens[0]), float(tokens[1])))
            row_lines.append(lineno)
            continue
        if rows:
            raise ConfigError(
                "non-numeric line inside the data", key=f"{path}:{lineno}"
            )
        match = _KEY_RE.match(line)
        if match and not (last_key == "description" and " " in match.group(1).strip()
                          and match.group(1).strip().lower() not in _KNOWN_KEYS):
            last_key = match.group(1).strip().lower()
            header[last_key] = match.group(2).strip()
            header_line[last_key] = lineno
        elif last_key is not None:
            header[last_key] = (header[last_key] + " " + line).strip()
        else:
            raise ConfigError("header line not understood", key=f"{path}:{lineno}")
    for needed in ("x units", "y units"):
        if needed not in header:
            raise ConfigError(
                f"header has no '{needed.title()}:' line; ECOSTRESS/ASTER files state the units "
                "of both columns",
                key=str(path),
            )
    if len(rows) < 2:
        raise ConfigError(f"{len(rows)} data row(s); a spectrum needs at least 2", key=str(path))
    xscale = _x_scale(header["x units"], f"{path}:{header_line['x units']}")
    quantity, yscale = _y_units(header["y units"], f"{path}:{header_line['y units']}")
    if "number of x values" in header:
        try:
            expected = int(float(header["number of x values"]))
        except ValueError:
            raise ConfigError(
                "Number of X Values is not a number",
                key=f"{path}:{header_line['number of x values']}",
            ) from None
        if expected != len(rows):
            raise ConfigError(
                f"the header announces {expected} rows (Number of X Values) but the file has "
                f"{len(rows)}: truncated or damaged file",
                key=f"{path}:{header_line['number of x values']}",
            )
    data = np.asarray(rows, dtype=float)
    line_no = np.asarray(row_lines, dtype=np.int64)
    x = data[:, 0]
    if xscale == "wavenumber":
        if np.any(x <= 0):
            i = int(np.argmax(x <= 0))
            raise ConfigError(f"wavenumber {x[i]:g} cm-1 must be > 0", key=f"{path}:{line_no[i]}")
        x = 1e4 / x
    else:
        x = x * xscale
    y = data[:, 1] * yscale
    bad = np.flatnonzero(~np.isfinite(y) | (y < 0.0) | ~np.isfinite(x) | (x <= 0.0))
    if bad.size:
        i = int(bad[0])
        raise ConfigError(
            f"spectrum {header.get('name', path.stem)!r}: {quantity} {data[i, 1]:g} at "
            f"{data[i, 0]:g} ({header['x units']}) is negative or not finite",
            key=f"{path}:{line_no[i]}",
        )
    order = np.argsort(x, kind="stable")
    x, y, line_no = x[order], y[order], line_no[order]
    unique, start, counts = np.unique(x, return_index=True, return_counts=True)
    metadata = dict(header)
    metadata["format"] = "ecostress"
    if unique.size != x.size:
        sums = np.add.reduceat(y, start)
        y = sums / counts
        line_no = line_no[start]
        x = unique
        metadata["merged_rows"] = (
            f"{int(np.sum(counts - 1))} rows at repeated wavelengths merged into their mean"
        )
    return LibrarySpectrum(
        name=header.get("name", path.stem),
        wavelength=x,
        values=y,
        quantity=quantity,
        source=str(path),
        lines=line_no,
        metadata=metadata,
    )


_KNOWN_KEYS = {
    "name", "type", "class", "subclass", "particle size", "sample no.", "owner",
    "wavelength range", "origin", "collection date", "description", "measurement",
    "first column", "second column", "x units", "y units", "first x value", "last x value",
    "number of x values", "additional information", "genus", "species",
}
