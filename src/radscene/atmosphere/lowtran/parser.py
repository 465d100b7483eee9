"""Read what one LOWTRAN7 run leaves behind.

* ``radscene.out``, written by radscene's driver (see
  :mod:`radscene.atmosphere.lowtran.build`): every spectral sample in full single precision.
  Units there are LOWTRAN's: W cm-2 (sr-1) um-1.
* ``out/TAPE6``, LOWTRAN's listing: the run's summary lines (integrated absorption, average
  transmittance, integrated radiance) and its warnings and error messages, which name what
  went wrong when a case fails.
* ``out/TAPE7``, LOWTRAN's spectral listing: of a radiance run with solar scattering
  (IEMSCT = 2) whose path ends on the ground, the only place where LOWTRAN reports the
  radiance the ground reflects along the path (RFLS: the sun's direct beam and the diffuse
  flux FDNSRT of its two-stream multiple scattering, times SALB / π and the path's
  transmittance), with three significant digits.
"""

from __future__ import annotations

import re

import numpy as np

__all__ = ["DRIVER_COLUMNS", "parse_driver_output", "parse_tape6_summary", "tape6_messages",
           "parse_tape7_ground"]

#: Columns of ``radscene.out``, in order, with their LOWTRAN names.
DRIVER_COLUMNS: tuple[str, ...] = (
    "wavenumber",  # V [cm-1]
    "wavelength",  # ALAM [um]
    "transmittance",  # TX(9), total
    "thermal_radiance",  # SUMVV [W cm-2 sr-1 um-1]
    "solar_irradiance",  # TSOLIL, transmitted direct solar [W cm-2 um-1]
    "toa_irradiance",  # SOLIL, extraterrestrial [W cm-2 um-1]
    "scattered_radiance",  # SUMSSR, single + multiple scattered solar [W cm-2 sr-1 um-1]
    "trace_transmittance",  # TRACE
    "uniform_transmittance",  # UNIF (CO2 and other uniformly mixed gases)
)

_HEADER = re.compile(r"^# radscene-lowtran7 (\d+) points (\d+)\s*$")


def parse_driver_output(text: str) -> dict[str, np.ndarray]:
    """Columns of ``radscene.out`` as float arrays, in LOWTRAN's order (increasing wavenumber).

    Parameters
    ----------
    text : str
        The file's content.

    Returns
    -------
    dict of str to numpy.ndarray
        One array per name of :data:`DRIVER_COLUMNS`, LOWTRAN's units.

    Raises
    ------
    ValueError
        If the file is incomplete (LOWTRAN stopped before the driver finished), holds no
        sample, or is not the driver's format.
    """
    lines = text.splitlines()
    if not lines:
        raise ValueError("empty output: LOWTRAN stopped before writing any result")
    match = _HEADER.match(lines[0])
    if match is None:
        raise ValueError(f"not radscene-lowtran7 output (first line {lines[0][:60]!r})")
    if match.group(1) != "1":
        raise ValueError(f"unknown radscene-lowtran7 output version {match.group(1)}")
    n = int(match.group(2))
    if len(lines) < n + 2 or lines[n + 1].strip() != "# end":
        raise ValueError("output ends early: LOWTRAN stopped before the driver finished")
    if n == 0:
        raise ValueError("LOWTRAN computed no spectral sample")
    data = np.array([[float(x) for x in line.split()] for line in lines[1:n + 1]])
    if data.shape != (n, len(DRIVER_COLUMNS)):
        raise ValueError(f"expected {len(DRIVER_COLUMNS)} columns, got shape {data.shape}")
    return {name: data[:, i].copy() for i, name in enumerate(DRIVER_COLUMNS)}


_SUMMARY_PATTERNS = {
    "integrated_absorption": re.compile(r"INTEGRATED ABSORPTION FROM\s*\d+\s*TO\s*\d+\s*CM-1 =\s*"
                                        r"([-+.\dEe]+)"),
    "average_transmittance": re.compile(r"AVERAGE TRANSMITTANCE =\s*([-+.\dEe]+)"),
    "integrated_radiance": re.compile(r"INTEGRATED RADIANCE =\s*([-+.\dEe]+)"),
    "integrated_irradiance": re.compile(r"INTEGRATED IRRADIANCE =\s*([-+.\dEe]+)"),
}


def parse_tape6_summary(text: str) -> dict[str, float]:
    """Summary figures of a TAPE6 listing (the last occurrence of each).

    Returns
    -------
    dict
        Any of ``integrated_absorption`` [cm-1], ``average_transmittance`` [-],
        ``integrated_radiance`` [W cm-2 sr-1], ``integrated_irradiance`` [W cm-2].

    Examples
    --------
    >>> parse_tape6_summary(" AVERAGE TRANSMITTANCE = .8697")
    {'average_transmittance': 0.8697}
    """
    out = {}
    for name, pattern in _SUMMARY_PATTERNS.items():
        found = pattern.findall(text)
        if found:
            out[name] = float(found[-1])
    return out


_MESSAGE = re.compile(r"(ERROR|WARNING|RESET|SKIP|INVALID|INTERSECTS|CANNOT|STOP)",
                      re.IGNORECASE)


def tape6_messages(text: str, limit: int = 12) -> list[str]:
    """LOWTRAN's warnings and error messages in a TAPE6 listing (stripped lines, in order)."""
    out = []
    for line in text.splitlines():
        stripped = line.strip().lstrip("0").strip()
        if stripped and _MESSAGE.search(stripped) and "*****" not in stripped:
            out.append(stripped)
            if len(out) >= limit:
                break
    return out


#: Fixed columns of a TAPE7 record of a radiance run with solar scattering (FORMAT 927:
#: F7.0, F8.4, 6E9.2, 2F8.4): wavenumber [cm-1], TX(9), then in W cm-2 sr-1 (cm-1)-1 the
#: thermal, scattered and singly scattered path radiance, the ground-reflected radiance
#: RFLS and its direct-sun part RFLSS, the total.
_TAPE7_FIELDS = {"wavenumber": (0, 7), "ground_radiance": (42, 51),
                 "direct_ground_radiance": (51, 60)}
_EXPONENT = re.compile(r"(\d)([-+]\d{3})$")


def _fortran_float(text: str) -> float:
    """A Fortran E field, also where a three-digit exponent dropped its ``E`` (1.23-100)."""
    text = text.strip()
    return float(_EXPONENT.sub(r"\1E\2", text))


def parse_tape7_ground(text: str) -> dict[str, np.ndarray]:
    """Ground-reflected radiance of a radiance run with solar scattering, from its TAPE7.

    Parameters
    ----------
    text : str
        TAPE7 of a run with IEMSCT = 2.

    Returns
    -------
    dict of str to numpy.ndarray
        ``wavenumber`` [cm-1] in LOWTRAN's order, ``ground_radiance`` (RFLS, the radiance
        the ground reflects towards the observer, attenuated along the path) and
        ``direct_ground_radiance`` (RFLSS, its direct-sun part), in LOWTRAN's
        W cm-2 sr-1 (cm-1)-1; both zero unless the path ends on the ground.

    Raises
    ------
    ValueError
        No spectral record (not a radiance run with solar scattering, or LOWTRAN stopped).

    Examples
    --------
    >>> rec = (" 18100.  0.6384 0.00E+00 4.16E-07 5.88E-08 9.13E-07 5.93E-07 1.33E-06"
    ...        "  0.3803  0.5105           4.488E-01")
    >>> out = parse_tape7_ground("  FREQ   TRANS     ATMOS   PATH\\n" + rec + "\\n -9999.")
    >>> float(out["ground_radiance"][0]), float(out["direct_ground_radiance"][0])
    (9.13e-07, 5.93e-07)
    """
    rows = []
    started = False
    for line in text.splitlines():
        if not started:
            started = line.lstrip().startswith("FREQ")
            continue
        if line.strip().startswith("-9999"):
            break
        if len(line) < 69:
            continue
        try:
            rows.append([_fortran_float(line[a:b]) for a, b in _TAPE7_FIELDS.values()])
        except ValueError:
            continue
    if not rows:
        raise ValueError("no spectral record of a radiance run with solar scattering in TAPE7")
    data = np.array(rows)
    return {name: data[:, i].copy() for i, name in enumerate(_TAPE7_FIELDS)}
