"""Spectral libraries: readers for the formats users download, and earthlib's library.

Formats (registry :data:`FORMATS`, case-insensitive names):

============  ===========================================================  =======================
format        files                                                        reader
============  ===========================================================  =======================
``ecostress`` ECOSTRESS / ASTER text, ``Name: ...`` header, 2 columns      :func:`read_ecostress`
``aster``     same as ``ecostress``                                        :func:`read_ecostress`
``usgs``      USGS splib07 ASCII, ``splib07a Record=N: ...`` + one column  :func:`read_usgs`
``envi``      ENVI spectral library ``.sli`` + ``.hdr``                    :func:`read_envi`
============  ===========================================================  =======================

:func:`read_library` detects the format from the file name and its first line (or takes
``format=``) and always returns a :class:`SpectralLibrary`; a folder is read file by file.
:func:`earthlib_library` gives earthlib's 7261 spectra (optional dependency).

Examples
--------
>>> import tempfile, pathlib
>>> folder = pathlib.Path(tempfile.mkdtemp())
>>> _ = (folder / "a.txt").write_text("Name: Tarmac\\nX Units: Wavelength (micrometers)\\n"
...                                   "Y Units: Reflectance (percent)\\n\\n0.5 5\\n14 6\\n")
>>> lib = read_library(folder)
>>> lib.names
['Tarmac']
>>> round(float(lib[0].to_material().emissivity(10.0)), 4)
0.943
"""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path

from radscene.errors import ConfigError, did_you_mean
from radscene.materials.libraries.base import QUANTITIES, LibrarySpectrum, SpectralLibrary
from radscene.materials.libraries.earthlib_reader import (
    EARTHLIB_CITATION,
    earthlib_classes,
    earthlib_data_dir,
    earthlib_library,
)
from radscene.materials.libraries.ecostress import read_ecostress, sniff_ecostress
from radscene.materials.libraries.envi import (
    read_envi,
    read_envi_header,
    sniff_envi,
    write_envi_library,
)
from radscene.materials.libraries.usgs import read_usgs, sniff_usgs

__all__ = [
    "LibrarySpectrum",
    "SpectralLibrary",
    "QUANTITIES",
    "FORMATS",
    "detect_format",
    "read_library",
    "read_spectrum",
    "read_ecostress",
    "read_usgs",
    "read_envi",
    "read_envi_header",
    "write_envi_library",
    "earthlib_library",
    "earthlib_classes",
    "earthlib_data_dir",
    "EARTHLIB_CITATION",
]


def _as_library(reader: Callable) -> Callable:
    def read(path, **kwargs) -> SpectralLibrary:
        out = reader(path, **kwargs)
        return out if isinstance(out, SpectralLibrary) else SpectralLibrary([out], name=str(path))

    read.__doc__ = reader.__doc__
    return read


#: Registered library formats: name -> reader returning a :class:`SpectralLibrary`.
FORMATS: dict[str, Callable[..., SpectralLibrary]] = {
    "ecostress": _as_library(read_ecostress),
    "aster": _as_library(read_ecostress),
    "usgs": _as_library(read_usgs),
    "envi": _as_library(read_envi),
}


def _head(path: Path, n: int = 5) -> list[str]:
    try:
        with path.open("rb") as f:
            raw = f.read(4096)
    except OSError as exc:
        raise ConfigError(f"cannot read spectral library file: {exc.strerror or exc}", key=str(path)) from exc
    if b"\x00" in raw[:1024] and path.suffix.lower() not in (".sli", ".hdr"):
        return []
    return raw.decode("utf-8", errors="replace").splitlines()[:n]


def detect_format(path) -> str:
    """The registered format of a library file, from its name and first line.

    Parameters
    ----------
    path : str or path-like

    Returns
    -------
    str
        One of :data:`FORMATS` (``"ecostress"``, ``"usgs"`` or ``"envi"``).

    Raises
    ------
    ConfigError
        An unknown format, naming the file and its first line and listing the accepted ones.
    """
    path = Path(path)
    if not path.is_file():
        raise ConfigError(f"spectral library file not found: {path}", key=str(path))
    head = _head(path)
    if sniff_envi(path, head):
        return "envi"
    if sniff_usgs(head):
        return "usgs"
    if sniff_ecostress(head):
        return "ecostress"
    raise ConfigError(
        "unknown spectral library format (by its first line); accepted: ECOSTRESS/ASTER "
        "text ('Name: ...'), USGS splib07 ASCII ('splib07a Record=N: ...'), ENVI .sli + .hdr",
        key=f"{path}:1",
    )


def read_library(path, format: str | None = None, **kwargs) -> SpectralLibrary:
    """Read a spectral library file, or every library file in a folder.

    Parameters
    ----------
    path : str or path-like
        A file of any registered format, or a folder (read non-recursively; files whose format
        is not recognised, such as USGS wavelength files and ECOSTRESS ``ancillary`` files, are
        skipped and listed in the library's ``skipped`` attribute).
    format : str, optional
        Force a format of :data:`FORMATS` instead of detecting it (case-insensitive).
    **kwargs
        Passed to the reader (e.g. ``wavelength_file=`` for ``usgs``).

    Returns
    -------
    SpectralLibrary

    Raises
    ------
    ConfigError
        Unknown format name or file format; any reader's error (naming file and line).
    """
    path = Path(path)
    if format is not None:
        key = str(format).lower()
        if key not in FORMATS:
            raise ConfigError(
                f"unknown library format {format!r}; known: {', '.join(sorted(FORMATS))}"
                f"{did_you_mean(format, sorted(FORMATS))}",
                key="format",
            )
        return FORMATS[key](path, **kwargs)
    if path.is_dir():
        spectra, skipped = [], []
        for p in sorted(path.iterdir()):
            if not p.is_file():
                continue
            if p.suffix.lower() == ".hdr" and (
                p.with_suffix(".sli").is_file() or p.with_suffix("").is_file()
            ):
                continue  # an ENVI header (x.hdr or x.sli.hdr): read with its data file
            if "avelength" in p.name or "ancillary" in p.name.lower() or "andpass" in p.name:
                skipped.append(p.name)
                continue
            try:
                fmt = detect_format(p)
            except ConfigError:
                skipped.append(p.name)
                continue
            spectra.extend(FORMATS[fmt](p, **kwargs))
        lib = SpectralLibrary(spectra, name=str(path))
        lib.skipped = skipped
        return lib
    return FORMATS[detect_format(path)](path, **kwargs)


def read_spectrum(path, format: str | None = None, **kwargs) -> LibrarySpectrum:
    """Read a file that holds exactly one spectrum (ECOSTRESS/ASTER or USGS; an ENVI library of one).

    Raises
    ------
    ConfigError
        The file holds several spectra (use :func:`read_library`), or any reader error.
    """
    lib = read_library(path, format=format, **kwargs)
    if len(lib) != 1:
        raise ConfigError(
            f"{path} holds {len(lib)} spectra; use read_library(...) and pick one", key=str(path)
        )
    return lib[0]
