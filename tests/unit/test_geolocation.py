"""Tests of radscene.platform.geolocation: WGS84, the local frame, per-pixel truth, round trips."""

import datetime as dt

import numpy as np
import pytest

from radscene.errors import ConfigError
from radscene.platform import OrthographicCamera, PerspectiveCamera
from radscene.platform.config import build_observer
from radscene.platform.geolocation import (
    WGS84_A,
    WGS84_B,
    WGS84_E2,
    LocalFrame,
    ecef_to_geodetic,
    enu_basis,
    geodetic_to_ecef,
    geolocation_truth,
    ground_points,
    intersect_ellipsoid,
    pixel_center_rays,
    project,
)
from radscene.platform.scanners import PushbroomScanner, WhiskbroomScanner
from radscene.platform.trajectory import Trajectory
from radscene.sun import sun_position

ROUND_TRIP = 0.1  # [px]: the requirement for pixel → ground → pixel
TIGHT = 1e-6  # [px]: what the closed forms and iterations actually achieve
MM = 1e-3  # [m]
UTC = dt.UTC


def _pixel_centres(shape):
    ny, nx = shape
    return np.meshgrid(np.arange(ny) + 0.5, np.arange(nx) + 0.5, indexing="ij")


# -- WGS84 and the local frame ----------------------------------------------------------------


def test_geodetic_ecef_reference_points():
    assert geodetic_to_ecef(0.0, 0.0, 0.0) == pytest.approx([WGS84_A, 0.0, 0.0], abs=MM)
    assert geodetic_to_ecef(90.0, 0.0, 100.0) == pytest.approx([0.0, 0.0, WGS84_B + 100.0],
                                                               abs=MM)
    assert WGS84_B == pytest.approx(6356752.314245, abs=MM)  # NIMA TR8350.2, Table 3.1
    # independent closed form: N = a / sqrt(1 - e² sin² φ)
    lat, lon, h = 37.5, -122.25, 1234.5
    e2 = 6.69437999014e-3  # NIMA TR8350.2
    n = WGS84_A / np.sqrt(1 - e2 * np.sin(np.radians(lat)) ** 2)
    expected = [(n + h) * np.cos(np.radians(lat)) * np.cos(np.radians(lon)),
                (n + h) * np.cos(np.radians(lat)) * np.sin(np.radians(lon)),
                (n * (1 - e2) + h) * np.sin(np.radians(lat))]
    assert geodetic_to_ecef(lat, lon, h) == pytest.approx(expected, abs=MM)


@pytest.mark.parametrize("height", [-400.0, 0.0, 705e3, 3.6e7])
def test_ecef_to_geodetic_inverts_at_any_height(height):
    lat = np.array([[-89.9, -45.0], [0.0, 67.3]])
    lon = np.array([[-179.0, 10.0], [100.0, -3.0]])
    back = ecef_to_geodetic(geodetic_to_ecef(lat, lon, height))
    assert back[0] == pytest.approx(lat, abs=1e-11)
    assert back[1] == pytest.approx(lon, abs=1e-11)
    assert back[2] == pytest.approx(np.full((2, 2), height), abs=MM)


def test_local_frame_is_east_north_up_at_its_origin():
    f = LocalFrame(52.0, 4.5, 30.0)
    assert f.from_geodetic(52.0, 4.5, 30.0) == pytest.approx([0.0, 0.0, 0.0], abs=MM)
    assert f.from_geodetic(52.0, 4.5, 130.0) == pytest.approx([0.0, 0.0, 100.0], abs=MM)
    # a small step north (east) moves along +y (+x)
    north = f.from_geodetic(52.001, 4.5, 30.0)
    east = f.from_geodetic(52.0, 4.501, 30.0)
    assert north[0] == pytest.approx(0.0, abs=MM) and north[1] > 100.0
    assert east[1] == pytest.approx(0.0, abs=0.01) and east[0] > 60.0
    pts = np.array([[1000.0, -2000.0, 50.0], [-3e4, 4e4, -100.0]])
    assert f.from_geodetic(*f.to_geodetic(pts)) == pytest.approx(pts, abs=MM)
    basis = f.local_basis(np.zeros(3))
    assert basis == pytest.approx(np.eye(3), abs=1e-12)
    assert enu_basis(0.0, 0.0) == pytest.approx(np.array([[0, 1, 0], [0, 0, 1], [1, 0, 0]]),
                                                 abs=1e-15)
    with pytest.raises(ConfigError, match=r"latitude: must be in \[-90, 90\] deg"):
        LocalFrame(91.0, 0.0)


def test_frame_crs_easting_northing_are_the_frame_coordinates_on_the_ellipsoid():
    from pyproj import Transformer

    f = LocalFrame(-33.9, 18.4, 0.0)
    to_map = Transformer.from_crs("EPSG:4326", f.crs(), always_xy=True)
    lat = np.array([-33.9, -33.5, -34.6])
    lon = np.array([18.4, 18.9, 17.8])
    enu = f.from_geodetic(lat, lon, 0.0)
    x, y = to_map.transform(lon, lat)
    assert np.column_stack([x, y]) == pytest.approx(enu[:, :2], abs=MM)


def test_intersect_ellipsoid_lands_on_the_height():
    origin = geodetic_to_ecef(10.0, 20.0, 800e3)
    up = enu_basis(10.0, 20.0)[2]
    tilt = enu_basis(10.0, 20.0)[0] * 0.3 - up
    directions = np.stack([-up, tilt / np.linalg.norm(tilt), up])
    for h in (0.0, 2500.0):
        t = intersect_ellipsoid(np.broadcast_to(origin, (3, 3)), directions, h)
        assert t[0] == pytest.approx(800e3 - h, abs=MM)
        hit = origin + t[1] * directions[1]
        assert ecef_to_geodetic(hit)[2] == pytest.approx(h, abs=MM)
        assert np.isnan(t[2])  # pointing away


# -- pixel → ground → pixel ------------------------------------------------------------------


def _round_trip(observer, surface=0.0, frame=None):
    o, d, _ = pixel_center_rays(observer)
    ground = ground_points(o, d, surface, frame)
    row, col = project(observer, ground)
    rr, cc = _pixel_centres(observer.shape)
    return np.nanmax(np.abs(row - rr)), np.nanmax(np.abs(col - cc)), np.isnan(row).sum()


@pytest.mark.parametrize("observer", [
    OrthographicCamera((100.0, -50.0), (30, 40), gsd=2.0),
    OrthographicCamera((0.0, 0.0), (30, 40), gsd=2.0, zenith=35.0, azimuth=120.0),
    PerspectiveCamera((0.0, -800.0, 300.0), (24, 32), fov=40.0, look_at=(0.0, 0.0, 0.0)),
    PerspectiveCamera((10.0, 20.0, 500.0), (24, 32), fov=60.0, attitude=(30.0, -70.0, 5.0)),
], ids=["ortho-nadir", "ortho-oblique", "perspective-look-at", "perspective-attitude"])
def test_frame_cameras_round_trip(observer):
    dr, dc, missing = _round_trip(observer)
    assert missing == 0
    assert max(dr, dc) < ROUND_TRIP
    assert max(dr, dc) == pytest.approx(0.0, abs=TIGHT)


@pytest.mark.parametrize(("off_nadir", "yaw_steering", "surface"), [
    (0.0, False, 0.0), (15.0, False, "ellipsoid"), (-25.0, True, ("ellipsoid", 800.0)),
])
def test_orbital_pushbroom_round_trip(off_nadir, yaw_steering, surface):
    frame = LocalFrame(40.0, -105.0, 1500.0)
    t = dt.datetime(2023, 6, 1, 17, 30, tzinfo=UTC)
    pb = build_observer({"type": "pushbroom", "name": "p", "shape": [120, 80], "gsd": 30.0,
                         "off_nadir": off_nadir,
                         "orbit": {"overpass": {"altitude": 705e3},
                                   "yaw_steering": yaw_steering}}, frame, t)
    dr, dc, missing = _round_trip(pb, surface, frame)
    assert missing == 0
    assert max(dr, dc) < ROUND_TRIP
    assert max(dr, dc) == pytest.approx(0.0, abs=TIGHT)


def test_whiskbroom_round_trip():
    tr = Trajectory.linear([0, -2000, 3000], [10, 90, 0], 60.0, start=-30.0)
    wb = WhiskbroomScanner(tr, (40, 60), ifov=0.2, detectors=4, off_nadir=5.0)
    dr, dc, missing = _round_trip(wb)
    assert missing == 0
    assert max(dr, dc) < ROUND_TRIP
    assert max(dr, dc) == pytest.approx(0.0, abs=TIGHT)


def test_ground_points_surfaces_and_errors():
    from radscene.geometry import RayTracer, plate

    o = np.array([[0.0, 0.0, 100.0]])
    d = np.array([[0.0, 0.0, -1.0]])
    assert ground_points(o, d, 20.0) == pytest.approx(np.array([[0.0, 0.0, 20.0]]))
    # the scene's own geometry: a raised plate hit, a miss beside it
    tracer = RayTracer([plate(10.0, 10.0).transformed(translation=(0.0, 0.0, 7.0))])
    both = ground_points(np.array([[0.0, 0.0, 100.0], [50.0, 0.0, 100.0]]),
                         np.array([[0.0, 0.0, -1.0]] * 2), tracer)
    assert both[0] == pytest.approx([0.0, 0.0, 7.0], abs=1e-5)
    assert np.isnan(both[1]).all()
    up = ground_points(o, -d, 0.0)
    assert np.isnan(up).all()
    with pytest.raises(ConfigError, match="frame: the ellipsoid needs"):
        ground_points(o, d, "ellipsoid")
    with pytest.raises(ConfigError, match="surface: unknown surface 'geoid'"):
        ground_points(o, d, "geoid")


# -- truth ----------------------------------------------------------------------------------------


def test_truth_of_a_line_scanner():
    frame = LocalFrame(48.0, 11.0, 500.0)
    t0 = dt.datetime(2024, 6, 21, 10, 0, tzinfo=UTC)
    height = 2000.0
    tr = Trajectory.linear([0, -500, height], [0, 50, 0], 20.0, start=-10.0, epoch=t0)
    pb = PushbroomScanner(tr, (20, 41), ifov=0.5, line_time=0.5, start=-5.0)
    ds = geolocation_truth(pb, frame)
    assert set(ds.data_vars) >= {"latitude", "longitude", "height", "view_zenith",
                                 "view_azimuth", "sun_zenith", "sun_azimuth",
                                 "acquisition_time", "slant_range"}
    assert ds.latitude.attrs["units"] == "degrees_north"
    assert ds.acquisition_time.values[:, 0] == pytest.approx(pb.line_times(), abs=1e-12)
    # the ground is the plane z = 0 of the frame; back to the frame it is the same point
    lat, lon, h = (ds[k].values for k in ("latitude", "longitude", "height"))
    back = frame.from_geodetic(lat, lon, h)
    ground = np.stack([ds.ground_x.values, ds.ground_y.values, ds.ground_z.values], -1)
    assert back == pytest.approx(ground, abs=MM)
    # view angles: column 0 (right of the northbound track, east) looks up towards the west
    x = ds.ground_x.values[10, 0]
    assert x > 0
    geodetic_tilt = np.degrees(x / 6.37e6)  # the ground's own vertical leans east, away
    assert ds.view_zenith.values[10, 0] == pytest.approx(
        np.degrees(np.arctan(x / height)) + geodetic_tilt, abs=1e-3)
    assert ds.view_azimuth.values[10, 0] == pytest.approx(270.0, abs=0.05)
    assert ds.slant_range.values[10, 20] == pytest.approx(height, rel=1e-9)
    # sun angles at the pixel over the origin are those of the SPA at the origin
    row = int(np.argmin(np.abs(ds.ground_y.values[:, 20])))
    when = t0 + dt.timedelta(seconds=float(ds.acquisition_time.values[row, 20]))
    here = frame.to_geodetic([ds.ground_x.values[row, 20], ds.ground_y.values[row, 20], 0.0])
    sun = sun_position(when, float(here[0]), float(here[1]), float(here[2]))
    assert ds.sun_zenith.values[row, 20] == pytest.approx(float(sun.zenith), abs=0.005)
    assert ds.sun_azimuth.values[row, 20] == pytest.approx(float(sun.azimuth), abs=0.005)


def test_truth_without_a_time_has_no_sun():
    cam = OrthographicCamera((0.0, 0.0), (3, 4), gsd=5.0)
    ds = geolocation_truth(cam, LocalFrame(0.0, 0.0))
    assert np.isnan(ds.sun_zenith.values).all()
    assert ds.view_zenith.values == pytest.approx(np.zeros((3, 4)), abs=1e-3)
    assert ds.acquisition_time.values == pytest.approx(np.zeros((3, 4)))
    with pytest.raises(ConfigError, match="epoch: must be timezone-aware"):
        geolocation_truth(cam, LocalFrame(0.0, 0.0), epoch=dt.datetime(2024, 1, 1))


def _pyproj_geodetic(xyz):
    """The previous ECEF → geodetic: pyproj's inverse, then two fixed-point latitude steps."""
    from pyproj import Transformer

    x, y, z = xyz[:, 0], xyz[:, 1], xyz[:, 2]
    lon, lat, _ = Transformer.from_crs("EPSG:4978", "EPSG:4979", always_xy=True).transform(x, y, z)
    rho, phi = np.hypot(x, y), np.radians(lat)
    for _ in range(2):
        s = np.sin(phi)
        phi = np.arctan2(z + WGS84_E2 * WGS84_A / np.sqrt(1 - WGS84_E2 * s * s) * s, rho)
    s, c = np.sin(phi), np.cos(phi)
    return np.degrees(phi), lon, rho * c + z * s - WGS84_A * np.sqrt(1 - WGS84_E2 * s * s)


@pytest.mark.parametrize("height", [-1000.0, 0.0, 1200.0, 8000.0, 705e3, 3.6e7])
def test_compiled_geodetic_matches_pyproj(height):
    rng = np.random.default_rng(5)
    lat = np.concatenate([rng.uniform(-90.0, 90.0, 500), [-90.0, 90.0, 0.0, 89.999999]])
    lon = np.concatenate([rng.uniform(-179.9, 179.9, 500), [0.0, 0.0, 179.5, -60.0]])
    h = height + rng.uniform(-50.0, 50.0, lat.size)
    xyz = geodetic_to_ecef(lat, lon, h)
    got = ecef_to_geodetic(xyz)
    ref = _pyproj_geodetic(xyz)
    poles = np.abs(lat) == 90.0  # longitude undefined there
    assert np.abs(got[0] - ref[0]).max() < 1e-9
    assert np.abs(got[1] - ref[1])[~poles].max() < 1e-9
    assert np.abs(got[2] - ref[2]).max() < 1e-4
    assert np.abs(got[0] - lat).max() < 1e-9 and np.abs(got[2] - h).max() < 1e-4


def test_local_frame_to_geodetic_matches_pyproj_over_a_scene():
    frame = LocalFrame(-25.75, 27.86, 1200.0)
    rng = np.random.default_rng(2)
    enu = np.column_stack([rng.uniform(-5e3, 5e3, 2000), rng.uniform(-5e3, 5e3, 2000),
                           rng.uniform(-400.0, 800.0, 2000)])
    got = frame.to_geodetic(enu.reshape(40, 50, 3))
    ref = _pyproj_geodetic(frame.to_ecef(enu))
    assert all(g.shape == (40, 50) for g in got)
    assert np.abs(got[0].ravel() - ref[0]).max() < 1e-9
    assert np.abs(got[1].ravel() - ref[1]).max() < 1e-9
    assert np.abs(got[2].ravel() - ref[2]).max() < 1e-4
    with pytest.raises(ConfigError, match="enu"):
        frame.to_geodetic(np.zeros((4, 2)))


def test_pixel_geolocation_is_to_geodetic_and_the_view_angles_per_pixel():
    from radscene.geometry.frames import angles_from_direction

    frame = LocalFrame(-25.75, 27.86, 1200.0)
    rng = np.random.default_rng(5)
    n, size = 300, 500
    enu = np.column_stack([rng.uniform(-5e3, 5e3, n), rng.uniform(-5e3, 5e3, n),
                           rng.uniform(-400.0, 800.0, n)])
    travel = rng.normal(size=(n, 3))
    travel[0] = [0.0, 0.0, -2.0]  # straight down, not unit: zenith 0
    pixel = rng.permutation(size)[:n]
    got = frame.pixel_geolocation(enu, travel, pixel, size)
    assert got.shape == (5, size)
    lat, lon, h = frame.to_geodetic(enu)
    zen, azi = angles_from_direction(-travel)
    for row, ref in zip(got, (lat, lon, h, zen, azi), strict=True):
        assert np.abs(row[pixel] - ref).max() < 1e-9
    assert got[3, pixel[0]] == 0.0
    assert np.all((got[4, pixel] >= 0.0) & (got[4, pixel] < 360.0))
    missing = np.setdiff1d(np.arange(size), pixel)
    assert np.isnan(got[:, missing]).all()
    assert np.isnan(frame.pixel_geolocation(np.zeros((0, 3)), np.zeros((0, 3)),
                                            np.zeros(0, int), 3)).all()
