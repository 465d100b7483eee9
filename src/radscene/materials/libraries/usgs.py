"""Reader of USGS Spectral Library Version 7 (splib07a/b) ASCII files.

Format
------
A spectrum file holds a title line and then one value per line; its wavelengths are in a
separate file of the same layout, one per instrument and channel count::

    splib07a Record=4785: Concrete_WTC01-37A  ASDFRa AREF      (spectrum file)
    -1.23e+34
    0.0712
    ...

    splib07a Record=2: Wavelengths ASD 0.35-2.5 microns 2151 ch (wavelength file)
    0.350
    ...

Rules (each stated, none silent)
--------------------------------
* Values equal to the library's deleted-channel marker, -1.23e34 (any value below -1e30), are
  dropped with their wavelengths; their count is recorded in ``metadata["deleted_channels"]``.
* Wavelengths are in micrometres (the library's unit). Values are fractions (reflectance
  0-1), used as written. The quantity is reflectance unless the title says ``TRAN``
  (transmittance).
* The wavelength file is the one given, or else found beside the spectrum (or up to two folders
  above): a ``*Wavelengths*`` file with the same number of channels whose name shares the
  spectrum's instrument (ASD, BECK, NIC4, AVIRIS, ...). No match, or several, raises and asks
  for ``wavelength_file``.
* Rows are sorted by wavelength; repeated wavelengths raise (a wavelength file never has them).

Reference
---------
R. F. Kokaly et al., "USGS Spectral Library Version 7", U.S. Geological Survey Data Series
1035 (2017), doi:10.3133/ds1035; data doi:10.5066/F7RR1WDJ (public domain).
"""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np

from radscene.errors import ConfigError
from radscene.materials.libraries.base import LibrarySpectrum

__all__ = ["read_usgs", "sniff_usgs", "DELETED_CHANNEL_THRESHOLD"]

#: Values below this mark deleted channels in splib07 (the marker is -1.23e34) [-].
DELETED_CHANNEL_THRESHOLD = -1e30

_TITLE_RE = re.compile(r"^\s*(splib\d+[a-z]?)\s+record\s*=\s*(\d+)\s*:\s*(.*)$", re.IGNORECASE)
_INSTRUMENTS = ("ASD", "BECK", "NIC4", "AVIRIS", "CRISM", "HYMAP", "ASTER", "LANDSAT")


def sniff_usgs(first_lines: list[str]) -> bool:
    """True when the text starts like a splib07 ASCII file (``splib07a Record=N: ...``)."""
    for line in first_lines:
        if line.strip():
            return bool(_TITLE_RE.match(line.lstrip("\ufeff")))
    return False


def _read_column(path: Path, what: str) -> tuple[str, np.ndarray, np.ndarray]:
    try:
        text = path.read_text(encoding="utf-8", errors="replace")
    except OSError as exc:
        raise ConfigError(f"cannot read {what}: {exc.strerror or exc}", key=str(path)) from exc
    lines = text.splitlines()
    title = None
    values, numbers = [], []
    for lineno, raw in enumerate(lines, start=1):
        line = raw.lstrip("\ufeff").strip()
        if not line:
            continue
        if title is None:
            if not _TITLE_RE.match(line):
                raise ConfigError(
                    f"not a USGS splib07 ASCII {what}: the first line must be "
                    "'splib07a Record=N: ...'",
                    key=f"{path}:{lineno}",
                )
            title = line
            continue
        try:
            values.append(float(line.split()[0]))
        except ValueError:
            raise ConfigError(
                "line is not a number (a splib07 ASCII file has one value per line)",
                key=f"{path}:{lineno}",
            ) from None
        numbers.append(lineno)
    if title is None:
        raise ConfigError(f"empty {what}", key=str(path))
    return title, np.asarray(values, dtype=float), np.asarray(numbers, dtype=np.int64)


def _instrument(title: str) -> str | None:
    upper = title.upper()
    for name in _INSTRUMENTS:
        if re.search(rf"\b{name}", upper):
            return name
    return None


def _find_wavelength_file(path: Path, n: int, instrument: str | None) -> Path:
    candidates: list[Path] = []
    folder = path.parent
    for _ in range(3):
        candidates += sorted(p for p in folder.glob("*avelength*") if p.is_file())
        folder = folder.parent
    matches = []
    for cand in candidates:
        name = cand.name.upper()
        if instrument and instrument not in name:
            continue
        if re.search(rf"\b{n}[ _-]?CH", name) or re.search(rf"_{n}_", name):
            matches.append(cand)
            continue
        try:
            _, vals, _ = _read_column(cand, "wavelength file")
        except ConfigError:
            continue
        if vals.size == n:
            matches.append(cand)
    unique = list(dict.fromkeys(matches))
    if len(unique) == 1:
        return unique[0]
    what = "no" if not unique else f"{len(unique)} ({', '.join(p.name for p in unique)})"
    raise ConfigError(
        f"{what} wavelength file with {n} channels"
        f"{' for instrument ' + instrument if instrument else ''} found beside the spectrum; "
        "pass wavelength_file= (e.g. splib07a_Wavelengths_ASD_0.35-2.5_microns_2151_ch.txt)",
        key=str(path),
    )


def read_usgs(path, wavelength_file=None) -> LibrarySpectrum:
    """Read one USGS splib07 ASCII spectrum.

    Parameters
    ----------
    path : str or path-like
        The spectrum file, e.g. ``splib07a_Concrete_WTC01-37A_ASDFRa_AREF.txt``.
    wavelength_file : str or path-like, optional
        Its wavelength file [um]; found automatically when omitted (see the module rules).

    Returns
    -------
    LibrarySpectrum
        Wavelength increasing [um], values [-]; ``metadata`` has ``title``, ``record``,
        ``library``, ``instrument``, ``wavelength_file``, ``deleted_channels`` and
        ``"format": "usgs"``.

    Raises
    ------
    ConfigError
        Naming the file and line: a title that is not splib07, a non-numeric line, a channel
        count that differs from the wavelength file's, a negative value, or no wavelength file.
    """
    path = Path(path)
    title, values, lines = _read_column(path, "spectrum file")
    match = _TITLE_RE.match(title)
    library, record, description = match.group(1), match.group(2), match.group(3).strip()
    instrument = _instrument(description)
    if wavelength_file is None:
        wpath = _find_wavelength_file(path, values.size, instrument)
    else:
        wpath = Path(wavelength_file)
    _, wavelength, _ = _read_column(wpath, "wavelength file")
    if wavelength.size != values.size:
        raise ConfigError(
            f"{values.size} values but the wavelength file {wpath.name} has {wavelength.size} "
            "channels",
            key=str(path),
        )
    keep = (values > DELETED_CHANNEL_THRESHOLD) & (wavelength > DELETED_CHANNEL_THRESHOLD)
    deleted = int(np.sum(~keep))
    wl, vals, lines = wavelength[keep], values[keep], lines[keep]
    quantity = "transmittance" if re.search(r"\bTRAN", description.upper()) else "reflectance"
    bad = np.flatnonzero(~np.isfinite(vals) | (vals < 0.0))
    if bad.size:
        i = int(bad[0])
        raise ConfigError(
            f"spectrum {description!r}: {quantity} {vals[i]:g} at {wl[i]:g} µm is negative",
            key=f"{path}:{lines[i]}",
        )
    order = np.argsort(wl, kind="stable")
    wl, vals, lines = wl[order], vals[order], lines[order]
    if np.any(np.diff(wl) <= 0):
        i = int(np.argmax(np.diff(wl) <= 0))
        raise ConfigError(
            f"wavelength {wl[i + 1]:g} µm repeats in {wpath.name}", key=f"{path}:{lines[i + 1]}"
        )
    name = description.split()[0] if description else path.stem
    return LibrarySpectrum(
        name=name,
        wavelength=wl,
        values=vals,
        quantity=quantity,
        source=str(path),
        lines=lines,
        metadata={
            "format": "usgs",
            "title": title,
            "library": library,
            "record": record,
            "description": description,
            "instrument": instrument or "",
            "wavelength_file": str(wpath),
            "deleted_channels": str(deleted),
        },
    )
