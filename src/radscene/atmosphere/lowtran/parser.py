"""Read what one LOWTRAN7 run leaves behind.

* ``radscene.out``, written by radscene's driver (see
  :mod:`radscene.atmosphere.lowtran.build`): every spectral sample in full single precision.
  Units there are LOWTRAN's: W cm-2 (sr-1) um-1.
* ``out/TAPE6``, LOWTRAN's listing: the run's summary lines (integrated absorption, average
  transmittance, integrated radiance) and its warnings and error messages, which name what
  went wrong when a case fails.
"""

from __future__ import annotations

import re

import numpy as np

__all__ = ["DRIVER_COLUMNS", "parse_driver_output", "parse_tape6_summary", "tape6_messages"]

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
