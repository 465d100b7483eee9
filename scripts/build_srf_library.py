"""Generate radscene's bundled library of real sensors' spectral response functions (SRF).

Writes ``src/radscene/data/srf/<sensor>.csv`` (columns ``band``, ``wavelength_um``,
``response``) and ``src/radscene/data/srf/library.yaml`` (title, kind, bands, original source
and extraction route of each sensor). Each entry's ``kind`` says what its responses are:

* ``measured``: the agencies' published relative spectral responses, from two packages that
  carry their tables:

* ``Py6S`` (``pip install Py6S``; LGPL-3): the filter functions of
  ``Py6S.PredefinedWavelengths`` that carry tabulated values (Landsat 8 OLI, Sentinel-2A/B MSI,
  Terra/Aqua MODIS bands 1-16, Sentinel-3A/B OLCI and SLSTR S1-S6). Py6S stores each band as
  (start, end, values every 2.5 nm from start), resampled by Py6S to the 2.5 nm grid 6S needs.
* ``pyrsr`` (``pip install pyrsr``; Apache-2.0): its ``data/<satellite>/<sensor>/band_*``
  tables (Landsat 8/9 TIRS and Landsat 9 OLI-2, Landsat 7 ETM+, Landsat 5 TM, Terra ASTER),
  each with a ``reference`` file naming the agency spreadsheet it was taken from.

* ``measured`` too, the thermal imagers of :data:`NETCDF_SENSORS` (Meteosat-11 SEVIRI
  IR3.9-IR13.4, NOAA-20 VIIRS M12-M16, I4, I5, MetOp-B AVHRR/3 3B, 4, 5): the agencies' tables
  as the public repository ``eradiate/eradiate-data`` stores them, one netCDF file per band
  (``spectra/srf/<platform>-<instrument>-<band>-raw.nc``: wavelength ``w`` [nm], ``srf``; the
  file's ``comment`` names the agency file). Those files are not in a package: give the folder
  holding them with ``--netcdf DIR`` (taken from that repository's history, at the commits in
  :data:`NETCDF_SENSORS`); without it their entries of ``library.yaml`` are kept as they are.
  Edit: samples before the first and after the last within 1e-3 of the peak are dropped
  (the tables run far into the out-of-band floor), keeping one sample below on each side;
  equivalent widths change by < 0.1 %.
* ``band model``: imagers whose measured responses are not on this machine (GOES-16 ABI bands
  7-16, Himawari-8/9 AHI bands 1-16, the AVHRR/3 series' channels 3B, 4 and 5): a trapezoid
  built from the band limits the instrument's published specification gives
  (:data:`BAND_MODELS`, each with its document). The trapezoid
  reaches 50 % at the published limits, with linear edges each ``RAMP`` (10 %) of the band's
  width wide, centred on the limits: its full width at half maximum and its equivalent width
  are the published width, its centroid the middle of the limits. The edge width is
  radscene's modelling choice, not a published figure; the measured responses differ in
  shape (and by up to a few hundredths of a micrometre in centroid).

Only the numbers are taken (facts, with their sources in ``library.yaml``); no code. Two edits,
both recorded in ``library.yaml`` per sensor: tiny negative responses (measurement noise, down
to -3.4e-4 in OLI band 4) are set to 0, since a response is >= 0; and the Landsat 8 TIRS tables,
tabulated every 1 nm over 9-14 um, keep every 5th sample (5 nm), which changes their
equivalent widths by less than 0.05 % and keeps the renderer's quadrature small.

Run from the repository root: ``python scripts/build_srf_library.py``. Py6S and pyrsr are needed
only here, never at run time; ``python scripts/build_srf_library.py --band-models`` rewrites
only the band models (no package needed) and keeps the measured entries of ``library.yaml``;
``--netcdf DIR`` (with either) rewrites the sensors of :data:`NETCDF_SENSORS` from the files in
DIR (needs h5py).
The script loads every written band with :func:`radscene.sensor.srf_library.get_sensor_bands`
and fails if one does not.
"""

from __future__ import annotations

import importlib.metadata
import importlib.resources
import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
OUT = ROOT / "src" / "radscene" / "data" / "srf"

OLI_NAMES = {"B1": "coastal aerosol", "B2": "blue", "B3": "green", "B4": "red", "B5": "NIR",
             "B6": "SWIR 1", "B7": "SWIR 2", "B8": "panchromatic", "B9": "cirrus"}
TIRS_NAMES = {"B10": "TIR 1 (10.9 um)", "B11": "TIR 2 (12.0 um)"}
S2_BANDS = ["01", "02", "03", "04", "05", "06", "07", "08", "8A", "09", "10", "11", "12"]

#: Every sensor: title, original source, and the bands as (band name, extractor argument).
SENSORS = {
    "landsat8_oli": {
        "title": "Landsat 8 Operational Land Imager (OLI), band-average RSR",
        "source": "NASA/Ball Aerospace OLI pre-launch relative spectral response (Barsi et al. "
                  "2014, Remote Sens. 6, 10232-10251, doi:10.3390/rs61010232), spreadsheet "
                  "from landsat.gsfc.nasa.gov",
        "py6s": [(f"B{i}", f"LANDSAT_OLI_B{i}") for i in range(1, 10)],
        "names": OLI_NAMES,
    },
    "landsat8_tirs": {
        "title": "Landsat 8 Thermal Infrared Sensor (TIRS), band-average RSR",
        "pyrsr": ("Landsat-8/OLI_TIRS", [("B10", "band_10"), ("B11", "band_11")]),
        "thin": 5,
        "names": TIRS_NAMES,
    },
    "landsat9_oli": {
        "title": "Landsat 9 Operational Land Imager 2 (OLI-2), band-average RSR",
        "pyrsr": ("Landsat-9/OLI_TIRS", [(f"B{i}", f"band_{i}") for i in range(1, 10)]),
        "names": OLI_NAMES,
    },
    "landsat9_tirs": {
        "title": "Landsat 9 Thermal Infrared Sensor 2 (TIRS-2), band-average RSR",
        "pyrsr": ("Landsat-9/OLI_TIRS", [("B10", "band_10"), ("B11", "band_11")]),
        "names": TIRS_NAMES,
    },
    "sentinel2a_msi": {
        "title": "Sentinel-2A MultiSpectral Instrument (MSI)",
        "source": "ESA, Sentinel-2 spectral response functions, document "
                  "COPE-GSEG-EOPG-TN-15-0007 (S2-SRF), from earth.esa.int",
        "py6s": [(f"B{b.lstrip('0')}", f"S2A_MSI_{b}") for b in S2_BANDS],
    },
    "sentinel2b_msi": {
        "title": "Sentinel-2B MultiSpectral Instrument (MSI)",
        "source": "ESA, Sentinel-2 spectral response functions, document "
                  "COPE-GSEG-EOPG-TN-15-0007 (S2-SRF), from earth.esa.int",
        "py6s": [(f"B{b.lstrip('0')}", f"S2B_MSI_{b}") for b in S2_BANDS],
    },
    "terra_modis": {
        "title": "Terra MODIS, reflective solar bands 1-16",
        "source": "NASA Ocean Biology Processing Group, HMODIST_RSRs.txt "
                  "(oceancolor.gsfc.nasa.gov/docs/rsr/)",
        "py6s": [(f"B{i}", f"ACCURATE_MODIS_TERRA_{i}") for i in range(1, 17)],
    },
    "aqua_modis": {
        "title": "Aqua MODIS, reflective solar bands 1-16",
        "source": "NASA Ocean Biology Processing Group, HMODISA_RSRs.txt "
                  "(oceancolor.gsfc.nasa.gov/docs/rsr/)",
        "py6s": [(f"B{i}", f"ACCURATE_MODIS_AQUA_{i}") for i in range(1, 17)],
    },
    "sentinel3a_olci": {
        "title": "Sentinel-3A Ocean and Land Colour Instrument (OLCI), mean SRF",
        "source": "ESA, Sentinel-3 OLCI spectral response function data (mean dataset), from "
                  "sentinel.esa.int",
        "py6s": [(f"Oa{i:02d}", f"S3A_OLCI_{i:02d}") for i in range(1, 22)],
    },
    "sentinel3b_olci": {
        "title": "Sentinel-3B Ocean and Land Colour Instrument (OLCI), mean SRF",
        "source": "ESA, Sentinel-3 OLCI spectral response function data (mean dataset), from "
                  "sentinel.esa.int",
        "py6s": [(f"Oa{i:02d}", f"S3B_OLCI_{i:02d}") for i in range(1, 22)],
    },
    "sentinel3a_slstr": {
        "title": "Sentinel-3A SLSTR, solar channels S1-S6 (pre-flight)",
        "source": "ESA, SLSTR pre-flight spectral response functions",
        "py6s": [(f"S{i}", f"S3A_SLSTR_{i:02d}") for i in range(1, 7)],
    },
    "sentinel3b_slstr": {
        "title": "Sentinel-3B SLSTR, solar channels S1-S6 (pre-flight)",
        "source": "ESA, SLSTR pre-flight spectral response functions",
        "py6s": [(f"S{i}", f"S3B_SLSTR_{i:02d}") for i in range(1, 7)],
    },
    "landsat7_etm": {
        "title": "Landsat 7 Enhanced Thematic Mapper Plus (ETM+)",
        "pyrsr": ("Landsat-7/ETM+", [("B1", "band_1"), ("B2", "band_2"), ("B3", "band_3"),
                                     ("B4", "band_4"), ("B5", "band_5"), ("B6", "band_6L"),
                                     ("B7", "band_7"), ("B8", "band_8")]),
        "note": "band 6 low and high gain (6L, 6H) share one response",
    },
    "landsat5_tm": {
        "title": "Landsat 5 Thematic Mapper (TM)",
        "pyrsr": ("Landsat-5/TM", [(f"B{i}", f"band_{i}") for i in range(1, 8)]),
    },
    "terra_aster": {
        "title": "Terra ASTER: VNIR, SWIR and TIR bands",
        "pyrsr": ("Terra/ASTER", [("B1", "band_1"), ("B2", "band_2"), ("B3N", "band_3N"),
                                  ("B3B", "band_3B")]
                  + [(f"B{i}", f"band_{i}") for i in range(4, 15)]),
    },
}

#: Thermal imagers from the netCDF tables of github.com/eradiate/eradiate-data: title, the
#: agency source, the repository commit the files were taken from, and the bands as (name,
#: file stem, common name).
ERADIATE_DATA = "github.com/eradiate/eradiate-data"
#: What may be done with these numbers: the agencies publish them for public use; the
#: repository states no licence of its own for its files.
NETCDF_LICENCE = ("agency data published for public use, cited above; carried as numbers (facts) "
                  "with their source; eradiate-data states no licence of its own for them")
NETCDF_SENSORS = {
    "meteosat11_seviri": {
        "title": "Meteosat-11 (MSG-4) SEVIRI, infrared channels IR3.9-IR13.4",
        "source": "EUMETSAT, MSG SEVIRI spectral response characterisation, "
                  "https://www.eumetsat.int/media/8871 (MSG-4's table, 0.011-0.04 um steps)",
        "commit": "cc6539bfbbf2487854b059c3c256cf8fa8429a67^ (the raw IR tables, removed there)",
        "bands": [("IR3.9", "msg4-seviri-ir39", "shortwave window"),
                  ("WV6.2", "msg4-seviri-ir62", "upper-level water vapour"),
                  ("WV7.3", "msg4-seviri-ir73", "mid-level water vapour"),
                  ("IR8.7", "msg4-seviri-ir87", "window, cloud phase"),
                  ("IR9.7", "msg4-seviri-ir97", "ozone"),
                  ("IR10.8", "msg4-seviri-ir108", "longwave window"),
                  ("IR12.0", "msg4-seviri-ir120", "split window"),
                  ("IR13.4", "msg4-seviri-ir134", "CO2")],
    },
    "noaa20_viirs": {
        "title": "NOAA-20 (JPSS-1) VIIRS, thermal bands M12-M16, I4, I5, at-launch RSR",
        "source": "NOAA/NESDIS, J1 (NOAA-20) VIIRS relative spectral response, DAWG at-launch "
                  "public release V2.1 (Nov 2016; Northrop Grumman measurements, 2011-10), "
                  "https://ncc.nesdis.noaa.gov/NOAA-20/docs/"
                  "J1_VIIRS_RSR_DAWG_At-Launch_Public_Release_V2.1_Nov2016.zip",
        "commit": "b27de31f81904b78c0786c0d33734ecf2d4b087c^ (that commit moved the files out)",
        "bands": [("M12", "jpss1-viirs-m12", "MWIR window (3.70 um)"),
                  ("M13", "jpss1-viirs-m13", "MWIR window, fires (4.05 um)"),
                  ("M14", "jpss1-viirs-m14", "cloud-top phase (8.55 um)"),
                  ("M15", "jpss1-viirs-m15", "LWIR window (10.763 um)"),
                  ("M16", "jpss1-viirs-m16", "split window (12.013 um)"),
                  ("I4", "jpss1-viirs-i4", "imagery MWIR (3.74 um)"),
                  ("I5", "jpss1-viirs-i5", "imagery LWIR (11.45 um)")],
    },
    "metopb_avhrr3": {
        "title": "MetOp-B AVHRR/3, thermal channels 3B, 4, 5",
        "source": "EUMETSAT NWP SAF, RTTOV v13 spectral response functions of MetOp-B AVHRR/3, "
                  "https://nwp-saf.eumetsat.int/downloads/rtcoef_rttov13/ir_srf/"
                  "rtcoef_metop_1_avhrr_srf/rtcoef_metop_1_avhrr_srf.tar.gz",
        "commit": "b27de31f81904b78c0786c0d33734ecf2d4b087c^ (that commit moved the files out)",
        "bands": [("3B", "metop_b-avhrr-3b", "MWIR window (3.7 um)"),
                  ("4", "metop_b-avhrr-4", "LWIR window (10.8 um)"),
                  ("5", "metop_b-avhrr-5", "split window (12.0 um)")],
    },
}
#: Relative response below which the ends of a netCDF table are dropped.
TRIM = 1e-3

#: Width of each linear edge of a band model's trapezoid, as a fraction of the band's width.
RAMP = 0.10

#: Thermal imagers as band models: title, source document, and the bands as (name, lower and
#: upper band limit [um] of the published specification, common name); ``centres``: the
#: centre wavelengths [um] the documents give (else the middle of the limits is recorded).
BAND_MODELS = {
    "goes16_abi": {
        "title": "GOES-16 Advanced Baseline Imager (ABI), infrared bands 7-16, band model",
        "source": "ABI band limits (bandwidths): T. J. Schmit et al., "
                  "Introducing the next-generation Advanced Baseline Imager on GOES-R, Bull. "
                  "Amer. Meteor. Soc. 86, 1079-1096 (2005), doi:10.1175/BAMS-86-8-1079, "
                  "Table 1; central wavelengths: T. J. Schmit et al., A closer look at the ABI "
                  "on the GOES-R series, Bull. Amer. Meteor. Soc. 98, 681-698 (2017), "
                  "doi:10.1175/BAMS-D-15-00230.1",
        "bands": [("B7", 3.80, 4.00, "shortwave window (3.9 um)"),
                  ("B8", 5.77, 6.60, "upper-level water vapour (6.2 um)"),
                  ("B9", 6.75, 7.15, "mid-level water vapour (6.9 um)"),
                  ("B10", 7.24, 7.44, "lower-level water vapour (7.3 um)"),
                  ("B11", 8.30, 8.70, "cloud-top phase (8.5 um)"),
                  ("B12", 9.42, 9.80, "ozone (9.6 um)"),
                  ("B13", 10.10, 10.60, "clean longwave window (10.3 um)"),
                  ("B14", 10.80, 11.60, "longwave window (11.2 um)"),
                  ("B15", 11.80, 12.80, "dirty longwave window (12.3 um)"),
                  ("B16", 13.00, 13.60, "CO2 longwave (13.3 um)")],
        "centres": {"B7": 3.90, "B8": 6.185, "B9": 6.95, "B10": 7.34, "B11": 8.50,
                    "B12": 9.61, "B13": 10.35, "B14": 11.20, "B15": 12.30, "B16": 13.30},
    },
    "himawari_ahi": {
        "title": "Himawari-8/9 Advanced Himawari Imager (AHI), bands 1-16, band model",
        "source": "AHI band limits: JMA and JAXA (K. Okamoto, M. Kachi, K. Bessho), "
                  "Himawari-8,9/AHI channel set; the instrument: K. Bessho et al., An "
                  "introduction to Himawari-8/9 - Japan's new-generation geostationary "
                  "meteorological satellites, J. Meteor. Soc. Japan 94, 151-183 (2016), "
                  "doi:10.2151/jmsj.2016-009; nominal central wavelengths: JMA, Himawari-8/9 "
                  "Himawari Standard Data User's Guide, version 1.3 (2017), Table 1",
        "bands": [("B01", 0.43, 0.48, "blue (0.47 um nominal)"),
                  ("B02", 0.50, 0.52, "green (0.51 um nominal)"),
                  ("B03", 0.63, 0.66, "red (0.64 um nominal)"),
                  ("B04", 0.85, 0.87, "NIR (0.86 um nominal)"),
                  ("B05", 1.60, 1.62, "SWIR snow/ice (1.6 um nominal)"),
                  ("B06", 2.25, 2.27, "SWIR particle size (2.3 um nominal)"),
                  ("B07", 3.74, 3.96, "shortwave window (3.9 um nominal)"),
                  ("B08", 6.06, 6.43, "upper-level water vapour (6.2 um nominal)"),
                  ("B09", 6.89, 7.01, "mid-level water vapour (6.9 um nominal)"),
                  ("B10", 7.26, 7.43, "lower-level water vapour (7.3 um nominal)"),
                  ("B11", 8.44, 8.76, "cloud phase, SO2 (8.6 um nominal)"),
                  ("B12", 9.54, 9.72, "ozone (9.6 um nominal)"),
                  ("B13", 10.30, 10.60, "clean longwave window (10.4 um nominal)"),
                  ("B14", 11.10, 11.30, "longwave window (11.2 um nominal)"),
                  ("B15", 12.20, 12.50, "dirty longwave window (12.4 um nominal)"),
                  ("B16", 13.20, 13.40, "CO2 longwave (13.3 um nominal)")],
    },
    "avhrr3": {
        "title": "AVHRR/3 (NOAA-15 to -19, MetOp-A to -C), thermal channels 3B, 4, 5, band model "
                 "(the series' nominal channels; MetOp-B measured: metopb_avhrr3)",
        "source": "AVHRR/3 channel limits: NOAA KLM User's Guide (NOAA NESDIS), section 3.1, "
                  "AVHRR/3 spectral channel characteristics",
        "bands": [("3B", 3.55, 3.93, "MWIR window"),
                  ("4", 10.30, 11.30, "LWIR window"),
                  ("5", 11.50, 12.50, "split window")],
    },
}


def _py6s_band(constant: str):
    from Py6S import PredefinedWavelengths

    _, start, _end, values = getattr(PredefinedWavelengths, constant)
    values = np.asarray(values, dtype=float)
    return start + 0.0025 * np.arange(values.size), values


def _pyrsr_root():
    return importlib.resources.files("pyrsr") / "data"


def _pyrsr_band(folder: str, stem: str):
    text = (_pyrsr_root() / folder / stem).read_text(encoding="utf-8")
    rows = []
    for number, line in enumerate(text.splitlines()):
        parts = line.split()
        if number == 0 or not parts or parts[0].startswith("#"):
            continue
        rows.append((float(parts[0]), float(parts[1])))
    data = np.array(rows)
    wl = data[:, 0] / 1000.0 if data[:, 0].max() > 100.0 else data[:, 0]  # nm or um
    order = np.argsort(wl)
    return wl[order], data[order, 1]


def _pyrsr_reference(folder: str) -> str:
    text = (_pyrsr_root() / folder / "reference").read_text(encoding="utf-8")
    fields = dict(line.split(":", 1) for line in text.splitlines() if ":" in line)
    return (f"{fields.get('AUTHORSHIP', '?').strip()}, {fields.get('URL', '?').strip()} "
            f"({fields.get('DATE', '?').strip()})")


def build() -> dict:
    OUT.mkdir(parents=True, exist_ok=True)
    versions = {p: importlib.metadata.version(p) for p in ("Py6S", "pyrsr")}
    library = {}
    for sensor, spec in SENSORS.items():
        edits = []
        rows = []
        if "py6s" in spec:
            bands = [(name, *_py6s_band(const)) for name, const in spec["py6s"]]
            source = spec["source"]
            via = (f"Py6S {versions['Py6S']}, Py6S.PredefinedWavelengths."
                   f"{{{', '.join(c for _, c in spec['py6s'])}}} (2.5 nm grid)")
        else:
            folder, items = spec["pyrsr"]
            bands = [(name, *_pyrsr_band(folder, stem)) for name, stem in items]
            source = _pyrsr_reference(folder)
            via = f"pyrsr {versions['pyrsr']}, pyrsr/data/{folder}/band_*"
        thin = spec.get("thin")
        band_meta = {}
        for name, wl, resp in bands:
            if thin:
                keep = np.zeros(wl.size, dtype=bool)
                keep[::thin] = True
                keep[-1] = True
                before = np.trapezoid(resp, wl)
                wl, resp = wl[keep], resp[keep]
                change = abs(np.trapezoid(resp, wl) / before - 1.0)
                if change > 5e-4:
                    raise SystemExit(f"{sensor} {name}: thinning changed the width by {change:.1e}")
            negative = resp < 0
            if negative.any():
                edits.append(f"{name}: {int(negative.sum())} negative values (min "
                             f"{resp.min():.2e}) set to 0")
                resp = np.where(negative, 0.0, resp)
            rows.extend((name, w, r) for w, r in zip(wl, resp, strict=True))
            meta = {}
            if name in spec.get("names", {}):
                meta["common_name"] = spec["names"][name]
            band_meta[name] = meta
        if thin:
            edits.append(f"every {thin}th sample of the 1 nm table kept (equivalent widths "
                         "change < 0.05 %)")
        if "note" in spec:
            edits.append(spec["note"])
        path = OUT / f"{sensor}.csv"
        with path.open("w", encoding="utf-8", newline="\n") as fh:
            fh.write(f"# {spec['title']}\n# source: {source}\n# via: {via}\n")
            fh.write("# generated by scripts/build_srf_library.py; relative response, "
                     "dimensionless\n")
            fh.write("band,wavelength_um,response\n")
            for name, w, r in rows:
                fh.write(f"{name},{w:.6f},{r:.6g}\n")
        library[sensor] = {"title": spec["title"], "file": path.name, "kind": "measured",
                           "source": source, "via": via, "edits": edits, "bands": band_meta}
    return library


def _netcdf_band(path):
    """(wavelength [um], response, comment) of one eradiate-data SRF file."""
    import h5py

    with h5py.File(path, "r") as f:
        wl = f["w"][:].astype(float)
        unit = f["w"].attrs.get("units", b"nm")
        resp = f["srf"][:].astype(float)
        comment = f.attrs.get("comment", b"")
    unit = unit.decode() if isinstance(unit, bytes) else str(unit)
    comment = comment.decode() if isinstance(comment, bytes) else str(comment)
    if unit != "nm":
        raise SystemExit(f"{path}: wavelength unit {unit!r}, expected nm")
    return wl / 1000.0, resp, comment


def build_netcdf(folder) -> dict:
    """Write the sensors of NETCDF_SENSORS from the eradiate-data files in ``folder``."""
    from pathlib import Path

    folder = Path(folder)
    library = {}
    for sensor, spec in NETCDF_SENSORS.items():
        rows, band_meta, changes, comments = [], {}, [], set()
        for name, stem, common in spec["bands"]:
            wl, resp, comment = _netcdf_band(folder / f"{stem}-raw.nc")
            comments.add(comment)
            if np.any(resp < 0):
                raise SystemExit(f"{sensor} {name}: negative responses")
            resp = resp / resp.max()
            keep = np.flatnonzero(resp >= TRIM)
            lo, hi = max(keep[0] - 1, 0), min(keep[-1] + 1, wl.size - 1)
            before = np.trapezoid(resp, wl)
            wl, resp = wl[lo:hi + 1], resp[lo:hi + 1]
            change = abs(np.trapezoid(resp, wl) / before - 1.0)
            if change > 1e-3:
                raise SystemExit(f"{sensor} {name}: trimming changed the width by {change:.1e}")
            changes.append(change)
            rows.extend((name, w, r) for w, r in zip(wl, resp, strict=True))
            band_meta[name] = {"common_name": common}
        via = (f"{ERADIATE_DATA} at commit {spec['commit']}: spectra/srf/"
               f"{{{', '.join(stem for _, stem, _ in spec['bands'])}}}-raw.nc; their comment: "
               + "; ".join(sorted(comments)))
        edits = [f"samples beyond the first and last within {TRIM:g} of the peak dropped (one "
                 f"kept on each side); equivalent widths change < {max(changes):.1e}"]
        path = OUT / f"{sensor}.csv"
        with path.open("w", encoding="utf-8", newline="\n") as fh:
            fh.write(f"# {spec['title']}\n# source: {spec['source']}\n# via: {via}\n")
            fh.write(f"# licence: {NETCDF_LICENCE}\n# edits: {edits[0]}\n")
            fh.write("# generated by scripts/build_srf_library.py; relative response, "
                     "dimensionless\n")
            fh.write("band,wavelength_um,response\n")
            for name, w, r in rows:
                fh.write(f"{name},{w:.6f},{r:.6g}\n")
        library[sensor] = {"title": spec["title"], "file": path.name, "kind": "measured",
                           "source": spec["source"], "via": via, "licence": NETCDF_LICENCE,
                           "edits": edits, "bands": band_meta}
    return library


def band_model(lower: float, upper: float):
    """(wavelength [um], response) of the trapezoid of a band model: 0.5 at the limits,
    linear edges RAMP of the width wide centred on them, 1 between."""
    half = 0.5 * RAMP * (upper - lower)
    return (np.array([lower - half, lower + half, upper - half, upper + half]),
            np.array([0.0, 1.0, 1.0, 0.0]))


def build_band_models() -> dict:
    """Write the band models' CSV files; their library entries."""
    library = {}
    shape = (f"trapezoid: 50 % response at the published band limits (taken as the "
             f"half-maximum points), linear edges each {RAMP:.0%} of the band's width wide "
             "centred on the limits (radscene's choice); a band model, not a measured response")
    for sensor, spec in BAND_MODELS.items():
        path = OUT / f"{sensor}.csv"
        band_meta = {}
        with path.open("w", encoding="utf-8", newline="\n") as fh:
            fh.write(f"# {spec['title']}\n# source: {spec['source']}\n")
            fh.write(f"# BAND MODEL, NOT A MEASURED RESPONSE. Shape: {shape}\n")
            fh.write("# generated by scripts/build_srf_library.py; relative response, "
                     "dimensionless\n")
            fh.write("band,wavelength_um,response\n")
            for name, lower, upper, common in spec["bands"]:
                for w, r in zip(*band_model(lower, upper), strict=True):
                    fh.write(f"{name},{w:.6f},{r:.6g}\n")
                published = spec.get("centres", {})
                band_meta[name] = {
                    "common_name": common, "band_limits_um": [lower, upper],
                    "center_um": published.get(name, round(0.5 * (lower + upper), 6)),
                    "center_from": ("the source" if name in published
                                    else "the middle of the limits")}
        library[sensor] = {"title": spec["title"], "file": path.name, "kind": "band model",
                           "shape": shape, "source": spec["source"],
                           "via": "band model written by scripts/build_srf_library.py",
                           "edits": [], "bands": band_meta}
    return library


def _measured_entries() -> dict:
    """The measured entries of the present library.yaml (kind set), for --band-models and the
    netCDF sensors without --netcdf."""
    import yaml

    old = yaml.safe_load((OUT / "library.yaml").read_text(encoding="utf-8"))
    out = {}
    for sensor, entry in old.items():
        if sensor in BAND_MODELS or entry.get("kind") == "band model":
            continue
        entry = {k: v for k, v in entry.items() if k != "kind"}
        items = list(entry.items())
        at = [k for k, _ in items].index("file") + 1
        out[sensor] = dict(items[:at] + [("kind", "measured")] + items[at:])
    return out


def _write_yaml(library: dict) -> None:
    import yaml

    header = ("# radscene's bundled spectral response functions: one entry per sensor.\n"
              "# Generated by scripts/build_srf_library.py; do not edit by hand.\n"
              "# source: where the numbers were first published; via: the package and table\n"
              "# they were read from; edits: what the build script changed; kind: measured\n"
              "# (a published relative spectral response) or band model (a trapezoid over\n"
              "# the published band limits, see shape).\n")
    text = yaml.safe_dump(library, sort_keys=False, allow_unicode=True, width=100)
    (OUT / "library.yaml").write_text(header + text, encoding="utf-8")


def main() -> int:
    args = sys.argv[1:]
    old = _measured_entries()
    measured = old if "--band-models" in args else build()
    if "--netcdf" in args:
        netcdf = build_netcdf(args[args.index("--netcdf") + 1])
    else:
        missing = [name for name in NETCDF_SENSORS if name not in old]
        if missing:
            raise SystemExit(f"{', '.join(missing)} not in library.yaml yet: give --netcdf DIR")
        netcdf = {name: old[name] for name in NETCDF_SENSORS}
    measured = {k: v for k, v in measured.items() if k not in NETCDF_SENSORS}
    library = {**measured, **netcdf, **build_band_models()}
    _write_yaml(library)
    sys.path.insert(0, str(ROOT / "src"))
    from radscene.sensor.srf_library import get_sensor_bands

    total = 0
    for sensor in library:
        bands = get_sensor_bands(sensor)
        total += len(bands)
        print(f"{sensor:18s} {len(bands):2d} bands: "
              + ", ".join(f"{n} {r.center:.3f}" for n, r in bands))
    print(f"{len(library)} sensors, {total} bands written to {OUT}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
