"""Generate radscene's bundled library of real sensors' spectral response functions (SRF).

Writes ``src/radscene/data/srf/<sensor>.csv`` (columns ``band``, ``wavelength_um``,
``response``) and ``src/radscene/data/srf/library.yaml`` (title, bands, original source and
extraction route of each sensor) from two packages that carry the agencies' published tables:

* ``Py6S`` (``pip install Py6S``; LGPL-3): the filter functions of
  ``Py6S.PredefinedWavelengths`` that carry tabulated values (Landsat 8 OLI, Sentinel-2A/B MSI,
  Terra/Aqua MODIS bands 1-16, Sentinel-3A/B OLCI and SLSTR S1-S6). Py6S stores each band as
  (start, end, values every 2.5 nm from start), resampled by Py6S to the 2.5 nm grid 6S needs.
* ``pyrsr`` (``pip install pyrsr``; Apache-2.0): its ``data/<satellite>/<sensor>/band_*``
  tables (Landsat 8/9 TIRS and Landsat 9 OLI-2, Landsat 7 ETM+, Landsat 5 TM, Terra ASTER),
  each with a ``reference`` file naming the agency spreadsheet it was taken from.

Only the numbers are taken (facts, with their sources in ``library.yaml``); no code. Two edits,
both recorded in ``library.yaml`` per sensor: tiny negative responses (measurement noise, down
to -3.4e-4 in OLI band 4) are set to 0, since a response is >= 0; and the Landsat 8 TIRS tables,
tabulated every 1 nm over 9-14 um, keep every 5th sample (5 nm), which changes their
equivalent widths by less than 0.05 % and keeps the renderer's quadrature small.

Run from the repository root: ``python scripts/build_srf_library.py``. Py6S and pyrsr are needed
only here, never at run time. The script loads every written band with
:func:`radscene.sensor.srf_library.get_sensor_bands` and fails if one does not.
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
        library[sensor] = {"title": spec["title"], "file": path.name, "source": source,
                           "via": via, "edits": edits, "bands": band_meta}
    return library


def _write_yaml(library: dict) -> None:
    import yaml

    header = ("# radscene's bundled spectral response functions: one entry per sensor.\n"
              "# Generated by scripts/build_srf_library.py; do not edit by hand.\n"
              "# source: where the numbers were first published; via: the package and table\n"
              "# they were read from; edits: what the build script changed.\n")
    text = yaml.safe_dump(library, sort_keys=False, allow_unicode=True, width=100)
    (OUT / "library.yaml").write_text(header + text, encoding="utf-8")


def main() -> int:
    library = build()
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
