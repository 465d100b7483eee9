"""earthlib's global library of 7261 VSWIR spectra (0.40-2.45 um), searchable by class and name.

earthlib (C. B. Anderson, MIT licence, https://github.com/earth-chris/earthlib) ships an ENVI
spectral library (``data/spectra.sli``) and a metadata table (``data/spectra.csv``: ``NAME``,
``LEVEL_1`` .. ``LEVEL_4`` class hierarchy, ``LAT``, ``LON``, ``SOURCE``, ``NOTES``). This module
reads both files from the installed package with radscene's own ENVI reader; it does not import
earthlib (nor its dependencies). earthlib is an optional dependency: without it,
:func:`earthlib_library` raises with the command that installs it.

Classes (``LEVEL_1/LEVEL_2/LEVEL_3``): ``impervious/built/{asphalt, road, sidewalk, parking_lot,
comp_shingle, concrete_tile, tile, wood_shingle, metal, paint, glass, gravel, ...}``,
``pervious/bare/{soil, sand, gravel, dirt}``, ``pervious/npv/{bark, litter, wood, npv}``,
``pervious/burned/char``, ``pervious/vegetation/canopy`` (PROSAIL simulations).

Examples
--------
>>> lib = earthlib_library()                                  # doctest: +SKIP
>>> len(lib)                                                  # doctest: +SKIP
7261
>>> roads = lib.search(cls="road")                            # doctest: +SKIP
>>> m = roads[0].to_material(extend="error")                  # doctest: +SKIP
"""

from __future__ import annotations

import csv
import functools
import importlib.util
from pathlib import Path

from radscene.errors import ConfigError
from radscene.materials.libraries.base import LibrarySpectrum, SpectralLibrary
from radscene.materials.libraries.envi import _read_arrays

__all__ = ["earthlib_library", "earthlib_data_dir", "earthlib_classes", "EARTHLIB_CITATION"]

#: How to cite the library.
EARTHLIB_CITATION = (
    "earthlib (C. B. Anderson, https://github.com/earth-chris/earthlib, MIT licence), "
    "compiling the Santa Barbara urban library (Herold et al. 2004, "
    "doi:10.1016/j.rse.2004.03.013), the ICRAF-ISRIC soil library, the JFSP and USGS "
    "libraries and PROSAIL simulations"
)

_INSTALL_HINT = (
    "the earthlib spectral library is an optional dependency of radscene: install it with "
    "`pip install earthlib` (from a radscene clone: `pip install '.[earthlib]'`)"
)


def earthlib_data_dir() -> Path:
    """Folder of earthlib's data files in the installed package.

    Raises
    ------
    ConfigError
        earthlib is not installed (the message says how to install it).
    """
    spec = importlib.util.find_spec("earthlib")
    if spec is None or not spec.submodule_search_locations:
        raise ConfigError(_INSTALL_HINT, key="earthlib")
    data = Path(list(spec.submodule_search_locations)[0]) / "data"
    if not (data / "spectra.sli").is_file() or not (data / "spectra.csv").is_file():
        raise ConfigError(
            f"earthlib is installed but {data}/spectra.sli or spectra.csv is missing; "
            "reinstall it",
            key="earthlib",
        )
    return data


@functools.lru_cache(maxsize=1)
def earthlib_library() -> SpectralLibrary:
    """earthlib's full library: 7261 spectra with their class hierarchy.

    Returns
    -------
    SpectralLibrary
        Each spectrum: wavelength 0.40-2.45 um [um] (180 bands; none in 1.36-1.45 and
        1.80-1.95 um), reflectance [-]; ``metadata`` keys ``level_1`` .. ``level_4``, ``source``,
        ``notes``, ``lat``, ``lon``, ``index`` and ``citation``. Search it with
        :meth:`SpectralLibrary.search`, e.g. ``search(cls="soil")``, ``search(name="lrx*")``,
        ``search(level_3="road", source="asd")``. Cached: read once per process.

    Raises
    ------
    ConfigError
        earthlib is not installed, or its metadata does not match its spectra.
    """
    data = earthlib_data_dir()
    wavelength, values, names, _, _, _ = _read_arrays(data / "spectra.sli")
    with (data / "spectra.csv").open(newline="", encoding="utf-8") as f:
        rows = list(csv.DictReader(f))
    if len(rows) != len(names):
        raise ConfigError(
            f"earthlib metadata has {len(rows)} rows but the library {len(names)} spectra",
            key=str(data / "spectra.csv"),
        )
    spectra = []
    for i, (name, row) in enumerate(zip(names, rows, strict=True)):
        metadata = {k.lower(): (v or "").strip() for k, v in row.items() if k != "NAME"}
        if row["NAME"].strip() != name:
            # earthlib 1.1.0: row 4251 is 'burnedcham' in the table, 'burncham' in the .sli;
            # the spectrum keeps its .sli name and the table's is recorded
            metadata["table_name"] = row["NAME"].strip()
        metadata.update(index=str(i), citation=EARTHLIB_CITATION, format="earthlib")
        spectra.append(
            LibrarySpectrum(
                name=name,
                wavelength=wavelength,
                values=values[i],
                quantity="reflectance",
                source=f"earthlib:{i}",
                metadata=metadata,
            )
        )
    return SpectralLibrary(spectra, name="earthlib")


def earthlib_classes() -> dict[str, int]:
    """Number of spectra per class path ``LEVEL_1/LEVEL_2/LEVEL_3/LEVEL_4``.

    Returns
    -------
    dict of str to int
        Sorted by class path.
    """
    counts: dict[str, int] = {}
    for s in earthlib_library():
        m = s.metadata
        path = "/".join(m.get(f"level_{k}", "") for k in range(1, 5))
        counts[path] = counts.get(path, 0) + 1
    return dict(sorted(counts.items()))
