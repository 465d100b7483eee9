"""A single render shows what moves where its motion puts it at the scene's instant (``t`` = 0 s
of every trajectory and spin): frame ``k`` of a sequence equals a single render at its instant
(docs/simulation.md), for objects on a route over the terrain, on a spline, on a 6-DOF track
file, and a spinning part carried by a moving parent."""

from __future__ import annotations

import numpy as np
import pytest
import xarray as xr
import yaml
from typer.testing import CliRunner

import radscene
from radscene.cli import app
from radscene.pipeline.simulation import render_sequence

START = "2026-06-21T09:00:00+00:00"
#: Frames trace through Embree's two-level scene, single renders through one BVH: the same hits,
#: radiances equal but for float32 rounding [-] (as tests/system/test_sequence.py).
SAME_RENDER = 1e-6
#: Poses are closed-form arithmetic on float64 [m].
EXACT = 1e-9
SLOPE = 5.0  # [deg]
SPEED = 10.0  # the truck's [m s-1]
SPIN = 30.0  # the blade's [deg s-1]


def _track(path, shift):
    """A 6-DOF track [s, m, deg], its times ``shift`` [s] earlier."""
    rows = [(-1.0, 22.4, -30.6, 18.0, 10.0, 0.0, 0.0), (3.0, -21.8, -26.2, 24.0, 50.0, 5.0, 0.0)]
    lines = ["time [s], x [m], y [m], z [m], yaw [deg], pitch [deg], roll [deg]"]
    lines += [", ".join(f"{v:g}" for v in (t - shift, *rest)) for t, *rest in rows]
    path.write_text("\n".join(lines) + "\n")


def _scene_file(tmp_path, shift=0.0, *, sequence=True, name="scene"):
    """A terrain rising east, a truck driven on it at 10 m/s (route, heading along the path,
    pitched by the slope), a drone on a spline, a hub on a track file carrying a spinning
    blade; every time axis ``shift`` [s] earlier and the clock ``shift`` later."""
    import datetime as dt

    x = np.arange(-100.0, 100.1, 5.0)
    xx, _ = np.meshgrid(x, x[::-1])
    instant = dt.datetime.fromisoformat(START) + dt.timedelta(seconds=shift)
    _track(tmp_path / f"{name}.csv", shift)
    spline = [[t - shift, *p] for t, p in ((0.0, (10.2, -20.1, 30.0)), (1.0, (15.3, -18.0, 31.0)),
                                           (2.5, (20.8, -12.2, 33.0)), (4.0, (22.1, -5.3, 34.0)))]
    scene = {
        "name": "instant",
        "environment": {"time": instant.isoformat(), "location": {"latitude": 45.0, "longitude": 5.0},
                        "atmosphere": {"type": "none"}},
        "terrain": {"type": "dem", "elevation": (np.tan(np.radians(SLOPE)) * xx).tolist(), "spacing": [5, 5],
                    "origin": [-100, -100], "material": "grey", "temperature": "290 K"},
        "materials": {"grey": {"reflectance": 0.3}, "paint": {"reflectance": 0.8}},
        "objects": [
            {"name": "truck", "shape": {"type": "box", "size": [2.5, 6, 3]}, "material": "paint",
             "temperature": "300 K", "position": [0.0, -30.0, 0.0],
             "trajectory": {"route": [[-40.3, 10.7, 0.5], [40.3, 10.7, 0.5]], "speed": f"{SPEED} m/s",
                            "start": -shift, "attitude": "path"}},
            {"name": "drone", "shape": {"type": "box", "size": [2, 3, 1]}, "material": "paint",
             "temperature": "300 K", "position": [-30.0, 30.0, 20.0], "on_ground": False,
             "trajectory": {"waypoints": spline, "interpolation": "spline", "attitude": "path"}},
            {"name": "hub", "shape": {"type": "box", "size": [3, 3, 2]}, "material": "grey",
             "temperature": "300 K", "position": [30.0, 30.0, 20.0], "on_ground": False,
             "trajectory": {"file": f"{name}.csv"}},
            {"name": "blade", "shape": {"type": "plate", "width": 1.5, "length": 18}, "material": "paint",
             "temperature": "300 K", "parent": "hub", "position": [0, 0, 1.5],
             "rotation": [-SPIN * shift, 0, 0], "spin": {"axis": [0, 0, 1], "rate": f"{SPIN} deg/s"}},
        ],
        "bands": [{"name": "vis", "min": 0.5, "max": 0.6}],
        "observers": [{"name": "map", "type": "orthographic", "center": [0.25, -0.35], "gsd": 1.0,
                       "shape": [96, 96], "altitude": 1000}],
        "render": {"sky_samples": 4, "seed": 3, "background_bounces": 0},
    }
    if sequence:
        scene["time"] = {"start": START, "end": "2026-06-21T09:00:02+00:00", "step": "1 s"}
    path = tmp_path / f"{name}.yaml"
    path.write_text(yaml.safe_dump(scene))
    return path


def _centre(ds, index):
    """Mean (x, y) [m] of the pixels that see object ``index``, and their number."""
    seen = ds.object_id.values == index
    x = np.broadcast_to(ds.x.values, seen.shape)[seen]
    y = np.broadcast_to(ds.y.values[:, None], seen.shape)[seen]
    return np.array([x.mean(), y.mean()]), int(seen.sum())


def _index(scene, name):
    return next(k for k, o in enumerate(scene.objects) if o.name == name)


def test_a_single_render_places_moving_objects_on_their_trajectories_at_the_scene_instant(tmp_path):
    """The truck stands at its route's start (-40.3, 10.7), not at its ``position`` (0, -30),
    pitched by the slope; the drone at its spline's first point; the hub at its track's point
    of t = 0; the blade on the hub, not yet turned by its spin."""
    scene = radscene.load_scene(_scene_file(tmp_path))
    position, rotation = scene.poses["truck"]
    np.testing.assert_allclose(position, [-40.3, 10.7, np.tan(np.radians(SLOPE)) * -40.3 + 0.5], atol=EXACT)
    np.testing.assert_allclose(rotation[:, 1], [np.cos(np.radians(SLOPE)), 0.0, np.sin(np.radians(SLOPE))],
                               atol=EXACT)  # forward: east, up the slope
    # the mesh stands there: the 2.5 x 6 x 3 m box's centre 1.5 m up its own (tilted) axis
    truck = scene.objects[_index(scene, "truck")].mesh.vertices.mean(axis=0)
    np.testing.assert_allclose(truck, position + 1.5 * rotation[:, 2], atol=EXACT)
    np.testing.assert_allclose(scene.poses["drone"][0], [10.2, -20.1, 30.0], atol=EXACT)
    # the track at t = 0: a quarter of the way from its sample at -1 s to that at 3 s
    np.testing.assert_allclose(scene.poses["hub"][0], [22.4 - 44.2 / 4, -30.6 + 4.4 / 4, 19.5], atol=EXACT)
    hub_position, hub_rotation = scene.poses["hub"]
    blade_position, blade_rotation = scene.poses["blade"]
    np.testing.assert_allclose(blade_position, hub_position + hub_rotation @ [0, 0, 1.5], atol=EXACT)
    np.testing.assert_allclose(blade_rotation, hub_rotation, atol=EXACT)  # no spin yet at t = 0
    ds = radscene.render(scene, "map")
    centre, count = _centre(ds, _index(scene, "truck"))
    assert count > 10
    np.testing.assert_allclose(centre, [-40.3, 10.7], atol=1.0)  # 1 m pixels
    static = np.hypot(np.broadcast_to(ds.x.values, ds.object_id.shape) - 0.0,
                      np.broadcast_to(ds.y.values[:, None], ds.object_id.shape) + 30.0) < 5.0
    assert not np.any(ds.object_id.values[static] == _index(scene, "truck"))


def test_frame_k_of_a_sequence_equals_a_single_render_at_its_instant(tmp_path):
    """Frame 0 of a sequence from the scene's instant equals the single render of the same file
    (radiance, object ids, shadows), by Python and by ``radscene render``; frame 2 (2 s later)
    equals a single render whose clock is 2 s later and whose trajectories, route start and
    blade angle are 2 s earlier — and differs from frame 0."""
    path = _scene_file(tmp_path)
    frames = render_sequence(path).radiance["map"]
    single = radscene.render(radscene.load_scene(_scene_file(tmp_path, sequence=False, name="single")), "map")
    first = frames.isel(time=0)
    np.testing.assert_allclose(first.radiance.values, single.radiance.values, rtol=SAME_RENDER, atol=0)
    np.testing.assert_array_equal(first.object_id.values, single.object_id.values)
    np.testing.assert_array_equal(first.shadow_fraction.values, single.shadow_fraction.values)
    # the command line's single render (no time span in the file)
    out = tmp_path / "out"
    result = CliRunner().invoke(app, ["render", str(tmp_path / "single.yaml"), "-o", str(out), "--no-quicklooks"])
    assert result.exit_code == 0, result.output
    with xr.open_dataset(out / "map.nc", engine="h5netcdf") as cli:
        np.testing.assert_array_equal(cli.object_id.values, single.object_id.values)
        np.testing.assert_allclose(cli.radiance.values, single.radiance.values, rtol=SAME_RENDER, atol=0)
    later = radscene.render(radscene.load_scene(_scene_file(tmp_path, 2.0, sequence=False, name="later")), "map")
    third = frames.isel(time=2)
    np.testing.assert_array_equal(third.object_id.values, later.object_id.values)
    np.testing.assert_allclose(third.radiance.values, later.radiance.values, rtol=SAME_RENDER, atol=0)
    assert float(third.frame_sun_zenith_deg) == later.attrs["sun_zenith_deg"]
    moved = np.mean(third.object_id.values != first.object_id.values)
    assert moved > 0.01  # the objects did move between frames 0 and 2
    truck = _index(radscene.load_scene(path), "truck")
    (x0, y0), _ = _centre(first, truck)
    (x2, y2), _ = _centre(third, truck)
    assert (x2 - x0, y2 - y0) == pytest.approx((2 * SPEED, 0.0), abs=0.5)  # 20 m east over the map


def test_a_trajectory_that_misses_the_scene_instant_is_refused_when_loaded(tmp_path):
    """A single render is t = 0 of every trajectory: waypoints from 5 s on cannot place it."""
    from radscene.errors import ConfigError

    scene = yaml.safe_load(_scene_file(tmp_path, sequence=False).read_text())
    scene["objects"][1]["trajectory"]["waypoints"] = [[5, 0, 0, 30], [10, 10, 0, 30]]
    with pytest.raises(ConfigError, match=r"^objects\[1\]\.trajectory: the clock at 0 s lies outside the "
                                          r"waypoints' 5 - 10 s"):
        radscene.load_scene(scene, base_dir=tmp_path)
