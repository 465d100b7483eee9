"""Tests of radscene.platform.orbit: TLE checks, SGP4, Kepler + J2, TEME → ECEF, overpasses."""

import datetime as dt

import numpy as np
import pytest

from radscene.errors import ConfigError
from radscene.platform.geolocation import (
    EARTH_ROTATION_RATE,
    LocalFrame,
    ecef_to_geodetic,
    intersect_ellipsoid,
)
from radscene.platform.orbit import (
    GM_EARTH,
    Orbit,
    gmst,
    parse_tle,
    sun_synchronous_inclination,
    teme_to_ecef,
    tle_checksum,
)

# Vallado, Crawford, Hujsak & Kelso, "Revisiting Spacetrack Report #3", AIAA 2006-6753: the
# verification TLE of satellite 00005 and its SGP4 states (tcppver.out), km and km/s.
L1 = "1 00005U 58002B   00179.78495062  .00000023  00000-0  28098-4 0  4753"
L2 = "2 00005  34.2682 348.7242 1859667 331.7664  19.3264 10.82419157413667"
R0_KM = (7022.46529266, -1400.08296755, 0.03995155)
V0_KMS = (1.893841015, 6.405893759, 4.534807250)
R360_KM = (-7154.03120202, -3783.17682504, -3536.19412294)
V360_KMS = (4.741887409, -4.151817765, -2.093935425)
SGP4_POS = 1e-3  # [m]: the tabulated states have 1e-8 km
SGP4_VEL = 1e-5  # [m s-1]
UTC = dt.UTC


def _corrupt(line: str) -> str:
    """The line with a wrong checksum digit."""
    return line[:68] + str((int(line[68]) + 1) % 10)


# -- TLE checks ------------------------------------------------------------------------------


def test_checksums_of_the_verification_tle():
    assert tle_checksum(L1) == 3 == int(L1[68])
    assert tle_checksum(L2) == 7 == int(L2[68])
    # a '-' counts 1, letters and '+' count 0
    assert tle_checksum("1 -A+" + " " * 64) == 2


def test_parse_two_and_three_line_sets():
    assert parse_tle([L1, L2]) == ("", L1, L2)
    assert parse_tle(f"VANGUARD 1\n{L1}\n{L2}\n") == ("VANGUARD 1", L1, L2)
    assert parse_tle(f"0 VANGUARD 1\n{L1}\n{L2}")[0] == "VANGUARD 1"


@pytest.mark.parametrize("which", [1, 2])
def test_bad_checksum_names_the_line(which):
    lines = [L1, L2]
    lines[which - 1] = _corrupt(lines[which - 1])
    with pytest.raises(ConfigError, match=rf"tle\.line{which}: checksum \d does not match"):
        parse_tle(lines)
    with pytest.raises(ConfigError, match=rf"orbit\.tle\.line{which}: checksum"):
        Orbit.from_tle(lines, key="orbit.tle")


@pytest.mark.parametrize(("lines", "match"), [
    ([L1], r"tle: a TLE has two lines"),
    ([L1, L2[:60]], r"tle\.line2: must have 69 characters"),
    ([L2, L1], r"tle\.line1: must start with '1 '"),
    ([L1, L2[:2] + "00006" + L2[7:68] + str(tle_checksum(L2[:2] + "00006" + L2[7:]))],
     r"tle\.line2: satellite numbers differ"),
])
def test_malformed_tle_is_refused(lines, match):
    with pytest.raises(ConfigError, match=match):
        parse_tle(lines)


# -- SGP4 --------------------------------------------------------------------------------------


def test_sgp4_reproduces_the_verification_states():
    orbit = Orbit.from_tle([L1, L2])
    assert orbit.epoch == dt.datetime(2000, 6, 27, 18, 50, 19, 733568, tzinfo=UTC)
    r, v = orbit.teme(orbit.epoch)
    assert r == pytest.approx(np.array(R0_KM) * 1e3, abs=SGP4_POS)
    assert v == pytest.approx(np.array(V0_KMS) * 1e3, abs=SGP4_VEL)
    r, v = orbit.teme([orbit.epoch + dt.timedelta(minutes=360)])
    assert r.shape == (1, 3)
    assert r[0] == pytest.approx(np.array(R360_KM) * 1e3, abs=SGP4_POS)
    assert v[0] == pytest.approx(np.array(V360_KMS) * 1e3, abs=SGP4_VEL)


def test_gmst_and_teme_to_ecef_match_vallado():
    # Vallado, Fundamentals of Astrodynamics (2013), Example 3-5: 1992-08-20 12:14 UT1
    assert np.degrees(gmst(2448854.5, (12 + 14 / 60) / 24)) == pytest.approx(152.578787810,
                                                                          abs=1e-6)
    # Vallado et al. (2006), TEME example: 2004-04-06 07:51:28.386009 UTC, dUT1 = -0.4399619 s
    t = dt.datetime(2004, 4, 6, 7, 51, 28, 386009, tzinfo=UTC).timestamp() - 0.4399619
    days = t / 86400.0
    theta = gmst(2440587.5 + np.floor(days), days - np.floor(days))
    r_teme = np.array([5094.18016210, 6127.64465950, 6380.34453270]) * 1e3
    r, v = teme_to_ecef(r_teme, np.zeros(3), theta)
    assert r == pytest.approx(np.array([-1033.47503130, 7901.30558560, 6380.34453270]) * 1e3,
                              abs=0.05)
    # a body at rest in TEME moves westward at ω r in the Earth-fixed frame
    assert v == pytest.approx(-np.cross([0, 0, EARTH_ROTATION_RATE], r), abs=1e-9)


# -- Kepler + J2 -------------------------------------------------------------------------------


def test_sun_synchronous_inclination_of_landsat():
    # Landsat 8/9: 705 km, 98.2 deg (USGS Landsat 8 Data Users Handbook, v5.0, 2019, §2)
    assert sun_synchronous_inclination(705e3) == pytest.approx(98.2, abs=0.05)
    with pytest.raises(ConfigError, match="altitude: must be > 0 m"):
        sun_synchronous_inclination(-1.0)


def test_two_body_orbit_closes_after_one_period():
    epoch = dt.datetime(2024, 3, 1, tzinfo=UTC)
    orbit = Orbit.from_elements(epoch, altitude=705e3, eccentricity=0.01, inclination=98.2,
                                raan=40.0, argument_of_perigee=90.0, mean_anomaly=10.0,
                                j2=False)
    a = 6378137.0 + 705e3
    assert orbit.period == pytest.approx(2 * np.pi * np.sqrt(a**3 / GM_EARTH), rel=1e-12)
    r0, v0 = orbit.teme(epoch)
    r1, v1 = orbit.teme(epoch + dt.timedelta(seconds=orbit.period))
    # datetimes resolve 1 us: 7.5 km/s x 0.5 us = 4 mm
    assert r1 == pytest.approx(r0, abs=5e-3)
    # vis-viva: v² = μ (2/r - 1/a)
    speed2 = GM_EARTH * (2 / np.linalg.norm(r0) - 1 / a)
    assert float(v0 @ v0) == pytest.approx(speed2, rel=1e-12)
    # angular momentum along the orbit normal of inclination 98.2 deg
    h = np.cross(r0, v0)
    assert np.degrees(np.arccos(h[2] / np.linalg.norm(h))) == pytest.approx(98.2, abs=1e-9)


def _ascending_node_ra(orbit, around):
    """Time and right ascension [deg] of the satellite's next northbound equator crossing."""
    steps = [around + dt.timedelta(seconds=30.0 * k) for k in range(220)]  # > one period
    z = orbit.teme(steps)[0][:, 2]
    k = int(np.nonzero((z[:-1] < 0) & (z[1:] >= 0))[0][0])
    lo, hi = 0.0, 30.0
    for _ in range(40):  # bisection on the crossing time
        mid = 0.5 * (lo + hi)
        if orbit.teme(steps[k] + dt.timedelta(seconds=mid))[0][2] < 0:
            lo = mid
        else:
            hi = mid
    when = steps[k] + dt.timedelta(seconds=hi)
    r = orbit.teme(when)[0]
    return when, np.degrees(np.arctan2(r[1], r[0]))


def test_j2_node_of_a_sun_synchronous_orbit_follows_the_sun():
    epoch = dt.datetime(2024, 3, 1, tzinfo=UTC)
    inc = sun_synchronous_inclination(705e3)
    orbit = Orbit.from_elements(epoch, altitude=705e3, inclination=inc, raan=0.0)
    t0, node0 = _ascending_node_ra(orbit, epoch)
    t1, node1 = _ascending_node_ra(orbit, epoch + dt.timedelta(days=10))
    days = (t1 - t0).total_seconds() / 86400.0
    # 360 deg per tropical year, eastward
    assert node1 - node0 == pytest.approx(360.0 / 365.2421897 * days, abs=1e-6)


def test_elements_are_checked():
    epoch = dt.datetime(2024, 3, 1, tzinfo=UTC)
    with pytest.raises(ConfigError, match="eccentricity: must be in"):
        Orbit.from_elements(epoch, altitude=700e3, eccentricity=1.0, inclination=98)
    with pytest.raises(ConfigError, match="altitude: the perigee"):
        Orbit.from_elements(epoch, altitude=100e3, eccentricity=0.1, inclination=98)
    with pytest.raises(ConfigError, match="semi_major_axis: give exactly one"):
        Orbit.from_elements(epoch, inclination=98)
    with pytest.raises(ConfigError, match="epoch: must be a timezone-aware"):
        Orbit.from_elements(dt.datetime(2024, 3, 1), altitude=700e3, inclination=98)
    with pytest.raises(ConfigError, match=r"inclination: must be a number in \[0, 180\]"):
        Orbit.from_elements(epoch, altitude=700e3, inclination=200)


# -- overpass and trajectories -----------------------------------------------------------------


@pytest.mark.parametrize("descending", [True, False])
def test_overpass_puts_the_satellite_above_the_point(descending):
    t = dt.datetime(2023, 6, 1, 17, 30, tzinfo=UTC)
    orbit = Orbit.overpass(40.0, -105.0, t, 705e3, descending=descending, height=1500.0)
    lat, lon, h = orbit.subsatellite_point([t - dt.timedelta(seconds=10), t,
                                            t + dt.timedelta(seconds=10)])
    assert lat[1] == pytest.approx(40.0, abs=1e-9)
    assert lon[1] == pytest.approx(-105.0, abs=1e-9)
    assert h[1] == pytest.approx(1500.0 + 705e3, abs=1e-3)
    assert (lat[2] < lat[0]) == descending
    with pytest.raises(ConfigError, match="inclination: an orbit inclined 30 deg never passes"):
        Orbit.overpass(50.0, 0.0, t, 705e3, inclination=30.0)


def test_nadir_trajectory_looks_at_the_subsatellite_point():
    t = dt.datetime(2023, 6, 1, 17, 30, tzinfo=UTC)
    frame = LocalFrame(40.0, -105.0, 1500.0)
    orbit = Orbit.overpass(40.0, -105.0, t, 705e3, height=1500.0)
    traj = orbit.trajectory(frame, t - dt.timedelta(seconds=5), 10.0)
    assert traj.epoch == t - dt.timedelta(seconds=5)
    times = np.array([0.0, 5.0, 7.3])
    pose = traj.pose(times)
    # the satellite is 705 km over the origin at the overpass
    assert pose.position[1] == pytest.approx([0.0, 0.0, 705e3], abs=1e-3)
    boresight = -pose.rotation[:, :, 2]
    dist = intersect_ellipsoid(frame.to_ecef(pose.position), frame.vector_to_ecef(boresight))
    foot = frame.to_ecef(pose.position) + dist[:, None] * frame.vector_to_ecef(boresight)
    lat, lon, _ = ecef_to_geodetic(foot)
    sub_lat, sub_lon, _ = orbit.subsatellite_point(
        [traj.epoch + dt.timedelta(seconds=float(s)) for s in times])
    assert lat == pytest.approx(sub_lat, abs=1e-7)  # 1 cm; slerp between 1 s samples
    assert lon == pytest.approx(sub_lon, abs=1e-7)
    # Hermite interpolation between 1 s samples follows the orbit to a millimetre
    r_true = frame.from_ecef(orbit.ecef(traj.epoch + dt.timedelta(seconds=7.3))[0])
    assert traj.position(7.3) == pytest.approx(r_true, abs=1e-3)


def test_earth_rotation_moves_the_ground_track_westward():
    t = dt.datetime(2023, 6, 1, 17, 30, tzinfo=UTC)
    orbit = Orbit.overpass(0.0, 0.0, t, 705e3, inclination=90.0)  # polar, over the equator
    times = [t, t + dt.timedelta(seconds=60)]
    _, lon_rot, _ = orbit.subsatellite_point(times)
    r, _ = orbit.ecef(times, earth_rotation=False)
    _, lon_frozen, _ = ecef_to_geodetic(r)
    # a polar orbit stays in its plane; the Earth turns 60 s x ω under it
    assert lon_frozen[1] == pytest.approx(0.0, abs=1e-9)
    assert lon_rot[1] == pytest.approx(-np.degrees(EARTH_ROTATION_RATE * 60.0), abs=1e-6)
