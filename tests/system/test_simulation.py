"""The step API (radscene.Simulation): the clock, the sun, moved objects and observers, bad input."""

from __future__ import annotations

import datetime as dt

import numpy as np
import pandas as pd
import pytest

import radscene
from radscene.errors import ConfigError

GSD = 2.0  # [m]
START = "2026-06-21T09:00:00+00:00"
LATITUDE, LONGITUDE = 45.0, 5.0
#: The heat balance's solar absorptance is weighted by the sun over the solved span
#: (pipeline._optics), which ends later in the simulation than in a single render [K].
SPAN_TOLERANCE = 1e-3
#: pvlib's SPA and radscene's agree to its stated accuracy (Reda & Andreas 2004) [deg].
SPA_TOLERANCE = 1e-4


def _scene(observers=None):
    nadir = {"name": "map", "type": "orthographic", "center": [0, 0], "gsd": GSD, "shape": [40, 40],
             "altitude": 1000}
    return {
        "name": "moving box",
        "environment": {"time": START, "location": {"latitude": LATITUDE, "longitude": LONGITUDE},
                        "atmosphere": {"type": "none"}},
        "materials": {"grey": {"reflectance": 0.3}, "white": {"reflectance": 0.8}},
        "objects": [
            {"name": "ground", "shape": {"type": "plate", "width": 400, "length": 400},
             "position": [0, 0, 0], "material": "grey", "temperature": "290 K"},
            {"name": "box", "shape": {"type": "box", "size": [10, 10, 4]}, "position": [-20, 0, 0],
             "material": "white", "temperature": "300 K"},
        ],
        "bands": [{"name": "vis", "min": 0.5, "max": 0.6}],
        "observers": observers or [nadir],
        "render": {"sky_samples": 4, "seed": 1},
    }


def _box_pixels(ds, box_id=1):
    rows, cols = np.nonzero(ds.object_id.values == box_id)
    return rows, cols


def test_a_box_moved_10_m_between_steps_moves_10_m_per_gsd_pixels():
    sim = radscene.Simulation(_scene())
    first = sim.step("40 ms").radiance["map"]
    rows0, cols0 = _box_pixels(first)
    assert len(cols0) == (10 / GSD) ** 2  # the 10 m square roof, whole pixels
    sim.set_pose("box", position=(-10.0, 0.0, 0.0))
    second = sim.step(0.04).radiance["map"]
    rows1, cols1 = _box_pixels(second)
    assert len(cols1) == len(cols0)
    assert cols1.min() - cols0.min() == 10.0 / GSD  # east is +column
    assert cols1.max() - cols0.max() == 10.0 / GSD
    np.testing.assert_array_equal(np.unique(rows1), np.unique(rows0))
    shift = second.x.values[cols1].mean() - first.x.values[cols0].mean()
    assert shift == pytest.approx(10.0, abs=1e-9)


def test_an_attitude_turns_the_box_about_its_centre():
    sim = radscene.Simulation(_scene())
    sim.set_pose("box", position=(0.0, 0.0, 0.0), attitude=(45.0, 0.0, 0.0))
    position, attitude = sim.pose("box")
    np.testing.assert_array_equal(attitude, [45.0, 0.0, 0.0])
    mesh = sim.scene.objects[1].mesh
    half_diagonal = 5.0 * np.sqrt(2.0)
    assert mesh.vertices[:, 0].max() == pytest.approx(half_diagonal, rel=1e-12)
    assert mesh.vertices[:, 1].max() == pytest.approx(half_diagonal, rel=1e-12)
    # only the attitude given: the position stays
    sim.set_pose("box", attitude=(0.0, 0.0, 0.0))
    np.testing.assert_array_equal(sim.pose("box")[0], position)
    assert mesh.vertices[:, 0].max() != pytest.approx(sim.scene.objects[1].mesh.vertices[:, 0].max())


def test_the_sun_advances_as_pvlib_says_for_the_step():
    from pvlib.atmosphere import alt2pres
    from pvlib.solarposition import spa_python

    sim = radscene.Simulation(_scene())
    frames = [sim.step("1 s"), sim.step("30 min")]
    start = dt.datetime.fromisoformat(START)
    times = pd.DatetimeIndex([start + dt.timedelta(seconds=1), start + dt.timedelta(seconds=1801)])
    spa = spa_python(times, LATITUDE, LONGITUDE, altitude=0.0, pressure=float(alt2pres(0.0)),
                     temperature=12.0, delta_t=67.0)
    zenith = [f.radiance["map"].attrs["sun_zenith_deg"] for f in frames]
    np.testing.assert_allclose(zenith, spa["zenith"].values, rtol=0, atol=SPA_TOLERANCE)
    assert zenith[0] - zenith[1] > 4.0  # a morning half hour raises the sun by several degrees
    assert sim.time == start.astimezone(dt.UTC) + dt.timedelta(seconds=1801)
    assert sim.elapsed == 1801.0
    assert frames[1].radiance["map"].attrs["time"] == sim.time.isoformat()


def test_moving_an_observer_moves_the_view():
    down = {"name": "cam", "type": "perspective", "position": [-20, 0, 200], "attitude": [0, -90, 0],
            "fov": 10.0, "shape": [41, 41]}
    nadir = {"name": "map", "type": "orthographic", "center": [0, 0], "gsd": GSD, "shape": [40, 40],
             "altitude": 1000}
    sim = radscene.Simulation(_scene([nadir, down]))
    frame = sim.step(1.0)
    cam = frame.radiance["cam"].object_id.values
    assert cam[20, 20] == 1  # the box under the camera
    np.testing.assert_array_equal(cam, cam[:, ::-1])  # centred: symmetric
    # the map camera 10 m east: the box 10 m / GSD columns further west in its image
    cols0 = _box_pixels(frame.radiance["map"])[1]
    sim.set_pose("map", position=(10.0, 0.0, 1000.0))
    sim.set_pose("cam", position=(60.0, 0.0, 200.0))  # the box leaves the 35 m wide view
    frame = sim.step(1.0)
    assert _box_pixels(frame.radiance["map"])[1].min() == cols0.min() - 10.0 / GSD
    assert not np.any(frame.radiance["cam"].object_id.values == 1)
    np.testing.assert_array_equal(sim.pose("cam")[1], [0.0, -90.0, 0.0])


@pytest.mark.parametrize("dt_value, match", [
    (0.0, "dt: must be a positive finite duration"),
    (-1.0, "dt: must be a positive finite duration"),
    ("forty ms", "dt"),
    ("3 furlongs", "dt"),
    (True, "dt: a duration is a number"),
])
def test_bad_steps_are_refused_naming_dt(dt_value, match):
    sim = radscene.Simulation(_scene())
    with pytest.raises(ConfigError, match=match):
        sim.step(dt_value)
    assert sim.elapsed == 0.0


def test_bad_poses_are_refused_naming_the_key():
    sim = radscene.Simulation(_scene())
    with pytest.raises(ConfigError, match=r"set_pose.name: unknown name 'truck'; objects: ground, box; observers: map"):
        sim.set_pose("truck", position=(0, 0, 0))
    with pytest.raises(ConfigError, match="set_pose.position: three values"):
        sim.set_pose("box", position=(0, 0))
    with pytest.raises(ConfigError, match=r"set_pose.attitude\[1\]"):
        sim.set_pose("box", attitude=(0, "north", 0))
    with pytest.raises(ConfigError, match="set_pose.attitude: .*orthographic"):
        sim.set_pose("map", attitude=(0, 0, 0))


def test_the_heat_balance_gives_each_frame_the_temperatures_of_its_instant():
    """Frame k of a stepped thermal scene carries the temperatures that a single render at that
    instant carries (the same heat balance span), and they change between the frames."""
    scene = _scene([{"name": "map", "type": "orthographic", "center": [0, 0], "gsd": 20.0,
                     "shape": [4, 4], "altitude": 1000}])
    scene["bands"] = [{"name": "lwir", "min": 8.0, "max": 12.0}]
    del scene["objects"][0]["temperature"]
    scene["objects"][0]["material"] = "asphalt"
    scene["thermal"] = {"enabled": True, "start": "2026-06-20T09:00:00+00:00", "step": "30 min", "spin_up": False,
                        "hemisphere_samples": 4}
    sim = radscene.Simulation(scene, thermal_horizon="2 h")
    frames = [sim.step("1 h"), sim.step("3 h")]  # the second runs past the first solution
    for frame in frames:
        single = dict(scene, environment=dict(scene["environment"], time=frame.time.isoformat()))
        want = radscene.render(single, "map")
        np.testing.assert_allclose(frame.radiance["map"].surface_temperature.values, want.surface_temperature.values,
                                   rtol=0, atol=SPAN_TOLERANCE)
    morning, noon = (float(f.radiance["map"].surface_temperature.values[0, 0]) for f in frames)
    assert noon - morning > 2.0  # asphalt in the June sun warms by more than 2 K from 10 to 13 h


def test_a_moved_box_takes_its_shadow_along():
    """The box's shadow on the ground (lit fraction < 0.5, the box itself excluded) moves the
    same 10 m / GSD columns as the box, and keeps its area."""
    sim = radscene.Simulation(_scene())
    frames = [sim.step(1.0)]
    sim.set_pose("box", position=(-10.0, 0.0, 0.0))
    frames.append(sim.step(1.0))
    cols, areas = [], []
    for frame in frames:
        ds = frame.radiance["map"]
        shade = (ds.shadow_fraction.values > 0.5) & (ds.object_id.values == 0)
        cols.append(np.nonzero(shade)[1])
        areas.append(int(shade.sum()))
    assert areas[0] > 0
    # the sun moves by a few thousandths of a degree in 1 s: the same shadow, shifted
    assert areas[1] == areas[0]
    assert cols[1].min() - cols[0].min() == 10.0 / GSD
    assert cols[1].max() - cols[0].max() == 10.0 / GSD


def _sensor_scene():
    return {
        "name": "thermal",
        "environment": {"time": START, "location": {"latitude": LATITUDE, "longitude": LONGITUDE},
                        "atmosphere": {"type": "none"}},
        "objects": [
            {"name": "ground", "shape": {"type": "plate", "width": 2000, "length": 2000},
             "material": "dry_grass", "temperature": "295 K"},
            {"name": "truck", "shape": {"type": "box", "size": [3, 8, 3]}, "position": [0, 0, 0],
             "material": "painted_metal", "temperature": "330 K"},
        ],
        "bands": [{"name": "lwir", "min": "8 um", "max": "14 um"}],
        "sensors": {"bolometer": {"example": "lwir_microbolometer", "detector": {"shape": [16, 16]}}},
        "observers": [{"name": "ir", "type": "perspective", "position": [0, -300, 60], "look_at": [0, 0, 0],
                       "sensor": "bolometer"}],
        "render": {"sky_samples": 4, "seed": 5},
    }


def test_a_sensor_records_every_frame_with_its_own_noise():
    from radscene.pipeline.simulation import render_sequence

    sim = radscene.Simulation(_sensor_scene())
    first, second = sim.step(0.04), sim.step(0.04)
    dn = [f.signal["ir"]["dn"].isel(frame=0, band=0).values for f in (first, second)]
    assert dn[0].shape == (16, 16)
    assert dn[0][8, 8] > dn[0][8, 0]  # the hot truck in the middle
    assert not np.array_equal(dn[0], dn[1])  # the same scene, a new noise draw
    # the same seed and frame numbers: the same signal again
    again = radscene.Simulation(_sensor_scene())
    np.testing.assert_array_equal(again.step(0.04).signal["ir"]["dn"].isel(frame=0, band=0).values, dn[0])
    scene = dict(_sensor_scene(), time={"start": START, "end": "2026-06-21T09:00:00.08+00:00", "step": "40 ms"})
    out = render_sequence(scene)
    assert out.signal["ir"]["dn"].dims[:2] == ("time", "frame")
    assert out.signal["ir"].sizes["time"] == 3
