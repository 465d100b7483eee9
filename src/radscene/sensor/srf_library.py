"""Real sensors' spectral response functions (SRF), bundled, and multi-band SRF files.

The library (``radscene/data/srf``) holds the published relative spectral responses
(``kind: measured`` in library.yaml) of:

=================  =============================================  =================================
name               bands                                          from (details in library.yaml)
=================  =============================================  =================================
landsat8_oli       B1-B9                                          NASA/Ball, via Py6S
landsat8_tirs      B10, B11                                       NASA/Ball, via pyrsr
landsat9_oli       B1-B9 (OLI-2)                                  NASA/Ball, via pyrsr
landsat9_tirs      B10, B11 (TIRS-2)                              NASA/Ball, via pyrsr
sentinel2a_msi     B1-B12, B8A                                    ESA S2-SRF, via Py6S
sentinel2b_msi     B1-B12, B8A                                    ESA S2-SRF, via Py6S
terra_modis        B1-B16 (reflective solar)                      NASA OBPG, via Py6S
aqua_modis         B1-B16 (reflective solar)                      NASA OBPG, via Py6S
sentinel3a_olci    Oa01-Oa21                                      ESA, via Py6S
sentinel3b_olci    Oa01-Oa21                                      ESA, via Py6S
sentinel3a_slstr   S1-S6                                          ESA pre-flight, via Py6S
sentinel3b_slstr   S1-S6                                          ESA pre-flight, via Py6S
landsat7_etm       B1-B8 (B6 thermal)                             NASA, via pyrsr
landsat5_tm        B1-B7 (B6 thermal)                             NASA, via pyrsr
terra_aster        B1, B2, B3N, B3B, B4-B14 (B10-B14 thermal)     NASA, via pyrsr
meteosat11_seviri  IR3.9, WV6.2, WV7.3, IR8.7, IR9.7, IR10.8,     EUMETSAT (MSG-4), via
                   IR12.0, IR13.4                                 eradiate-data
noaa20_viirs       M12-M16, I4, I5                                NOAA/NESDIS J1 at-launch RSR
                                                                  V2.1, via eradiate-data
metopb_avhrr3      3B, 4, 5                                       EUMETSAT NWP SAF (RTTOV v13),
                                                                  via eradiate-data
=================  =============================================  =================================

and, as band models (``kind: band model``: a trapezoid reaching 50 % at the band limits of the
instrument's published specification, with edges 10 % of the width wide — not a measured
response; the measured ones are not shipped):

=================  ==================================  ======================================
name               bands                               band limits from
=================  ==================================  ======================================
goes16_abi         B7-B16 (3.9-13.3 um)                Schmit et al. 2005, BAMS 86, Table 1
himawari_ahi       B01-B16 (0.47-13.3 um)              JMA/JAXA AHI channel set (Okamoto,
                                                       Kachi, Bessho); Bessho et al. 2016,
                                                       JMSJ 94, doi:10.2151/jmsj.2016-009
avhrr3             3B, 4, 5 (the AVHRR/3 series)       NOAA KLM User's Guide, section 3.1
=================  ==================================  ======================================

Each sensor's entry in ``library.yaml`` names the original publication or agency file
(``source``), the package, repository and table the numbers were read from (``via``), what the
build script (``scripts/build_srf_library.py``) changed (``edits``) and, for the tables read from
a repository, a ``licence`` note. Responses are linear between
samples and zero outside, as :class:`~radscene.radiometry.srf.TabulatedResponse`.

User files (:func:`read_srf_table`) hold several bands in one CSV/text table, either *wide*
(a wavelength column, then one column per band, blank or NaN where a band is not tabulated) or
*long* (columns ``band, wavelength, response``, the library's own format).

Config snippet (the lead's band schema)::

    bands:
      - {name: red, sensor: landsat8_oli, band: B4}
      - {name: tir1, sensor: landsat8_tirs, band: B10}
      - {name: mine, sensor: srf/my_camera.csv, band: G, wavelength_unit: nm}

Examples
--------
>>> bands = get_sensor_bands("landsat8_oli", ["B4", "B5"])
>>> [(name, round(r.center, 3)) for name, r in bands]
[('B4', 0.655), ('B5', 0.865)]
"""

from __future__ import annotations

import re
from functools import lru_cache
from importlib import resources
from pathlib import Path

import numpy as np

from radscene.errors import ConfigError, did_you_mean, unreadable
from radscene.radiometry.srf import TabulatedResponse

__all__ = [
    "list_sensors",
    "sensor_info",
    "get_sensor_bands",
    "get_band",
    "read_srf_table",
    "library_response",
    "resolve_responses",
]


def _data_dir() -> Path:
    return Path(str(resources.files("radscene") / "data" / "srf"))


@lru_cache(maxsize=1)
def _library() -> dict:
    import yaml

    path = _data_dir() / "library.yaml"
    with path.open(encoding="utf-8") as fh:
        return yaml.safe_load(fh)


def list_sensors() -> list[str]:
    """Names of the bundled sensors, in library order."""
    return list(_library())


def sensor_info(name: str) -> dict:
    """Metadata of a bundled sensor: title, file, kind (``measured`` or ``band model``, then
    with its ``shape``), source, via, edits and bands.

    Parameters
    ----------
    name : str
        A name of :func:`list_sensors` (case-insensitive).

    Returns
    -------
    dict
        A copy of the sensor's ``library.yaml`` entry.
    """
    key = _sensor_key(name)
    entry = dict(_library()[key])
    entry["bands"] = dict(entry["bands"])
    entry["name"] = key
    return entry


def _sensor_key(name) -> str:
    lib = _library()
    key = str(name).strip().lower()
    if key not in lib:
        raise ConfigError(f"unknown sensor {name!r}; known: {', '.join(lib)}"
                          f"{did_you_mean(name, lib)} (or the path of a "
                          "multi-band SRF file)", key="sensor")
    return key


def _split(line: str) -> list[str]:
    if re.search(r"[,;\t]", line):
        return [f.strip() for f in re.split(r"[,;\t]", line)]
    return line.split()


def _number(text: str) -> float:
    return float(text) if text not in ("", "nan", "NaN", "NA") else np.nan


@lru_cache(maxsize=64)
def _read_table(path: str, scale: float) -> tuple[tuple[str, np.ndarray, np.ndarray], ...]:
    """Bands of a wide or long SRF table: ((name, wavelength [um], response), ...)."""
    try:
        text = Path(path).read_text(encoding="utf-8-sig")
    except (OSError, UnicodeError) as exc:
        raise ConfigError(f"cannot read the SRF table: {unreadable(exc)}", key=path) from None
    header = None
    rows = []
    for lineno, line in enumerate(text.splitlines(), start=1):
        stripped = line.strip()
        if not stripped or stripped.startswith("#"):
            continue
        fields = _split(stripped)
        if header is None:
            header = fields
            if len(header) < 2:
                raise ConfigError(f"line {lineno}: a header of at least two columns "
                                  "(wavelength, band...) is needed", key=path)
            continue
        if len(fields) != len(header):
            raise ConfigError(f"line {lineno}: {len(fields)} fields, the header has "
                              f"{len(header)}", key=path)
        rows.append((lineno, fields))
    if header is None or not rows:
        raise ConfigError("no data rows after the header", key=path)
    lower = [h.lower() for h in header]
    out = []
    if lower[0] == "band":  # long: band, wavelength, response
        if len(header) != 3:
            raise ConfigError("a long table has exactly the columns band, wavelength, "
                              "response", key=path)
        groups: dict[str, list] = {}
        for lineno, (band, wl, resp) in rows:
            try:
                groups.setdefault(band, []).append((float(wl), float(resp)))
            except ValueError:
                raise ConfigError(f"line {lineno}: wavelength and response must be numbers",
                                  key=path) from None
        for band, values in groups.items():
            data = np.array(values)
            out.append((band, data[:, 0] * scale, data[:, 1]))
    else:  # wide: wavelength, band1, band2, ...
        try:
            data = np.array([[_number(f) for f in fields] for _, fields in rows])
        except ValueError:
            bad = next(n for n, f in rows if not all(_is_number(x) for x in f))
            raise ConfigError(f"line {bad}: every field must be a number (or blank)",
                              key=path) from None
        wl = data[:, 0] * scale
        for c, band in enumerate(header[1:], start=1):
            keep = np.isfinite(data[:, c]) & np.isfinite(wl)
            out.append((band, wl[keep], data[keep, c]))
    return tuple(out)


def _is_number(text: str) -> bool:
    try:
        _number(text)
    except ValueError:
        return False
    return True


def read_srf_table(path, wavelength_unit: str = "um", bands=None,
                   prefix: str | None = None) -> list[tuple[str, TabulatedResponse]]:
    """Read a multi-band SRF table (wide or long, see the module docstring).

    Parameters
    ----------
    path : str or path-like
        The CSV/text file; ``#`` lines are comments; fields separated by commas, semicolons,
        tabs or spaces.
    wavelength_unit : str
        Unit of the wavelength column (``"um"``, ``"nm"``, any wavelength unit of
        :func:`radscene.radiometry.units.parse_quantity`).
    bands : sequence of str, optional
        Only these bands, in this order (case-insensitive); default all, in file order.
    prefix : str, optional
        Prefix of the responses' names (``"<prefix> <band>"``); default the file's stem.

    Returns
    -------
    list of (str, TabulatedResponse)
        Band name and response.

    Raises
    ------
    ConfigError
        An unreadable or malformed file, an unknown band, or a band whose response is
        negative or does not integrate to a positive value; the key names the file and band.
    """
    from radscene.radiometry.units import parse_quantity

    scale = float(parse_quantity(f"1 {wavelength_unit}", "wavelength", key="wavelength_unit"))
    path = str(Path(path))
    table = _read_table(path, scale)
    prefix = Path(path).stem if prefix is None else prefix
    return _select(table, bands, prefix, where=path)


def _select(table, bands, prefix, where):
    names = [b for b, _, _ in table]
    if bands is None:
        chosen = list(range(len(table)))
    else:
        if isinstance(bands, str):
            bands = [bands]
        lookup = {n.lower(): i for i, n in enumerate(names)}
        chosen = []
        for b in bands:
            if str(b).lower() not in lookup:
                raise ConfigError(f"unknown band {b!r}; known: {', '.join(names)}"
                                  f"{did_you_mean(b, names)}",
                                  key=f"{where}.band")
            chosen.append(lookup[str(b).lower()])
    out = []
    for i in chosen:
        name, wl, resp = table[i]
        try:
            response = TabulatedResponse(wl, resp, name=f"{prefix} {name}")
        except ConfigError as err:
            raise ConfigError(err.message, key=f"{where}.{name}.{err.key}") from None
        out.append((name, response))
    return out


def get_sensor_bands(sensor, bands=None, wavelength_unit: str = "um"
                     ) -> list[tuple[str, TabulatedResponse]]:
    """Spectral responses of a bundled sensor, or of a user's multi-band SRF file.

    Parameters
    ----------
    sensor : str or path-like
        A bundled sensor (:func:`list_sensors`, case-insensitive), or the path of a
        multi-band table (anything with a path separator or an existing file).
    bands : sequence of str, optional
        Only these bands, in this order (case-insensitive); default all.
    wavelength_unit : str
        Unit of a user file's wavelength column; the library's are in um.

    Returns
    -------
    list of (str, TabulatedResponse)
        ``(band name, response)``; responses are named ``"<sensor> <band>"``.

    Examples
    --------
    >>> [name for name, _ in get_sensor_bands("landsat8_tirs")]
    ['B10', 'B11']
    """
    text = str(sensor)
    if isinstance(sensor, Path) or ("/" in text or "\\" in text) or Path(text).is_file():
        return read_srf_table(sensor, wavelength_unit, bands)
    key = _sensor_key(sensor)
    path = _data_dir() / _library()[key]["file"]
    return _select(_read_table(str(path), 1.0), bands, key, where=f"sensor {key}")


def get_band(sensor, band: str, wavelength_unit: str = "um") -> TabulatedResponse:
    """One band's response: ``get_band("landsat8_oli", "B4")``.

    Parameters
    ----------
    sensor : str or path-like
        As :func:`get_sensor_bands`.
    band : str
        Band name (case-insensitive).
    wavelength_unit : str
        Unit of a user file's wavelength column.

    Returns
    -------
    TabulatedResponse
    """
    return get_sensor_bands(sensor, [band], wavelength_unit)[0][1]


def library_response(spec, key: str = "response") -> TabulatedResponse:
    """A response from a mapping ``{type: library, sensor: <name or file>, band: <band>}``.

    ``type`` may be left out; ``wavelength_unit`` applies to a user file.

    Raises
    ------
    ConfigError
        Missing or unknown keys, unknown sensor or band (the key names the mapping).
    """
    allowed = {"type", "sensor", "band", "wavelength_unit"}
    if not isinstance(spec, dict) or not {"sensor", "band"} <= set(spec) or \
            str(spec.get("type", "library")).lower() != "library" or set(spec) - allowed:
        raise ConfigError(f"a library response is {{type: library, sensor: <name>, band: "
                          f"<band>}} (optionally wavelength_unit); got {spec!r}", key=key)
    try:
        return get_band(spec["sensor"], spec["band"], spec.get("wavelength_unit", "um"))
    except ConfigError as err:
        raise ConfigError(err.message, key=f"{key}.{err.key}" if err.key else key) from None


def resolve_responses(config, key: str = ""):
    """Copy of a sensor configuration with every library response made a response object.

    Walks ``response`` and ``bands.<band>.response`` of a sensor-chain mapping (the format of
    :func:`radscene.sensor.make_sensor`) and replaces each ``{type: library, ...}`` mapping
    (:func:`library_response`) by its :class:`TabulatedResponse`; other values are kept.

    Parameters
    ----------
    config : mapping
        A sensor configuration.
    key : str
        Key path of the mapping, for errors (``sensors.landsat``).

    Returns
    -------
    dict
    """
    import copy

    def is_library(value):
        return isinstance(value, dict) and "sensor" in value and \
            str(value.get("type", "library")).lower() == "library"

    out = copy.deepcopy(dict(config))
    prefix = f"{key}." if key else ""
    if is_library(out.get("response")):
        out["response"] = library_response(out["response"], f"{prefix}response")
    bands = out.get("bands")
    if isinstance(bands, dict):
        for band, override in bands.items():
            if isinstance(override, dict) and is_library(override.get("response")):
                override["response"] = library_response(
                    override["response"], f"{prefix}bands.{band}.response")
    return out
