"""Generate LOWTRAN7's own radiance of a Lambertian ground for the LOWTRAN closure test.

For each case LOWTRAN runs in radiance mode with solar scattering and multiple scattering
(IEMSCT = 2, IMULT = 1) along the line of sight from the observer down to the ground, whose
albedo is the plate's reflectance (card 1 SALB), over one band (card 4 V1, V2 at 5 cm-1); the
band radiance is TAPE6's ``INTEGRATED RADIANCE``: path radiance, scattered and thermal, plus
the ground's reflection of the direct sun and of LOWTRAN's diffuse flux, attenuated to the
observer, integrated over the band (trapezoid in wavenumber). Two more figures per band let
the test account for radscene's own solar spectrum, which lights the rendered plate's direct
sun: LOWTRAN's extraterrestrial band irradiance, the direct band irradiance on the ground
(an IEMSCT = 3 run) and the band-mean transmittance of the line of sight.

Shared: US Standard atmosphere (MODEL 6), rural (IHAZE 1) and maritime (IHAZE 4) aerosols at
23 and 5 km visibility, sea-level ground at 290 K (card 1 TBOUND, the rendered plate's
temperature), sun at 30 deg zenith, mean Earth-Sun distance (IDAY 0), Mie phase functions
(IPH 2); lines of sight from 99 km (LOWTRAN's atmosphere ends at 100 km, below which a
tilted camera's rays must start) and 3.5 km, nadir and 40 deg from the zenith at the ground,
90 deg in azimuth from the sun; rho 0, 0.2, 0.5; six bands from 0.45 to 2.2 um whose edges
lie on LOWTRAN's 5 cm-1 grid.

It does NOT import radscene: it writes its own card decks and runs the LOWTRAN7 executable
(``radscene-lowtran7``, built by ``make lowtran``; LOWTRAN7 with a driver that also writes
the spectra it computed, full precision, to ``radscene.out``). It writes
``tests/validation/lowtran_closure_references.py``, one case per line.

Run from the repository root:
    .venv/bin/python tests/validation/scripts/make_lowtran_closure_references.py [EXECUTABLE]
"""
import concurrent.futures
import datetime
import math
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[3]
OUT = ROOT / "tests" / "validation" / "lowtran_closure_references.py"
SETTINGS = S = dict(  # written verbatim as constants at the top of the generated module
    MODEL=6, AEROSOLS={"rural": 1, "maritime": 4}, TBOUND_K=290.0, VISIBILITIES_KM=(23.0, 5.0),
    SUN_ZENITH=30.0, RELATIVE_AZIMUTH=90.0,
    OBSERVERS_KM={"toa99km": 99.0, "air3500m": 3.5}, VIEW_ZENITHS=(0.0, 40.0),
    RHOS=(0.0, 0.2, 0.5),
    # band edges [cm-1] on LOWTRAN's grid: 0.44-0.46, 0.54-0.56, 0.65-0.67, 0.86-0.88,
    # 1.59-1.61, 2.19-2.21 um
    BANDS_CM1=((21740.0, 22725.0), (17860.0, 18515.0), (14925.0, 15385.0),
               (11365.0, 11625.0), (6210.0, 6290.0), (4525.0, 4565.0)),
    DV=5.0, EARTH_RADIUS_KM=6371.23)


def band_id(band):
    return f"b{1e4 / (0.5 * (band[0] + band[1])):.2f}"


def case_id(aerosol, vis, sensor, vz, band, rho):
    return f"{aerosol}-vis{vis:02.0f}-{sensor}-vz{vz:02.0f}-{band_id(band)}-r{rho:.2f}"


def card(fmt, *values):
    """One card: fmt is a list of (kind, width[, decimals]), kind 'i' or 'f'."""
    out = []
    for (kind, width, *dec), value in zip(fmt, values, strict=True):
        text = f"{int(value):d}" if kind == "i" else f"{float(value):.{dec[0]}f}"
        if len(text) > width:
            raise ValueError(f"{value!r} does not fit {width} columns")
        out.append(text.rjust(width))
    return "".join(out)


def deck(iemsct, h1, angle, band, ihaze, vis, salb=0.0, parm1=0.0, parm2=0.0):
    """TAPE5 of one run (LOWTRAN7 manual, cards 1, 2, 3 [, 3A1, 3A2], 4, 5)."""
    i5, f10 = ("i", 5), ("f", 10, 3)
    itype = 3 if iemsct == 3 else 2
    lines = [
        # MODEL ITYPE IEMSCT IMULT M1-M6 MDEF IM NOPRT TBOUND SALB: (13I5, F8.3, F7.2)
        card([i5] * 13 + [("f", 8, 3), ("f", 7, 2)], S["MODEL"], itype, iemsct,
             1 if iemsct == 2 else 0, 0, 0, 0, 0, 0, 0, 0, 0, 1, S["TBOUND_K"], salb),
        # IHAZE ISEASN IVULCN ICSTL ICLD IVSA VIS WSS WHH RAINRT GNDALT: (6I5, 5F10.3)
        card([i5] * 6 + [f10] * 5, ihaze, 0, 0, 0, 0, 0, vis, 0.0, 0.0, 0.0, 0.0),
    ]
    if iemsct == 3:  # H1 H2 ANGLE IDAY (5X) RO ISOURC ANGLEM: (3F10.3, I5, 5X, F10.3, I5, F10.3)
        lines.append(card([f10] * 3 + [i5], h1, 0.0, angle, 0) + " " * 5
                     + card([f10, i5, f10], 0.0, 0, 0.0))
    else:  # H1 H2 ANGLE RANGE BETA RO LEN: (6F10.3, I5)
        lines.append(card([f10] * 6 + [i5], h1, 0.0, angle, 0.0, 0.0, 0.0, 0))
        lines.append(card([i5] * 4, 2, 2, 0, 0))  # IPARM 2, IPH 2 (Mie), IDAY, ISOURC
        lines.append(card([f10] * 8, parm1, parm2, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0))
    lines.append(card([("f", 10, 1)] * 3, band[0], band[1], S["DV"]))
    lines.append(card([i5], 0))
    return "\n".join(lines) + "\n"


def run(executable, text, key):
    """(TAPE6's figure after ``key``, driver columns) of one deck, in its own directory."""
    with tempfile.TemporaryDirectory(prefix="lowtran-ref-") as tmp:
        work = Path(tmp)
        (work / "out").mkdir()
        for tape in ("TAPE6", "TAPE7", "TAPE8"):
            (work / "out" / tape).touch()
        (work / "TAPE5").write_text(text)
        subprocess.run([str(executable)], cwd=work, capture_output=True, timeout=300,
                       stdin=subprocess.DEVNULL, check=False)
        tape6 = (work / "out" / "TAPE6").read_text(errors="replace")
        rows = (work / "radscene.out").read_text().splitlines()
    found = [line for line in tape6.splitlines() if key in line]
    if not found or rows[-1].strip() != "# end":
        raise RuntimeError(f"LOWTRAN failed on\n{text}\n{tape6[-2000:]}")
    value = float(found[-1].split("=")[1].split()[0])
    data = np.array([[float(x) for x in r.split()] for r in rows[1:-1]])
    return value, data


def compact(value):
    """A figure as text, floats to 7 significant digits (LOWTRAN's single precision)."""
    return f"{value:.7g}" if isinstance(value, float) else repr(value)


def trapezoid(values, v):
    """LOWTRAN's band sum: DV times the samples, half at the ends."""
    w = np.full(v.size, S["DV"])
    w[0] = w[-1] = 0.5 * S["DV"]
    return float(np.sum(w * values))


def geometry(h_km, view_zenith):
    """(ANGLE at the observer, sun zenith at the observer) for a straight line of sight."""
    r = S["EARTH_RADIUS_KM"]
    alpha = math.degrees(math.asin(r * math.sin(math.radians(view_zenith)) / (r + h_km)))
    beta = math.radians(view_zenith - alpha)  # central angle, target to observer
    # relative azimuth 90 deg: the observer is displaced at right angles to the sun
    cos_sun = (math.cos(math.radians(S["SUN_ZENITH"])) * math.cos(beta)
               + math.sin(math.radians(S["SUN_ZENITH"])) * math.sin(beta)
               * math.cos(math.radians(S["RELATIVE_AZIMUTH"])))
    return 180.0 - alpha, math.degrees(math.acos(cos_sun))


def one_case(args):
    executable, aerosol, vis, sensor, vz, band, rho = args
    ihaze = S["AEROSOLS"][aerosol]
    h1 = S["OBSERVERS_KM"][sensor]
    angle, sun_obs = geometry(h1, vz)
    radiance, path = run(executable, deck(2, round(h1, 7), round(angle, 6), band, ihaze, vis, rho,
                                          S["RELATIVE_AZIMUTH"], round(sun_obs, 4)),
                          "INTEGRATED RADIANCE =")
    _, sun = run(executable, deck(3, 0.0, S["SUN_ZENITH"], band, ihaze, vis),
                 "INTEGRATED IRRADIANCE =")
    v = sun[:, 0]
    to_cm1 = 1e4 / v**2  # per um -> per cm-1
    mu_s = math.cos(math.radians(S["SUN_ZENITH"]))
    return case_id(aerosol, vis, sensor, vz, band, rho), {
        "aerosol": aerosol, "visibility_km": vis, "sensor": sensor, "view_zenith": vz, "band_cm1": band, "rho": rho,
        # W cm-2 sr-1 -> W m-2 sr-1; W cm-2 -> W m-2
        "band_radiance": radiance * 1e4,
        "toa_band_irradiance": trapezoid(sun[:, 5] * to_cm1, v) * 1e4,
        "direct_band_irradiance": mu_s * trapezoid(sun[:, 4] * to_cm1, v) * 1e4,
        "band_transmittance": float(np.mean(path[:, 2])),
    }


def main():
    executable = Path(sys.argv[1] if len(sys.argv) > 1 else os.environ.get(
        "RADSCENE_LOWTRAN", ROOT / "build" / "lowtran" / "radscene-lowtran7"))
    jobs = [(executable, aerosol, vis, sensor, vz, band, rho) for aerosol in S["AEROSOLS"]
            for vis in S["VISIBILITIES_KM"]
            for sensor in S["OBSERVERS_KM"] for vz in S["VIEW_ZENITHS"]
            for band in S["BANDS_CM1"] for rho in S["RHOS"]]
    start = time.time()
    with concurrent.futures.ThreadPoolExecutor(max_workers=2) as pool:
        cases = dict(pool.map(one_case, jobs))
    took = time.time() - start
    lines = [
        '"""LOWTRAN7\'s own radiance of a Lambertian ground, for the LOWTRAN closure test',
        "(generated: do not edit, rerun the script).",
        "",
        "Generated by tests/validation/scripts/make_lowtran_closure_references.py on "
        f"{datetime.date.today().isoformat()}: {2 * len(jobs)} LOWTRAN runs in {took:.0f} s.",
        "",
        "One case per line: the inputs that identify it, then ``band_radiance`` (TAPE6's",
        "integrated radiance of the line of sight down to a ground of albedo rho, W m-2 sr-1),",
        "``toa_band_irradiance`` and ``direct_band_irradiance`` (LOWTRAN's extraterrestrial and",
        "direct horizontal band irradiance, W m-2) and ``band_transmittance`` (the band-mean",
        "transmittance of the line of sight).",
        '"""',
        "",
    ]
    lines += [f"{k} = {v!r}" for k, v in S.items()]
    lines += ["", "CASES = {"]
    lines += [f"    {k!r}: {{{', '.join(f'{n!r}: {compact(x)}' for n, x in v.items())}}},"
              for k, v in sorted(cases.items())]
    lines += ["}", ""]
    OUT.write_text("\n".join(lines))
    print(f"{len(cases)} cases, {2 * len(jobs)} runs in {took:.0f} s -> {OUT}")


if __name__ == "__main__":
    main()
