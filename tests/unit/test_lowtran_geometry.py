"""Line-of-sight geometry and path nodes of the LOWTRAN engine; user profiles."""

from __future__ import annotations

import numpy as np
import pytest

from radscene.atmosphere.lowtran.geometry import (
    DEFAULT_EARTH_RADIUS,
    observer_geometry,
    path_node_grid,
)
from radscene.atmosphere.lowtran.profiles import profile_levels
from radscene.errors import ConfigError

ANGLE_ABS = 1e-9  # [deg], double-precision trigonometry
LENGTH_REL = 1e-9


def test_nadir_and_zenith_paths():
    z, beta, s = observer_geometry(5000.0, 1000.0, 0.0)
    assert (float(z), float(beta)) == (180.0, 0.0)
    assert float(s) == pytest.approx(4000.0, rel=LENGTH_REL)
    z, beta, s = observer_geometry(0.0, 2000.0, 180.0)  # observer below, looking up
    assert float(z) == pytest.approx(0.0, abs=ANGLE_ABS)
    assert float(s) == pytest.approx(2000.0, rel=LENGTH_REL)


def test_flat_earth_limit():
    # on a huge sphere the path is a straight line over a plane: s = dh / cos(vz)
    vz = np.array([10.0, 45.0, 70.0])
    z, beta, s = observer_geometry(3000.0, 0.0, vz, earth_radius=1e10)
    assert z == pytest.approx(180.0 - vz, abs=1e-4)  # the central angle, s sin(vz) / R
    # curvature changes s by ~ s tan(vz)^2 / R: 1e-6 here
    assert s == pytest.approx(3000.0 / np.cos(np.radians(vz)), rel=1e-5)
    assert beta == pytest.approx(np.degrees(s * np.sin(np.radians(vz)) / 1e10), rel=1e-4)


def test_spherical_earth_invariants():
    # r sin(theta) is constant along a straight line, and the triangle closes
    h_o, h_t, vz = 20000.0, 500.0, 75.0
    z, beta, s = (float(x) for x in observer_geometry(h_o, h_t, vz))
    r_o, r_t = DEFAULT_EARTH_RADIUS + h_o, DEFAULT_EARTH_RADIUS + h_t
    assert r_o * np.sin(np.radians(180.0 - z)) == pytest.approx(
        r_t * np.sin(np.radians(vz)), rel=LENGTH_REL)
    assert r_o**2 == pytest.approx(r_t**2 + s**2 + 2 * r_t * s * np.cos(np.radians(vz)),
                                   rel=LENGTH_REL)
    assert np.radians(beta) * r_t == pytest.approx(s * np.sin(np.radians(vz)), rel=0.05)
    assert 180.0 - z < vz  # the line is steeper at the observer's end


def test_geometry_broadcasts_and_flags_impossible_paths():
    z, beta, s = observer_geometry([[3000.0], [0.0]], [0.0, 1000.0, 2000.0], [[30.0], [150.0]])
    assert z.shape == beta.shape == s.shape == (2, 3)
    assert np.isfinite(s[0, :2]).all() and np.isfinite(s[1, 1:]).all()
    # observer above the target looking down, or below it looking up: no straight path
    assert np.isnan(observer_geometry(3000.0, 0.0, 120.0)[2])
    assert np.isnan(observer_geometry(0.0, 3000.0, 60.0)[2])


def test_few_distinct_geometries_become_nodes_of_their_own():
    nodes = path_node_grid([3000.0] * 4, [0.0, 0.0, 100.0, 100.0], [10.0, 10.0, 20.0, 20.0])
    assert nodes.size == 2
    assert nodes.index[:, 0].tolist() in ([0, 0, 1, 1], [1, 1, 0, 0])
    assert nodes.weight.tolist() == [[1.0]] * 4


def test_grid_weights_interpolate_linear_functions_exactly():
    rng = np.random.default_rng(7)
    n = 2000
    obs = np.full(n, 3000.0)
    tgt = rng.uniform(0.0, 400.0, n)
    vz = rng.uniform(0.0, 60.0, n)
    nodes = path_node_grid(obs, tgt, vz, zenith_nodes=5, max_distinct=8)
    assert nodes.size == 5 * 2  # air mass x target altitude; one observer altitude
    assert nodes.weight.sum(axis=1) == pytest.approx(np.ones(n), abs=1e-12)
    assert nodes.weight.min() >= 0 and nodes.index.max() < nodes.size
    np.testing.assert_array_equal(nodes.observer_altitude, 3000.0)

    def f(o, t, z):  # linear in air mass and altitudes
        return 2.0 / np.cos(np.radians(z)) + 0.01 * t - 0.003 * o
    at_nodes = f(nodes.observer_altitude, nodes.target_altitude, nodes.view_zenith)
    mixed = np.sum(nodes.weight * at_nodes[nodes.index], axis=1)
    assert mixed == pytest.approx(f(obs, tgt, vz), rel=1e-10)


def test_grid_nodes_are_real_paths_when_altitudes_overlap():
    # observers from 200 to 800 m over targets from 0 to 600 m: an observer-altitude axis
    # would pair 200 m observers with 600 m targets; the altitude difference never does
    rng = np.random.default_rng(3)
    n = 500
    tgt = rng.uniform(0.0, 600.0, n)
    obs = tgt + rng.uniform(200.0, 300.0, n)
    vz = rng.uniform(0.0, 40.0, n)
    up = np.arange(n) < 50  # and a few lines of sight looking up at higher targets
    obs[up], tgt[up], vz[up] = 100.0, 400.0 + tgt[up], 150.0
    nodes = path_node_grid(obs, tgt, vz, zenith_nodes=4)
    down_nodes = nodes.view_zenith <= 90.0
    assert np.all(nodes.observer_altitude[down_nodes] >= nodes.target_altitude[down_nodes])
    assert np.all(nodes.observer_altitude[~down_nodes] <= nodes.target_altitude[~down_nodes])
    assert nodes.weight.sum(axis=1) == pytest.approx(np.ones(n), abs=1e-12)
    # each line of sight mixes only nodes looking its way
    assert np.all(nodes.view_zenith[nodes.index[up]][nodes.weight[up] > 0] > 90.0)
    assert np.all(nodes.view_zenith[nodes.index[~up]][nodes.weight[~up] > 0] <= 90.0)


def test_empty_pixels_give_a_valid_node():
    nodes = path_node_grid([], [], [])
    assert nodes.size == 1 and nodes.index.shape == (0, 1)


def test_profile_levels_convert_units_and_flags():
    levels = profile_levels({"altitude": [0.0, 1000.0, 5000.0],
                             "pressure": [1013.0, 900.0, 540.0],
                             "temperature": [288.0, 281.5, 255.7],
                             "h2o": [70.0, 50.0, 20.0],
                             "base_model": "tropical"})
    assert [lv.z for lv in levels] == [0.0, 1.0, 5.0]  # km on the cards
    assert levels[1].p == 900.0 and levels[1].t == 281.5
    assert levels[0].wmol[0] == 70.0
    assert levels[0].jchar == "AAH11" + "1" * 9  # RH %, O3 and other gases from model 1


@pytest.mark.parametrize("profile, key, match", [
    ({"altitude": [0, 1000]}, "atmosphere.profile", "missing 'pressure'"),
    ({"altitude": [0, 1000], "pressure": [1000, 900], "temperature": [280]},
     "atmosphere.profile", "equal lists"),
    ({"altitude": [1000, 0], "pressure": [900, 1000], "temperature": [280, 285]},
     "atmosphere.profile.altitude", "increase"),
    ({"altitude": [0, 1000], "pressure": [900, 1000], "temperature": [285, 280]},
     "atmosphere.profile.pressure", "decrease"),
    ({"altitude": [0, 1000], "pressure": [1000, 900], "temperature": [0, 280]},
     "atmosphere.profile.temperature", "> 0 K"),
    ({"altitude": [0, 1000], "pressure": [1000, 900], "temperature": [285, 280],
      "h2o": [1, 2], "h2o_unit": "percent"}, "atmosphere.profile.h2o_unit", "unknown unit"),
    ({"altitude": [0, 1000], "pressure": [1000, 900], "temperature": [285, 280],
      "base_model": "martian"}, "atmosphere.profile.base_model", "unknown model"),
])
def test_bad_profiles(profile, key, match):
    with pytest.raises(ConfigError, match=match) as info:
        profile_levels(profile)
    assert info.value.key == key
