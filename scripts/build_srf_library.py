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

* ``band model``: thermal infrared imagers whose measured responses are not on this machine
  (GOES-16 ABI bands 7-16, Meteosat-11 SEVIRI IR3.9-IR13.4, NOAA-20 VIIRS M12-M16 and I4-I5,
  AVHRR/3 channels 3B, 4 and 5): a trapezoid built from the band limits the instrument's
  published specification gives (:data:`BAND_MODELS`, each with its document). The trapezoid
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
only the band models (no package needed) and keeps the measured entries of ``library.yaml``.
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
    "meteosat11_seviri": {
        "title": "Meteosat-11 SEVIRI, infrared channels IR3.9-IR13.4, band model (the nominal "
                 "channels of every MSG SEVIRI)",
        "source": "SEVIRI channel limits (lambda_min, lambda_max): J. Schmetz et al., An "
                  "introduction to Meteosat Second Generation (MSG), Bull. Amer. Meteor. Soc. "
                  "83, 977-992 (2002), Table 1",
        "bands": [("IR3.9", 3.48, 4.36, "shortwave window"),
                  ("WV6.2", 5.35, 7.15, "upper-level water vapour"),
                  ("WV7.3", 6.85, 7.85, "mid-level water vapour"),
                  ("IR8.7", 8.30, 9.10, "window, cloud phase"),
                  ("IR9.7", 9.38, 9.94, "ozone"),
                  ("IR10.8", 9.80, 11.80, "longwave window"),
                  ("IR12.0", 11.00, 13.00, "split window"),
                  ("IR13.4", 12.40, 14.40, "CO2")],
    },
    "noaa20_viirs": {
        "title": "NOAA-20 VIIRS, thermal bands M12-M16, I4, I5, band model (the VIIRS design "
                 "bands, shared with S-NPP)",
        "source": "VIIRS design band centres and bandwidths: C. Cao et al., Early on-orbit "
                  "performance of the Visible Infrared Imaging Radiometer Suite onboard the "
                  "Suomi National Polar-Orbiting Partnership (S-NPP) satellite, IEEE Trans. "
                  "Geosci. Remote Sens. 52, 1142-1156 (2014), Table I",
        "centres": {"M12": 3.70, "M13": 4.05, "M14": 8.55, "M15": 10.763, "M16": 12.013,
                    "I4": 3.74, "I5": 11.45},
        "bands": [("M12", 3.61, 3.79, "MWIR window (3.70 um, 0.180 um wide)"),
                  ("M13", 3.9725, 4.1275, "MWIR window, fires (4.05 um, 0.155 um wide)"),
                  ("M14", 8.40, 8.70, "cloud-top phase (8.55 um, 0.3 um wide)"),
                  ("M15", 10.263, 11.263, "LWIR window (10.763 um, 1.0 um wide)"),
                  ("M16", 11.538, 12.488, "split window (12.013 um, 0.95 um wide)"),
                  ("I4", 3.55, 3.93, "imagery MWIR (3.74 um, 0.38 um wide)"),
                  ("I5", 10.50, 12.40, "imagery LWIR (11.45 um, 1.9 um wide)")],
    },
    "avhrr3": {
        "title": "AVHRR/3 (NOAA-15 to -19, MetOp-A to -C), thermal channels 3B, 4, 5, band model",
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
    """The measured entries of the present library.yaml (kind set), for --band-models."""
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
    measured = _measured_entries() if "--band-models" in sys.argv[1:] else build()
    library = {**measured, **build_band_models()}
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
