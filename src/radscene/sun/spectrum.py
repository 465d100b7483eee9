"""Top-of-atmosphere solar spectral irradiance, 0.25-20 µm, from one of three spectra.

=============  ==================================================================================
spectrum       source
=============  ==================================================================================
``radscene``   (the default) ASTM G173-03 extraterrestrial (Gueymard 2004), 0.28-4 µm, a scaled
               5772 K blackbody beyond
``tsis1``      TSIS-1 HSRS version 2 (Coddington et al. 2021, 2023), 0.2025-2.7295 µm, the
               ``radscene`` spectrum beyond
``lowtran``    LOWTRAN7's own extraterrestrial spectrum (Kneizys et al. 1988), 0.25-20 µm at
               its 5 cm-1 sampling: the sun of the ``lowtran`` engine
=============  ==================================================================================

Every function takes ``spectrum`` (:data:`SOLAR_SPECTRUM_NAMES`); the atmosphere engines and the
renderer pass the one the atmosphere was set up with (``solar_spectrum``).

Source of ``radscene``
----------------------
0.28-4.0 µm: the extraterrestrial column of ASTM G173-03 as shipped with pvlib
(``pvlib.spectrum.get_reference_spectra``), 2002 samples at 0.5-5 nm spacing, converted
from W m-2 nm-1 to W m-2 um-1. The column is Gueymard's (2004) synthetic extraterrestrial
spectrum, normalised to a solar constant of 1366.1 W m-2 over all wavelengths.

Beyond 4.0 µm (up to 20 µm) the Sun is a blackbody disk at the IAU 2015 nominal effective
temperature 5772 K, seen at 1 AU under ``SUN_SOLID_ANGLE``, scaled so that its mean over
3.5-4.0 µm equals the measured mean there (scale 0.9587; the join at 4.0 µm then steps by
0.9 %). Below 0.28 µm (down to 0.25 µm) the same blackbody is scaled to the measured mean
over 0.280-0.285 µm (scale 0.356; this window averages over the Mg II h and k absorption
lines at 0.2796/0.2803 µm, so the join at 0.28 µm steps up from the line core). Between
table samples the spectrum is linear.

The integral over 0.25-20 µm, :func:`solar_constant`, is 1366.0 W m-2: 0.38 % above the
TSI of Kopp & Lean (2011), 1360.8 W m-2, as expected from the 1366.1 W m-2 normalisation of
the source.

Source of ``tsis1``
-------------------
0.2025-2.7295 µm: the TSIS-1 Hybrid Solar Reference Spectrum, version 2 (LASP, 2022-11-30;
Coddington et al. 2021, 2023), its 0.1 nm-resolution file averaged in 1 nm bins
(``radscene/data/solar/tsis1_hsrs_v2_1nm.csv``, vacuum wavelengths, written by
``scripts/build_solar_spectrum.py``; the header names the file, its checksum and the copy it was
read from), linear between the bin centres. The HSRS is TSIS-1 SIM's irradiance scale, adjusted
to TSIS-1 TIM's total solar irradiance. It stops at 2.73 µm; beyond 2.7295 µm the ``radscene``
spectrum is used as it is, unscaled (at the join it is 2.7 % below the HSRS; over 2.5-2.73 µm
the HSRS is 1.4 % above it). Integrals: 1325.74 W m-2 over the bins' centres 0.2025-2.7295 µm
(the file's own integral over 202-2730 nm is 1325.76 W m-2, 97.4 % of the TSI of 1360.8 W m-2),
1323.85 W m-2 over 0.25-2.7295 µm, 35.96 W m-2 from the ``radscene`` spectrum over
2.7295-20 µm: :func:`solar_constant` ``("tsis1")`` is 1359.8 W m-2, 0.07 % below 1360.8 W m-2.

Source of ``lowtran``
---------------------
LOWTRAN7's extraterrestrial irradiance (SOLIL, its block data SUNRAD) at every wavenumber of its
5 cm-1 grid from 500 to 40000 cm-1 (0.25-20 µm), at the mean Earth-Sun distance, as LOWTRAN7
evaluates it in a run (``radscene/data/solar/lowtran7_5cm1.csv``, written by
``scripts/build_lowtran_solar_spectrum.py``), linear between the samples. The ``lowtran``
engine's scattered radiances, sky and coupling are lit by this spectrum, so the renderer lights
that engine's direct sun with it too: in the 2.19-2.21 µm band it is 11 % below ``radscene``'s,
within 1 % of it over 0.44-0.88 µm. Integral over 0.25-20 µm: 1370.7 W m-2.

References
----------
ASTM G173-03(2020), Standard Tables for Reference Solar Spectral Irradiances.
C. A. Gueymard, "The sun's total and spectral irradiance for solar energy applications and
solar radiation models", Solar Energy 76, 423-453 (2004),
https://doi.org/10.1016/j.solener.2003.08.039
G. Kopp and J. L. Lean, "A new, lower value of total solar irradiance", Geophys. Res. Lett.
38, L01706 (2011), https://doi.org/10.1029/2010GL045777
E. E. Mamajek et al., IAU 2015 Resolution B3 on nominal solar values,
https://arxiv.org/abs/1510.07674
O. M. Coddington et al., "The TSIS-1 Hybrid Solar Reference Spectrum", Geophys. Res. Lett. 48,
e2020GL091709 (2021), https://doi.org/10.1029/2020GL091709
O. M. Coddington et al., "Version 2 of the TSIS-1 Hybrid Solar Reference Spectrum and Extension
to the Full Spectrum", Earth Space Sci. 10, e2022EA002637 (2023),
https://doi.org/10.1029/2022EA002637
F. X. Kneizys et al., Users Guide to LOWTRAN 7, AFGL-TR-88-0177, Air Force Geophysics
Laboratory (1988)
"""

from __future__ import annotations

import math
from functools import lru_cache
from importlib import resources

import numpy as np

from radscene.errors import ConfigError
from radscene.radiometry.planck import band_radiance, spectral_radiance

__all__ = [
    "SUN_RADIUS",
    "ASTRONOMICAL_UNIT",
    "SUN_SOLID_ANGLE",
    "SUN_TEMPERATURE",
    "SOLAR_WAVELENGTH_RANGE",
    "SOLAR_SPECTRUM_NAMES",
    "toa_solar_irradiance",
    "toa_solar_spectrum",
    "solar_constant",
    "engine_spectrum",
    "engine_distance",
    "sun_radiance",
]

#: Nominal solar radius [m] (IAU 2015 Resolution B3).
SUN_RADIUS = 6.957e8
#: Astronomical unit [m] (IAU 2012 Resolution B2, exact).
ASTRONOMICAL_UNIT = 1.495978707e11
#: Solid angle of the solar disk seen from 1 AU [sr], π (R_sun / AU)².
SUN_SOLID_ANGLE = math.pi * (SUN_RADIUS / ASTRONOMICAL_UNIT) ** 2
#: Nominal effective temperature of the Sun [K] (IAU 2015 Resolution B3).
SUN_TEMPERATURE = 5772.0
#: Wavelengths [um] covered by :func:`toa_solar_irradiance`.
SOLAR_WAVELENGTH_RANGE = (0.25, 20.0)
#: The spectra radscene evaluates itself (``spectrum`` of the functions below); the first is
#: the default.
SOLAR_SPECTRUM_NAMES = ("radscene", "tsis1", "lowtran")
_TSIS1_FILE = "tsis1_hsrs_v2_1nm.csv"
_LOWTRAN_FILE = "lowtran7_5cm1.csv"

_HEAD_WINDOW = (0.280, 0.285)  # [um] window the short-wave blackbody is scaled to
_TAIL_WINDOW = (3.5, 4.0)  # [um] window the long-wave blackbody is scaled to
_HEAD_STEP = 0.0005  # [um] sampling of the blackbody head in toa_solar_spectrum
_TAIL_STEP = 0.005  # [um] sampling of the blackbody tail in toa_solar_spectrum


def _disk(wavelength):
    """Irradiance of the 5772 K blackbody disk at 1 AU [W m-2 um-1]."""
    return spectral_radiance(wavelength, SUN_TEMPERATURE) * SUN_SOLID_ANGLE


@lru_cache(maxsize=1)
def _measured():
    """(wavelength [um], irradiance [W m-2 um-1], head scale, tail scale), read once."""
    from pvlib.spectrum import get_reference_spectra

    table = get_reference_spectra(standard="ASTM G173-03")
    wavelength = table.index.to_numpy(dtype=float) / 1000.0
    irradiance = table["extraterrestrial"].to_numpy(dtype=float) * 1e3
    wavelength.flags.writeable = False
    irradiance.flags.writeable = False

    def scale(window):
        m = (wavelength >= window[0]) & (wavelength <= window[1])
        measured = np.trapezoid(irradiance[m], wavelength[m])
        model = np.trapezoid(_disk(wavelength[m]), wavelength[m])
        return float(measured / model)

    return wavelength, irradiance, scale(_HEAD_WINDOW), scale(_TAIL_WINDOW)


@lru_cache(maxsize=2)
def _table(name):
    """(wavelength [um], irradiance [W m-2 um-1]) of a shipped table, read once."""
    path = resources.files("radscene") / "data" / "solar" / name
    rows = [line.split(",")[:2] for line in path.read_text(encoding="utf-8").splitlines()
            if line and not line.startswith("#") and not line.startswith("wavelength")]
    data = np.array(rows, dtype=float)
    wavelength, irradiance = data[:, 0], data[:, 1]
    wavelength.flags.writeable = False
    irradiance.flags.writeable = False
    return wavelength, irradiance


def _tsis1():
    """The TSIS-1 HSRS table (:func:`_table`)."""
    return _table(_TSIS1_FILE)


def _lowtran():
    """LOWTRAN7's table (:func:`_table`), 0.25-20 µm."""
    return _table(_LOWTRAN_FILE)


def _check_spectrum(spectrum) -> str:
    name = str(spectrum).strip().lower()
    if name not in SOLAR_SPECTRUM_NAMES:
        raise ConfigError(f"unknown solar spectrum {spectrum!r}; known: "
                          f"{', '.join(SOLAR_SPECTRUM_NAMES)}", key="solar_spectrum")
    return name


def engine_spectrum(atmosphere) -> str:
    """The spectrum that lights an atmosphere engine's sun where radscene evaluates it: the
    engine's ``solar_spectrum`` when it is one of :data:`SOLAR_SPECTRUM_NAMES`, else
    ``radscene`` (6S's own spectrum exists only inside 6S).

    Examples
    --------
    >>> class Engine:
    ...     solar_spectrum = "lowtran"
    >>> engine_spectrum(Engine()), engine_spectrum(object())
    ('lowtran', 'radscene')
    """
    name = str(getattr(atmosphere, "solar_spectrum", "radscene") or "radscene").lower()
    return name if name in SOLAR_SPECTRUM_NAMES else "radscene"


def engine_distance(atmosphere, distance) -> float:
    """The Earth–Sun distance [AU] at which an atmosphere engine's sun shines: the engine's
    own ``earth_sun_distance`` where it keeps one (set up for the scene's sun; the ``lowtran``
    engine's comes from LOWTRAN's table of its day of the year), else ``distance``.

    Examples
    --------
    >>> class Engine:
    ...     earth_sun_distance = 0.99
    >>> engine_distance(Engine(), 1.01), engine_distance(object(), 1.01)
    (0.99, 1.01)
    """
    own = getattr(atmosphere, "earth_sun_distance", None)
    return float(distance if own is None else own)


def _check_distance(distance):
    d = np.asarray(distance, dtype=float)
    if np.any(~(d > 0)):
        raise ConfigError(f"must be > 0 AU; got {distance!r}", key="distance")
    return d


def toa_solar_irradiance(wavelength, distance=1.0, spectrum="radscene"):
    """Solar spectral irradiance at the top of the atmosphere, normal to the beam.

    Parameters
    ----------
    wavelength : array_like
        Wavelength [um], 0.25-20.
    distance : array_like
        Earth-Sun distance [AU], > 0 (see :func:`radscene.sun.earth_sun_distance`).
        Broadcast against `wavelength`.
    spectrum : str
        ``radscene``, ``tsis1`` or ``lowtran`` (:data:`SOLAR_SPECTRUM_NAMES`; module docstring).

    Returns
    -------
    numpy.ndarray
        Spectral irradiance [W m-2 um-1], scaled by 1 / distance².

    Raises
    ------
    ConfigError
        A wavelength outside 0.25-20 um, a distance <= 0 or an unknown spectrum.

    Notes
    -----
    See the module docstring for the sources and the extensions.

    Examples
    --------
    >>> round(float(toa_solar_irradiance(0.5)), 1)
    1916.0
    >>> round(float(toa_solar_irradiance(0.5, spectrum="tsis1")), 1)
    1945.8
    """
    name = _check_spectrum(spectrum)
    wl = np.asarray(wavelength, dtype=float)
    lo, hi = SOLAR_WAVELENGTH_RANGE
    if np.any(np.isnan(wl)):
        raise ConfigError(f"must lie in {lo:g}-{hi:g} µm; got NaN", key="wavelength")
    if np.any((wl < lo) | (wl > hi)):
        raise ConfigError(
            f"must lie in {lo:g}-{hi:g} µm; got {wl.min():g}-{wl.max():g} µm",
            key="wavelength",
        )
    d = _check_distance(distance)
    table_wl, table_e, head, tail = _measured()
    disk = _disk(wl)
    irradiance = np.where(
        wl < table_wl[0],
        head * disk,
        np.where(wl > table_wl[-1], tail * disk, np.interp(wl, table_wl, table_e)),
    )
    if name == "tsis1":
        tsis_wl, tsis_e = _tsis1()
        irradiance = np.where(wl <= tsis_wl[-1], np.interp(wl, tsis_wl, tsis_e), irradiance)
    elif name == "lowtran":
        lt_wl, lt_e = _lowtran()
        irradiance = np.interp(wl, lt_wl, lt_e)
    return irradiance / d**2


def toa_solar_spectrum(spectrum="radscene"):
    """The solar spectrum at 1 AU on its native sampling, for exact band integration.

    Parameters
    ----------
    spectrum : str
        ``radscene``, ``tsis1`` or ``lowtran`` (:data:`SOLAR_SPECTRUM_NAMES`).

    Returns
    -------
    wavelength : numpy.ndarray
        Wavelength [um], 0.25-20, strictly increasing. ``radscene``: 0.5 nm steps below
        0.28 um, the ASTM G173 samples to 4 um, 5 nm steps beyond. ``tsis1``: 0.25 um, the
        TSIS-1 HSRS bin centres (1 nm apart) to 2.7295 um, then the ``radscene`` samples.
        ``lowtran``: LOWTRAN7's 5 cm-1 grid.
    irradiance : numpy.ndarray
        Spectral irradiance [W m-2 um-1] at 1 AU, equal to :func:`toa_solar_irradiance`.

    Examples
    --------
    >>> wl, e = toa_solar_spectrum()
    >>> (float(wl[0]), float(wl[-1]))
    (0.25, 20.0)
    """
    name = _check_spectrum(spectrum)
    if name == "lowtran":
        lt_wl, lt_e = _lowtran()
        return lt_wl.copy(), lt_e.copy()
    table_wl, _, _, _ = _measured()
    lo, hi = SOLAR_WAVELENGTH_RANGE
    head = lo + _HEAD_STEP * np.arange(round((table_wl[0] - lo) / _HEAD_STEP))
    tail = table_wl[-1] + _TAIL_STEP * np.arange(1, round((hi - table_wl[-1]) / _TAIL_STEP) + 1)
    wavelength = np.concatenate((head, table_wl, tail))
    wavelength[-1] = hi
    if name == "tsis1":
        tsis_wl, _ = _tsis1()
        tsis_wl = tsis_wl[tsis_wl > lo]
        wavelength = np.concatenate(([lo], tsis_wl, wavelength[wavelength > tsis_wl[-1]]))
    return wavelength, toa_solar_irradiance(wavelength, spectrum=name)


def solar_constant(spectrum="radscene") -> float:
    """Solar irradiance at 1 AU integrated over 0.25-20 um [W m-2].

    The tables are integrated exactly (trapezoids of the piecewise-linear tables), the
    blackbody parts with :func:`radscene.radiometry.band_radiance`. Result: 1366.0 W m-2
    (``radscene``), 1359.8 W m-2 (``tsis1``), 1370.7 W m-2 (``lowtran``).

    Parameters
    ----------
    spectrum : str
        ``radscene``, ``tsis1`` or ``lowtran`` (:data:`SOLAR_SPECTRUM_NAMES`).

    Examples
    --------
    >>> round(solar_constant(), 1)
    1366.0
    >>> round(solar_constant("tsis1"), 1)
    1359.8
    """
    name = _check_spectrum(spectrum)
    if name == "lowtran":
        lt_wl, lt_e = _lowtran()
        return float(np.trapezoid(lt_e, lt_wl))
    table_wl, table_e, head, tail = _measured()
    lo, hi = SOLAR_WAVELENGTH_RANGE
    tail_part = float(tail * SUN_SOLID_ANGLE * band_radiance(table_wl[-1], hi, SUN_TEMPERATURE))
    if name == "tsis1":
        tsis_wl, _ = _tsis1()
        join = float(tsis_wl[-1])
        wl = np.concatenate(([lo], tsis_wl[tsis_wl > lo]))
        measured = float(np.trapezoid(toa_solar_irradiance(wl, spectrum=name), wl))
        after = np.concatenate(([join], table_wl[table_wl > join]))
        measured += float(np.trapezoid(toa_solar_irradiance(after), after))
        return measured + tail_part
    measured = float(np.trapezoid(table_e, table_wl))
    head_part = head * SUN_SOLID_ANGLE * band_radiance(lo, table_wl[0], SUN_TEMPERATURE)
    return measured + float(head_part) + tail_part


def sun_radiance(wavelength, distance=1.0, spectrum="radscene"):
    """Mean spectral radiance of the solar disk.

    Parameters
    ----------
    wavelength : array_like
        Wavelength [um], 0.25-20.
    distance : array_like
        Earth-Sun distance [AU], > 0. Radiance is conserved along the beam, so the result
        does not depend on it: irradiance and solid angle both scale as 1 / distance².
    spectrum : str
        ``radscene``, ``tsis1`` or ``lowtran`` (:data:`SOLAR_SPECTRUM_NAMES`).

    Returns
    -------
    numpy.ndarray
        Spectral radiance [W m-2 sr-1 um-1], ``toa_solar_irradiance(wavelength, 1) /
        SUN_SOLID_ANGLE`` broadcast against `distance`.

    Examples
    --------
    >>> round(float(sun_radiance(0.5)) / 1e7, 3)
    2.82
    """
    d = _check_distance(distance)
    irradiance = toa_solar_irradiance(wavelength, d, spectrum)
    return irradiance / (SUN_SOLID_ANGLE / d**2)
