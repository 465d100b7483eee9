"""The sun at each ray's time (render/sun_track.py) against the ephemeris (NREL SPA)."""

import datetime as dt
from types import SimpleNamespace

import numpy as np
import pytest

from radscene.atmosphere import PathNodes
from radscene.geometry.frames import direction_from_angles
from radscene.render.sun_track import (
    SUN_NODE_STEP,
    SunGeometry,
    SunTrack,
    combine_nodes,
    sun_track,
)
from radscene.sun import sun_position

EPOCH = dt.datetime(2026, 6, 21, 15, 0, tzinfo=dt.UTC)
PLACE = SimpleNamespace(latitude=35.0, longitude=-106.0, altitude=1500.0)
#: Interpolating the ephemeris between samples 10 s apart [deg].
ANGLE_TOLERANCE = 1e-4


def _scene(sun=None):
    return SimpleNamespace(sun=sun, time=EPOCH, location=PLACE)


def _ephemeris(seconds):
    stamps = [EPOCH + dt.timedelta(seconds=float(s)) for s in seconds]
    return sun_position(stamps, PLACE.latitude, PLACE.longitude, PLACE.altitude)


def _angle(a, b):
    return np.degrees(np.arccos(np.clip(np.einsum("...c,...c->...", a, b), -1.0, 1.0)))


def test_a_frame_has_one_fixed_sun():
    track = sun_track(_scene(), None)
    assert not track.moving and len(track.nodes) == 1
    pos = _ephemeris([0.0])
    assert track.nodes[0].zenith == pytest.approx(float(pos.zenith[0]), abs=1e-9)
    assert track.direction().shape == (1, 3)
    index, weight = track.node_weights()
    assert index.tolist() == [[0]] and weight.tolist() == [[1.0]]
    # a hand-placed sun stays put whatever the rays' times
    placed = SimpleNamespace(zenith=40.0, azimuth=200.0, distance=1.0)
    track = sun_track(_scene(placed), np.linspace(0.0, 900.0, 50))
    assert not track.moving and track.nodes[0] == SunGeometry(40.0, 200.0, 1.0)


def test_rays_at_one_instant_see_one_sun():
    track = sun_track(_scene(), np.full(20, 30.0))
    assert not track.moving and len(track.nodes) == 1
    assert track.nodes[0].zenith == pytest.approx(float(_ephemeris([30.0]).zenith[0]), abs=1e-9)


def test_the_sun_of_each_ray_time_is_the_ephemeris():
    times = np.linspace(0.0, 1200.0, 997)  # a 20-minute pass
    track = sun_track(_scene(), times)
    assert track.moving
    pos = _ephemeris(times)
    exact = direction_from_angles(pos.zenith, pos.azimuth)
    assert _angle(track.direction(times), exact).max() < ANGLE_TOLERANCE
    zenith, azimuth = track.angles(times)
    assert zenith == pytest.approx(pos.zenith, abs=ANGLE_TOLERANCE)
    assert azimuth == pytest.approx(pos.azimuth, abs=ANGLE_TOLERANCE)


def test_sun_nodes_are_at_most_a_step_apart_and_mix_linearly_in_time():
    times = np.sort(np.random.default_rng(2).uniform(-300.0, 900.0, 500))
    track = sun_track(_scene(), times)
    assert track.node_time[0] == times.min() and track.node_time[-1] == times.max()
    dirs = np.array([s.direction for s in track.nodes])
    assert len(track.nodes) >= 3
    assert _angle(dirs[1:], dirs[:-1]).max() <= SUN_NODE_STEP
    index, weight = track.node_weights(times)
    assert weight.sum(axis=1) == pytest.approx(np.ones(times.size), rel=1e-12)
    assert (track.node_time[index] * weight).sum(axis=1) == pytest.approx(times, rel=1e-12)
    assert 0 <= track.reference < len(track.nodes)


def test_combine_nodes_multiplies_sun_and_path_weights():
    path = PathNodes(np.array([3000.0, 3000.0]), np.zeros(2), np.array([0.0, 10.0]),
                     np.array([[0, 1], [1, 0]]), np.array([[0.25, 0.75], [1.0, 0.0]]))
    sun_index, sun_weight = np.array([[0, 1], [2, 3]]), np.array([[0.5, 0.5], [0.9, 0.1]])
    both = combine_nodes(path, sun_index, sun_weight)
    assert both.index.tolist() == [[0, 1, 2, 3], [5, 4, 7, 6]]
    assert both.weight == pytest.approx(np.array([[0.125, 0.375, 0.125, 0.375],
                                                  [0.9, 0.0, 0.1, 0.0]]), rel=1e-12)
    one = combine_nodes(path, *SunTrack.fixed(SunGeometry(30.0, 0.0, 1.0)).node_weights())
    assert one is path


def test_a_short_scan_has_one_sun_node_but_each_ray_its_sun():
    times = np.linspace(0.0, 1.5, 300)  # a satellite's image: the sun moves 0.006 deg
    track = sun_track(_scene(), times)
    assert track.moving and len(track.nodes) == 1
    assert track.node_time[0] == pytest.approx(0.75, rel=1e-12)
    pos = _ephemeris(times[[0, -1]])
    zenith, _ = track.angles(times[[0, -1]])
    assert zenith == pytest.approx(pos.zenith, abs=1e-6)
    assert abs(zenith[0] - zenith[1]) > 1e-3
    index, weight = track.node_weights(times)
    assert index.shape == (300, 1) and np.all(weight == 1.0)
