"""The ``lowtran`` atmosphere engine: LOWTRAN7 (Kneizys et al. 1988) through card decks.

Every query becomes one LOWTRAN run per distinct geometry, each in its own process (see
:mod:`~radscene.atmosphere.lowtran.runner`), run in parallel and cached on disk. A run covers
the fixed spectral windows the asked wavelengths touch (0.235-0.4-1-2.6-6-28.6 um, edges
where few sensor bands straddle, so the bands of one render share runs) at
``wavenumber_step``; spectra are interpolated linearly in wavenumber onto the asked
wavelengths. LOWTRAN's resolution is 20 cm-1 whatever the step. Runs entirely beyond 6 um
leave out scattered sunlight (below 1e-4 of the thermal path radiance there), which makes
the thermal sky independent of azimuth and its table cheap.

==========================  ==========  ===================  ===============================================
name                        unit        default              meaning
==========================  ==========  ===================  ===============================================
``model``                   -           midlatitude_summer   tropical, midlatitude_summer, midlatitude_winter,
                                                             subarctic_summer, subarctic_winter, us_standard,
                                                             or ``user`` (then ``profile``)
``profile``                 -           (none)               user atmosphere: see :func:`profile_levels`
``water``                   g cm-2      (none)               the model's water-vapour column scaled to it,
                                                             (0, 15] (:func:`scaled_model_levels`)
``ozone``                   cm-atm      (none)               the model's ozone column scaled to it, (0, 1.5];
                                                             with either: no ground_altitude, cloud, rain
``aerosol``                 -           rural                none, rural, urban, maritime, navy_maritime,
                                                             tropospheric, desert, advective_fog,
                                                             radiative_fog
``visibility``              km          23                   meteorological range at sea level (> 0);
                                                             None: the aerosol model's own; a
                                                             string may carry its unit ("23 km")
``multiple_scattering``     -           true                 LOWTRAN's multiple scattering (IMULT)
``ground_temperature``      K           (none)               boundary temperature (TBOUND): only for the
                                                             ``boundary_radiance`` of :meth:`line_of_sight`
``albedo``                  -           0                    surface albedo (SALB) of the path and sky runs
                                                             (multiple scattering); a render with coupling
                                                             refuses it (it takes the scene's albedo)
``ground_altitude``         m           0                    surface altitude (GNDALT, < 6000); no path may
                                                             go below it
``season``                  -           auto                 aerosol season: auto, spring_summer, fall_winter
``stratospheric_aerosol``   -           background           IVULCN: background, aged_moderate, fresh_high,
                                                             aged_high, fresh_moderate, background_moderate,
                                                             background_high, fresh_extreme
``cloud``                   -           none                 ICLD: cumulus, altostratus, stratus, ..., rain
                                                             models, standard_cirrus, subvisual_cirrus,
                                                             noaa_cirrus
``rain_rate``               mm h-1      0                    RAINRT
``wind_speed``              m s-1       (none)               WSS (navy_maritime, desert)
``wind_speed_24h``          m s-1       (none)               WHH (navy_maritime)
``air_mass_character``      -           (none)               ICSTL 1 (open ocean) - 10 (navy_maritime)
``sun_zenith``              deg         (none)               sun at the scene, for the path's scattered
                                                             sunlight; None: no sunlight in ``path``
``sun_azimuth``             deg         (none)               clockwise from north
``view_azimuth``            deg         (none)               azimuth from target towards observer;
                                                             None: 90 deg from the sun (the azimuthal mean
                                                             of the scattering angle's cosine)
``day_of_year``             -           (none)               Earth-Sun distance of LOWTRAN's sun (IDAY);
                                                             None: mean distance; ``with_sun`` with a
                                                             distance: the nearest day of LOWTRAN's
                                                             orbit table (:func:`day_for_distance`)
``time``, ``latitude``,     -, deg,     (none)               instead of ``sun_*``: the sun from the place
``longitude``               deg                              and time (NREL SPA), ``day_of_year`` too
``phase_function``          -           mie                  mie (LOWTRAN's tables) or henyey_greenstein
``asymmetry``               -           0.7                  g of henyey_greenstein
``wavenumber_step``         cm-1        5                    sampling of the runs (a multiple of 5)
``max_path_nodes``          -           8                    distinct geometries run as-is by ``path_nodes``
``path_zenith_nodes``       -           6                    view-zenith nodes of the grid beyond that
``sky_zenith``              deg         0 30 50 65 75 85 89  zenith nodes of the sky table
``sky_azimuth``             deg         0, 45, ..., 315      azimuth nodes of the sky table
``cache_dir``               -           ~/.cache/radscene/   where results are cached (``cache``: on/off)
                                        lowtran
``workers``                 -           CPUs                 parallel LOWTRAN processes
``timeout``                 s           300                  limit of one run ("5 min" too)
``executable``              -           (found)              the radscene-lowtran7 executable
==========================  ==========  ===================  ===============================================

Config snippet::

    atmosphere:
      type: lowtran
      model: midlatitude_summer
      aerosol: rural
      visibility: 23.0
      multiple_scattering: true
      albedo: 0.15
      sun_zenith: 35.0
      sun_azimuth: 160.0

How the queries map onto LOWTRAN (H1 is always the observer, as LOWTRAN wants it):

* ``path``: ITYPE 2 from the observer to the target, IEMSCT 2 when the sun is up (1 when it
  is not or not given), TBOUND 0 so that no boundary emission enters; a target at the bottom
  of the atmosphere is placed 1 m above it so LOWTRAN adds no ground term either (the
  renderer adds the surface's own emission and reflection). The zenith angle at the observer
  and the sun's zenith there follow from the target's view zenith on a spherical Earth. A
  line of sight within the atmosphere is the flat scene's, of length Δh/|cos θ|
  (:func:`~.geometry.path_kind`): spanning up to 100 m of altitude, or near the horizon
  with a chord on the sphere that would dip below its lower end, it runs level (ITYPE 1)
  at its mean altitude; near the horizon otherwise, as ITYPE 2 from both altitudes and its
  length (``level_path``: level lines of sight of given lengths).
* ``sun``: IEMSCT 3, ITYPE 3 from the target at the sun's zenith angle: τ_so; the irradiance
  is τ_so times the renderer's top-of-atmosphere spectrum, which for this engine is LOWTRAN's
  own (``solar_spectrum`` ``lowtran``, :mod:`radscene.sun.spectrum`), the one that lights its
  scattered radiances.
* ``sky``: ITYPE 3 from the surface towards (zenith, azimuth), IEMSCT 2 (1 at night),
  thermal plus scattered; relative azimuths are folded into [0, 180] deg (the sky is
  symmetric about the sun's vertical).
* ``coupling``: each line of sight run down to the ground at SALB 0, ½ and 1, and for a
  molecular atmosphere at 0 and 1, plus a nadir line of sight from 100 km and the sun's run:
  the diffuse transmittance, its molecular share, the spherical albedo and the direct and
  diffuse irradiance over black ground (:mod:`~radscene.atmosphere.lowtran.coupling`).
* ``path_nodes``: up to ``max_path_nodes`` distinct geometries (altitudes rounded to 1 m,
  zenith to 0.01 deg) become one node each; beyond that a grid of ``path_zenith_nodes``
  view zeniths, uniform in air mass (1/|cos θ|, capped at 89 deg), times one or two observer
  and target altitudes (their extremes when they spread more than 1 m), with weights linear
  in air mass and altitude (:func:`~radscene.atmosphere.lowtran.geometry.path_node_grid`).

Limits worth knowing: LOWTRAN's atmosphere ends at 100 km, so observers above it (satellites)
are refused rather than silently moved; altitudes below the ground (``ground_altitude``, or
the lowest level of a user profile) are refused too. LOWTRAN refracts slant paths with the
refractivity at the run's mean wavenumber, so a slant path's spectra depend on the run's
spectral window by up to ~5e-4 at 60 deg. The line of sight's azimuth is not part of
``path``'s own argument or the engine's ``view_azimuth`` (or the azimuthal-mean default);
the renderer gives each path node's (``path_nodes`` with ``relative_azimuth``).
``sun_zenith`` set to None means no sunlight in ``path``; ``sun`` and ``sky`` take the sun
from their arguments.

Register with ``ENGINES["lowtran"] = LowtranAtmosphere`` (``radscene.atmosphere``).
"""

from __future__ import annotations

import copy
import math

import numpy as np

from radscene.atmosphere.base import (
    Atmosphere,
    CouplingSpectra,
    PathNodes,
    PathSpectra,
    SkyGeometry,
    SkyParts,
    SunSpectra,
)
from radscene.atmosphere.lowtran import coupling as _coupling
from radscene.atmosphere.lowtran import datasets
from radscene.atmosphere.lowtran.cards import (
    AEROSOLS,
    CLOUDS,
    MODELS,
    PHASE_FUNCTIONS,
    SEASONS,
    STRATOSPHERIC_AEROSOLS,
    TOP_ALTITUDE,
    LowtranCase,
    lookup,
)
from radscene.atmosphere.lowtran.datasets import SAME_ALTITUDE_M
from radscene.atmosphere.lowtran.geometry import (
    DEFAULT_EARTH_RADIUS,
    observer_geometry,
    path_kind,
    path_node_grid,
)
from radscene.atmosphere.lowtran.profiles import profile_levels, scaled_model_levels
from radscene.atmosphere.lowtran.runner import LowtranResult, LowtranRunner
from radscene.errors import ConfigError, EngineError

__all__ = ["LowtranAtmosphere", "day_for_distance", "lowtran_line_of_sight",
           "lowtran_sky_radiance", "orbit_factor"]

#: Earth radius LOWTRAN uses per model [km] (card 3 RO blank).
_EARTH_RADIUS_KM = {1: 6378.39, 4: 6356.91, 5: 6356.91}
_DEFAULT_EARTH_RADIUS_KM = DEFAULT_EARTH_RADIUS / 1e3
#: Edges of the spectral windows runs cover [cm-1]: 2500 nm, 6 um, 2.6 um, 1 um, 0.4 um and
#: 0.235 um, where few sensor bands straddle; a query runs the windows its wavelengths touch,
#: so the bands of one render share runs (0.25-28 um is 357-40000 cm-1).
_WINDOW_EDGES = np.array([350.0, 1650.0, 3850.0, 10000.0, 25000.0, 42500.0])
#: Windows entirely below this wavenumber [cm-1] (beyond 6 um) leave out scattered sunlight,
#: there below 1e-4 of the thermal path radiance, and with it the sky's azimuth dependence.
_SOLAR_MIN_WAVENUMBER = 1650.0
#: Targets closer than this to the bottom of the atmosphere are lifted to it [km].
_BOTTOM_OFFSET_KM = 0.001
#: LOWTRAN7's factor of the Sun's elliptic orbit on its solar spectrum, linear between these
#: days of the year (its subroutine SOURCE; Kneizys et al. 1988); 1 at IDAY 0.
_ORBIT_DAYS = np.array([1, 32, 60, 91, 121, 152, 182, 213, 244, 274, 305, 335, 366], float)
_ORBIT_FACTORS = np.array([1.034, 1.030, 1.019, 1.001, 0.985, 0.972, 0.967, 0.971, 0.982, 0.998,
                           1.015, 1.029, 1.034])
#: Largest relative difference accepted between an asked Earth–Sun factor 1/d² and the
#: nearest day's of LOWTRAN's table.
_ORBIT_TOLERANCE = 0.005


def orbit_factor(day_of_year) -> float:
    """LOWTRAN7's factor on its solar spectrum for a day of the year (1 for None or 0).

    Examples
    --------
    >>> orbit_factor(None), orbit_factor(1), orbit_factor(182)
    (1.0, 1.034, 0.967)
    """
    if not day_of_year:
        return 1.0
    return float(np.interp(float(day_of_year), _ORBIT_DAYS, _ORBIT_FACTORS))


def day_for_distance(distance, key="earth_sun_distance") -> int | None:
    """The day of the year whose LOWTRAN7 orbit factor is nearest 1/d² (None at 1 AU, IDAY 0).

    Examples
    --------
    >>> day_for_distance(1.0) is None, day_for_distance(1.0167), day_for_distance(0.9833)
    (True, 185, 1)
    """
    d = float(distance)
    if not d > 0:
        raise ConfigError(f"must be > 0 AU; got {distance!r}", key=key)
    if abs(d - 1.0) < 1e-12:
        return None
    days = np.arange(1, 366)
    factors = np.interp(days.astype(float), _ORBIT_DAYS, _ORBIT_FACTORS)
    i = int(np.argmin(np.abs(factors - d**-2)))
    if abs(factors[i] * d**2 - 1.0) > _ORBIT_TOLERANCE:
        raise ConfigError(f"LOWTRAN's sun lies {_ORBIT_FACTORS.max() ** -0.5:.4f}-"
                          f"{_ORBIT_FACTORS.min() ** -0.5:.4f} AU from the Earth (its orbit "
                          f"table); got {d:g} AU", key=key)
    return int(days[i])


def _wrap180(angle):
    return (np.asarray(angle, float) + 180.0) % 360.0 - 180.0


def _number(value, key, low=-math.inf, high=math.inf, low_open=False, high_open=False,
            unit=""):
    """``value`` as a float within the bounds, or ConfigError naming ``key``."""
    try:
        x = float(value)
    except (TypeError, ValueError):
        raise ConfigError(f"must be a number; got {value!r}", key=key) from None
    bad = (not math.isfinite(x) or (x <= low if low_open else x < low)
           or (x >= high if high_open else x > high))
    if bad:
        lo, hi = ("(" if low_open else "["), (")" if high_open else "]")
        unit = f" {unit}" if unit else ""
        raise ConfigError(f"must lie in {lo}{low:g}, {high:g}{hi}{unit}; got {value!r}", key=key)
    return x


def _km(value, key):
    """A length given with its unit ("23 km", "5000 m") in km; anything else as given (a bare
    number is in km)."""
    if isinstance(value, str):
        try:
            float(value)
        except ValueError:
            from radscene.radiometry.units import parse_quantity

            return parse_quantity(value, "length", key=key) / 1e3
    return value


# -- the engine -------------------------------------------------------------------------------
class LowtranAtmosphere(Atmosphere):
    """LOWTRAN7 engine; parameters in the module table. Checks everything before any run."""

    name = "lowtran"
    wavelength_range = (0.25, 28.0)
    geometry_dependent = True
    #: The top-of-atmosphere spectrum that lights LOWTRAN's scattered radiances; the renderer
    #: lights this engine's direct sun with it (:mod:`radscene.sun.spectrum`).
    solar_spectrum = "lowtran"

    def __init__(
        self,
        model: str = "midlatitude_summer",
        aerosol: str = "rural",
        visibility: float | None = 23.0,
        multiple_scattering: bool = True,
        ground_temperature: float | None = None,
        albedo: float = 0.0,
        ground_altitude: float = 0.0,
        season: str = "auto",
        stratospheric_aerosol: str = "background",
        cloud: str = "none",
        rain_rate: float = 0.0,
        wind_speed: float | None = None,
        wind_speed_24h: float | None = None,
        air_mass_character: int | None = None,
        profile: dict | None = None,
        water: float | None = None,
        ozone: float | None = None,
        sun_zenith: float | None = None,
        sun_azimuth: float | None = None,
        view_azimuth: float | None = None,
        day_of_year: int | None = None,
        time=None,
        latitude: float | None = None,
        longitude: float | None = None,
        phase_function: str = "mie",
        asymmetry: float = 0.7,
        wavenumber_step: float = 5.0,
        max_path_nodes: int = 8,
        path_zenith_nodes: int = 6,
        sky_zenith=(0.0, 30.0, 50.0, 65.0, 75.0, 85.0, 89.0),
        sky_azimuth=tuple(float(a) for a in range(0, 360, 45)),
        cache_dir=None,
        cache: bool = True,
        workers: int | None = None,
        timeout: float = 300.0,
        executable=None,
    ):
        k = "atmosphere"
        self._params = {
            name: value for name, value in locals().items()
            if name not in ("self", "k", "__class__")
        }
        # -- atmosphere and aerosols
        if str(model).lower() == "user":
            if profile is None:
                raise ConfigError("model 'user' needs a profile", key=f"{k}.profile")
            self.levels = profile_levels(profile, key=f"{k}.profile")
            self._model_code = 7
        else:
            if profile is not None:
                raise ConfigError("a profile needs model: user", key=f"{k}.model")
            self._model_code = lookup(MODELS, model, f"{k}.model", "model atmosphere")
            self.levels = ()
        #: Whether the levels are the model's own with its water-vapour or ozone column scaled.
        self._scaled = water is not None or ozone is not None
        if self._scaled:
            if self._model_code == 7:
                raise ConfigError("a user profile gives its own water vapour and ozone; water "
                                  "and ozone scale a model atmosphere",
                                  key=f"{k}.{'water' if water is not None else 'ozone'}")
            self.levels = scaled_model_levels(model, water, ozone, key=k)
        self._ihaze = lookup(AEROSOLS, aerosol, f"{k}.aerosol", "aerosol model")
        if visibility is None:
            self._vis = 0.0
        else:
            self._vis = _number(_km(visibility, f"{k}.visibility"), f"{k}.visibility", 0.0,
                                1.0e4, low_open=True, unit="km")
        if self._ihaze == 0:
            self._vis = 0.0
        self._iseasn = lookup(SEASONS, season, f"{k}.season", "season")
        self._ivulcn = lookup(STRATOSPHERIC_AEROSOLS, stratospheric_aerosol,
                              f"{k}.stratospheric_aerosol", "stratospheric aerosol")
        self._icld = lookup(CLOUDS, cloud, f"{k}.cloud", "cloud model")
        self._rainrt = _number(rain_rate, f"{k}.rain_rate", 0.0, unit="mm/h")
        self._wss = 0.0 if wind_speed is None else _number(wind_speed, f"{k}.wind_speed", 0.0,
                                                           unit="m/s")
        self._whh = 0.0 if wind_speed_24h is None else _number(
            wind_speed_24h, f"{k}.wind_speed_24h", 0.0, unit="m/s")
        if air_mass_character is None:
            self._icstl = 0
        elif isinstance(air_mass_character, int) and 1 <= air_mass_character <= 10:
            self._icstl = air_mass_character
        else:
            raise ConfigError(f"an integer 1 (open ocean) to 10 (strong continental "
                              f"influence); got {air_mass_character!r}",
                              key=f"{k}.air_mass_character")
        if not isinstance(multiple_scattering, bool):
            raise ConfigError(f"true or false; got {multiple_scattering!r}",
                              key=f"{k}.multiple_scattering")
        self.multiple_scattering = multiple_scattering
        self.ground_temperature = None if ground_temperature is None else _number(
            ground_temperature, f"{k}.ground_temperature", 0.0, 1000.0, low_open=True, unit="K")
        self.albedo = _number(albedo, f"{k}.albedo", 0.0, 1.0)
        self.ground_altitude = _number(ground_altitude, f"{k}.ground_altitude", 0.0, 6000.0,
                                       high_open=True, unit="m")
        if self._scaled:
            # LOWTRAN places a model's levels on a raised ground (GNDALT) and its clouds and rain
            # on their own levels, but not a user atmosphere's: there the scaled model would not
            # be the model
            for name, given in (("ground_altitude", self.ground_altitude > 0.0),
                                ("cloud", self._icld != 0), ("rain_rate", self._rainrt > 0.0)):
                if given:
                    raise ConfigError(f"water and ozone scale a model at sea level without "
                                      f"clouds or rain; remove {name} or the columns",
                                      key=f"{k}.{name}")
        bottom = self.levels[0].z * 1e3 if self.levels else 0.0
        #: Lowest altitude a path may reach [m].
        self.bottom_altitude = max(self.ground_altitude, bottom)
        # -- sun
        given_sun = sun_zenith is not None or sun_azimuth is not None
        if time is not None:
            if given_sun:
                raise ConfigError("give either time with latitude and longitude, or sun_zenith "
                                  "and sun_azimuth, not both", key=f"{k}.time")
            if latitude is None or longitude is None:
                raise ConfigError("time needs latitude and longitude", key=f"{k}.latitude")
            import pandas as pd

            from radscene.sun import sun_position

            try:
                stamp = pd.Timestamp(time)
            except (TypeError, ValueError):
                raise ConfigError(f"a timezone-aware time, e.g. '2026-03-15T09:30:00+02:00'; "
                                  f"got {time!r}", key=f"{k}.time") from None
            if stamp.tzinfo is None:
                raise ConfigError(f"the time must carry its time zone; got {time!r}",
                                  key=f"{k}.time")
            try:
                sun = sun_position(stamp, latitude, longitude, self.ground_altitude)
            except ConfigError as err:
                raise ConfigError(err.message, key=f"{k}.{err.key}") from None
            sun_zenith, sun_azimuth = float(sun.zenith), float(sun.azimuth)
            if day_of_year is None:
                day_of_year = int(stamp.tz_convert("UTC").day_of_year)
        self.sun_zenith = None if sun_zenith is None else _number(
            sun_zenith, f"{k}.sun_zenith", 0.0, 180.0, unit="deg")
        self.sun_azimuth = None if sun_azimuth is None else _number(
            sun_azimuth, f"{k}.sun_azimuth", -360.0, 360.0, unit="deg") % 360.0
        if self.sun_zenith is not None and self.sun_azimuth is None:
            if view_azimuth is not None:
                raise ConfigError("sun_azimuth is needed with view_azimuth",
                                  key=f"{k}.sun_azimuth")
            self.sun_azimuth = 0.0  # only the relative azimuth matters, and it defaults to 90
        self.view_azimuth = None if view_azimuth is None else _number(
            view_azimuth, f"{k}.view_azimuth", -360.0, 360.0, unit="deg") % 360.0
        if day_of_year is None:
            self.day_of_year = None
        elif isinstance(day_of_year, int | np.integer) and 1 <= day_of_year <= 366:
            self.day_of_year = int(day_of_year)
        else:
            raise ConfigError(f"an integer 1-366; got {day_of_year!r}", key=f"{k}.day_of_year")
        self._iph = lookup(PHASE_FUNCTIONS, phase_function, f"{k}.phase_function",
                           "phase function")
        self._g = _number(asymmetry, f"{k}.asymmetry", -1.0, 1.0, low_open=True, high_open=True)
        # -- sampling and nodes
        dv = _number(wavenumber_step, f"{k}.wavenumber_step", 5.0, 1000.0, unit="cm-1")
        if abs(dv / 5.0 - round(dv / 5.0)) > 1e-9:
            raise ConfigError(f"a multiple of 5 cm-1; got {wavenumber_step!r}",
                              key=f"{k}.wavenumber_step")
        self.wavenumber_step = dv
        for name, value, low in (("max_path_nodes", max_path_nodes, 1),
                                 ("path_zenith_nodes", path_zenith_nodes, 2)):
            if not isinstance(value, int) or isinstance(value, bool) or value < low:
                raise ConfigError(f"an integer >= {low}; got {value!r}", key=f"{k}.{name}")
        self.max_path_nodes = max_path_nodes
        self.path_zenith_nodes = path_zenith_nodes
        self._sky_zenith = self._nodes(sky_zenith, f"{k}.sky_zenith", 0.0, 90.0)
        self._sky_azimuth = self._nodes(sky_azimuth, f"{k}.sky_azimuth", 0.0, 360.0,
                                        high_open=True)
        self.runner = LowtranRunner(executable=executable, cache_dir=cache_dir, cache=cache,
                                    workers=workers, timeout=timeout)

    @staticmethod
    def _nodes(values, key, low, high, high_open=False):
        a = np.atleast_1d(np.asarray(values, dtype=float))
        if a.ndim != 1 or a.size < 1 or np.any(~np.isfinite(a)) or np.any(np.diff(a) <= 0):
            raise ConfigError("a list of increasing angles [deg]", key=key)
        if a[0] < low or (a[-1] >= high if high_open else a[-1] > high):
            raise ConfigError(f"angles must lie in [{low:g}, {high:g}{')' if high_open else ']'} "
                              "deg", key=key)
        return a

    # -- copies with the sun -------------------------------------------------------------------
    def with_sun(self, sun_zenith, sun_azimuth, day_of_year=None,
                 view_azimuth=None, earth_sun_distance=None) -> LowtranAtmosphere:
        """A copy of this engine with the sun (and the line of sight's azimuth) set.

        Parameters
        ----------
        sun_zenith, sun_azimuth : float
            [deg]; azimuth clockwise from north.
        day_of_year : int, optional
        view_azimuth : float, optional
            Azimuth from target towards observer [deg]; None keeps this engine's.
        earth_sun_distance : float, optional
            [AU]; without ``day_of_year`` and without a day of this engine's own (given, or
            from its time), the day whose LOWTRAN orbit factor is nearest 1/d²
            (:func:`day_for_distance`; LOWTRAN takes the distance from the day alone).
        """
        params = dict(self._params)
        params.update(sun_zenith=sun_zenith, sun_azimuth=sun_azimuth, time=None,
                      latitude=None, longitude=None)
        if day_of_year is None:
            day_of_year = self.day_of_year
        if day_of_year is None and earth_sun_distance is not None:
            day_of_year = day_for_distance(earth_sun_distance)
        params["day_of_year"] = day_of_year
        if view_azimuth is not None:
            params["view_azimuth"] = view_azimuth
        new = type(self)(**params)
        new.runner = self.runner  # share the in-memory cache
        return new

    @property
    def earth_sun_distance(self) -> float:
        """The Earth–Sun distance of LOWTRAN's sun [AU], 1/√(orbit factor of its day): the one
        that lights its scattered radiances, and so the renderer's direct sun."""
        return orbit_factor(self.day_of_year) ** -0.5

    @property
    def parameters(self) -> dict:
        """The constructor's arguments (for provenance; ``time`` as text)."""
        params = copy.deepcopy({k: v for k, v in self._params.items() if k != "time"})
        time = self._params.get("time")
        params["time"] = None if time is None else str(time)
        return params

    # -- cases ------------------------------------------------------------------------------------
    def _earth_radius_km(self) -> float:
        return _EARTH_RADIUS_KM.get(self._model_code, _DEFAULT_EARTH_RADIUS_KM)

    def _base(self, v1: float, v2: float) -> dict:
        fields = dict(
            model=self._model_code, imult=1 if self.multiple_scattering else 0,
            salb=self.albedo, tbound=0.0, noprt=1,
            ihaze=self._ihaze, iseasn=self._iseasn, ivulcn=self._ivulcn, icstl=self._icstl,
            icld=self._icld, vis=self._vis, wss=self._wss, whh=self._whh, rainrt=self._rainrt,
            gndalt=self.ground_altitude / 1e3, iday=self.day_of_year or 0, isourc=0,
            iph=self._iph, g=self._g if self._iph == 0 else 0.0,
            v1=v1, v2=v2, dv=self.wavenumber_step,
        )
        if self._scaled:
            # the model as a user atmosphere: LOWTRAN's defaults for a user atmosphere are those
            # of no model, so its season and Earth radius are given as the model's
            fields.update(model=7, im=1, levels=self.levels, title="radscene scaled columns",
                          ro=self._earth_radius_km(),
                          iseasn=self._iseasn or (2 if self._model_code in (3, 5) else 1))
        elif self.levels:
            fields.update(im=1, levels=self.levels, title="radscene user profile")
        return fields

    def _path_case(self, h_obs, h_tgt, view_zenith, window, view_azimuth=None,
                   kind="slant", length=None) -> tuple[LowtranCase, str]:
        """The run of one line of sight of :func:`~.geometry.path_kind` ``kind``: ITYPE 2
        from the observer's altitude, zenith and the target's ("slant"), or from both
        altitudes and the flat scene's ``length`` [m] ("chord"); ITYPE 1 at the mean altitude
        over ``length`` ("horizontal")."""
        r_earth = self._earth_radius_km() * 1e3
        bottom = self.bottom_altitude / 1e3 if self.levels else 0.0
        # a target at the bottom is lifted off it (a slant path spans more than 100 m, see
        # path_kind, and loses under 1 % of it); a level or chord path is lifted whole
        h1, h2 = h_obs / 1e3, max(h_tgt / 1e3, bottom + _BOTTOM_OFFSET_KM)
        if kind != "slant":
            h1 = max(h1, h1 - h_tgt / 1e3 + h2)
        fields = self._base(*window)
        if kind == "slant":
            angle, central, _ = observer_geometry(h_obs, h_tgt, view_zenith, r_earth)
            angle, central = float(angle), float(central)
            fields.update(itype=2, h1=round(h1, 7), h2=round(h2, 7), angle=round(angle, 6))
        elif kind == "chord":
            central = math.degrees(length / r_earth)
            fields.update(itype=2, h1=round(h1, 7), h2=round(h2, 7), angle=0.0,
                          range=round(length / 1e3, 7))
        else:
            central = math.degrees(length / r_earth)
            fields.update(itype=1, h1=round(0.5 * (h1 + h2), 7), h2=0.0, angle=0.0,
                          range=round(length / 1e3, 7))
        iemsct, sun_obs, rel = 1, None, None
        if self.sun_zenith is not None:
            va = self.view_azimuth if view_azimuth is None else view_azimuth
            delta = 90.0 if va is None else float(_wrap180(self.sun_azimuth - va))
            sz, b, d = (math.radians(x) for x in (self.sun_zenith, central, delta))
            cos_sun = math.cos(sz) * math.cos(b) + math.sin(sz) * math.sin(b) * math.cos(d)
            sun_obs = math.degrees(math.acos(max(-1.0, min(1.0, cos_sun))))
            rel = abs(float(_wrap180(delta - 180.0)))
            if sun_obs < 89.99 and self._solar(window):
                iemsct = 2
        fields["iemsct"] = iemsct
        if iemsct == 2:
            fields.update(iparm=2, parm1=round(rel, 4), parm2=round(sun_obs, 4))
        name = (f"path observer {h_obs:g} m, target {h_tgt:g} m, view zenith "
                f"{view_zenith:g} deg" + ("" if kind == "slant" else f", {kind} of {length:g} m")
                + (f", sun zenith {sun_obs:.2f} deg" if sun_obs is not None else ""))
        return LowtranCase(**fields), name

    def _sun_case(self, h_tgt, sun_zenith, window) -> tuple[LowtranCase, str]:
        fields = self._base(*window)
        fields.update(itype=3, iemsct=3, imult=0, h1=round(h_tgt / 1e3, 7), h2=0.0,
                      angle=round(sun_zenith, 6), iph=2, g=0.0)
        return LowtranCase(**fields), f"sun at {h_tgt:g} m, zenith {sun_zenith:g} deg"

    def _sky_case(self, h_tgt, zenith, relative_azimuth, sun_zenith,
                  window) -> tuple[LowtranCase, str]:
        fields = self._base(*window)
        fields.update(itype=3, h1=round(h_tgt / 1e3, 7), h2=0.0, angle=round(zenith, 6))
        if sun_zenith is not None and sun_zenith < 89.99:
            fields.update(iemsct=2, iparm=2, parm1=round(relative_azimuth, 4),
                          parm2=round(sun_zenith, 4))
            name = (f"sky from {h_tgt:g} m, zenith {zenith:g} deg, {relative_azimuth:g} deg "
                    f"from the sun at zenith {sun_zenith:g} deg")
        else:
            fields["iemsct"] = 1
            name = f"sky from {h_tgt:g} m, zenith {zenith:g} deg, no sun"
        return LowtranCase(**fields), name

    # -- checks -----------------------------------------------------------------------------
    def _check_altitude(self, altitude, key) -> np.ndarray:
        a = np.asarray(altitude, dtype=float)
        if a.size and (np.any(~np.isfinite(a))):
            raise ConfigError("altitudes must be finite [m]", key=key)
        if a.size and np.nanmin(a) < self.bottom_altitude - SAME_ALTITUDE_M:
            raise ConfigError(f"a path below the ground: {np.nanmin(a):g} m is below the "
                              f"surface at {self.bottom_altitude:g} m", key=key)
        if a.size and np.nanmax(a) > TOP_ALTITUDE * 1e3:
            raise ConfigError(f"LOWTRAN's atmosphere ends at 100 km; got {np.nanmax(a):g} m",
                              key=key)
        return a

    def _window(self, wavelength, key="wavelength") -> tuple[np.ndarray, tuple[float, float]]:
        """Checked wavelengths and the spectral window [cm-1] of the runs that cover them."""
        wl = self.check_wavelength(wavelength, key=key)
        if wl.ndim != 1 or wl.size == 0 or np.any(~np.isfinite(wl)) or np.any(wl <= 0):
            raise ConfigError("a non-empty 1-D array of wavelengths > 0 µm", key=key)
        v_lo, v_hi = 1e4 / wl.max(), 1e4 / wl.min()
        edges = _WINDOW_EDGES
        i1 = max(int(np.searchsorted(edges, v_lo, side="right")) - 1, 0)
        i2 = min(int(np.searchsorted(edges, v_hi, side="left")), edges.size - 1)
        if i2 <= i1:  # every wavelength on one edge: the window above it
            i1, i2 = min(i1, edges.size - 2), min(i1, edges.size - 2) + 1
        return wl, (float(edges[i1]), float(edges[i2]))

    @staticmethod
    def _solar(window) -> bool:
        """Whether runs over this window include scattered sunlight."""
        return window[1] > _SOLAR_MIN_WAVENUMBER

    @staticmethod
    def _interp(result: LowtranResult, values, wavenumber) -> np.ndarray:
        v = result.wavenumber
        if wavenumber.min() < v[0] - 1e-6 or wavenumber.max() > v[-1] + 1e-6:
            raise EngineError(f"LOWTRAN case {result.name!r} covers {v[0]:g}-{v[-1]:g} cm-1, "
                              f"not {wavenumber.min():g}-{wavenumber.max():g} cm-1")
        return np.interp(wavenumber, v, values)

    def _check_geometry(self, observer_altitude, target_altitude, view_zenith):
        """(observer, target, view zenith) checked and broadcast to one shape."""
        obs = self._check_altitude(observer_altitude, "observer_altitude")
        tgt = self._check_altitude(target_altitude, "target_altitude")
        vz = np.asarray(view_zenith, dtype=float)
        if vz.size and (np.any(~np.isfinite(vz)) or vz.min() < 0 or vz.max() > 180):
            raise ConfigError("view zenith angles must lie in [0, 180] deg", key="view_zenith")
        return np.broadcast_arrays(obs, tgt, vz)

    # -- Atmosphere interface ---------------------------------------------------------------
    def path(self, observer_altitude, target_altitude, view_zenith, wavelength,
             view_azimuth=None) -> PathSpectra:
        """Line-of-sight spectra (see :class:`~radscene.atmosphere.base.Atmosphere`);
        ``view_azimuth`` [deg, target → observer] overrides the engine's for this call."""
        wl, window = self._window(wavelength)
        if view_azimuth is not None:
            view_azimuth = _number(view_azimuth, "view_azimuth", -360.0, 360.0,
                                   unit="deg") % 360.0
        obs, tgt, vz = self._check_geometry(observer_altitude, target_altitude, view_zenith)
        shape = obs.shape
        flat = [a.ravel() for a in (obs, tgt, vz)]
        n = flat[0].size
        tau = np.ones((n, wl.size))
        thermal = np.zeros((n, wl.size))
        scattered = np.zeros((n, wl.size))
        geoms: dict[tuple, list[int]] = {}
        for i in range(n):
            g = (round(float(flat[0][i]), 3), round(float(flat[1][i]), 3),
                 round(float(flat[2][i]), 6))
            geoms.setdefault(g, []).append(i)
        cases, names, rows = [], [], []
        r_earth = self._earth_radius_km() * 1e3
        for (h_o, h_t, z), idx in geoms.items():
            kind, length = path_kind(h_o, h_t, z, r_earth, SAME_ALTITUDE_M)
            if kind == "none":
                continue  # zero-length path: tau 1, no radiance
            if kind == "slant":
                _, _, s = observer_geometry(h_o, h_t, z, r_earth)
            if kind == "contradiction" or (kind == "slant" and not np.isfinite(s)):
                side = "above" if h_o > h_t else "below"
                raise ConfigError(
                    f"no line of sight joins a target at {h_t:g} m to an observer {side} it at "
                    f"{h_o:g} m with view zenith {z:g} deg (observer above: zenith < 90; "
                    "below: > 90)", key="view_zenith")
            case, name = self._path_case(h_o, h_t, z, window, view_azimuth, kind, length)
            cases.append(case)
            names.append(name)
            rows.append(idx)
        results = self._run_with_airlight(cases, names, window)
        v_req = 1e4 / wl
        for (result, airlight), idx in zip(results, rows, strict=True):
            tau[idx] = self._interp(result, result.transmittance, v_req)
            thermal[idx] = self._interp(result, result.thermal_radiance, v_req)
            if airlight is not None:
                scattered[idx] = self._interp(airlight, airlight.scattered_radiance, v_req) * (
                    1.0 - tau[idx])
            elif result.scattered_radiance is not None:
                scattered[idx] = self._interp(result, result.scattered_radiance, v_req)
        full = shape + wl.shape
        return PathSpectra(transmittance=tau.reshape(full),
                           thermal_radiance=thermal.reshape(full),
                           scattered_radiance=scattered.reshape(full))

    def _run_with_airlight(self, cases, names, window) -> list:
        """Run ``cases``; [(result, sky result or None)]: a level path (ITYPE 1) in sunlight
        also runs the sky at 89 deg from the zenith along its line of sight, whose scattered
        radiance times 1 - τ is its scattered sunlight (Koschmieder 1924: the sky near the
        horizon is the light a level path of such air scatters without end). LOWTRAN's own
        level-path sunlight does not follow the sun's azimuth: at 0.55 um under a sun 40 deg
        from the zenith it was 3.5 times its slant paths' per unit of extinction, 1 - τ, and
        its sky's at the horizon, at any azimuth."""
        skies = {}
        for k, case in enumerate(cases):
            if case.itype == 1 and case.iemsct == 2:
                skies[k] = self._sky_case(case.h1 * 1e3, 89.0, case.parm1, case.parm2, window)
        results = self.runner.run(list(cases) + [c for c, _ in skies.values()],
                                  list(names) + [n for _, n in skies.values()])
        extra = dict(zip(skies, results[len(cases):], strict=True))
        return [(r, extra.get(k)) for k, r in enumerate(results[:len(cases)])]

    def level_path(self, altitude, length, wavelength, view_azimuth=None) -> PathSpectra:
        """Spectra of level lines of sight: ``length`` [m] of air at ``altitude`` [m] (LOWTRAN's
        horizontal path, ITYPE 1; broadcast), as :meth:`path` gives them."""
        wl, window = self._window(wavelength)
        alt = self._check_altitude(altitude, "altitude")
        length = np.asarray(length, dtype=float)
        if length.size and (np.any(~np.isfinite(length)) or length.min() <= 0):
            raise ConfigError("path lengths must be finite and > 0 [m]", key="length")
        alt, length = np.broadcast_arrays(alt, length)
        out = [np.ones(alt.shape + wl.shape), np.zeros(alt.shape + wl.shape),
               np.zeros(alt.shape + wl.shape)]
        flat = list(zip(alt.ravel(), length.ravel(), strict=True))
        cases = [self._path_case(float(h), float(h), 90.0, window, view_azimuth, "horizontal",
                                 float(r)) for h, r in flat]
        results = self._run_with_airlight([c for c, _ in cases], [n for _, n in cases], window)
        v_req = 1e4 / wl
        for k, (result, airlight) in enumerate(results):
            idx = np.unravel_index(k, alt.shape)
            out[0][idx] = self._interp(result, result.transmittance, v_req)
            out[1][idx] = self._interp(result, result.thermal_radiance, v_req)
            if airlight is not None:
                out[2][idx] = self._interp(airlight, airlight.scattered_radiance, v_req) * (
                    1.0 - out[0][idx])
            elif result.scattered_radiance is not None:
                out[2][idx] = self._interp(result, result.scattered_radiance, v_req)
        return PathSpectra(transmittance=out[0], thermal_radiance=out[1],
                           scattered_radiance=out[2])

    def sun(self, target_altitude, sun_zenith, wavelength, toa_irradiance) -> SunSpectra:
        wl, window = self._window(wavelength)
        tgt = self._check_altitude(target_altitude, "target_altitude")
        sz = np.asarray(sun_zenith, dtype=float)
        if sz.size and (np.any(~np.isfinite(sz)) or sz.min() < 0 or sz.max() > 180):
            raise ConfigError("sun zenith angles must lie in [0, 180] deg", key="sun_zenith")
        tgt, sz = np.broadcast_arrays(tgt, sz)
        shape = tgt.shape
        n = tgt.size
        tau = np.zeros((n, wl.size))
        geoms: dict[tuple, list[int]] = {}
        for i, (h, z) in enumerate(zip(tgt.ravel(), sz.ravel(), strict=True)):
            if z < 90.0:  # sun below the horizon: no direct sunlight
                geoms.setdefault((round(float(h), 3), round(float(z), 6)), []).append(i)
        built = [self._sun_case(h, z, window) for (h, z) in geoms]
        results = self.runner.run([c for c, _ in built], [nm for _, nm in built])
        v_req = 1e4 / wl
        for result, idx in zip(results, geoms.values(), strict=True):
            tau[idx] = self._interp(result, result.transmittance, v_req)
        tau = tau.reshape(shape + wl.shape)
        return SunSpectra(transmittance=tau, irradiance=tau * np.asarray(toa_irradiance, float))

    def sky(self, zenith, azimuth, wavelength, geometry: SkyGeometry | None = None) -> np.ndarray:
        thermal, scattered = self._sky_parts(zenith, azimuth, wavelength, geometry)
        return thermal + scattered

    def sky_parts(self, zenith, azimuth, wavelength, geometry: SkyGeometry | None = None
                  ) -> SkyParts:
        """The sky's scattered sunlight (TAPE7's SUMSSR) and emission (its thermal path
        radiance) apart, from the same LOWTRAN runs as :meth:`sky`."""
        thermal, scattered = self._sky_parts(zenith, azimuth, wavelength, geometry)
        return SkyParts(solar=scattered, thermal=thermal)

    def _sky_parts(self, zenith, azimuth, wavelength, geometry, window=None):
        if window is None:
            wl, window = self._window(wavelength)
        else:
            wl = np.asarray(wavelength, float)
        geometry = geometry if geometry is not None else SkyGeometry(
            self.bottom_altitude, 180.0 if self.sun_zenith is None else self.sun_zenith,
            self.sun_azimuth or 0.0)
        h = float(self._check_altitude(geometry.target_altitude, "geometry.target_altitude"))
        if h > TOP_ALTITUDE * 1e3 - 1.0:
            raise ConfigError("the sky must be seen from below 100 km",
                              key="geometry.target_altitude")
        sun_zenith = _number(geometry.sun_zenith, "geometry.sun_zenith", 0.0, 180.0)
        sun_azimuth = _number(geometry.sun_azimuth, "geometry.sun_azimuth", -360.0, 360.0)
        z, a = np.broadcast_arrays(np.asarray(zenith, float), np.asarray(azimuth, float))
        if z.size and (np.any(~np.isfinite(z)) or z.min() < 0 or z.max() > 90):
            raise ConfigError("sky directions must have zenith angles in [0, 90] deg",
                              key="zenith")
        if z.size and np.any(~np.isfinite(a)):
            raise ConfigError("azimuths must be finite [deg]", key="azimuth")
        shape = z.shape
        sun_up = sun_zenith < 90.0 and self._solar(window)
        geoms: dict[tuple, list[int]] = {}
        for i, (zz, aa) in enumerate(zip(z.ravel(), a.ravel(), strict=True)):
            rel = round(abs(float(_wrap180(sun_azimuth - aa))), 4) if sun_up else 0.0
            geoms.setdefault((round(float(zz), 6), rel), []).append(i)
        built = [self._sky_case(h, zz, rel, sun_zenith if sun_up else None, window)
                 for (zz, rel) in geoms]
        results = self.runner.run([c for c, _ in built], [nm for _, nm in built])
        n = z.size
        thermal = np.zeros((n, wl.size))
        scattered = np.zeros((n, wl.size))
        v_req = 1e4 / wl
        for result, idx in zip(results, geoms.values(), strict=True):
            thermal[idx] = self._interp(result, result.thermal_radiance, v_req)
            if result.scattered_radiance is not None:
                scattered[idx] = self._interp(result, result.scattered_radiance, v_req)
        full = shape + wl.shape
        return thermal.reshape(full), scattered.reshape(full)

    couples = True
    #: The scene key of this engine's fixed ground albedo (refused in a render with coupling).
    surface_albedo_key = "albedo"

    @property
    def surface_albedo(self) -> float:
        """The ground albedo of the path and sky runs (SALB) [-]: ``albedo``."""
        return self.albedo

    def coupling(self, observer_altitude, target_altitude, view_zenith, wavelength
                 ) -> CouplingSpectra:
        """Diffuse transmittance, its molecular share, spherical albedo and irradiances over
        black ground, from LOWTRAN runs at ground albedos 0, ½ and 1 (see
        :mod:`radscene.atmosphere.lowtran.coupling`)."""
        return _coupling.coupling(self, observer_altitude, target_altitude, view_zenith,
                                  wavelength)

    def sky_zenith_nodes(self) -> np.ndarray:
        return self._sky_zenith.copy()

    def sky_azimuth_nodes(self) -> np.ndarray:
        return self._sky_azimuth.copy()

    @property
    def azimuth_dependent(self) -> bool:
        """True while the sun is up: the scattered path radiance depends on the azimuth."""
        return self.sun_zenith is not None and self.sun_zenith < 90.0

    def path_nodes(self, observer_altitude, target_altitude, view_zenith,
                   relative_azimuth=None) -> PathNodes:
        """Nodes of the pixels' lines of sight: :func:`~.geometry.path_node_grid` with
        ``max_path_nodes`` and ``path_zenith_nodes`` (module docstring); with the pixels'
        ``relative_azimuth`` [deg] and the sun up, a relative-azimuth axis for the path
        radiance (:mod:`radscene.atmosphere.nodes`)."""
        obs, tgt, vz = np.broadcast_arrays(np.asarray(observer_altitude, dtype=float),
                                           np.asarray(target_altitude, dtype=float),
                                           np.asarray(view_zenith, dtype=float))
        if obs.size:
            self._check_altitude(obs, "observer_altitude")
            self._check_altitude(tgt, "target_altitude")
            if np.any(~np.isfinite(vz)) or vz.min() < 0 or vz.max() > 180:
                raise ConfigError("view zenith angles must lie in [0, 180] deg",
                                  key="view_zenith")
        nodes = path_node_grid(obs, tgt, vz, zenith_nodes=self.path_zenith_nodes,
                               max_distinct=self.max_path_nodes)
        return self.azimuth_axis(nodes, vz.ravel(), relative_azimuth)

    # -- datasets ---------------------------------------------------------------------------
    def line_of_sight(self, observer_altitude, target_altitude, view_zenith, wavelength=None,
                      wavelength_range=None):
        """Everything LOWTRAN says about one slant path: see :func:`.datasets.line_of_sight`."""
        return datasets.line_of_sight(self, observer_altitude, target_altitude, view_zenith,
                                      wavelength, wavelength_range)

    def sky_radiance(self, zenith, azimuth, wavelength=None, wavelength_range=None,
                     target_altitude=None, sun_zenith=None, sun_azimuth=None):
        """Sky radiance on a zenith × azimuth grid: see :func:`.datasets.sky_radiance`."""
        return datasets.sky_radiance(self, zenith, azimuth, wavelength, wavelength_range,
                                     target_altitude, sun_zenith, sun_azimuth)


def lowtran_line_of_sight(observer_altitude, target_altitude, view_zenith, wavelength=None,
                          wavelength_range=None, **parameters):
    """One slant path through LOWTRAN7 as an xarray Dataset over wavelength.

    ``parameters`` are those of :class:`LowtranAtmosphere`; the rest as in
    :meth:`LowtranAtmosphere.line_of_sight` (radiance in W m-2 sr-1 um-1).
    """
    return LowtranAtmosphere(**parameters).line_of_sight(
        observer_altitude, target_altitude, view_zenith, wavelength, wavelength_range)


def lowtran_sky_radiance(zenith, azimuth, wavelength=None, wavelength_range=None,
                         target_altitude=None, **parameters):
    """Sky radiance map from the surface through LOWTRAN7 (see
    :meth:`LowtranAtmosphere.sky_radiance`)."""
    return LowtranAtmosphere(**parameters).sky_radiance(
        zenith, azimuth, wavelength, wavelength_range, target_altitude)
