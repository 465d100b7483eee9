"""Incremental frames (radscene.render.frame_cache): frame k ≥ 1 of a sequence that keeps the
rays nothing moved through equals the frame traced in full — the radiance to 1e-6 relative,
the truth maps exactly — while it traces a fraction of the rays. Every frame shaded at its own
instant (``render.key_frames: false``; with key frames: tests/system/test_key_frames.py)."""

from __future__ import annotations

import copy
import datetime as dt

import numpy as np
import pytest
import yaml

import radscene
from radscene.radiometry.units import parse_quantity

#: Kept rays give the answers of tracing them again, folded in the same order [-].
SAME_FRAME = 1e-6
#: Truth maps: integer labels and per-pixel geometry, compared exactly (the geolocation too:
#: an incremental frame works it out again only for the pixels with a sample traced again).
TRUTH = ("object_id", "material_id", "shadow_fraction", "sky_view_fraction", "cos_incidence",
         "surface_temperature", "range", "latitude", "longitude", "height", "view_zenith",
         "view_azimuth", "sun_zenith", "sun_azimuth")


def _compare(full, incremental):
    """Every observer's radiance layers to SAME_FRAME, the truth maps exactly."""
    for name, want in full.radiance.items():
        got = incremental.radiance[name]
        for var in want.data_vars:
            a, b = want[var].values, got[var].values
            if var in TRUTH:
                np.testing.assert_array_equal(b, a, err_msg=f"{name}.{var}")
            elif a.dtype.kind == "f":
                np.testing.assert_allclose(b, a, rtol=SAME_FRAME, atol=0.0, err_msg=f"{name}.{var}")


def _run(scene, steps, *, between=None, base_dir=None):
    """Step a full-frame and an incremental simulation of ``scene`` in lockstep; ``between(sim,
    k)`` moves things before step k. Returns the incremental simulation, its frames and, per
    frame after the first, the rays it traced again per observer and kind."""
    scene = copy.deepcopy(scene)
    scene["render"]["key_frames"] = False
    sims = [radscene.Simulation(radscene.load_scene(copy.deepcopy(scene), base_dir=base_dir),
                                incremental=flag) for flag in (False, True)]
    traced, kept = [], []
    for k, seconds in enumerate(steps):
        frames = []
        for sim in sims:
            if between is not None:
                between(sim, k)
            frames.append(sim.render() if seconds == 0 else sim.step(seconds))
        kept.append(frames[1])
        if k:
            _compare(*frames)
            traced.append({n: dict(c.traced) for n, c in sims[1]._caches.items()})
    return sims[1], kept, traced


def _demo(supersample=2):
    """The bundled demo at a quarter of its size, without its heat balance, its truck driven
    at 10 m/s along its heading (as benchmarks/bench_motion.py)."""
    path = radscene.example_path("demo")
    scene = yaml.safe_load(path.read_text())
    del scene["thermal"]
    truck = next(o for o in scene["objects"] if o["name"] == "truck")
    x, y, z = (float(parse_quantity(v, "length")) for v in truck["position"])
    heading = np.radians(20.0)
    end = [x + 100.0 * np.sin(heading), y + 100.0 * np.cos(heading)]
    truck["trajectory"] = {"waypoints": [[0.0, x, y, z], [10.0, *end, z]], "attitude": "path"}
    truck["rotation"] = [0, 0, 0]
    for obs in scene["observers"]:
        obs["shape"] = [n // 4 for n in obs["shape"]]
        obs["supersample"] = supersample
        if obs["type"] == "orthographic":
            obs["gsd"] = "6 m"
            obs["center"] = ["690 m", "460 m"]
    scene["render"].update({"sky_samples": 9, "specular_samples": 4, "background_samples": 8})
    return scene, path.parent


@pytest.mark.slow  # about 100 s on 2 cores: make validate runs it
def test_the_demo_with_a_moving_truck_at_supersample_2_equals_full_frames():
    scene, base = _demo()
    sim, _, traced = _run(scene, [0, 0.5, 0.5], base_dir=base)
    for frame in traced:
        for name, setup in ((s.name, s) for s in sim.scene.observers):
            samples = setup.camera.shape[0] * setup.camera.shape[1] * 4
            # the truck is a few dozen samples of each image: most rays are kept
            assert 0 < frame[name]["primary"] < samples / 10
            assert frame[name]["sky"] < samples * 9 / 4


def _terrain_scene():
    return {
        "name": "incremental",
        "environment": {"time": "2026-06-21T09:00:00Z", "location": {"latitude": 45.0, "longitude": 5.0},
                        "atmosphere": {"type": "uniform"}},
        "materials": {"grey": {"reflectance": 0.3},
                      "paint": {"reflectance": 0.6, "specular_reflectance": 0.3, "specular_exponent": 20}},
        "terrain": {"type": "procedural", "size": [200, 200], "spacing": 4, "relief": 10, "seed": 3,
                    "material": "grey", "temperature": "290 K"},
        "objects": [
            {"name": "truck", "shape": {"type": "box", "size": [2.5, 6, 3]}, "position": [80, 100, 0],
             "material": "paint", "temperature": "305 K",
             "trajectory": {"waypoints": [[0, 80, 100, 0], [10, 130, 110, 0]], "attitude": "path"}},
            {"name": "shed", "shape": {"type": "box", "size": [8, 6, 5]}, "position": [110, 110, 0],
             "material": "grey", "temperature": "295 K"},
            {"name": "drone", "shape": {"type": "box", "size": [2, 2, 1]}, "position": [95, 95, 20],
             "on_ground": False, "material": "paint", "temperature": "300 K"},
        ],
        "bands": [{"name": "vis", "min": 0.5, "max": 0.6}, {"name": "lwir", "min": 8, "max": 12}],
        "observers": [
            {"name": "map", "type": "orthographic", "center": [100, 100], "gsd": 1.0, "shape": [64, 64],
             "altitude": 1000, "supersample": 2},
            {"name": "cam", "type": "perspective", "position": [40, 10, 50], "look_at": [100, 100, 0],
             "fov": 40, "shape": [48, 64], "supersample": 2}],
        "render": {"sky_samples": 16, "specular_samples": 16, "seed": 3, "background_bounces": 1,
                   "background_samples": 8},
    }


def test_the_reflected_background_of_moved_objects_equals_full_frames():
    """The background term on, a truck on its trajectory, a drone moved by set_pose and, once,
    the camera moved (its rays change: that frame starts afresh, the next keeps its rays)."""

    def between(sim, k):
        sim.set_pose("drone", position=(95.0 + 3.0 * k, 95.0, 20.0 + k))
        if k == 2:
            sim.set_pose("cam", position=(42.0, 10.0, 50.0))

    _, frames, traced = _run(_terrain_scene(), [0, 0.5, 0.5, 0.5], between=between)
    assert traced[1]["cam"]["primary"] == 48 * 64 * 4  # the camera moved: traced in full
    assert traced[2]["cam"]["primary"] < 48 * 64 * 4 / 4
    assert 0 < traced[2]["map"]["primary"] < 64 * 64 * 4 / 4
    assert float(frames[-1].radiance["map"].background_reflected.max()) > 0.0


def test_the_heat_balance_between_frames_equals_full_frames():
    """With thermal: the temperatures of each frame's instant (they change between the
    frames) and a box moved between them."""
    scene = _terrain_scene()
    scene["terrain"]["material"] = "asphalt"
    del scene["terrain"]["temperature"]
    scene["objects"] = scene["objects"][1:2]  # the shed
    scene["objects"][0]["material"] = "concrete"
    scene["objects"].append({"name": "box", "shape": {"type": "box", "size": [6, 6, 3]},
                             "position": [90, 100, 0], "material": "painted_metal"})
    for obj in scene["objects"]:
        obj.pop("temperature", None)
    scene["thermal"] = {"enabled": True, "start": "2026-06-20T09:00:00+00:00", "step": "30 min", "spin_up": False,
                        "hemisphere_samples": 4, "resolution": "8 m"}
    scene["render"]["background_bounces"] = 0

    def between(sim, k):
        sim.set_pose("box", position=(90.0 + 2.0 * k, 100.0, sim.pose("box")[0][2]))

    _, frames, traced = _run(scene, [0, 600.0, 600.0], between=between)
    first, last = (f.radiance["map"].surface_temperature.values for f in (frames[0], frames[-1]))
    assert np.nanmax(np.abs(last - first)) > 0.1  # the frames' temperatures differ [K]
    assert traced[-1]["map"]["primary"] < 64 * 64 * 4 / 4


def test_render_sequence_incremental_or_not_gives_the_same_frames():
    scene = _terrain_scene()
    scene["observers"] = scene["observers"][:1]
    scene["observers"][0]["shape"] = [24, 24]
    scene["render"].update({"background_bounces": 0, "key_frames": False})
    start = dt.datetime(2026, 6, 21, 9, tzinfo=dt.UTC)
    runs = [radscene.render_sequence(copy.deepcopy(scene), start=start, end=start + dt.timedelta(seconds=1),
                                     step=0.5, progress=False, incremental=flag) for flag in (False, True)]
    want, got = (run.radiance["map"] for run in runs)
    assert got.sizes["time"] == 3
    np.testing.assert_allclose(got.radiance.values, want.radiance.values, rtol=SAME_FRAME, atol=0.0)
    for var in ("object_id", "shadow_fraction", "sky_view_fraction"):
        np.testing.assert_array_equal(got[var].values, want[var].values)
