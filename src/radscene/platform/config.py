"""Scene-file models (pydantic) of the scanning observers and their platforms, and the factory.

These models are ready to join the scene schema's observer union (discriminator ``type``):
:class:`PushbroomSpec` (``type: pushbroom``) and :class:`WhiskbroomSpec` (``type:
whiskbroom``). Each carries the common observer fields (``name``, ``shape``, ``supersample``,
``bands``) and exactly one platform:

* ``orbit`` — :class:`OrbitSpec`: ``{tle: [line1, line2]}``, ``{elements: {...}}`` or
  ``{overpass: {altitude: 705 km}}`` (a circular orbit over the scene origin at the scene
  time, sun-synchronous unless an inclination is given);
* ``platform`` — :class:`LinearPlatformSpec`: a straight line at constant velocity (an
  aircraft; ``earth_rotation: true`` makes the velocity inertial, as for a satellite);
* ``waypoints`` — :class:`WaypointsSpec`: sampled positions and attitudes, interpolated.

Clock: the observer's t = 0 is the scene time (``environment.time``); the acquisition is
centred on it unless ``start`` [s] says when line 0 begins. :func:`build_observer` turns a
spec into a :class:`~radscene.platform.scanners.PushbroomScanner` or
:class:`~radscene.platform.scanners.WhiskbroomScanner`.

Config snippet::

    observers:
      - type: pushbroom
        name: oli
        shape: [512, 512]
        gsd: 30 m
        orbit: {overpass: {altitude: 705 km, descending: true}}
      - type: whiskbroom
        name: linescan
        shape: [200, 400]
        ifov: 0.1 deg
        detectors: 4
        platform: {position: [0, 0, 1500], velocity: [0, 80, 0]}
"""

from __future__ import annotations

import datetime as _dt
from typing import Annotated, Any, Literal

import numpy as np
from pydantic import BaseModel, BeforeValidator, ConfigDict, Field, model_validator

from radscene.errors import ConfigError
from radscene.radiometry.units import parse_quantity

__all__ = [
    "OrbitSpec",
    "TLESpec",
    "ElementsSpec",
    "OverpassSpec",
    "LinearPlatformSpec",
    "WaypointsSpec",
    "PushbroomSpec",
    "WhiskbroomSpec",
    "build_observer",
    "build_trajectory",
    "check_sensor_sampling",
]


def _quantity(kind: str, minimum: float | None = None, exclusive: bool = False):
    def parse(value: Any) -> float:
        if isinstance(value, bool):
            raise ValueError(f"expected a {kind}, got {value!r}")
        try:
            number = float(parse_quantity(value, kind))
        except ConfigError as err:
            raise ValueError(err.message) from None
        if minimum is not None and (number <= minimum if exclusive else number < minimum):
            raise ValueError(f"must be {'>' if exclusive else '>='} {minimum:g} "
                             f"(canonical unit), got {value!r}")
        return number

    # read by the scene-file reference and the JSON schema (radscene.scene.reference)
    parse.quantity_kind, parse.quantity_minimum, parse.quantity_exclusive = kind, minimum, exclusive
    return BeforeValidator(parse)


Length = Annotated[float, _quantity("length")]
PositiveLength = Annotated[float, _quantity("length", 0.0, exclusive=True)]
Angle = Annotated[float, _quantity("angle")]
PositiveAngle = Annotated[float, _quantity("angle", 0.0, exclusive=True)]
Duration = Annotated[float, _quantity("time")]
PositiveDuration = Annotated[float, _quantity("time", 0.0, exclusive=True)]


class _Model(BaseModel):
    model_config = ConfigDict(extra="forbid", frozen=True)


class TLESpec(_Model):
    """A two-line element set: the lines (a list or one string), an optional name, UT1-UTC."""

    lines: list[str] | str = Field(description="the two element lines, as a list or one string")
    name: str | None = Field(
        None, description="the satellite's name; default the TLE's name line, if any")
    dut1: float = Field(0.0, description="UT1 - UTC [s], for the Earth's rotation angle")


class ElementsSpec(_Model):
    """Keplerian elements at an epoch (two-body + secular J2)."""

    epoch: _dt.datetime = Field(description="instant of the elements, with its UTC offset")
    altitude: PositiveLength | None = Field(
        None, description="semi-major axis minus the Earth's equatorial radius [m]; exactly one "
        "of altitude and semi_major_axis")
    semi_major_axis: PositiveLength | None = Field(None, description="semi-major axis [m]")
    eccentricity: Annotated[float, Field(ge=0.0, lt=1.0)] = Field(
        0.0, description="orbital eccentricity [-]; 0: circular")
    inclination: Annotated[Angle, Field(ge=0.0, le=180.0)] = Field(
        description="inclination to the equator [deg]")
    raan: Angle = Field(
        0.0, description="right ascension of the ascending node [deg] (equator of date, mean "
        "equinox)")
    argument_of_perigee: Angle = Field(0.0, description="argument of perigee [deg]")
    mean_anomaly: Angle = Field(0.0, description="mean anomaly at the epoch [deg]")
    j2: bool = Field(
        True, description="add the secular J2 drift of the node, perigee and mean anomaly; false: "
        "two-body motion")

    @model_validator(mode="after")
    def _size(self):
        if (self.altitude is None) == (self.semi_major_axis is None):
            raise ValueError("give exactly one of 'altitude' and 'semi_major_axis'")
        if self.epoch.tzinfo is None:
            raise ValueError("epoch must carry a timezone (e.g. 2024-06-01T10:30:00Z)")
        return self


class OverpassSpec(_Model):
    """A circular orbit over a ground point (default the scene origin) at the scene time."""

    altitude: PositiveLength = Field(
        description="height of the satellite above the ground point [m]")
    inclination: Annotated[Angle, Field(ge=0.0, le=180.0)] | None = Field(
        None, description="orbit inclination [deg]; default sun-synchronous at that altitude")
    descending: bool = Field(
        True, description="cross the point southbound (true) or northbound (false)")
    latitude: Annotated[float, Field(ge=-90.0, le=90.0)] | None = Field(
        None, description="latitude of the ground point [deg]; default the scene origin's")
    longitude: float | None = Field(
        None, description="longitude of the ground point [deg]; default the scene origin's")


class OrbitSpec(_Model):
    """A satellite platform: exactly one of ``tle``, ``elements``, ``overpass``."""

    tle: TLESpec | list[str] | str | None = Field(
        None, description="a two-line element set: {lines, name, dut1}, or the lines alone")
    elements: ElementsSpec | None = Field(None, description="Keplerian elements at an epoch")
    overpass: OverpassSpec | None = Field(
        None, description="a circular orbit over a ground point at the scene time")
    yaw_steering: bool = Field(
        False, description="turn the platform so that its forward axis follows the Earth-relative "
        "velocity (no skew of the image by the Earth's rotation)")
    earth_rotation: bool = Field(
        True, description="false freezes the Earth at its orientation at the start, to show what "
        "the rotation does to an image")
    step: PositiveDuration = Field(
        1.0, description="spacing of the orbit's samples [s]; positions are interpolated between "
        "them")

    @model_validator(mode="after")
    def _one(self):
        given = [k for k in ("tle", "elements", "overpass") if getattr(self, k) is not None]
        if len(given) != 1:
            raise ValueError(f"give exactly one of tle, elements, overpass; got "
                             f"{', '.join(given) or 'none'}")
        return self


class LinearPlatformSpec(_Model):
    """A straight line at constant velocity; ``position`` is where the platform is at t = 0."""

    position: tuple[Length, Length, Length] = Field(
        description="(x, y, z) of the platform at t = 0, the scene time [m]")
    velocity: tuple[float, float, float] = Field(
        description="(east, north, up) velocity [m/s], a bare number in m/s per component")
    attitude: tuple[Angle, Angle, Angle] | None = Field(
        None, description="(yaw, pitch, roll) [deg]; default level, heading along the velocity's "
        "horizontal part (north when it has none)")
    earth_rotation: bool = Field(
        False, description="true: position, velocity and attitude are inertial and the Earth "
        "turns under them (as for a satellite)")


class WaypointsSpec(_Model):
    """Sampled positions (and attitudes) at times [s after the scene time]."""

    times: list[Duration] = Field(
        min_length=1, description="sample times after the scene time [s], increasing")
    positions: list[tuple[Length, Length, Length]] = Field(
        min_length=1, description="(x, y, z) of the platform at each time [m]")
    attitudes: list[tuple[Angle, Angle, Angle]] | None = Field(
        None, description="(yaw, pitch, roll) at each time [deg]; default level, heading north")

    @model_validator(mode="after")
    def _lengths(self):
        if len(self.positions) != len(self.times) or (
                self.attitudes is not None and len(self.attitudes) != len(self.times)):
            raise ValueError("times, positions and attitudes must have one entry each per "
                             "waypoint")
        return self


class _ScannerCommon(_Model):
    name: str = Field(
        description="unique name of the observer; its output files are named after it")
    shape: tuple[Annotated[int, Field(ge=1)], Annotated[int, Field(ge=1)]] = Field(
        description="rendered samples (lines, columns)")
    supersample: Annotated[int, Field(ge=1, le=16)] = Field(
        1, description="rays per sample along each axis: supersample² averaged into each sample")
    bands: list[str] | None = Field(
        None, description="names of the scene's bands this observer renders; default all of them")
    sensor: str | None = Field(None, description="name of an entry of the scene's `sensors`")
    frames: Annotated[int, Field(ge=1, le=1000)] = Field(
        1, description="frames the observer's sensor records from one render, each with its own "
        "temporal noise; unused without a sensor")
    orbit: OrbitSpec | None = Field(
        None, description="a satellite platform; exactly one of orbit, platform and waypoints")
    platform: LinearPlatformSpec | None = Field(
        None, description="a straight line at constant velocity (an aircraft)")
    waypoints: WaypointsSpec | None = Field(
        None, description="sampled positions and attitudes, interpolated")
    ifov: PositiveAngle | None = Field(
        None, description="angle of one sample [deg]; exactly one of ifov and gsd")
    gsd: PositiveLength | None = Field(
        None, description="ground sample distance on z = 0 at the boresight at the start [m], "
        "perpendicular to the line of sight")
    start: Duration | None = Field(
        None, description="when line 0 begins [s after the scene time]; default the acquisition "
        "centred on the scene time")
    off_nadir: Annotated[Angle, Field(gt=-90.0, lt=90.0)] = Field(
        0.0, description="roll of the line of sight towards the right of the flight direction "
        "[deg]")
    forward_tilt: Annotated[Angle, Field(gt=-90.0, lt=90.0)] = Field(
        0.0, description="then its pitch towards the front [deg]")

    @model_validator(mode="after")
    def _platform(self):
        given = [k for k in ("orbit", "platform", "waypoints") if getattr(self, k) is not None]
        if len(given) != 1:
            raise ValueError(f"give exactly one of orbit, platform, waypoints; got "
                             f"{', '.join(given) or 'none'}")
        if (self.ifov is None) == (self.gsd is None):
            raise ValueError("give exactly one of 'ifov' (angle) and 'gsd' (length)")
        return self


class PushbroomSpec(_ScannerCommon):
    """A pushbroom scanner (``type: pushbroom``)."""

    type: Literal["pushbroom"] = Field(
        description="`pushbroom`: a line of detectors across the track")
    line_time: PositiveDuration | None = Field(
        None, description="line period [s]; default the time the boresight's footprint takes to "
        "move one sample (square samples)")


class WhiskbroomSpec(_ScannerCommon):
    """A whiskbroom / line scanner (``type: whiskbroom``)."""

    type: Literal["whiskbroom"] = Field(
        description="`whiskbroom`: a scanning mirror sweeping across the track")
    scan_period: PositiveDuration | None = Field(
        None, description="time from one sweep to the next [s]; default contiguous sweeps at the "
        "scan centre")
    detectors: Annotated[int, Field(ge=1)] = Field(
        1, description="detectors along the track, i.e. lines per sweep; the shape's lines are a "
        "multiple of it")
    sample_time: PositiveDuration | None = Field(
        None, description="dwell per sample [s]; default scan_period / columns (no dead time)")
    bidirectional: bool = Field(
        False, description="odd sweeps run from the last column to the first")
    mirror_profile: list[tuple[float, Angle]] | None = Field(
        None, description="(sweep phase in [0, 1], mirror angle [deg], positive to the right) "
        "rows of a forward sweep, angles decreasing; default linear")


def build_trajectory(spec, frame, time: _dt.datetime | None, t0: float, t1: float):
    """The trajectory of a scanner spec's platform covering ``[t0, t1]`` s after ``time``.

    Parameters
    ----------
    spec : PushbroomSpec or WhiskbroomSpec
    frame : LocalFrame
        The scene's frame.
    time : datetime or None
        The scene time (t = 0); needed for orbits.
    t0, t1 : float
        Span to cover [s].

    Returns
    -------
    Trajectory
    """
    from radscene.platform.orbit import Orbit
    from radscene.platform.trajectory import Trajectory

    if spec.orbit is not None:
        o = spec.orbit
        if time is None:
            raise ConfigError("an orbit needs the scene time (environment.time)", key="orbit")
        if o.tle is not None:
            tle = o.tle if not isinstance(o.tle, TLESpec) else o.tle.lines
            name = None if not isinstance(o.tle, TLESpec) else o.tle.name
            dut1 = 0.0 if not isinstance(o.tle, TLESpec) else o.tle.dut1
            orbit = Orbit.from_tle(tle, name=name, dut1=dut1, key="orbit.tle")
        elif o.elements is not None:
            e = o.elements
            orbit = Orbit.from_elements(
                e.epoch, semi_major_axis=e.semi_major_axis, altitude=e.altitude,
                eccentricity=e.eccentricity, inclination=e.inclination, raan=e.raan,
                argument_of_perigee=e.argument_of_perigee, mean_anomaly=e.mean_anomaly,
                j2=e.j2)
        else:
            p = o.overpass
            lat = frame.latitude if p.latitude is None else p.latitude
            lon = frame.longitude if p.longitude is None else p.longitude
            orbit = Orbit.overpass(lat, lon, time, p.altitude, inclination=p.inclination,
                                   descending=p.descending, height=frame.height)
        start = time + _dt.timedelta(seconds=t0)
        tr = orbit.trajectory(frame, start, t1 - t0, step=o.step, yaw_steering=o.yaw_steering,
                              earth_rotation=o.earth_rotation)
        # re-clock so that t = 0 is the scene time
        return Trajectory(tr.times + t0, tr.positions, quaternions=tr.quaternions,
                          velocities=tr.velocities, epoch=time)
    if spec.platform is not None:
        p = spec.platform
        v = np.asarray(p.velocity, dtype=float)
        start_pos = np.asarray(p.position, dtype=float) + t0 * v
        if p.earth_rotation:
            # inertial line through `position` at t = 0; the rotation is taken from t0
            return Trajectory.linear(start_pos, v, t1 - t0, p.attitude, start=t0, frame=frame,
                                     epoch=time)
        return Trajectory.linear(start_pos, v, t1 - t0, p.attitude, start=t0, epoch=time)
    w = spec.waypoints
    return Trajectory(w.times, w.positions, w.attitudes, epoch=time)


def _make(spec, trajectory, start, fixed=None):
    """A scanner from a spec; ``fixed`` (another scanner) supplies ifov and periods."""
    from radscene.platform.scanners import PushbroomScanner, WhiskbroomScanner

    ifov, gsd = (spec.ifov, spec.gsd) if fixed is None else (fixed.ifov, None)
    common = {"gsd": gsd, "start": start, "off_nadir": spec.off_nadir,
              "forward_tilt": spec.forward_tilt}
    if spec.type == "pushbroom":
        line_time = spec.line_time if fixed is None else fixed.line_time
        return PushbroomScanner(trajectory, spec.shape, ifov, line_time, **common)
    period, sample = ((spec.scan_period, spec.sample_time) if fixed is None
                      else (fixed.scan_period, fixed.sample_time))
    return WhiskbroomScanner(trajectory, spec.shape, ifov, period, detectors=spec.detectors,
                             sample_time=sample, bidirectional=spec.bidirectional,
                             mirror_profile=spec.mirror_profile, **common)


#: Largest relative difference allowed between a sensor's IFOV and ``oversample`` × the ifov of
#: the scanner that renders for it.
SAMPLING_TOLERANCE = 0.01


def check_sensor_sampling(scanner, sensor, key: str = "observer", gsd=None) -> None:
    """Check that a scanner renders ``sensor.oversample`` samples per detector IFOV.

    Parameters
    ----------
    scanner : PushbroomScanner or WhiskbroomScanner
        Its ``ifov`` [deg] is the angle of one rendered sample.
    sensor : radscene.sensor.Sensor
        Its ``ifov`` [deg] is the angle of one detector pitch (base channel).
    key : str
        Key path of the observer, for errors.
    gsd : float, optional
        The observer's ``gsd`` [m] when it gave one (the error then suggests a gsd).

    Raises
    ------
    ConfigError
        The two differ by more than :data:`SAMPLING_TOLERANCE`; the message gives the
        ``gsd`` / ``ifov`` that would fit (keys ``<key>.gsd`` or ``<key>.ifov``).
    """
    per_sample = sensor.ifov / sensor.oversample
    ratio = scanner.ifov / per_sample
    if abs(ratio - 1.0) <= SAMPLING_TOLERANCE:
        return
    fit_ifov = f"{per_sample * 3600:.4g} arcsec"
    fit_gsd = "" if gsd is None else f"gsd {gsd / ratio:.4g} m or "
    raise ConfigError(
        f"the scanner's sample is {scanner.ifov * 3600:.4g} arcsec but sensor "
        f"{sensor.name!r} needs {sensor.oversample} samples per {sensor.ifov * 3600:.4g} arcsec "
        f"detector IFOV; give {fit_gsd}ifov {fit_ifov}",
        key=f"{key}.{'gsd' if fit_gsd else 'ifov'}")


def build_observer(spec, frame, time: _dt.datetime | None = None, key: str = "observer"):
    """Build a scanner from its spec.

    Parameters
    ----------
    spec : PushbroomSpec, WhiskbroomSpec or mapping
        A validated spec, or a dict validated here.
    frame : LocalFrame
        The scene's frame (its location).
    time : datetime, optional
        The scene time, t = 0 of the observer's clock (needed for orbits and sun angles).
    key : str
        Key path for error messages (``observers[2]``).

    Returns
    -------
    PushbroomScanner or WhiskbroomScanner

    Raises
    ------
    ConfigError
        Invalid spec (the message names the key).
    """
    from pydantic import TypeAdapter, ValidationError

    if not isinstance(spec, PushbroomSpec | WhiskbroomSpec):
        try:
            spec = TypeAdapter(Annotated[PushbroomSpec | WhiskbroomSpec,
                                         Field(discriminator="type")]).validate_python(spec)
        except ValidationError as exc:
            err = exc.errors()[0]
            parts = [str(p) for p in err["loc"]]
            if parts and parts[0] in ("pushbroom", "whiskbroom"):
                parts = parts[1:]  # the union's tag
            loc = ".".join(parts)
            raise ConfigError(err["msg"], key=f"{key}.{loc}" if loc else key) from None
    try:
        # a first scanner, at the scene time, turns gsd into ifov and fixes the periods,
        # hence the duration; the final one keeps them
        probe_span = (-1.0, 1.0) if spec.waypoints is None else (
            spec.waypoints.times[0], spec.waypoints.times[-1])
        probe_start = 0.0 if spec.waypoints is None else max(0.0, probe_span[0])
        probe = _make(spec, build_trajectory(spec, frame, time, *probe_span), probe_start)
        if spec.type == "pushbroom":
            duration = spec.shape[0] * probe.line_time
        else:
            duration = spec.shape[0] // probe.detectors * probe.scan_period
        start = -0.5 * duration if spec.start is None else spec.start
        if spec.waypoints is not None:
            return _make(spec, probe.trajectory, start, fixed=probe)
        margin = 1.0
        trajectory = build_trajectory(spec, frame, time, start - margin,
                                      start + duration + margin)
        return _make(spec, trajectory, start, fixed=probe)
    except ConfigError as err:
        raise ConfigError(err.message, key=f"{key}.{err.key}" if err.key else key) from None
