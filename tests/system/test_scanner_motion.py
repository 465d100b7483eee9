"""Scanners see what moves where it is at each pixel's time (radscene.pipeline.scan_motion):
a box driven during a pushbroom's or a whiskbroom's scan comes out stretched along the track
and sheared across it by the closed-form amounts, where a frame camera sees it as it is."""

from __future__ import annotations

import numpy as np
import pytest

import radscene
from radscene.pipeline.scan_motion import compose, motion_groups

START = "2026-06-21T09:00:00+00:00"
ALTITUDE = 1000.0  # [m]
PLATFORM_SPEED = 100.0  # northwards [m s-1]
GSD = 1.0  # [m]
#: The box's velocity [m s-1]: east (across the track) and north (along it).
VX, VY = 30.0, 50.0
LENGTH, WIDTH = 8.0, 4.0  # the box's along- and across-track size [m]


def _scene(observer):
    scanner = {"name": "scan", "type": observer, "shape": [64, 48], "gsd": f"{GSD} m",
               "platform": {"position": [0, 0, ALTITUDE], "velocity": [0, PLATFORM_SPEED, 0]}}
    return {
        "name": "scan-motion",
        "environment": {"time": START, "location": {"latitude": 45.0, "longitude": 5.0},
                        "atmosphere": {"type": "none"}},
        "materials": {"grey": {"reflectance": 0.2}, "paint": {"reflectance": 0.8}},
        "objects": [
            {"name": "ground", "shape": {"type": "plate", "width": 400, "length": 400}, "material": "grey",
             "temperature": "290 K"},
            {"name": "car", "shape": {"type": "box", "size": [WIDTH, LENGTH, 1.5]}, "material": "paint",
             "temperature": "300 K", "position": [0, 0, 0],
             # through (0, 0) at the scene's instant, which is the middle of the scan
             "trajectory": {"waypoints": [[-1, -VX, -VY, 0], [1, VX, VY, 0]]}},
        ],
        "bands": [{"name": "vis", "min": 0.5, "max": 0.6}],
        "observers": [scanner, {"name": "frame", "type": "orthographic", "center": [0, 0], "gsd": GSD,
                                "shape": [64, 48], "altitude": ALTITUDE}],
        "render": {"sky_samples": 1, "shadows": False, "background_bounces": 0},
    }


def _rows_and_shear(ids, car):
    """The rows that see the car, and the slope of its column centroid against the row [px/px]."""
    rows = np.flatnonzero((ids == car).any(axis=1))
    cols = [np.flatnonzero(ids[r] == car).mean() for r in rows]
    return rows, np.polyfit(rows, cols, 1)[0]


@pytest.mark.parametrize("observer", ["pushbroom", "whiskbroom"])
def test_a_car_driven_during_the_scan_is_stretched_and_sheared_by_the_closed_form(observer):
    """The lines sweep north at V = 100 m/s over the ground, the car drives north at 50 m/s:
    the lines pass its 8 m in 8 / (V - 50) = 0.16 s, 16 lines of 0.01 s, twice the 8 lines a
    frame camera gives it. Driving east at 30 m/s it moves 0.3 m, 0.3 pixel, per line, to
    the right of the flight direction, towards lower columns (columns grow to the left): a
    shear of -0.3 pixel per row. Its middle is where it is at the scene's instant, the middle
    of the scan: row 31.5, column 23.5."""
    scene = radscene.load_scene(_scene(observer))
    car = next(k for k, o in enumerate(scene.objects) if o.name == "car")
    ds = radscene.render(scene, "scan")
    ids = ds.object_id.values
    rows, shear = _rows_and_shear(ids, car)
    stretch = LENGTH / ((PLATFORM_SPEED - VY) * (GSD / PLATFORM_SPEED))  # 16 lines
    assert len(rows) == pytest.approx(stretch, abs=1)
    assert shear == pytest.approx(-VX / PLATFORM_SPEED, abs=0.05)
    seen = np.argwhere(ids == car)
    assert seen[:, 0].mean() == pytest.approx(31.5, abs=0.5)
    assert seen[:, 1].mean() == pytest.approx(23.5, abs=0.5)
    assert ds.attrs["scan_time_groups"] > 10
    # the frame camera at the scene's instant: the car as it is, 8 x 4 pixels
    frame = radscene.render(scene, "frame").object_id.values
    frame_rows, frame_shear = _rows_and_shear(frame, car)
    assert len(frame_rows) == LENGTH / GSD
    assert frame_shear == pytest.approx(0.0, abs=1e-9)
    assert (frame == car).sum() == LENGTH * WIDTH / GSD**2
    # the scene is left at its instant: the car's mesh where it was loaded
    np.testing.assert_array_equal(scene.objects[car].mesh.vertices,
                                  radscene.load_scene(_scene(observer)).objects[car].mesh.vertices)


def test_a_sequence_frame_of_a_scanner_is_its_single_render():
    """The simulation's scanner frames take the same groups: frame 0 equals the single render."""
    scene = _scene("pushbroom")
    scene["observers"] = scene["observers"][:1]
    single = radscene.render(radscene.load_scene(scene), "scan")
    frame = radscene.Simulation(radscene.load_scene(scene)).render().radiance["scan"]
    assert frame.attrs["scan_time_groups"] == single.attrs["scan_time_groups"]
    np.testing.assert_array_equal(frame.object_id.values, single.object_id.values)
    np.testing.assert_allclose(frame.radiance.values, single.radiance.values, rtol=1e-6, atol=0)


def test_nothing_moving_during_the_scan_is_one_group():
    group, times = motion_groups(np.linspace(0.0, 1.0, 50), lambda t: np.zeros((3, 3)),
                                 lambda t: np.array([0.0, 0.0, 1000.0]), 0.05)
    assert set(group.tolist()) == {0}
    assert times.tolist() == [0.5]


def test_compose_takes_each_pixel_from_its_part():
    import xarray as xr

    parts = [xr.Dataset({"radiance": (("band", "y", "x"), np.full((1, 2, 3), float(k))),
                         "view_zenith": ((), 10.0 * k)}, attrs={"render_seconds": 1.0}) for k in (1, 2)]
    masks = [np.array([[True, True, True], [False, False, False]]), np.array([[False] * 3, [True] * 3])]
    out = compose(parts, masks)
    np.testing.assert_array_equal(out.radiance.values[0], [[1, 1, 1], [2, 2, 2]])
    np.testing.assert_array_equal(out.view_zenith.values, [[10, 10, 10], [20, 20, 20]])
    assert out.attrs["render_seconds"] == 2.0 and out.attrs["scan_time_groups"] == 2
