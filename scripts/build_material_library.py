"""Generate the spectra of radscene's built-in material library.

Writes ``src/radscene/data/materials/<material>.csv`` (columns ``wavelength_um``,
``reflectance`` = total hemispherical reflectance, and for water ``specular_reflectance``) from

* VSWIR, 0.40-2.45 um: measured (or, for green vegetation, PROSAIL-modelled) spectra of the
  ``earthlib`` package (``pip install earthlib``; MIT licence). For each material a group of
  earthlib spectra is selected by the rule in ``RECIPES`` and the group's *medoid* is kept: the one
  measured spectrum closest (RMS over all bands) to the per-band median of the group. It is a real
  spectrum, named in the file header and in ``library.yaml``. The earthlib bands in the water-vapour
  absorption regions (1.36-1.45 um, 1.80-1.95 um) are absent; the library's piecewise-linear
  spectra interpolate linearly across them.
* Thermal, 3-20 um: reflectance = 1 - emissivity with the assumed emissivity nodes of
  ``sources/thermal_emissivity.csv``.
* Join: between the last VSWIR point (2.45 um) and the first thermal node (3.0 um) the
  reflectance is linear in wavelength (nothing is tabulated there).
* water: specular reflectance = Fresnel reflectance at normal incidence from the Hale & Querry
  (1973) optical constants (``sources/water_nk_hale_querry_1973.csv``), 0.4-20 um; diffuse
  reflectance from ``sources/water_diffuse_reflectance.csv`` (assumed).
* bare_aluminium: 0.36-2.48 um Fresnel reflectance at normal incidence from Rakic (1995)
  (``sources/aluminium_nk_rakic_1995.csv``); 3-20 um from the assumed emissivity table.

Run from the repository root: ``python scripts/build_material_library.py``. It checks that every
selected earthlib spectrum is named in ``library.yaml``'s ``source`` of its material, and that every
library material loads and obeys Kirchhoff's law, and fails otherwise. earthlib is needed only here,
never at run time.
"""

from __future__ import annotations

import argparse
import re
import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
DATA = ROOT / "src" / "radscene" / "data" / "materials"
SOURCES = DATA / "sources"

#: Selection rule of each material's earthlib group: a filter on earthlib's metadata table.
RECIPES = {
    "green_vegetation": {
        "rule": "PROSAIL canopy spectra with 3 <= LAI <= 6 and 30 <= CHL <= 60 ug cm-2",
        "select": lambda m: (
            (m.SOURCE == "prosail")
            & m.NAME.map(
                lambda s: 3.0 <= _param(s, "LAI") <= 6.0 and 30.0 <= _param(s, "CHL") <= 60.0
            )
        ),
    },
    "dry_grass": {
        "rule": "JFSP dead/cured grass spectra deadgras, goldgras, brte_br",
        "select": lambda m: m.NAME.isin(["deadgras", "goldgras", "brte_br"]),
    },
    "bare_soil": {
        "rule": "Santa Barbara urban library bare soil, names lrxnxx.*",
        "select": lambda m: m.NAME.str.startswith("lrxnxx"),
    },
    "sand": {
        "rule": "Santa Barbara urban library beach sand, names lbxsxx.*",
        "select": lambda m: m.NAME.str.startswith("lbxsxx"),
    },
    "asphalt": {
        "rule": "Santa Barbara urban library asphalt road surfaces, class road, names rpa*",
        "select": lambda m: (m.LEVEL_3 == "road") & m.NAME.str.startswith("rpa"),
    },
    "concrete": {
        "rule": "Santa Barbara urban library concrete sidewalks, class sidewalk, names spc*",
        "select": lambda m: (m.LEVEL_3 == "sidewalk") & m.NAME.str.startswith("spc"),
    },
    "painted_metal": {
        "rule": "Santa Barbara urban library metal roofs, class metal, names fhzgmg.*",
        "select": lambda m: (m.LEVEL_3 == "metal") & m.NAME.str.startswith("fhzgmg"),
    },
    "roof_tile": {
        "rule": "Santa Barbara urban library red clay roof tiles, class tile, names fttr*",
        "select": lambda m: (m.LEVEL_3 == "tile") & m.NAME.str.startswith("fttr"),
    },
}

VSWIR_MAX = 2.45  # last earthlib band [um]


def _param(name: str, label: str) -> float:
    match = re.search(rf"{label}-([0-9.]+)", name)
    return float(match.group(1)) if match else float("nan")


def fresnel_normal(n, k):
    """Reflectance at normal incidence of a medium of index n + ik from air [-]."""
    return ((n - 1.0) ** 2 + k**2) / ((n + 1.0) ** 2 + k**2)


def read_csv(path: Path):
    """Header and float rows of a radscene source CSV ('#' comments)."""
    lines = [ln for ln in path.read_text().splitlines() if ln.strip() and not ln.startswith("#")]
    header = lines[0].split(",")
    data = np.array([[float(v) for v in ln.split(",")] for ln in lines[1:]])
    return header, data


def thermal_reflectance(material: str):
    header, data = read_csv(SOURCES / "thermal_emissivity.csv")
    return data[:, 0], 1.0 - data[:, header.index(material)]


def load_earthlib():
    import earthlib
    import pandas as pd
    from earthlib import config, read

    spectra, names, sensor = read.envi_library(config.full_endmember_path)
    meta = pd.read_csv(config.full_metadata_path)
    if len(meta) != len(names):
        raise SystemExit("earthlib metadata and spectra differ in length")
    wavelength = np.round(np.asarray(sensor.band_centers, dtype=float), 4)
    return earthlib.__version__, np.asarray(spectra, dtype=float), meta, wavelength


def medoid(group: np.ndarray) -> int:
    """Index (in ``group``) of the spectrum closest in RMS to the per-band median."""
    median = np.median(group, axis=0)
    rms = np.sqrt(np.mean((group - median) ** 2, axis=1))
    return int(np.argmin(rms))


def write_csv(path: Path, comments: list[str], columns: dict[str, np.ndarray]):
    names = list(columns)
    rows = np.column_stack([columns[n] for n in names])
    with path.open("w", encoding="utf-8", newline="\n") as f:
        for c in comments:
            f.write(f"# {c}\n")
        f.write(",".join(names) + "\n")
        for row in rows:
            f.write(f"{row[0]:.4f}," + ",".join(f"{v:.6f}" for v in row[1:]) + "\n")


def build_earthlib_materials(selected: dict):
    version, spectra, meta, wavelength = load_earthlib()
    keep = wavelength <= VSWIR_MAX + 1e-9
    for material, recipe in RECIPES.items():
        mask = np.asarray(recipe["select"](meta), dtype=bool)
        idx = np.flatnonzero(mask)
        if idx.size == 0:
            raise SystemExit(f"{material}: recipe selected no earthlib spectrum")
        best = int(idx[medoid(spectra[idx][:, keep])])
        row = meta.iloc[best]
        vswir = spectra[best, keep]
        if np.any(vswir <= 0.0) or np.any(vswir >= 1.0):
            raise SystemExit(f"{material}: earthlib spectrum {row.NAME} leaves (0, 1)")
        wl_t, rho_t = thermal_reflectance(material)
        wl = np.concatenate([wavelength[keep], wl_t])
        rho = np.concatenate([vswir, rho_t])
        selected[material] = row.NAME
        write_csv(
            DATA / f"{material}.csv",
            [
                f"radscene built-in material '{material}' - generated by "
                "scripts/build_material_library.py; do not edit by hand.",
                "reflectance: total hemispherical reflectance [-] (rho_d + rho_s).",
                f"0.40-{VSWIR_MAX:.2f} um: earthlib {version} spectrum '{row.NAME}' (row {best} of "
                f"earthlib's full library spectra.sli), original library: {row.SOURCE} / {row.NOTES}, "
                f"class {row.LEVEL_1}/{row.LEVEL_2}/{row.LEVEL_3}/{row.LEVEL_4}.",
                f"It is the medoid of {idx.size} spectra selected as: {recipe['rule']}.",
                "3.0-20 um: 1 - emissivity, assumed values of sources/thermal_emissivity.csv.",
                f"{VSWIR_MAX:.2f}-3.0 um: linear in wavelength (no tabulated point).",
            ],
            {"wavelength_um": wl, "reflectance": rho},
        )
        print(f"{material:17s} {row.NAME:40s} row {best:5d}  (medoid of {idx.size})")


def build_water():
    _, nk = read_csv(SOURCES / "water_nk_hale_querry_1973.csv")
    _, diffuse = read_csv(SOURCES / "water_diffuse_reflectance.csv")
    wl = np.union1d(nk[:, 0], diffuse[:, 0])
    wl = wl[(wl >= 0.4) & (wl <= 20.0)]
    rho_s = fresnel_normal(np.interp(wl, nk[:, 0], nk[:, 1]), np.interp(wl, nk[:, 0], nk[:, 2]))
    rho_d = np.interp(wl, diffuse[:, 0], diffuse[:, 1])
    write_csv(
        DATA / "water.csv",
        [
            "radscene built-in material 'water' - generated by scripts/build_material_library.py; "
            "do not edit by hand.",
            "specular_reflectance: Fresnel reflectance at normal incidence, ((n-1)^2+k^2)/((n+1)^2+k^2),",
            "  from Hale & Querry (1973) n, k (sources/water_nk_hale_querry_1973.csv), n and k",
            "  interpolated linearly where only the diffuse table has a point.",
            "reflectance: specular_reflectance + assumed diffuse reflectance "
            "(sources/water_diffuse_reflectance.csv).",
        ],
        {"wavelength_um": wl, "reflectance": rho_s + rho_d, "specular_reflectance": rho_s},
    )
    print(f"{'water':17s} Fresnel(Hale & Querry 1973) + assumed diffuse")


def build_aluminium():
    _, nk = read_csv(SOURCES / "aluminium_nk_rakic_1995.csv")
    vswir = nk[nk[:, 0] <= 2.5]
    rho_v = fresnel_normal(vswir[:, 1], vswir[:, 2])
    wl_t, rho_t = thermal_reflectance("bare_aluminium")
    write_csv(
        DATA / "bare_aluminium.csv",
        [
            "radscene built-in material 'bare_aluminium' - generated by "
            "scripts/build_material_library.py; do not edit by hand.",
            "reflectance: total hemispherical reflectance [-].",
            "0.36-2.48 um: Fresnel reflectance at normal incidence of clean aluminium from Rakic "
            "(1995) n, k (sources/aluminium_nk_rakic_1995.csv).",
            "3.0-20 um: 1 - emissivity, assumed flat emissivity of sources/thermal_emissivity.csv.",
            "2.48-3.0 um: linear in wavelength (no tabulated point).",
        ],
        {
            "wavelength_um": np.concatenate([vswir[:, 0], wl_t]),
            "reflectance": np.concatenate([rho_v, rho_t]),
        },
    )
    print(f"{'bare_aluminium':17s} Fresnel(Rakic 1995) + assumed thermal emissivity")


def verify(selected: dict):
    import yaml

    sys.path.insert(0, str(ROOT / "src"))
    from radscene.materials import library

    info = yaml.safe_load((DATA / "library.yaml").read_text())["materials"]
    for material, name in selected.items():
        if name not in info[material]["source"]:
            raise SystemExit(
                f"library.yaml: the source of {material} must name earthlib spectrum {name!r}"
            )
    library.clear_cache()
    grid = np.linspace(0.4, 20.0, 2000)
    for name in library.list_materials():
        comps = library.get_material(name).components(grid)
        total = comps["diffuse_reflectance"] + comps["specular_reflectance"]
        total = total + comps["transmittance"] + comps["emissivity"]
        assert np.allclose(total, 1.0, rtol=1e-12), name
    print(f"verified {len(library.list_materials())} materials on 0.4-20 um")


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--no-verify", action="store_true", help="skip the library.yaml check")
    args = parser.parse_args(argv)
    selected: dict = {}
    build_earthlib_materials(selected)
    build_water()
    build_aluminium()
    if not args.no_verify:
        verify(selected)


if __name__ == "__main__":
    main()
