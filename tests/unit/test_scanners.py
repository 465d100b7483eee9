"""Tests of radscene.platform.{trajectory, scanners, config}: poses, pushbroom, whiskbroom."""

import datetime as dt

import numpy as np
import pytest

from radscene.errors import ConfigError
from radscene.geometry import rotation_matrix
from radscene.platform import OrthographicCamera
from radscene.platform.config import PushbroomSpec, build_observer
from radscene.platform.geolocation import EARTH_ROTATION_RATE, WGS84_A, WGS84_E2, LocalFrame
from radscene.platform.scanners import (
    PushbroomScanner,
    WhiskbroomScanner,
    mount_rotation,
    to_body_frame,
)
from radscene.platform.trajectory import (
    Trajectory,
    attitude_from_matrix,
    matrix_from_quaternion,
    quaternion_from_matrix,
    slerp,
)

EXACT = 1e-9  # [m] on coordinates up to ~1e4 m, [s] on times, [-] on unit vectors
ANGLE = 1e-9  # [deg]
UTC = dt.UTC


def _by_pixel(bundle, values):
    order = np.argsort(bundle.pixel, kind="stable")
    return np.asarray(values)[order].reshape(bundle.shape + np.shape(values)[1:])


def _ground(bundle):
    """Where pixel-centre rays meet z = 0, (ny, nx, 3)."""
    t = -bundle.origins[:, 2] / bundle.directions[:, 2]
    return _by_pixel(bundle, bundle.origins + t[:, None] * bundle.directions)


def _north_flight(height=1000.0, speed=50.0, duration=10.0, start=-1.0):
    return Trajectory.linear([0.0, speed * start, height], [0.0, speed, 0.0], duration,
                             attitude=(0.0, 0.0, 0.0), start=start)


# -- poses and trajectories ------------------------------------------------------------------


def test_quaternions_round_trip_and_match_rotation_matrix():
    rng = np.random.default_rng(3)
    att = np.column_stack([rng.uniform(0, 360, 50), rng.uniform(-89, 89, 50),
                           rng.uniform(-179, 179, 50)])
    m = rotation_matrix(att[:, 0], att[:, 1], att[:, 2])
    q = quaternion_from_matrix(m)
    assert np.linalg.norm(q, axis=1) == pytest.approx(np.ones(50), abs=EXACT)
    assert matrix_from_quaternion(q) == pytest.approx(m, abs=EXACT)
    yaw, pitch, roll = attitude_from_matrix(m)
    assert np.column_stack([yaw, pitch, roll]) == pytest.approx(att, abs=1e-7)


def test_slerp_turns_at_constant_rate_along_the_short_arc():
    q0 = quaternion_from_matrix(rotation_matrix(10.0))
    q1 = -quaternion_from_matrix(rotation_matrix(70.0))  # same rotation, other hemisphere
    f = np.array([0.0, 0.25, 0.5, 1.0])
    yaw = attitude_from_matrix(matrix_from_quaternion(slerp(q0, q1, f)))[0]
    assert yaw == pytest.approx([10.0, 25.0, 40.0, 70.0], abs=ANGLE)


def test_trajectory_interpolates_positions_and_attitudes():
    tr = Trajectory([0.0, 2.0, 4.0], [[0, 0, 100], [10, 0, 100], [10, 20, 100]],
                    [[0, 0, 0], [90, 0, 0], [90, 10, 0]])
    assert tr.position(1.0) == pytest.approx([5.0, 0.0, 100.0], abs=EXACT)
    assert tr.velocity(3.0) == pytest.approx([0.0, 10.0, 0.0], abs=EXACT)
    yaw, pitch, _ = tr.pose(np.array([1.0, 3.0])).attitude
    assert yaw == pytest.approx([45.0, 90.0], abs=ANGLE)
    assert pitch == pytest.approx([0.0, 5.0], abs=1e-6)
    # Hermite interpolation with velocities is exact for cubic motion
    t = np.array([0.0, 1.0, 3.0])
    x = lambda s: 2 * s**3 - s**2 + 4 * s  # noqa: E731
    v = lambda s: 6 * s**2 - 2 * s + 4  # noqa: E731
    cubic = Trajectory(t, np.column_stack([x(t), 0 * t, 0 * t]),
                       velocities=np.column_stack([v(t), 0 * t, 0 * t]))
    s = np.array([0.3, 1.7, 2.9])
    assert cubic.position(s)[:, 0] == pytest.approx(x(s), abs=1e-9)
    assert cubic.velocity(s)[:, 0] == pytest.approx(v(s), abs=1e-9)


def test_trajectory_refuses_bad_input():
    with pytest.raises(ConfigError, match="times: must be a 1-D, finite, strictly increasing"):
        Trajectory([0.0, 0.0], [[0, 0, 0], [1, 0, 0]])
    with pytest.raises(ConfigError, match=r"positions: must have shape \(2, 3\)"):
        Trajectory([0.0, 1.0], [[0, 0, 0]])
    with pytest.raises(ConfigError, match=r"time: times must lie within .* \[0, 1\] s"):
        Trajectory([0.0, 1.0], [[0, 0, 0], [1, 0, 0]]).position(1.5)
    with pytest.raises(ConfigError, match="epoch: must be a timezone-aware"):
        Trajectory([0.0], [[0, 0, 0]], epoch=dt.datetime(2024, 1, 1))
    with pytest.raises(ConfigError, match="duration: must be > 0 s"):
        Trajectory.linear([0, 0, 0], [1, 0, 0], 0.0)


# -- pushbroom ---------------------------------------------------------------------------------


def test_pushbroom_lines_follow_the_platform():
    tr = _north_flight()
    pb = PushbroomScanner(tr, (6, 5), gsd=2.0, start=0.0)
    assert pb.ifov == pytest.approx(np.degrees(np.arctan(2.0 / 1000.0)), abs=ANGLE)
    assert pb.line_time == pytest.approx(2.0 / 50.0, rel=1e-9)  # square pixels
    bundle = pb.rays()
    times = _by_pixel(bundle, bundle.time)
    assert times == pytest.approx(np.repeat(((np.arange(6) + 0.5) * 0.04)[:, None], 5, 1),
                                  abs=EXACT)
    g = _ground(bundle)
    # rows advance north with the platform, columns run to the left of the track (west)
    assert g[..., 1] == pytest.approx(50.0 * times, abs=1e-6)
    assert g[0, :, 0] == pytest.approx(-2.0 * (np.arange(5) + 0.5 - 2.5), abs=1e-6)
    assert _by_pixel(bundle, bundle.origins)[:, 0, 1] == pytest.approx(50.0 * times[:, 0],
                                                                       abs=EXACT)


def test_pushbroom_supersamples_share_their_line_time():
    pb = PushbroomScanner(_north_flight(), (4, 3), ifov=0.1, line_time=0.01)
    k = 3
    bundle = pb.rays(supersample=k, window=(1, 3, 0, 2))
    assert len(bundle) == 2 * 2 * k * k
    assert np.bincount(bundle.pixel, bundle.weight)[[3, 4, 6, 7]] == pytest.approx(np.ones(4))
    line = bundle.pixel // 3
    assert bundle.time == pytest.approx(pb.start + (line + 0.5) * 0.01, abs=EXACT)
    # sub-rows look along the track within the detector's footprint: tan offsets (a+1/2)/k - 1/2
    a = bundle.subsample // k
    fwd = bundle.directions[:, 1] / -bundle.directions[:, 2]
    assert fwd == pytest.approx(((a + 0.5) / k - 0.5) * np.tan(np.radians(0.1)), abs=EXACT)


@pytest.mark.parametrize(("off_nadir", "tilt"), [(20.0, 0.0), (-35.0, 10.0), (0.0, -15.0)])
def test_off_nadir_pointing(off_nadir, tilt):
    pb = PushbroomScanner(_north_flight(), (1, 3), ifov=0.01, line_time=0.01, start=0.0,
                          off_nadir=off_nadir, forward_tilt=tilt)
    g = _ground(pb.rays())[0, 1]  # centre column
    t = 0.005
    # roll towards the right of the track (east), then pitch ahead
    assert g[0] == pytest.approx(1000.0 * np.tan(np.radians(off_nadir)), abs=1e-6)
    assert g[1] - 50.0 * t == pytest.approx(
        1000.0 * np.tan(np.radians(tilt)) / np.cos(np.radians(off_nadir)), abs=1e-6)
    assert -mount_rotation(30.0)[:, 2] == pytest.approx([0.5, 0.0, -np.sqrt(0.75)], abs=EXACT)


@pytest.mark.parametrize(("u", "stretch"), [(0.0, 1.0), (25.0, 2.0), (-50.0, 0.5)])
def test_pushbroom_stretches_a_target_moving_along_the_track(u, stretch):
    """A plate of length L moving at u north: line i (time t_i) sees ground y = V t_i, so it
    samples the plate while y0 <= (V - u) t_i <= y0 + L: L/((V - u) lt) lines instead of L/g."""
    speed, height, gsd, length, y0 = 50.0, 1000.0, 1.0, 20.0, 30.3
    tr = _north_flight(height, speed, duration=6.0, start=-0.5)
    pb = PushbroomScanner(tr, (250, 21), gsd=gsd, start=0.0)
    target = Trajectory.linear([0.0, y0 - 0.5 * u, 0.0], [0.0, u, 0.0], 7.0,
                               attitude=(0, 0, 0), start=-0.5)  # at y0 at t = 0
    body = to_body_frame(pb.rays(), target)
    t = -body.origins[:, 2] / body.directions[:, 2]
    hit_point = body.origins + t[:, None] * body.directions
    inside = (np.abs(hit_point[:, 0]) <= 3.0) & (hit_point[:, 1] >= 0) & \
        (hit_point[:, 1] <= length)
    mask = _by_pixel(body, inside)
    lines = np.nonzero(mask.any(axis=1))[0]
    t_line = (np.arange(250) + 0.5) * pb.line_time
    expected = np.nonzero((y0 <= (speed - u) * t_line) &
                          ((speed - u) * t_line <= y0 + length))[0]
    assert lines.tolist() == expected.tolist()
    assert len(lines) == pytest.approx(stretch * length / gsd, abs=1.0)
    assert np.nonzero(mask.any(axis=0))[0].tolist() == list(range(7, 14))  # |x| <= 3 m


def test_earth_rotation_drags_the_ground_track_west():
    lat = 45.0
    frame = LocalFrame(lat, 10.0, 0.0)
    height, speed = 700e3, 7000.0
    still = Trajectory.linear([0, 0, height], [0, speed, 0], 3.0, attitude=(0, 0, 0))
    turning = Trajectory.linear([0, 0, height], [0, speed, 0], 3.0, attitude=(0, 0, 0),
                                frame=frame)
    args = dict(shape=(201, 1), ifov=0.002, line_time=0.01, start=0.0)
    g_still = _ground(PushbroomScanner(still, **args).rays())[:, 0]
    g_turn = _ground(PushbroomScanner(turning, **args).rays())[:, 0]
    elapsed = 200 * 0.01
    # the ground moves east at ω (N + h) cos φ under an inertial platform
    n = WGS84_A / np.sqrt(1 - WGS84_E2 * np.sin(np.radians(lat)) ** 2)
    drift = EARTH_ROTATION_RATE * n * np.cos(np.radians(lat)) * elapsed
    assert g_still[-1, 0] - g_still[0, 0] == pytest.approx(0.0, abs=1e-6)
    assert g_turn[-1, 0] - g_turn[0, 0] == pytest.approx(-drift, rel=5e-3)


def test_pushbroom_project_inverts_every_subsample():
    pb = PushbroomScanner(_north_flight(), (8, 6), ifov=0.05, line_time=0.02,
                          off_nadir=10.0, start=0.0)
    bundle = pb.rays(supersample=3)
    t = -bundle.origins[:, 2] / bundle.directions[:, 2]
    ground = bundle.origins + t[:, None] * bundle.directions
    row, col = pb.project(ground)
    k = 3
    a, b = bundle.subsample // k, bundle.subsample % k
    assert row == pytest.approx(bundle.pixel // 6 + (a + 0.5) / k, abs=1e-6)
    assert col == pytest.approx(bundle.pixel % 6 + (b + 0.5) / k, abs=1e-6)
    r, c = pb.project([[0.0, 0.0, 2000.0]])  # above the sensor
    assert np.isnan(r).all() and np.isnan(c).all()


def test_pushbroom_refuses_bad_input():
    tr = _north_flight()
    with pytest.raises(ConfigError, match="trajectory: must be a Trajectory"):
        PushbroomScanner(OrthographicCamera((0, 0), (2, 2)), (2, 2), ifov=1.0)
    with pytest.raises(ConfigError, match="ifov, gsd: give exactly one"):
        PushbroomScanner(tr, (2, 2), ifov=1.0, gsd=2.0)
    with pytest.raises(ConfigError, match=r"line_time: must be a finite number in \(0"):
        PushbroomScanner(tr, (2, 2), ifov=1.0, line_time=0.0)
    with pytest.raises(ConfigError, match="shape: must be two positive integers"):
        PushbroomScanner(tr, (2, 0), ifov=1.0)
    with pytest.raises(ConfigError, match="time: times must lie within"):
        PushbroomScanner(tr, (1000, 2), ifov=1.0, line_time=0.1).rays()
    with pytest.raises(ConfigError, match="the platform does not move"):
        PushbroomScanner(Trajectory.static([0, 0, 100]), (2, 2), ifov=1.0)


# -- whiskbroom ---------------------------------------------------------------------------------


def test_whiskbroom_gives_each_sample_its_time():
    tr = _north_flight()
    wb = WhiskbroomScanner(tr, (6, 4), ifov=0.5, scan_period=0.2, detectors=2,
                           sample_time=0.03, bidirectional=True, start=0.0)
    bundle = wb.rays()
    times = _by_pixel(bundle, bundle.time)
    sweep = np.arange(6)[:, None] // 2
    col = np.arange(4)[None, :]
    expected = sweep * 0.2 + np.where(sweep % 2 == 1, 4 - col - 0.5, col + 0.5) * 0.03
    assert times == pytest.approx(expected, abs=EXACT)
    # within a sweep, later detectors (rows) look further ahead, by tan(α) H / cos(θ) (the
    # footprint grows away from nadir: the bow-tie)
    g = _ground(bundle)
    along = g[..., 1] - 50.0 * times
    step = 1000.0 * np.tan(np.radians(0.5)) / np.cos(np.radians(0.75))  # column 0: θ = 0.75
    assert along[0, 0] == pytest.approx(-0.5 * step, rel=1e-9)
    assert along[1, 0] == pytest.approx(0.5 * step, rel=1e-9)
    # a linear mirror steps one ifov per column, from the right of the track to the left
    across = np.degrees(np.arctan2(g[0, :, 0], 1000.0))
    assert np.diff(across) == pytest.approx(np.full(3, -0.5), abs=1e-3)


def test_whiskbroom_mirror_profile_sets_the_angles():
    profile = [[0.0, 20.0], [0.5, 0.0], [1.0, -5.0]]  # fast sweep, then slow
    wb = WhiskbroomScanner(_north_flight(), (1, 4), ifov=1.0, scan_period=0.1,
                           mirror_profile=profile, start=0.0)
    g = _ground(wb.rays())[0]
    phase = (np.arange(4) + 0.5) / 4
    angle = np.interp(phase, [0.0, 0.5, 1.0], [20.0, 0.0, -5.0])
    assert g[:, 0] == pytest.approx(1000.0 * np.tan(np.radians(angle)), abs=1e-6)
    row, col = wb.project(g)
    assert col == pytest.approx(np.arange(4) + 0.5, abs=1e-6)


@pytest.mark.parametrize(("u", "factor"), [(300.0, 1000.0 / 1300.0), (-300.0, 1000.0 / 700.0)])
def test_whiskbroom_stretches_a_target_moving_across_the_track(u, factor):
    """The spot sweeps west at H ifov / dt = 1000 m/s; a plate moving east (u > 0) meets it
    sooner and looks narrower, one moving west looks wider: W ω / (ω + u)."""
    height, ifov, dt_sample, width, x0 = 1000.0, np.degrees(1e-3), 1e-3, 30.0, -15.2
    nx = 101
    tr = _north_flight(height, 50.0, duration=2.0, start=-0.5)
    wb = WhiskbroomScanner(tr, (4, nx), ifov=ifov, scan_period=0.2, sample_time=dt_sample,
                           start=0.0)
    target = Trajectory.linear([x0 - 0.5 * u, -1e4, 0.0], [u, 0.0, 0.0], 3.0,
                               attitude=(0, 0, 0), start=-0.5)  # at x0 at t = 0
    body = to_body_frame(wb.rays(), target)
    s = -body.origins[:, 2] / body.directions[:, 2]
    p = body.origins + s[:, None] * body.directions
    mask = _by_pixel(body, (p[:, 0] >= 0.0) & (p[:, 0] <= width) & (p[:, 1] <= 2e4))
    # independent: sample j of sweep s at τ = s P + (j + 1/2) dt sees x = H tan θ_j
    sweep = np.arange(4)[:, None]
    j = np.arange(nx)[None, :]
    tau = sweep * 0.2 + (j + 0.5) * dt_sample
    x = height * np.tan((nx / 2 - j - 0.5) * 1e-3)
    expected = (x0 + u * tau <= x) & (x <= x0 + width + u * tau)
    assert mask.tolist() == expected.tolist()
    assert mask[0].sum() == pytest.approx(width * factor, abs=1.0)  # it then leaves the field


def test_whiskbroom_refuses_bad_input():
    tr = _north_flight()
    with pytest.raises(ConfigError, match="shape: the number of lines 5 must be a multiple"):
        WhiskbroomScanner(tr, (5, 4), ifov=1.0, detectors=2)
    with pytest.raises(ConfigError, match="detectors: must be an integer >= 1"):
        WhiskbroomScanner(tr, (4, 4), ifov=1.0, detectors=0)
    with pytest.raises(ConfigError, match="sample_time: samples x sample_time"):
        WhiskbroomScanner(tr, (4, 4), ifov=1.0, scan_period=0.1, sample_time=0.05)
    with pytest.raises(ConfigError, match="mirror_profile: angles must decrease"):
        WhiskbroomScanner(tr, (4, 4), ifov=1.0, mirror_profile=[[0, 0], [1, 5]])
    with pytest.raises(ConfigError, match=r"mirror_profile: phases must .* cover \[0, 1\]"):
        WhiskbroomScanner(tr, (4, 4), ifov=1.0, mirror_profile=[[0.1, 5], [1, 0]])


def test_to_body_frame_of_a_static_body_is_a_translation():
    cam = OrthographicCamera((0, 0), (2, 2), gsd=1.0, altitude=100.0)
    body = to_body_frame(cam.rays(), Trajectory.static([5.0, 0.0, 0.0], (90.0, 0, 0)), time=0.0)
    assert body.time == pytest.approx(np.zeros(4))
    # yaw 90: the body's forward (+y) is east, so a world offset -5 east is -5 along body y
    assert body.origins[:, 1] == pytest.approx(cam.rays().origins[:, 0] - 5.0, abs=EXACT)
    with pytest.raises(ConfigError, match="time: the rays carry no times"):
        to_body_frame(cam.rays(), Trajectory.static([0, 0, 0]))


# -- scene-file specs ---------------------------------------------------------------------------


def test_build_observer_from_specs():
    frame = LocalFrame(40.0, -105.0, 1500.0)
    t = dt.datetime(2023, 6, 1, 17, 30, tzinfo=UTC)
    pb = build_observer({"type": "pushbroom", "name": "oli", "shape": [101, 51],
                         "gsd": "30 m", "orbit": {"overpass": {"altitude": "705 km"}}},
                        frame, t)
    assert isinstance(pb, PushbroomScanner) and pb.epoch == t
    assert pb.start == pytest.approx(-50.5 * pb.line_time, abs=EXACT)  # centred on t
    g = _ground(pb.rays())
    assert g[50, 25] == pytest.approx([0.0, 0.0, 0.0], abs=0.1)  # the origin, at t
    assert np.linalg.norm(g[50, 26] - g[50, 25]) == pytest.approx(30.0, rel=1e-3)
    assert np.linalg.norm(g[51, 25] - g[50, 25]) == pytest.approx(30.0, rel=2e-2)
    wb = build_observer({"type": "whiskbroom", "name": "scan", "shape": [8, 20],
                         "ifov": "0.1 deg", "detectors": 4,
                         "platform": {"position": [0, 0, 1500], "velocity": [0, 80, 0]}},
                        frame, t)
    assert isinstance(wb, WhiskbroomScanner)
    assert wb.scan_period == pytest.approx(4 * 1500 * np.tan(np.radians(0.1)) / 80, rel=1e-9)
    spec = PushbroomSpec(type="pushbroom", name="p", shape=(4, 4), ifov=0.01, line_time=0.1,
                         waypoints={"times": [-1, 1], "positions": [[0, -10, 500],
                                                                    [0, 10, 500]]})
    assert build_observer(spec, frame, t).line_time == 0.1


@pytest.mark.parametrize(("spec", "match"), [
    ({"shape": [4, 4], "gsd": 30}, r"observers\[1\]: .*exactly one of orbit, platform"),
    ({"shape": [4, 4], "platform": {"position": [0, 0, 9], "velocity": [0, 1, 0]}},
     r"observers\[1\]: .*exactly one of 'ifov'"),
    ({"shape": [4, 4], "gsd": "30 kg", "platform": {"position": [0, 0, 9],
                                                     "velocity": [0, 1, 0]}},
     r"observers\[1\]\.gsd: .*unit"),
    ({"shape": [4, 4], "gsd": 30, "orbit": {"overpass": {"altitude": 7e5}}},
     r"observers\[1\]\.orbit: an orbit needs the scene time"),
])
def test_build_observer_errors_name_the_key(spec, match):
    frame = LocalFrame(40.0, -105.0, 0.0)
    with pytest.raises(ConfigError, match=match):
        build_observer({"type": "pushbroom", "name": "x", **spec}, frame, None,
                       key="observers[1]")


def test_landsat_like_example_observer():
    from importlib import resources

    import yaml

    path = resources.files("radscene") / "data" / "sensors" / "landsat_like.yaml"
    spec = PushbroomSpec(**yaml.safe_load(path.read_text(encoding="utf-8"))["observer"])
    frame = LocalFrame(40.0, -105.0, 1500.0)
    t = dt.datetime(2023, 6, 1, 17, 30, tzinfo=UTC)
    pb = build_observer(spec, frame, t)
    # 10 m samples; three of them make the 30 m detector's 4.4 ms line at 705 km
    assert pb.ifov == pytest.approx(np.degrees(10.0 / 705e3), rel=1e-4)
    assert 3 * pb.line_time == pytest.approx(30.0 / 6780.0, rel=0.01)
    small = PushbroomScanner(pb.trajectory, (3, 3), ifov=pb.ifov, line_time=pb.line_time,
                             start=-1.5 * pb.line_time)
    assert _ground(small.rays())[1, 1] == pytest.approx([0.0, 0.0, 0.0], abs=0.05)


def test_scanner_sampling_must_fit_the_sensor():
    from radscene.platform.config import check_sensor_sampling
    from radscene.sensor import load_sensor

    sensor = load_sensor("landsat_like")  # 42.55 urad detectors, 3 samples each
    frame = LocalFrame(40.0, -105.0, 1500.0)
    t = dt.datetime(2023, 6, 1, 17, 30, tzinfo=UTC)

    def scanner(**sampling):
        return build_observer({"type": "pushbroom", "name": "x", "shape": [6, 6], **sampling,
                               "orbit": {"overpass": {"altitude": 705e3}}}, frame, t)

    check_sensor_sampling(scanner(gsd=10.0), sensor, "observers[0]", gsd=10.0)
    with pytest.raises(ConfigError, match=r"observers\[0\]\.gsd: .* give gsd 10(\.0)? m or ifov "
                                          r"2\.92\d arcsec"):
        check_sensor_sampling(scanner(gsd=15.0), sensor, "observers[0]", gsd=15.0)
    with pytest.raises(ConfigError, match=r"observers\[0\]\.ifov: .*needs 3 samples per"):
        check_sensor_sampling(scanner(ifov=0.001), sensor, "observers[0]")
