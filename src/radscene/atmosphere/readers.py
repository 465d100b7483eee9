"""Readers of other radiative-transfer codes' output: MODTRAN ``tape7`` and libRadtran
``uvspec``, into the Dataset form of radscene's atmosphere engines.

The form (the same as :meth:`radscene.atmosphere.lowtran.LowtranAtmosphere.line_of_sight`):
a coordinate ``wavelength`` [um], increasing, with ``wavenumber`` [cm-1] alongside; spectral
radiance in W m-2 sr-1 um-1, spectral irradiance in W m-2 um-1, transmittance [1]; each
variable with ``units`` and ``long_name``; the source file and the format read in the
attributes.

MODTRAN tape7 — format assumed (MODTRAN 4 and 5, one or more runs per file):

* header lines (the card images) until a line that names the first column ``FREQ``
  (wavenumber, cm-1) or ``WAVLEN`` (wavelength: µm, or nm when the header says ``NM``);
* IEMSCT = 0 (transmittance): two header lines, names and units (``FREQ COMBIN H2O UMIX
  ...`` over ``1/CM TRANS TRANS ...``); IEMSCT = 1, 2 (radiance): one line, ``FREQ
  TOT_TRANS PTH_THRML THRML_SCT SURF_EMIS SOL_SCAT SING_SCAT GRND_RFLT DRCT_RFLT TOTAL_RAD
  REF_SOL SOL@OBS DEPTH DIR_EM TOA_SUN BBODY_T[K]`` (MODTRAN 4 may write the two-word
  names with a space instead of ``_``); in IEMSCT = 1 the solar columns have headers but
  no numbers; IEMSCT = 3 (solar irradiance): ``FREQ TRANS SOL TR SOLAR DEPTH``;
* numbers, one spectral sample a line, until ``-9999.``;
* IEMSCT is read from columns 11-15 of the first card image (LOWTRAN format) or 13-15
  (MODTRAN 4/5 card 1, ``MODTRN SPEED [BINARY]`` first); it may be given instead;
* units: per wavenumber, W cm-2 sr-1 (cm-1)-1 for radiance and W cm-2 (cm-1)-1 for
  irradiance; per µm (``WAVLEN`` in µm), W cm-2 sr-1 µm-1; per nm, µW cm-2 sr-1 nm-1
  (MODTRAN's ``N`` units flag). ``radiance_unit`` overrides.

libRadtran uvspec — format assumed (the default output, ``output_user`` not set):

* per wavelength: ``lambda edir edn eup uavgdir uavgdn uavgup`` on one line;
* with ``umu`` and ``phi`` in the input, then a line of the phi values and, per umu, a line
  ``umu u0u uu(phi_1) ... uu(phi_n)``; with ``umu`` only, lines ``umu u0u``;
* lambda in nm; irradiances and radiances in the units of the extraterrestrial spectrum,
  mW m-2 nm-1 for libRadtran's solar atlases (numerically W m-2 µm-1); with
  ``output_quantity transmittance`` they are divided by the extraterrestrial irradiance
  (``edir`` = μ0 τ_dir), with ``reflectance`` also by μ0/π;
* ``umu``, ``phi``, ``sza`` and ``output_quantity`` are read from the uvspec input file when
  it is given, or passed as arguments. umu > 0 looks up (libRadtran's convention); the
  view zenith given alongside is arccos(umu). phi is kept in libRadtran's convention.
"""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np

from radscene.errors import ConfigError, unreadable

__all__ = ["read_modtran_tape7", "read_uvspec", "parse_uvspec_input"]

_RADIANCE = "W m-2 sr-1 um-1"
_IRRADIANCE = "W m-2 um-1"


def _read_text(path, key: str) -> tuple[Path, str]:
    p = Path(path).expanduser()
    if not p.is_file():
        raise ConfigError(f"no such file: {p}", key=key)
    return p, p.read_text(errors="replace")


def _dataset(wavelength, variables: dict, attrs: dict):
    """Dataset over increasing wavelength [um] from {name: (values, units, long_name)}."""
    import xarray as xr

    wl = np.asarray(wavelength, dtype=float)
    order = np.argsort(wl, kind="stable")
    data = {}
    for name, (values, units, long_name) in variables.items():
        values = np.asarray(values, dtype=float)
        dims = ("wavelength",) + tuple(f"{name}_dim{i}" for i in range(values.ndim - 1))
        if isinstance(long_name, tuple):  # (long_name, extra dims)
            long_name, dims = long_name
        data[name] = (dims, values[order], {"units": units, "long_name": long_name})
    coords = {
        "wavelength": ("wavelength", wl[order], {"units": "um", "long_name": "wavelength"}),
        "wavenumber": ("wavelength", 1e4 / wl[order], {"units": "cm-1",
                                                       "long_name": "wavenumber"}),
    }
    return xr.Dataset(data, coords=coords, attrs=attrs)


# -- MODTRAN tape7 -------------------------------------------------------------------------------
_TWO_WORD = ("TOT TRANS", "PTH THRML", "THRML SCT", "SURF EMIS", "SOL SCAT", "SING SCAT",
             "GRND RFLT", "DRCT RFLT", "TOTAL RAD", "REF SOL", "SOL TR", "DIR EM", "TOA SUN")

#: tape7 radiance-mode columns → (radscene name, long name, kind).
_TAPE7_RADIANCE = {
    "TOT_TRANS": ("transmittance", "path transmittance", "1"),
    "PTH_THRML": ("path_emitted_radiance", "thermal emission of the path", "L"),
    "THRML_SCT": ("path_thermal_scattered_radiance", "thermal radiance scattered into the path",
                  "L"),
    "SURF_EMIS": ("surface_emitted_radiance", "surface emission through the path", "L"),
    "SOL_SCAT": ("path_scattered_radiance", "scattered solar path radiance", "L"),
    "SING_SCAT": ("single_scattered_radiance", "single-scattered solar path radiance", "L"),
    "GRND_RFLT": ("ground_reflected_radiance", "ground-reflected radiance through the path",
                  "L"),
    "DRCT_RFLT": ("direct_reflected_radiance", "ground-reflected direct sunlight", "L"),
    "TOTAL_RAD": ("total_radiance", "total radiance at the observer", "L"),
    "TOA_SUN": ("toa_irradiance", "extraterrestrial solar irradiance", "E"),
}
#: tape7 transmittance-mode columns (name and unit line joined by "_") → radscene name.
_TAPE7_TRANSMITTANCE = {
    "COMBIN_TRANS": "transmittance", "H2O_TRANS": "h2o_transmittance",
    "UMIX_TRANS": "uniformly_mixed_transmittance", "O3_TRANS": "o3_transmittance",
    "TRACE_TRANS": "trace_transmittance", "N2_CONT": "n2_continuum_transmittance",
    "H2O_CONT": "h2o_continuum_transmittance", "MOLEC_SCAT": "rayleigh_transmittance",
    "AER+CLD_TRANS": "aerosol_cloud_transmittance", "HNO3_TRANS": "hno3_transmittance",
    "CO2_TRANS": "co2_transmittance", "CO_TRANS": "co_transmittance",
    "CH4_TRANS": "ch4_transmittance", "N2O_TRANS": "n2o_transmittance",
    "O2_TRANS": "o2_transmittance", "CLOUD_TRANS": "cloud_transmittance",
}


def _split_runs(lines: list[str]) -> list[list[str]]:
    runs, current = [], []
    for line in lines:
        current.append(line)
        if line.strip() in ("-9999.", "-9999", "-9999.0"):
            runs.append(current)
            current = []
    if any(line.strip() for line in current):
        runs.append(current)
    return runs


def _is_number(token: str) -> bool:
    try:
        float(token)
    except ValueError:
        return False
    return True


def read_modtran_tape7(path, run: int = 0, iemsct: int | None = None,
                       radiance_unit: str | None = None):
    """Read one run of a MODTRAN tape7 file (format in the module docstring).

    Parameters
    ----------
    path : path
        The tape7 (``.tp7``) file.
    run : int
        Which run of a multi-run file (0 the first).
    iemsct : int, optional
        MODTRAN's mode (0 transmittance, 1 thermal radiance, 2 with sunlight, 3 solar
        irradiance), when card 1 is not the first line.
    radiance_unit : str, optional
        Units of the file's radiance columns: ``"W cm-2 sr-1 (cm-1)-1"``,
        ``"W cm-2 sr-1 um-1"`` or ``"uW cm-2 sr-1 nm-1"``; default from the spectral column.

    Returns
    -------
    xarray.Dataset
        Over ``wavelength`` [um]: ``transmittance`` and, in radiance mode,
        ``path_thermal_radiance`` (emitted + thermal scattered), ``path_scattered_radiance``
        (solar), ``path_radiance`` and every other tape7 column under a descriptive name
        [W m-2 sr-1 um-1]; in mode 3 ``sun_transmittance`` and
        ``direct_solar_irradiance``, ``toa_irradiance`` [W m-2 um-1]; in mode 0 the
        component transmittances.
    """
    p, text = _read_text(path, "path")
    runs = _split_runs(text.splitlines())
    if not runs:
        raise ConfigError(f"{p}: empty file", key="path")
    if not 0 <= run < len(runs):
        raise ConfigError(f"{p} holds {len(runs)} run(s); got run={run}", key="run")
    lines = runs[run]
    if iemsct is None:
        iemsct = _tape7_iemsct(lines[0], p)
    if iemsct not in (0, 1, 2, 3):
        raise ConfigError(f"IEMSCT must be 0-3; got {iemsct}", key="iemsct")
    head = next((i for i, line in enumerate(lines)
                 if re.match(r"^\s*(FREQ|WAVLEN)", line.upper())), None)
    if head is None:
        raise ConfigError(f"{p}: no column header (a line starting with FREQ or WAVLEN)",
                          key="path")
    header = lines[head].upper()
    for two in _TWO_WORD:
        header = header.replace(two, two.replace(" ", "_"))
    names = header.split()
    start = head + 1
    units_line = ""
    if start < len(lines) and not _is_number(lines[start].split()[0] if lines[start].split()
                                             else "x"):
        units_line = lines[start].upper()
        start += 1
    rows = []
    for line in lines[start:]:
        tokens = line.split()
        if not tokens or tokens[0] in ("-9999.", "-9999", "-9999.0"):
            continue
        if not all(_is_number(t) for t in tokens):
            raise ConfigError(f"{p}: a data line holds something other than numbers", key="path")
        rows.append([float(t) for t in tokens])
    if not rows:
        raise ConfigError(f"{p}: no spectral data after the header", key="path")
    width = min(len(r) for r in rows)
    data = np.array([r[:width] for r in rows])
    spectral = names[0]
    if spectral == "FREQ":
        wavenumber = data[:, 0]
        if np.any(wavenumber <= 0):
            raise ConfigError(f"{p}: wavenumbers must be > 0 cm-1", key="path")
        wavelength = 1e4 / wavenumber
        default_unit = "W cm-2 sr-1 (cm-1)-1"
    else:
        nm = "NM" in header or "NM" in units_line
        wavelength = data[:, 0] / 1e3 if nm else data[:, 0]
        default_unit = "uW cm-2 sr-1 nm-1" if nm else "W cm-2 sr-1 um-1"
    unit = radiance_unit or default_unit
    to_per_um = _tape7_unit_factor(unit, wavelength)
    attrs = {"source": str(p), "format": "MODTRAN tape7", "iemsct": iemsct, "run": run,
             "radiance_unit_read": unit}

    if iemsct == 0:
        units = units_line.split()
        if len(units) == len(names):  # names over units: join them ("H2O" over "CONT")
            keys = [f"{n}_{u}" for n, u in zip(names, units, strict=True)]
        else:
            keys = [f"{n}_TRANS" for n in names]
        variables = {}
        for j, key in enumerate(keys[1:width], start=1):
            target = _TAPE7_TRANSMITTANCE.get(key)
            if target and target not in variables:
                variables[target] = (data[:, j], "1", key.lower().replace("_", " "))
        if "transmittance" not in variables:  # the total is always the second column
            variables["transmittance"] = (data[:, 1], "1", "total transmittance")
        return _dataset(wavelength, variables, attrs)
    if iemsct == 3:
        if width < 4:
            raise ConfigError(f"{p}: IEMSCT 3 needs FREQ TRANS SOL_TR SOLAR columns", key="path")
        variables = {
            "sun_transmittance": (data[:, 1], "1", "sun-to-observer transmittance"),
            "direct_solar_irradiance": (data[:, 2] * to_per_um, _IRRADIANCE,
                                        "transmitted direct solar irradiance"),
            "toa_irradiance": (data[:, 3] * to_per_um, _IRRADIANCE,
                               "extraterrestrial solar irradiance"),
        }
        return _dataset(wavelength, variables, attrs)
    # radiance modes: columns with numbers are the first ones; in mode 1 the solar
    # columns carry headers only, so map names to numbers in order, skipping those
    solar_only = {"SOL_SCAT", "SING_SCAT", "DRCT_RFLT", "REF_SOL", "SOL@OBS", "TOA_SUN"}
    present = [n for n in names[1:] if not (iemsct == 1 and n in solar_only)]
    variables = {}
    for j, name in enumerate(present[: width - 1], start=1):
        if name not in _TAPE7_RADIANCE:
            continue
        target, long_name, kind = _TAPE7_RADIANCE[name]
        scale = 1.0 if kind == "1" else to_per_um
        units = {"1": "1", "L": _RADIANCE, "E": _IRRADIANCE}[kind]
        variables[target] = (data[:, j] * scale, units, long_name)
    if "transmittance" not in variables:
        raise ConfigError(f"{p}: no TOT_TRANS column in the header", key="path")
    n = wavelength.size
    emitted = variables.get("path_emitted_radiance", (np.zeros(n),))[0]
    thermal_sct = variables.get("path_thermal_scattered_radiance", (np.zeros(n),))[0]
    solar = variables.get("path_scattered_radiance", (np.zeros(n),))[0]
    variables["path_thermal_radiance"] = (emitted + thermal_sct, _RADIANCE,
                                          "thermal path radiance, emitted + scattered")
    variables.setdefault("path_scattered_radiance", (solar, _RADIANCE,
                                                     "scattered solar path radiance"))
    variables["path_radiance"] = (emitted + thermal_sct + solar, _RADIANCE,
                                  "path radiance, thermal + scattered")
    return _dataset(wavelength, variables, attrs)


def _tape7_iemsct(first: str, p: Path) -> int:
    """IEMSCT from card 1, columns 11-15 in LOWTRAN (13I5) and MODTRAN 4/5 alike."""
    try:
        return int(first[10:15])
    except ValueError:
        raise ConfigError(f"{p}: cannot read IEMSCT from columns 11-15 of the first line; "
                          "give iemsct=", key="iemsct") from None


def _tape7_unit_factor(unit: str, wavelength: np.ndarray) -> np.ndarray:
    """Factor from the file's spectral radiance unit to W m-2 (sr-1) um-1."""
    u = unit.replace(" ", "").lower()
    if u in ("wcm-2sr-1(cm-1)-1", "wcm-2(cm-1)-1", "wcm-2sr-1/cm-1"):
        # L_lambda = L_nu * nu^2 / 1e4 per um (nu in cm-1); W cm-2 -> W m-2: * 1e4
        return (1e4 / wavelength) ** 2
    if u in ("wcm-2sr-1um-1", "wcm-2um-1"):
        return np.full_like(wavelength, 1e4)
    if u in ("uwcm-2sr-1nm-1", "uwcm-2nm-1"):
        return np.full_like(wavelength, 1e-6 * 1e4 * 1e3)
    raise ConfigError(f"unknown radiance unit {unit!r}; known: 'W cm-2 sr-1 (cm-1)-1', "
                      "'W cm-2 sr-1 um-1', 'uW cm-2 sr-1 nm-1'", key="radiance_unit")


# -- libRadtran uvspec ---------------------------------------------------------------------------
def parse_uvspec_input(path) -> dict:
    """The settings of a uvspec input file that shape its output.

    Returns
    -------
    dict
        ``umu`` and ``phi`` (lists), ``sza`` [deg], ``output_quantity``, ``output_user``
        (list of column names), ``zout`` (list) — those present.
    """
    p, text = _read_text(path, "input_file")
    out: dict = {}
    for raw in text.splitlines():
        line = raw.split("#", 1)[0].strip()
        if not line:
            continue
        word, *rest = line.split()
        word = word.lower()
        if word in ("umu", "phi", "zout"):
            try:
                out[word] = [float(x) for x in rest]
            except ValueError:
                if word != "zout":  # zout may be 'sur', 'toa', ...
                    raise ConfigError(f"{p}: numbers after {word}", key="input_file") from None
                out[word] = rest
        elif word == "sza" and rest:
            out["sza"] = float(rest[0])
        elif word == "output_quantity" and rest:
            out["output_quantity"] = rest[0].lower()
        elif word == "output_user":
            out["output_user"] = [r.lower() for r in rest]
    return out


def read_uvspec(path, input_file=None, umu=None, phi=None, sza=None, output_quantity=None,
                unit_scale: float = 1.0):
    """Read libRadtran ``uvspec`` output in its default format (module docstring).

    Parameters
    ----------
    path : path
        The output file.
    input_file : path, optional
        The uvspec input, from which ``umu``, ``phi``, ``sza`` and ``output_quantity`` are
        read (arguments given explicitly take precedence).
    umu, phi : sequence of float, optional
        Radiance directions of the run: cosines of the view zenith (> 0 looks up) and
        azimuths [deg].
    sza : float, optional
        Solar zenith angle [deg]; with ``output_quantity transmittance`` it gives
        ``sun_transmittance`` = edir / cos(sza).
    output_quantity : str, optional
        ``radiance`` (absolute, default), ``transmittance`` or ``reflectance``.
    unit_scale : float
        Factor from the file's absolute units to W m-2 (sr-1) um-1: 1 for mW m-2 nm-1
        (libRadtran's solar atlases), 1e3 for W m-2 nm-1.

    Returns
    -------
    xarray.Dataset
        Over ``wavelength`` [um]: absolute output gives ``direct_irradiance``,
        ``diffuse_down_irradiance``, ``diffuse_up_irradiance`` [W m-2 um-1] and, with
        umu, ``azimuthal_mean_radiance`` (wavelength, umu) and ``radiance`` (wavelength,
        umu, phi) [W m-2 sr-1 um-1], with coordinates ``umu``, ``view_zenith`` [deg],
        ``phi`` [deg]; normalised output gives the same quantities relative to the
        extraterrestrial irradiance (units ``1`` and ``sr-1``) and ``sun_transmittance``.
    """
    p, text = _read_text(path, "path")
    settings = parse_uvspec_input(input_file) if input_file is not None else {}
    if settings.get("output_user"):
        raise ConfigError("output_user files are not read; use uvspec's default output",
                          key="input_file")
    umu = list(settings.get("umu", []) if umu is None else umu)
    phi = list(settings.get("phi", []) if phi is None else phi)
    sza = settings.get("sza") if sza is None else sza
    quantity = (output_quantity or settings.get("output_quantity") or "radiance").lower()
    if quantity not in ("radiance", "transmittance", "reflectance"):
        raise ConfigError(f"unknown output_quantity {quantity!r}; known: radiance, "
                          "transmittance, reflectance", key="output_quantity")
    if phi and not umu:
        raise ConfigError("phi without umu: radiances need umu", key="umu")
    if umu and any(not -1.0 <= u <= 1.0 for u in umu):
        raise ConfigError("umu values are cosines in [-1, 1]", key="umu")
    rows = [line.split() for line in text.splitlines() if line.strip()]
    block = 1 + (1 if phi else 0) + len(umu)
    if not rows or len(rows) % block:
        raise ConfigError(f"{p}: {len(rows)} lines do not split into blocks of {block} (one "
                          f"wavelength line{', one phi line' if phi else ''}, {len(umu)} umu "
                          "lines): check umu and phi", key="path")
    n_wl = len(rows) // block
    lam = np.empty(n_wl)
    irr = np.empty((n_wl, 6))
    u0u = np.empty((n_wl, len(umu)))
    uu = np.empty((n_wl, len(umu), len(phi)))
    try:
        for i in range(n_wl):
            first = [float(x) for x in rows[i * block]]
            if len(first) != 7:
                raise ValueError(f"wavelength line {i} has {len(first)} numbers, not 7")
            lam[i] = first[0]
            irr[i] = first[1:]
            k = i * block + 1
            if phi:
                got = [float(x) for x in rows[k]]
                if not np.allclose(got, phi, atol=1e-3):
                    raise ValueError(f"phi line {got} differs from phi {phi}")
                k += 1
            for j, u in enumerate(umu):
                vals = [float(x) for x in rows[k + j]]
                if len(vals) != 2 + len(phi) or abs(vals[0] - u) > 1e-3:
                    raise ValueError(f"umu line {vals[:2]} does not match umu {u}")
                u0u[i, j] = vals[1]
                uu[i, j] = vals[2:]
    except ValueError as err:
        raise ConfigError(f"{p}: {unreadable(err)}", key="path") from None
    if np.any(lam <= 0):
        raise ConfigError(f"{p}: wavelengths must be > 0 nm", key="path")
    wavelength = lam / 1e3
    absolute = quantity == "radiance"
    e_units = _IRRADIANCE if absolute else "1"
    l_units = _RADIANCE if absolute else "sr-1"
    scale = unit_scale if absolute else 1.0
    what = "" if absolute else f" ({quantity}: relative to the extraterrestrial irradiance)"
    variables = {
        "direct_irradiance": (irr[:, 0] * scale, e_units, "direct irradiance" + what),
        "diffuse_down_irradiance": (irr[:, 1] * scale, e_units, "diffuse downward irradiance"
                                    + what),
        "diffuse_up_irradiance": (irr[:, 2] * scale, e_units, "diffuse upward irradiance" + what),
    }
    if umu:
        variables["azimuthal_mean_radiance"] = (u0u * scale, l_units, (
            "azimuthally averaged radiance" + what, ("wavelength", "umu")))
    if phi:
        variables["radiance"] = (uu * scale, l_units, ("radiance" + what,
                                                       ("wavelength", "umu", "phi")))
    if quantity == "transmittance" and sza is not None:
        mu0 = np.cos(np.radians(float(sza)))
        if mu0 <= 0:
            raise ConfigError("sza must be < 90 deg", key="sza")
        variables["sun_transmittance"] = (irr[:, 0] / mu0, "1",
                                          "direct sun-to-level transmittance, edir / cos(sza)")
    ds = _dataset(wavelength, variables, {"source": str(p), "format": "libRadtran uvspec",
                                          "output_quantity": quantity,
                                          "sza_deg": "none" if sza is None else float(sza)})
    if umu:
        ds = ds.assign_coords(
            umu=("umu", np.asarray(umu, float), {"units": "1",
                                                 "long_name": "cosine of view zenith, > 0 up"}),
            view_zenith=("umu", np.degrees(np.arccos(np.asarray(umu, float))),
                         {"units": "deg", "long_name": "zenith of the view direction"}))
    if phi:
        ds = ds.assign_coords(phi=("phi", np.asarray(phi, float),
                                   {"units": "deg", "long_name": "azimuth (libRadtran)"}))
    return ds
