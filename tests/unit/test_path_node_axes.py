"""The path nodes' view-zenith (air mass) and relative-azimuth axes (atmosphere/nodes.py)."""

import numpy as np
import pytest

from radscene.atmosphere import (
    PathNodes,
    UniformAtmosphere,
    air_mass,
    fold_relative_azimuth,
    make_atmosphere,
    relative_azimuth_axis,
)
from radscene.atmosphere.nodes import (
    AZIMUTH_STEPS,
    azimuth_step,
    zenith_from_air_mass,
)

EXACT = 1e-12


def test_fold_is_the_absolute_difference_wrapped_to_180():
    view = np.array([[0.0, 10.0, 350.0], [180.0, 190.0, -170.0]])
    np.testing.assert_allclose(fold_relative_azimuth(view, 0.0),
                               [[0.0, 10.0, 10.0], [180.0, 170.0, 170.0]], atol=EXACT)
    # broadcast over the sun's azimuth, symmetric in its arguments
    sun = np.array([[355.0], [5.0]])
    np.testing.assert_allclose(fold_relative_azimuth(5.0, sun), [[10.0], [0.0]], atol=EXACT)
    np.testing.assert_allclose(fold_relative_azimuth(sun, 5.0), [[10.0], [0.0]], atol=EXACT)
    assert np.isnan(fold_relative_azimuth(np.nan, 0.0))


def test_air_mass_round_trip():
    zenith = np.array([[0.0, 30.0], [60.0, 89.0]])
    assert air_mass(zenith) == pytest.approx(1.0 / np.cos(np.radians(zenith)), rel=EXACT)
    assert zenith_from_air_mass(air_mass(zenith)) == pytest.approx(zenith, abs=1e-9)


def test_azimuth_axis_weights_reproduce_the_folded_azimuth():
    rng = np.random.default_rng(3)
    phi = rng.uniform(-360.0, 720.0, 400)
    vz = rng.uniform(5.0, 50.0, 400)
    nodes, index, weight = relative_azimuth_axis(phi, vz)
    assert index.shape == weight.shape == (400, 2)
    assert weight.sum(axis=1) == pytest.approx(np.ones(400), rel=EXACT)
    assert np.all(weight >= 0.0)
    mixed = (nodes[index] * weight).sum(axis=1)
    assert mixed == pytest.approx(fold_relative_azimuth(phi, 0.0), abs=1e-9)
    assert np.all(np.diff(nodes) == 10.0)  # multiples of the step, none unused
    assert np.all(np.isin(np.arange(nodes.size), index[weight > 0.0]))


def test_azimuth_axis_wraps_around_north_and_refines_towards_the_horizon():
    # 355 deg is 5 deg from the sun's azimuth: in the bracket of 7 deg
    nodes, index, weight = relative_azimuth_axis([355.0, 7.0], [40.0, 40.0])
    assert nodes.tolist() == [0.0, 10.0]
    np.testing.assert_allclose(weight, [[0.5, 0.5], [0.3, 0.7]], rtol=EXACT)
    assert AZIMUTH_STEPS == ((10.0, 30.0), (60.0, 10.0), (90.0, 5.0))
    assert azimuth_step(np.array([])) == 30.0
    nodes, _, _ = relative_azimuth_axis([22.0, 38.0], [5.0, 10.0])  # near the vertical
    assert nodes.tolist() == [0.0, 30.0, 60.0]
    nodes, _, _ = relative_azimuth_axis([22.0, 38.0], [40.0, 60.0])
    assert nodes.tolist() == [20.0, 30.0, 40.0]
    nodes, _, _ = relative_azimuth_axis([22.0, 38.0], [40.0, 70.0])
    assert nodes.tolist() == [20.0, 25.0, 35.0, 40.0]
    nodes, _, _ = relative_azimuth_axis([22.0, 38.0], [40.0, 110.0])  # looking up, 70 off
    assert nodes.tolist() == [20.0, 25.0, 35.0, 40.0]


def test_vertical_lines_of_sight_do_not_widen_the_axis():
    # the nadir pixel's azimuth (arbitrary) must not add nodes: it takes the nearest end
    nodes, index, weight = relative_azimuth_axis([170.0, 30.0, 31.0], [0.0, 20.0, 20.0])
    assert nodes.tolist() == [30.0, 40.0]
    assert (nodes[index[0]] * weight[0]).sum() == pytest.approx(31.0, rel=EXACT)
    one, index, weight = relative_azimuth_axis([123.0, 77.0], [0.0, 0.2])
    assert one.size == 1 and index.shape == (2, 1) and np.all(weight == 1.0)


def test_azimuth_axis_refuses_bad_input():
    with pytest.raises(ValueError, match="step must be > 0"):
        relative_azimuth_axis([10.0], [20.0], step=0.0)
    with pytest.raises(ValueError, match="one per line of sight"):
        relative_azimuth_axis([10.0, 20.0], [20.0])


def _nodes(n=3):
    return PathNodes(np.array([3000.0]), np.array([0.0]), np.array([30.0]),
                     np.zeros((n, 1), dtype=np.int64), np.ones((n, 1)))


def test_path_nodes_azimuth_mixing_and_subset():
    plain = _nodes()
    index, weight = plain.azimuth_mixing()
    assert plain.azimuth_size == 1 and index.shape == weight.shape == (3, 1)
    with_axis = plain.with_azimuth([10.0, 25.0, 60.0], [30.0, 30.0, 30.0])
    assert with_axis.relative_azimuth.tolist() == [10.0, 20.0, 30.0, 60.0]
    assert with_axis.size == 1 and with_axis.azimuth_size == 4
    sub = with_axis.subset(np.array([2, 0]))
    assert sub.azimuth_index.tolist() == [with_axis.azimuth_index[2].tolist(),
                                          with_axis.azimuth_index[0].tolist()]
    assert sub.relative_azimuth is with_axis.relative_azimuth
    with pytest.raises(ValueError, match="one per pixel"):
        plain.with_azimuth([10.0], [30.0])


def test_only_sunlit_scattering_engines_add_the_axis():
    obs, tgt = np.full(3, 3000.0), np.zeros(3)
    vz, phi = np.array([20.0, 30.0, 40.0]), np.array([0.0, 45.0, 90.0])
    uniform = UniformAtmosphere()
    assert not uniform.azimuth_dependent
    assert uniform.path_nodes(obs, tgt, vz, relative_azimuth=phi).relative_azimuth is None
    db = make_atmosphere({"type": "database"})
    assert not db.azimuth_dependent  # no sun yet
    assert db.path_nodes(obs, tgt, vz, relative_azimuth=phi).relative_azimuth is None
    lit = db.with_sun(50.0, 120.0)
    assert lit.azimuth_dependent
    nodes = lit.path_nodes(obs, tgt, vz, relative_azimuth=phi)
    assert nodes.relative_azimuth.tolist() == [0.0, 40.0, 50.0, 90.0]  # the used ones
    assert lit.path_nodes(obs, tgt, vz).relative_azimuth is None  # no azimuths given
    night = db.with_sun(95.0, 120.0)
    assert night.path_nodes(obs, tgt, vz, relative_azimuth=phi).relative_azimuth is None


def test_path_radiance_at_an_azimuth_node_is_the_engines():
    """The node's view azimuth is the sun's plus its relative azimuth: the scattered path
    radiance looking into the sun's side (backscatter, 0) and away (forward, 180) differ."""
    db = make_atmosphere({"type": "database"}).with_sun(60.0, 135.0)
    wl = np.array([0.55])
    back = db.path(3000.0, 0.0, 50.0, wl, view_azimuth=135.0).scattered_radiance
    side = db.path(3000.0, 0.0, 50.0, wl, view_azimuth=135.0 + 90.0).scattered_radiance
    fore = db.path(3000.0, 0.0, 50.0, wl, view_azimuth=135.0 + 180.0).scattered_radiance
    mirror = db.path(3000.0, 0.0, 50.0, wl, view_azimuth=135.0 - 90.0).scattered_radiance
    assert side == pytest.approx(mirror, rel=EXACT)  # even in the relative azimuth
    assert fore[0] > 1.2 * side[0] and back[0] != pytest.approx(side[0], rel=0.01)


# -- lines of sight near the horizon: nodes over their length -------------------------------
def _ground_camera(n=200):
    """A camera 2 m up over ground 0-10 m below it (relief) at 80-89.99 deg, and a few lines
    of sight up a hillside (looking up, 90.5-95 deg)."""
    rng = np.random.default_rng(4)
    down = np.column_stack([np.full(n, 2.0), rng.uniform(-10.0, 0.0, n),
                            rng.uniform(80.0, 89.99, n)])
    up = np.column_stack([np.full(20, 2.0), rng.uniform(5.0, 30.0, 20),
                          rng.uniform(90.5, 95.0, 20)])
    return np.vstack([down, up]).T


def test_level_nodes_follow_the_length_of_each_line_of_sight():
    """Mixed with its weights, the nodes' lengths Δh/|cos θ| give back each line of sight's
    (linear in length along the length axis), their spans and targets its own; looking up
    and down keep to their side."""
    from radscene.atmosphere.nodes import LEVEL_LENGTH_RATIO, level_lines, level_nodes

    obs, tgt, vz = _ground_camera()
    sel = level_lines(obs, tgt, vz)
    assert sel.sum() == np.sum(np.minimum(vz, 180 - vz) > 85.0)
    o, t, z = obs[sel], tgt[sel], vz[sel]
    nodes = level_nodes(o, t, z)
    np.testing.assert_allclose(nodes.weight.sum(axis=1), 1.0, atol=EXACT)
    span = np.abs(nodes.observer_altitude - nodes.target_altitude)
    length = span / np.abs(np.cos(np.radians(nodes.view_zenith)))
    want = np.abs(o - t) / np.abs(np.cos(np.radians(z)))
    np.testing.assert_allclose((nodes.weight * length[nodes.index]).sum(axis=1), want, rtol=1e-9)
    low = np.minimum(nodes.observer_altitude, nodes.target_altitude)
    np.testing.assert_allclose((nodes.weight * low[nodes.index]).sum(axis=1), np.minimum(o, t),
                               atol=1e-9)
    assert low.min() >= np.minimum(o, t).min() - 1e-9  # no node below the lines' lowest end
    used = nodes.weight > 0
    node_up = (nodes.view_zenith > 90.0)[nodes.index]
    assert np.all(node_up[used] == np.repeat(z > 90.0, nodes.index.shape[1]).reshape(
        used.shape)[used])
    lengths = np.unique(np.round(length[nodes.view_zenith < 90.0], 6))
    assert np.all(lengths[1:] / lengths[:-1] <= LEVEL_LENGTH_RATIO + 1e-9)


def test_an_engines_nodes_split_at_the_horizon():
    """``with_level_nodes``: the engine's own grid away from the horizon, the length grid near
    it, one set of nodes and rows that still sum to 1."""
    from radscene.atmosphere.nodes import level_lines, with_level_nodes

    obs, tgt, vz = _ground_camera()
    vz[:50] = np.linspace(10.0, 80.0, 50)
    calls = []

    def steep(o, t, z):
        calls.append(z.copy())
        return PathNodes(observer_altitude=np.array([2.0]), target_altitude=np.array([0.0]),
                         view_zenith=np.array([45.0]), index=np.zeros((z.size, 1), np.int64),
                         weight=np.ones((z.size, 1)))

    nodes = with_level_nodes(obs, tgt, vz, steep)
    level = level_lines(obs, tgt, vz)
    assert len(calls) == 1 and calls[0].size == np.sum(~level) and calls[0].max() <= 85.0
    np.testing.assert_allclose(nodes.weight.sum(axis=1), 1.0, atol=EXACT)
    assert np.all(nodes.index[~level, 0] == 0) and np.all(nodes.index[level] >= 1)
    # every level node carries its length: a span of at least 1 m (the engines hold spans up
    # to 0.5 m at 89 deg)
    assert np.all(np.abs(nodes.observer_altitude - nodes.target_altitude)[1:] >= 1.0 - 1e-12)


def test_level_nodes_looking_up_keep_their_observer_on_the_ground():
    """A 2 m camera looking up a hillside 12-52 m high: every node's observer is a real
    observer altitude (the lower end's axis), none below the ground."""
    from radscene.atmosphere.lowtran.geometry import path_node_grid

    nodes = path_node_grid(2.0, np.linspace(12.0, 52.0, 20), np.linspace(91.0, 93.0, 20))
    assert nodes.observer_altitude.min() == 2.0 and np.all(nodes.view_zenith > 90.0)


def test_a_few_lines_near_the_horizon_keep_their_zenith():
    """Below the distinct-geometry count a line at 89.996 deg is not rounded to 90."""
    from radscene.atmosphere.lowtran.geometry import path_node_grid

    nodes = path_node_grid([2.0], [0.0], [89.996])
    assert 89.99 < nodes.view_zenith[0] < 90.0
