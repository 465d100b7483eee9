"""The options of :mod:`radscene.atmosphere.api` beyond the geometry: the aerosol amount
(visibility or AOT at 550 nm), the gas columns, the date (Earth–Sun distance) and the solar
spectrum, checked against the engine that is to use them.

=================  =======================================================================
spectrum           source
=================  =======================================================================
``radscene``       the extraterrestrial column of ASTM G173-03, i.e. Gueymard (2004), 0.28-4
                   um, with a 5772 K blackbody scaled to it beyond
                   (:func:`radscene.sun.toa_solar_irradiance`); engines ``sixs`` and
                   ``database``
``tsis1``          the TSIS-1 Hybrid Solar Reference Spectrum, version 2 (Coddington et al.
                   2021, 2023), 1 nm bins over 0.2025-2.7295 um, the ``radscene`` spectrum
                   beyond (``radscene/data/solar``); engines ``sixs`` and ``database``
``6s``             the spectrum built into 6S, as 6S prints it (Vermote et al. 1997); engine
                   ``sixs`` only
``lowtran``        LOWTRAN7's built-in extraterrestrial spectrum (Kneizys et al. 1988), with
                   which LOWTRAN computes its scattered radiances, as a table
                   (``radscene/data/solar/lowtran7_5cm1.csv``); engine ``lowtran`` only
=================  =======================================================================

The renderer's direct sun uses the atmosphere's spectrum where radscene evaluates it
(``radscene``, ``tsis1``, ``lowtran``), else ``radscene``'s (6S's own).

References
----------
C. A. Gueymard, Solar Energy 76, 423-453 (2004), https://doi.org/10.1016/j.solener.2003.08.039
O. M. Coddington et al., Geophys. Res. Lett. 48, e2020GL091709 (2021),
https://doi.org/10.1029/2020GL091709; version 2: Earth Space Sci. 10, e2022EA002637 (2023),
https://doi.org/10.1029/2022EA002637 (TSIS-1 HSRS).
E. F. Vermote et al., IEEE Trans. Geosci. Remote Sens. 35, 675-686 (1997) (6S),
https://doi.org/10.1109/36.581987
F. X. Kneizys et al., Users guide to LOWTRAN 7, AFGL-TR-88-0177 (1988).
I. Reda and A. Andreas, Solar position algorithm for solar radiation applications, NREL/TP-560-
34302 (2008) (the Earth–Sun distance).
"""

from __future__ import annotations

import datetime as _dt
import inspect
import re

import numpy as np

from radscene.errors import ConfigError

__all__ = ["SOLAR_SPECTRA", "ENGINE_SPECTRA", "sun_date", "check_options", "database_keywords",
           "option_attrs", "visibility_m"]

#: Top-of-atmosphere solar spectra, by name: where each comes from.
SOLAR_SPECTRA = {
    "radscene": "ASTM G173-03 extraterrestrial spectrum (Gueymard 2004) 0.28-4 µm, a scaled "
                "5772 K blackbody beyond: radscene.sun.toa_solar_irradiance",
    "tsis1": "TSIS-1 HSRS v2 (Coddington et al. 2021, GRL 48, e2020GL091709; v2 2022-11-30) "
             "in 1 nm bins 0.2025-2.7295 µm, the radscene spectrum beyond: "
             "radscene.sun.toa_solar_irradiance(spectrum='tsis1')",
    "6s": "the solar spectrum built into 6S (Vermote et al. 1997), as 6S prints it",
    "lowtran": "LOWTRAN7's built-in extraterrestrial solar spectrum (Kneizys et al. 1988)",
}
#: The spectra each engine can use; the first is its default.
ENGINE_SPECTRA = {"sixs": ("radscene", "6s", "tsis1"), "database": ("radscene", "tsis1"),
                  "lowtran": ("lowtran",)}
#: Largest column amounts accepted [g cm-2], [cm-atm]: far above any measured column, they
#: catch amounts given in other units (ozone in Dobson units: 300 DU = 0.3 cm-atm).
_MAX_WATER, _MAX_OZONE = 10.0, 1.0
_DATE = re.compile(r"\d{4}-\d{2}-\d{2}")


def visibility_m(visibility) -> float:
    """Visibility [m] from a number [m] or a string with a unit; > 0."""
    from radscene.radiometry.units import parse_quantity

    v = parse_quantity(visibility, "length", key="visibility")
    if not v > 0:
        raise ConfigError(f"must be > 0; got {visibility!r}", key="visibility")
    return v


def sun_date(date) -> tuple[float, int, str]:
    """Earth–Sun distance and day of year of a calendar date.

    Parameters
    ----------
    date : str or datetime.date
        ``YYYY-MM-DD``.

    Returns
    -------
    distance : float
        Earth–Sun distance at 12:00 UTC that day [AU] (NREL SPA,
        :func:`radscene.sun.earth_sun_distance`).
    day_of_year : int
        1-366.
    iso : str
        The date as ``YYYY-MM-DD``.

    Raises
    ------
    ConfigError
        Not a valid date in that form (key ``date``).

    Examples
    --------
    >>> d, doy, iso = sun_date("2024-01-03")
    >>> (round(d, 4), doy, iso)
    (0.9833, 3, '2024-01-03')
    """
    from radscene.sun import earth_sun_distance

    if isinstance(date, _dt.datetime):
        day = date.date()
    elif isinstance(date, _dt.date):
        day = date
    else:
        text = str(date).strip()
        try:
            if not _DATE.fullmatch(text):
                raise ValueError
            day = _dt.date.fromisoformat(text)
        except ValueError:
            raise ConfigError(f"a date YYYY-MM-DD, e.g. 2024-06-21; got {date!r}",
                              key="date") from None
    noon = _dt.datetime(day.year, day.month, day.day, 12, tzinfo=_dt.UTC)
    return (float(earth_sun_distance(noon)), int(day.timetuple().tm_yday), day.isoformat())


def _amount(value, key, high, unit):
    if value is None:
        return None
    try:
        x = float(value)
    except (TypeError, ValueError):
        raise ConfigError(f"must be a number; got {value!r}", key=key) from None
    if not (np.isfinite(x) and 0.0 <= x <= high):
        bounds = f"lie in [0, {high:g}]{unit}" if np.isfinite(high) else f"be >= 0{unit}"
        raise ConfigError(f"must {bounds}; got {value!r}", key=key)
    return x


def check_options(name, visibility, aot550, water, ozone, date, earth_sun_distance,
                  solar_spectrum) -> dict:
    """Check the aerosol, gas, date and spectrum options against an engine.

    Parameters
    ----------
    name : str
        The engine: ``sixs``, ``database`` or ``lowtran``.
    visibility : float or str or None
        [m] or with a unit; None: 23 km unless ``aot550`` is given.
    aot550 : float or None
        Aerosol optical thickness at 550 nm [-], >= 0.
    water, ozone : float or None
        Columns [g cm-2] (0-10) and [cm-atm] (0-1).
    date : str or datetime.date or None
        ``YYYY-MM-DD`` (:func:`sun_date`).
    earth_sun_distance : float or None
        [AU], instead of ``date``.
    solar_spectrum : str or None
        A key of :data:`SOLAR_SPECTRA` the engine uses (:data:`ENGINE_SPECTRA`); None: the
        engine's first.

    Returns
    -------
    dict
        ``visibility`` [m] or None, ``aot550``, ``water``, ``ozone``, ``distance`` [AU],
        ``day_of_year`` and ``date`` (None without a date), ``solar_spectrum``.

    Raises
    ------
    ConfigError
        A value out of range, two exclusive options, or an option the engine does not take;
        the key names the option.
    """
    aot = _amount(aot550, "aot550", np.inf, "")
    w = _amount(water, "water", _MAX_WATER, " g cm-2")
    o3 = _amount(ozone, "ozone", _MAX_OZONE, " cm-atm (300 DU = 0.3 cm-atm)")
    if aot is not None and visibility is not None:
        raise ConfigError("give visibility or aot550, not both", key="aot550")
    vis = None if aot is not None else visibility_m(
        "23 km" if visibility is None else visibility)
    if date is not None and earth_sun_distance is not None:
        raise ConfigError("give date or earth_sun_distance, not both", key="earth_sun_distance")
    distance, day_of_year, iso = 1.0, None, None
    if date is not None:
        distance, day_of_year, iso = sun_date(date)
    elif earth_sun_distance is not None:
        distance = float(earth_sun_distance)
        if not (np.isfinite(distance) and distance > 0):
            raise ConfigError(f"must be > 0 AU; got {earth_sun_distance!r}",
                              key="earth_sun_distance")
    spectra = ENGINE_SPECTRA[name]
    spectrum = spectra[0] if solar_spectrum is None else str(solar_spectrum).lower()
    if spectrum not in SOLAR_SPECTRA:
        raise ConfigError(f"unknown solar spectrum {solar_spectrum!r}; known: "
                          f"{', '.join(SOLAR_SPECTRA)}", key="solar_spectrum")
    if spectrum not in spectra:
        raise ConfigError(f"the {name} engine uses {' or '.join(spectra)}, not {spectrum}",
                          key="solar_spectrum")
    if name == "lowtran":
        if aot is not None:
            raise ConfigError("the lowtran engine does not take aot550: its aerosol is set by "
                              "visibility; use engine sixs or database", key="aot550")
        if earth_sun_distance is not None:
            raise ConfigError("LOWTRAN takes the Earth-Sun distance from its day of year: "
                              "give date", key="earth_sun_distance")
    return {"visibility": vis, "aot550": aot, "water": w, "ozone": o3, "distance": distance,
            "day_of_year": day_of_year, "date": iso, "solar_spectrum": spectrum}


def database_keywords(settings) -> dict:
    """The keywords of the database engine for aot550, water, ozone and the spectrum, as far
    as its constructor takes them; ConfigError for one it does not take."""
    from radscene.atmosphere.database import DatabaseAtmosphere

    accepted = inspect.signature(DatabaseAtmosphere).parameters
    out = {}
    for key in ("aot550", "water", "ozone"):
        if settings[key] is None:
            continue
        if key not in accepted:
            raise ConfigError(f"the database engine does not take {key}; use engine sixs",
                              key=key)
        out[key] = settings[key]
    if "solar_spectrum" in accepted:
        out["solar_spectrum"] = settings["solar_spectrum"]
    return out


def option_attrs(settings, profile, aerosol) -> dict:
    """The Dataset attributes that record the atmosphere and the sun's settings."""
    out = {"profile": str(profile), "aerosol": str(aerosol),
           "earth_sun_distance_au": settings["distance"],
           "solar_spectrum": settings["solar_spectrum"],
           "solar_spectrum_source": SOLAR_SPECTRA[settings["solar_spectrum"]]}
    if settings["visibility"] is not None:
        out["visibility_m"] = settings["visibility"]
    for key, attr in (("aot550", "aot550"), ("water", "water_g_cm-2"),
                      ("ozone", "ozone_cm-atm"), ("date", "date"),
                      ("day_of_year", "day_of_year")):
        if settings[key] is not None:
            out[attr] = settings[key]
    return out
