"""Write radscene's TSIS-1 HSRS table, ``src/radscene/data/solar/tsis1_hsrs_v2_1nm.csv``.

Input: LASP's netCDF file of the TSIS-1 Hybrid Solar Reference Spectrum, version 2,
``hybrid_reference_spectrum_p1nm_resolution_c2022-11-30_with_unc.nc`` (0.1 nm resolution,
sampled every 0.025 nm over 202-2730 nm, vacuum wavelengths, W m-2 nm-1 at 1 AU; variables
``Vacuum Wavelength``, ``SSI``, ``SSI_UNC``). Its source and the copy it was read from are in
the header written below and in ``src/radscene/data/solar/README.md``.

Processing: the samples are averaged in 1 nm bins [n, n + 1) nm (40 samples each), written at
the bin centre n + 0.5 nm, and converted to W m-2 um-1. The sum of the bins times 1 nm is the
file's own integral (the sum of its samples times 0.025 nm), 1325.76 W m-2. Only the numbers are
taken (facts, with their sources); no code.

Run from the repository root: ``python scripts/build_solar_spectrum.py PATH/TO/FILE.nc``
(needs h5py, only here). The script checks the file's identity (its ``id`` attribute and the
sample grid) and that the written table integrates to the file's integral.
"""

from __future__ import annotations

import hashlib
import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
OUT = ROOT / "src" / "radscene" / "data" / "solar" / "tsis1_hsrs_v2_1nm.csv"
FILE_ID = "final-v2_hybrid_reference_spectrum_p1nm_resolution_c2022-11-30_with_unc.nc"
PER_BIN = 40  # 0.025 nm samples in a 1 nm bin

HEADER = """\
# TSIS-1 Hybrid Solar Reference Spectrum (HSRS), version 2 (2022-11-30), 1 nm bins, 202-2730 nm
# source: O. M. Coddington, E. C. Richard, D. Harber, P. Pilewskie, T. N. Woods, K. Chance, X. Liu
#   and K. Sun, The TSIS-1 Hybrid Solar Reference Spectrum, Geophys. Res. Lett. 48, e2020GL091709
#   (2021), doi:10.1029/2020GL091709; version 2: O. M. Coddington et al., Version 2 of the TSIS-1
#   Hybrid Solar Reference Spectrum and Extension to the Full Spectrum, Earth Space Sci. 10,
#   e2022EA002637 (2023), doi:10.1029/2022EA002637
# file: {name} (LASP LISIRD,
#   https://lasp.colorado.edu/lisird/data/tsis1_hsrs_p1nm; id {file_id}; created 2022-11-30;
#   0.1 nm resolution sampled every 0.025 nm, vacuum wavelengths), sha256 {sha256}
# via: the copy of that file in the public repository LIME-ESA/lime_tbx,
#   lime_tbx/business/lime_algorithms/lime/assets/ (commit d50173b86c037c79df72e94f3ced0c6572957efb)
# licence: data published by LASP (University of Colorado) for public use with citation of the
#   papers above; only the numbers are carried here, as facts with their source
# processing (scripts/build_solar_spectrum.py): mean of the 40 samples in each 1 nm bin
#   [n, n+1) nm, written at the bin centre n+0.5 nm; W m-2 nm-1 -> W m-2 um-1 (x 1000). The bins
#   times 1 nm sum to the file's integral, {total:.2f} W m-2 over 202-2730 nm.
# columns: wavelength_um (vacuum, bin centre), irradiance_w_m2_um (at 1 AU),
#   uncertainty_w_m2_um (the file's SSI_UNC averaged over the bin)
wavelength_um,irradiance_w_m2_um,uncertainty_w_m2_um
"""


def main() -> int:
    import h5py

    if len(sys.argv) != 2:
        raise SystemExit(__doc__)
    path = Path(sys.argv[1])
    raw = path.read_bytes()
    with h5py.File(path, "r") as f:
        file_id = f.attrs["id"].decode()
        if file_id != FILE_ID:
            raise SystemExit(f"not the HSRS v2 0.1 nm file: id {file_id!r}")
        wl = f["Vacuum Wavelength"][:].astype(float)
        ssi = f["SSI"][:].astype(float)
        unc = f["SSI_UNC"][:].astype(float)
    if not np.allclose(wl, 202.0 + 0.025 * np.arange(wl.size), atol=1e-6) or wl.size % PER_BIN:
        raise SystemExit("unexpected wavelength grid")
    total = float(ssi.sum() * 0.025)
    mean = ssi.reshape(-1, PER_BIN).mean(axis=1) * 1e3  # W m-2 um-1
    mean_unc = unc.reshape(-1, PER_BIN).mean(axis=1) * 1e3
    centre = (202.5 + np.arange(mean.size)) / 1e3  # um
    if abs(mean.sum() * 1e-3 / total - 1.0) > 1e-9:
        raise SystemExit("binning changed the integral")
    OUT.parent.mkdir(parents=True, exist_ok=True)
    with OUT.open("w", encoding="utf-8", newline="\n") as fh:
        fh.write(HEADER.format(name=path.name, file_id=file_id, total=total,
                               sha256=hashlib.sha256(raw).hexdigest()))
        for w, e, u in zip(centre, mean, mean_unc, strict=True):
            fh.write(f"{w:.4f},{e:.6g},{u:.3g}\n")
    # what is written, re-read: the rounding to 6 digits keeps the integral to < 1e-6
    data = np.loadtxt(OUT, delimiter=",", comments="#", skiprows=HEADER.count("\n"))
    change = abs(data[:, 1].sum() * 1e-3 / total - 1.0)
    if change > 1e-6:
        raise SystemExit(f"written table changes the integral by {change:.1e}")
    print(f"{OUT}: {mean.size} bins {centre[0]:.4f}-{centre[-1]:.4f} um, "
          f"integral {total:.3f} W m-2")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
