"""Orbits: two-line element sets (SGP4) or Keplerian elements, and their ground geometry.

An :class:`Orbit` gives a satellite's position and velocity at any time, in the inertial
TEME frame (true equator, mean equinox: the frame of SGP4) and in ECEF (Earth-fixed), and
turns a stretch of it into a :class:`~radscene.platform.trajectory.Trajectory` in a scene's
local frame with a nadir-pointing attitude. Three ways in:

* :meth:`Orbit.from_tle` — a NORAD two-line element set, propagated by SGP4 (the ``sgp4``
  package, WGS72 constants as the element sets are fitted with). Each line's checksum is
  verified; a bad one is an error naming the line.
* :meth:`Orbit.from_elements` — osculating Keplerian elements at an epoch, propagated as a
  two-body orbit with the secular J2 drift of the node, perigee and mean anomaly.
* :meth:`Orbit.overpass` — a circular orbit that passes exactly over a ground point at a
  given time (sun-synchronous by default): the quickest way to put a scene under a satellite.

TEME → ECEF uses the Greenwich mean sidereal time of IAU 1982 (as SGP4 does) on UT1 = UTC +
``dut1``; polar motion (< 20 m) is neglected.

========================  =======  ========  ===============================================
parameter                 unit     default   meaning
========================  =======  ========  ===============================================
``tle``                   -        required  two lines (optionally a name line before them)
``altitude``              m        required  circular orbit height (overpass, elements)
``inclination``           deg      sun-sync  orbit inclination
``descending``            -        true      overpass on the descending (southbound) node
``eccentricity``          -        0         Keplerian eccentricity, [0, 1)
``raan``                  deg      0         right ascension of the ascending node
``argument_of_perigee``   deg      0
``mean_anomaly``          deg      0         at the epoch
========================  =======  ========  ===============================================

Config snippet::

    orbit: {tle: ["1 25544U 98067A   ...", "2 25544  51.6416 ..."]}
    orbit: {overpass: {altitude: 705 km, descending: true}}

References
----------
D. A. Vallado, P. Crawford, R. Hujsak and T. S. Kelso, "Revisiting Spacetrack Report #3",
AIAA 2006-6753 (2006), https://doi.org/10.2514/6.2006-6753 (SGP4, TEME, GMST).
D. A. Vallado, *Fundamentals of Astrodynamics and Applications*, 4th ed. (2013), §9.6 (J2
secular rates) and §11.4 (sun-synchronous orbits).
"""

from __future__ import annotations

import datetime as _dt

import numpy as np

from radscene.errors import ConfigError, EngineError
from radscene.platform.geolocation import (
    EARTH_ROTATION_RATE,
    WGS84_A,
    LocalFrame,
    ecef_to_geodetic,
    enu_basis,
    geodetic_to_ecef,
)
from radscene.platform.trajectory import Trajectory, quaternion_from_matrix

__all__ = [
    "GM_EARTH",
    "J2_EARTH",
    "tle_checksum",
    "parse_tle",
    "gmst",
    "teme_to_ecef",
    "sun_synchronous_inclination",
    "Orbit",
]

#: Earth's gravitational parameter (WGS84 / EGM96) [m3 s-2].
GM_EARTH = 3.986004418e14
#: Earth's second zonal harmonic (EGM96, unnormalised) [-].
J2_EARTH = 1.08262668e-3
_YEAR = 365.2421897 * 86400.0  # tropical year [s]
_UNIX_JD = 2440587.5


def tle_checksum(line: str) -> int:
    """Modulo-10 checksum of a TLE line: the sum of its digits, each '-' counting 1.

    Parameters
    ----------
    line : str
        A TLE line; its first 68 characters are summed.

    Examples
    --------
    >>> tle_checksum("1 00005U 58002B   00179.78495062  .00000023  00000-0  28098-4 0  4753")
    3
    """
    return sum(int(c) if c.isdigit() else (1 if c == "-" else 0) for c in line[:68]) % 10


def parse_tle(tle, key: str = "tle") -> tuple[str, str, str]:
    """Check a two-line element set and split it into (name, line 1, line 2).

    Parameters
    ----------
    tle : str or sequence of str
        The element set: two lines, or three with a name line first; a string is split at
        newlines.
    key : str
        Key path used in error messages (``orbit.tle``).

    Returns
    -------
    name, line1, line2 : str

    Raises
    ------
    ConfigError
        A missing line, a line that does not start with its number, a line shorter than 69
        characters, differing satellite numbers, or a checksum that does not match; the
        message names the line (``orbit.tle.line2``).
    """
    lines = tle.splitlines() if isinstance(tle, str) else list(tle)
    lines = [str(s).rstrip() for s in lines if str(s).strip()]
    if len(lines) == 3:
        name, l1, l2 = lines[0].strip(), lines[1], lines[2]
        if name.startswith("0 "):
            name = name[2:].strip()
    elif len(lines) == 2:
        name, l1, l2 = "", lines[0], lines[1]
    else:
        raise ConfigError(f"a TLE has two lines (and optionally a name line first); got "
                          f"{len(lines)} lines", key=key)
    for number, line in ((1, l1), (2, l2)):
        where = f"{key}.line{number}"
        if not line.startswith(f"{number} "):
            raise ConfigError(f"must start with '{number} '; got {line[:10]!r}", key=where)
        if len(line) < 69:
            raise ConfigError(f"must have 69 characters; got {len(line)}", key=where)
        if not line[68].isdigit():
            raise ConfigError(f"column 69 must be the checksum digit; got {line[68]!r}",
                              key=where)
        expected = tle_checksum(line)
        if int(line[68]) != expected:
            raise ConfigError(f"checksum {line[68]} does not match the computed {expected}: "
                              "the line is corrupt", key=where)
    if l1[2:7] != l2[2:7]:
        raise ConfigError(f"satellite numbers differ: {l1[2:7]!r} and {l2[2:7]!r}",
                          key=f"{key}.line2")
    return name, l1[:69], l2[:69]


def _julian(times) -> tuple[np.ndarray, np.ndarray]:
    """(whole, fraction) Julian dates (UTC) of timezone-aware datetimes (any array shape).

    The fraction is the UTC time of day / 86400, exact to double precision.
    """
    arr = np.asarray(times, dtype=object)
    flat = arr.ravel()
    whole = np.empty(flat.size)
    frac = np.empty(flat.size)
    for k, t in enumerate(flat):
        if not isinstance(t, _dt.datetime) or t.tzinfo is None:
            raise ConfigError(f"must be timezone-aware datetimes; got {t!r}", key="time")
        u = t.astimezone(_dt.UTC)
        whole[k] = _UNIX_JD + (u.date() - _dt.date(1970, 1, 1)).days
        frac[k] = (u.hour * 3600 + u.minute * 60 + u.second + u.microsecond * 1e-6) / 86400.0
    return whole.reshape(arr.shape), frac.reshape(arr.shape)


def _elapsed(times, epoch) -> np.ndarray:
    """Seconds from `epoch` to each time (exact to the microsecond), shape of `times`."""
    arr = np.asarray(times, dtype=object)
    return np.array([(t - epoch).total_seconds() for t in arr.ravel()]).reshape(arr.shape)


def gmst(jd_ut1, fraction=0.0) -> np.ndarray:
    """Greenwich mean sidereal time, IAU 1982 [rad], in [0, 2π).

    Parameters
    ----------
    jd_ut1, fraction : array_like
        Julian date in UT1, split in two for precision [day].

    Notes
    -----
    .. math:: \\theta = 67310.54841 + (876600 \\cdot 3600 + 8640184.812866) T
              + 0.093104 T^2 - 6.2\\times10^{-6} T^3 \\ \\mathrm{[s]},
              \\quad T = (JD_{UT1} - 2451545) / 36525

    (Vallado et al. 2006, eq. 4; 1 s of time = 15 arcsec).
    """
    jd = np.asarray(jd_ut1, dtype=float)
    fr = np.asarray(fraction, dtype=float)
    t = ((jd - 2451545.0) + fr) / 36525.0
    sec = (67310.54841 + (876600.0 * 3600.0 + 8640184.812866) * t + 0.093104 * t * t
           - 6.2e-6 * t * t * t)
    return np.mod(np.radians(sec / 240.0), 2.0 * np.pi)


def _rot3(angle) -> np.ndarray:
    c, s = np.cos(angle), np.sin(angle)
    z, o = np.zeros_like(c), np.ones_like(c)
    return np.stack([c, s, z, -s, c, z, z, z, o], axis=-1).reshape(np.shape(angle) + (3, 3))


def teme_to_ecef(position, velocity, theta) -> tuple[np.ndarray, np.ndarray]:
    """Rotate TEME states into ECEF (pseudo-Earth-fixed: polar motion neglected).

    Parameters
    ----------
    position, velocity : array_like
        ``(..., 3)`` TEME position [m] and velocity [m s-1].
    theta : array_like
        ``(...)`` Greenwich mean sidereal time [rad] (:func:`gmst`).

    Returns
    -------
    position, velocity : numpy.ndarray
        ``(..., 3)`` ECEF position [m] and Earth-relative velocity [m s-1]:
        :math:`r = R_3(\\theta) r_{TEME}`, :math:`v = R_3(\\theta) v_{TEME} - \\omega \\times r`.
    """
    rot = _rot3(np.asarray(theta, dtype=float))
    r = np.einsum("...ij,...j->...i", rot, np.asarray(position, dtype=float))
    v = np.einsum("...ij,...j->...i", rot, np.asarray(velocity, dtype=float))
    omega = np.array([0.0, 0.0, EARTH_ROTATION_RATE])
    return r, v - np.cross(omega, r)


def sun_synchronous_inclination(altitude, eccentricity: float = 0.0) -> float:
    """Inclination of a sun-synchronous orbit [deg] (the node precesses 360 deg a year).

    Parameters
    ----------
    altitude : float
        Semi-major axis minus the equatorial radius [m], > 0.
    eccentricity : float
        Orbital eccentricity, [0, 1).

    Notes
    -----
    .. math:: \\cos i = -\\frac{2 a^{7/2} (1-e^2)^2 \\dot\\Omega}{3 J_2 R_E^2 \\sqrt{\\mu}},
              \\quad \\dot\\Omega = 2\\pi / (365.2421897\\ \\mathrm{d})

    Examples
    --------
    >>> round(sun_synchronous_inclination(705e3), 2)  # Landsat 8: 98.2 deg
    98.21
    """
    h = float(altitude)
    e = float(eccentricity)
    if not (np.isfinite(h) and h > 0):
        raise ConfigError(f"must be > 0 m; got {altitude!r}", key="altitude")
    if not 0.0 <= e < 1.0:
        raise ConfigError(f"must be in [0, 1); got {eccentricity!r}", key="eccentricity")
    a = WGS84_A + h
    rate = 2.0 * np.pi / _YEAR
    cos_i = -2.0 * a**3.5 * (1 - e * e) ** 2 * rate / (3.0 * J2_EARTH * WGS84_A**2
                                                       * np.sqrt(GM_EARTH))
    if cos_i < -1.0:
        raise ConfigError(f"no sun-synchronous orbit at {h / 1e3:g} km", key="altitude")
    return float(np.degrees(np.arccos(cos_i)))


def _angle(value, key, low=-np.inf, high=np.inf) -> float:
    try:
        v = float(value)
    except (TypeError, ValueError):
        v = np.nan
    if not (np.isfinite(v) and low <= v <= high):
        raise ConfigError(f"must be a number in [{low:g}, {high:g}] deg; got {value!r}", key=key)
    return v


class Orbit:
    """A satellite orbit; build it with :meth:`from_tle`, :meth:`from_elements` or
    :meth:`overpass`.

    Attributes
    ----------
    epoch : datetime
        Epoch of the elements (UTC).
    name : str
        Satellite name ("" when unknown).
    dut1 : float
        UT1 - UTC [s] used for the Earth's rotation angle.
    """

    def __init__(self, *, epoch, name="", satrec=None, elements=None, dut1: float = 0.0):
        self.epoch = epoch
        self.name = name
        self._satrec = satrec
        self._elements = elements
        self.dut1 = float(dut1)

    def __repr__(self) -> str:
        kind = "SGP4" if self._satrec is not None else "Kepler+J2"
        return f"Orbit({self.name!r}, {kind}, epoch={self.epoch.isoformat()})"

    # -- constructors ---------------------------------------------------------------------

    @classmethod
    def from_tle(cls, tle, name: str | None = None, dut1: float = 0.0, key: str = "tle"):
        """An orbit from a two-line element set, propagated by SGP4.

        Parameters
        ----------
        tle : str or sequence of str
            See :func:`parse_tle`.
        name : str, optional
            Overrides the name line.
        dut1 : float
            UT1 - UTC [s].
        key : str
            Key path for error messages.
        """
        from sgp4.api import WGS72, Satrec

        tle_name, l1, l2 = parse_tle(tle, key=key)
        sat = Satrec.twoline2rv(l1, l2, WGS72)
        if sat.error:
            raise ConfigError(f"SGP4 rejected the elements (error {sat.error})", key=key)
        seconds = (sat.jdsatepoch - _UNIX_JD + sat.jdsatepochF) * 86400.0
        epoch = _dt.datetime(1970, 1, 1, tzinfo=_dt.UTC) + _dt.timedelta(seconds=seconds)
        return cls(epoch=epoch, name=name if name is not None else tle_name, satrec=sat,
                   dut1=dut1)

    @classmethod
    def from_elements(cls, epoch, *, semi_major_axis=None, altitude=None, eccentricity=0.0,
                      inclination, raan=0.0, argument_of_perigee=0.0, mean_anomaly=0.0,
                      j2: bool = True, name: str = "", dut1: float = 0.0):
        """An orbit from Keplerian elements (two-body motion plus the secular J2 drift).

        Parameters
        ----------
        epoch : datetime
            Timezone-aware epoch of the elements.
        semi_major_axis : float, optional
            [m]; or ``altitude`` = a - R_E [m] (exactly one of the two).
        eccentricity : float
            [0, 1).
        inclination, raan, argument_of_perigee, mean_anomaly : float
            [deg]; the frame is TEME-like (equator of date, mean equinox).
        j2 : bool
            Add the secular J2 rates of the node, perigee and mean anomaly.
        """
        if not isinstance(epoch, _dt.datetime) or epoch.tzinfo is None:
            raise ConfigError(f"must be a timezone-aware datetime; got {epoch!r}", key="epoch")
        if (semi_major_axis is None) == (altitude is None):
            raise ConfigError("give exactly one of semi_major_axis and altitude",
                              key="semi_major_axis")
        a = float(semi_major_axis) if semi_major_axis is not None else WGS84_A + float(altitude)
        e = float(eccentricity)
        if not (np.isfinite(e) and 0.0 <= e < 1.0):
            raise ConfigError(f"must be in [0, 1); got {eccentricity!r}", key="eccentricity")
        if not (np.isfinite(a) and a * (1.0 - e) > WGS84_A):
            raise ConfigError(f"the perigee {a * (1 - e) - WGS84_A:g} m must be above the "
                              "Earth's surface", key="altitude" if altitude is not None
                              else "semi_major_axis")
        el = {
            "a": a, "e": e, "i": np.radians(_angle(inclination, "inclination", 0.0, 180.0)),
            "raan": np.radians(_angle(raan, "raan")),
            "argp": np.radians(_angle(argument_of_perigee, "argument_of_perigee")),
            "m0": np.radians(_angle(mean_anomaly, "mean_anomaly")), "j2": bool(j2),
        }
        return cls(epoch=epoch.astimezone(_dt.UTC), name=name, elements=el, dut1=dut1)

    @classmethod
    def overpass(cls, latitude, longitude, time, altitude, *, inclination=None,
                 descending: bool = True, height: float = 0.0, name: str = "",
                 dut1: float = 0.0):
        """A circular orbit whose satellite is exactly above a ground point at a time.

        "Above" is along the ellipsoid normal: the satellite is at ``height + altitude``
        over ``(latitude, longitude)`` at ``time``, so its geodetic nadir is the point.

        Parameters
        ----------
        latitude, longitude : float
            The ground point [deg].
        time : datetime
            Timezone-aware time of the overpass (the epoch of the elements).
        altitude : float
            Height of the satellite above the point [m], > 0.
        inclination : float, optional
            [deg]; default sun-synchronous at that altitude.
        descending : bool
            Cross the point southbound (True) or northbound.
        height : float
            Height of the point above the ellipsoid [m].
        """
        h = float(altitude)
        if not (np.isfinite(h) and h > 0):
            raise ConfigError(f"must be > 0 m; got {altitude!r}", key="altitude")
        inc = (sun_synchronous_inclination(h) if inclination is None
               else _angle(inclination, "inclination", 0.0, 180.0))
        ecef = geodetic_to_ecef(latitude, longitude, float(height) + h)
        jd, fr = _julian(time)
        theta = gmst(jd, fr + dut1 / 86400.0)
        r_eci = _rot3(-theta) @ ecef
        r = float(np.linalg.norm(r_eci))
        dec = np.arcsin(r_eci[2] / r)
        ra = np.arctan2(r_eci[1], r_eci[0])
        si = np.sin(np.radians(inc))
        if abs(np.sin(dec)) > si + 1e-12:
            raise ConfigError(f"an orbit inclined {inc:g} deg never passes over latitude "
                              f"{latitude!r}", key="inclination")
        u = np.arcsin(np.clip(np.sin(dec) / si, -1.0, 1.0)) if si > 0 else 0.0
        if descending:
            u = np.pi - u
        node = ra - np.arctan2(np.cos(np.radians(inc)) * np.sin(u), np.cos(u))
        return cls.from_elements(time, semi_major_axis=r, eccentricity=0.0, inclination=inc,
                                 raan=np.degrees(node) % 360.0, argument_of_perigee=0.0,
                                 mean_anomaly=np.degrees(u) % 360.0, name=name, dut1=dut1)

    # -- states ----------------------------------------------------------------------------

    @property
    def period(self) -> float:
        """Anomalistic (Keplerian) period [s]."""
        if self._satrec is not None:
            return float(2.0 * np.pi / self._satrec.no_kozai * 60.0)
        return float(2.0 * np.pi * np.sqrt(self._elements["a"] ** 3 / GM_EARTH))

    def teme(self, times) -> tuple[np.ndarray, np.ndarray]:
        """Inertial (TEME) position [m] and velocity [m s-1], shape ``times.shape + (3,)``.

        Parameters
        ----------
        times : datetime or array_like of datetimes
            Timezone-aware times.
        """
        jd, fr = _julian(times)
        if self._satrec is not None:
            from sgp4.api import SGP4_ERRORS

            err, r, v = self._satrec.sgp4_array(jd.ravel(), fr.ravel())
            if np.any(err):
                code = int(err[np.nonzero(err)[0][0]])
                raise EngineError(f"SGP4 failed for {self.name or 'the satellite'}: "
                                  f"{SGP4_ERRORS.get(code, code)}")
            shape = jd.shape + (3,)
            return np.asarray(r).reshape(shape) * 1e3, np.asarray(v).reshape(shape) * 1e3
        return self._kepler(_elapsed(times, self.epoch))

    def _kepler(self, dt) -> tuple[np.ndarray, np.ndarray]:
        el = self._elements
        a, e, i = el["a"], el["e"], el["i"]
        n = np.sqrt(GM_EARTH / a**3)
        p = a * (1 - e * e)
        raan, argp, m = el["raan"] + 0 * dt, el["argp"] + 0 * dt, el["m0"] + n * dt
        raan_rate = argp_rate = m_extra = 0.0
        if el["j2"]:
            k = 1.5 * J2_EARTH * (WGS84_A / p) ** 2 * n
            ci = np.cos(i)
            raan_rate = -k * ci
            argp_rate = 0.5 * k * (5 * ci * ci - 1)
            m_extra = 0.5 * k * np.sqrt(1 - e * e) * (3 * ci * ci - 1)
            raan = raan + raan_rate * dt
            argp = argp + argp_rate * dt
            m = m + m_extra * dt
        big_e = np.array(m, dtype=float)
        for _ in range(30):  # Newton on Kepler's equation
            step = (big_e - e * np.sin(big_e) - m) / (1 - e * np.cos(big_e))
            big_e = big_e - step
            if np.all(np.abs(step) < 1e-15):
                break
        nu = 2 * np.arctan2(np.sqrt(1 + e) * np.sin(big_e / 2), np.sqrt(1 - e) * np.cos(big_e / 2))
        r = a * (1 - e * np.cos(big_e))
        u = argp + nu
        # perifocal → inertial; the velocity is the time derivative of this position model
        # (two-body motion at the drifted mean motion, plus the drift of perigee and node)
        cu, su, co, so = np.cos(u), np.sin(u), np.cos(raan), np.sin(raan)
        ci_, si_ = np.cos(i), np.sin(i)
        radial = np.stack([co * cu - so * su * ci_, so * cu + co * su * ci_, su * si_], -1)
        pos = r[..., None] * radial
        h = np.sqrt(GM_EARTH * p)
        scale = (n + m_extra) / n
        vr = GM_EARTH / h * e * np.sin(nu) * scale
        vt = h / r * scale + r * argp_rate
        along = np.stack([-co * su - so * cu * ci_, -so * su + co * cu * ci_, cu * si_], -1)
        vel = vr[..., None] * radial + vt[..., None] * along
        vel = vel + raan_rate * np.stack([-pos[..., 1], pos[..., 0], 0 * pos[..., 2]], -1)
        return pos, vel

    def ecef(self, times, earth_rotation: bool = True) -> tuple[np.ndarray, np.ndarray]:
        """ECEF position [m] and Earth-relative velocity [m s-1] at times.

        Parameters
        ----------
        times : datetime or array_like of datetimes
        earth_rotation : bool
            False freezes the Earth at its orientation at the first time (the satellite's
            inertial motion drawn on a non-rotating Earth): for showing what the rotation
            does to an image.
        """
        jd, fr = _julian(times)
        r, v = self.teme(times)
        theta = gmst(jd, fr + self.dut1 / 86400.0)
        if not earth_rotation:
            theta = np.full_like(theta, np.ravel(theta)[0])
            rot = _rot3(theta)
            return (np.einsum("...ij,...j->...i", rot, r), np.einsum("...ij,...j->...i", rot, v))
        return teme_to_ecef(r, v, theta)

    def subsatellite_point(self, times) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Geodetic latitude [deg], longitude [deg] and height [m] of the satellite."""
        return ecef_to_geodetic(self.ecef(times)[0])

    def trajectory(self, frame: LocalFrame, start, duration: float, *, step: float = 1.0,
                   margin: float = 2.0, yaw_steering: bool = False,
                   earth_rotation: bool = True) -> Trajectory:
        """A stretch of the orbit as a trajectory in a scene frame, pointing at nadir.

        The body's up axis is the ellipsoid normal through the satellite (so the boresight,
        -up, meets the ground at the geodetic sub-satellite point); its forward axis is the
        inertial velocity (no yaw steering: the scan lines stay perpendicular to the orbit
        plane and the Earth's rotation skews the image) or, with ``yaw_steering``, the
        Earth-relative velocity, made perpendicular to up.

        Parameters
        ----------
        frame : LocalFrame
            The scene's frame.
        start : datetime
            Timezone-aware time of t = 0 (the trajectory's epoch).
        duration : float
            [s], > 0; samples cover ``[-margin, duration + margin]``.
        step : float
            Sample spacing [s]; positions are Hermite-interpolated (errors < 1 mm at 1 s).
        margin : float
            Extra time before and after [s].
        yaw_steering, earth_rotation : bool
            See above and :meth:`ecef`.

        Returns
        -------
        Trajectory
        """
        if not isinstance(start, _dt.datetime) or start.tzinfo is None:
            raise ConfigError(f"must be a timezone-aware datetime; got {start!r}", key="start")
        d, s, mg = float(duration), float(step), float(margin)
        if not (np.isfinite(d) and d > 0):
            raise ConfigError(f"must be > 0 s; got {duration!r}", key="duration")
        if not (np.isfinite(s) and s > 0):
            raise ConfigError(f"must be > 0 s; got {step!r}", key="step")
        n = int(np.ceil((d + 2 * mg) / s)) + 1
        tau = -mg + s * np.arange(n)
        times = [start + _dt.timedelta(seconds=float(t)) for t in tau]
        r, v = self.ecef(times, earth_rotation)
        lat, lon, _ = ecef_to_geodetic(r)
        up_ecef = enu_basis(lat, lon)[:, 2, :]
        heading = v + np.cross([0.0, 0.0, EARTH_ROTATION_RATE], r) if (
            not yaw_steering and earth_rotation) else v
        fwd = heading - np.sum(heading * up_ecef, axis=1, keepdims=True) * up_ecef
        fwd /= np.linalg.norm(fwd, axis=1, keepdims=True)
        up = frame.vector_from_ecef(up_ecef)
        forward = frame.vector_from_ecef(fwd)
        right = np.cross(forward, up)
        rot = np.stack([right, forward, up], axis=-1)
        return Trajectory(tau, frame.from_ecef(r), quaternions=quaternion_from_matrix(rot),
                          velocities=frame.vector_from_ecef(v), epoch=start)
