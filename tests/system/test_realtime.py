"""Real-time frames (radscene.Simulation(realtime=True)) against full renders of the same instant."""

from __future__ import annotations

import numpy as np
import pytest

import radscene
from radscene.errors import ConfigError

#: A key frame runs the full render's kernels on the same tables and random numbers: measured
#: equal to the last bit; allowed 1e-12 relative.
KEY_FRAME_TOLERANCE = 1e-12
#: Terms that real-time frames do not approximate (sun, emission, path) after objects moved,
#: against a full render of the same instant, under a fixed sun [-] (measured 0).
MOVED_TOLERANCE = 1e-12
TERMS = ("sun_diffuse", "sun_specular", "thermal_emission", "sky_reflected", "path_radiance")
#: A uniform atmosphere with a sky, for the reflected sky that real-time frames freeze.
_WL = [0.4, 0.7, 1.0, 3.0, 5.0, 8.0, 14.0]
SKY = {"type": "uniform",
       "transmittance": {"wavelength": _WL, "values": [0.7, 0.85, 0.9, 0.8, 0.75, 0.8, 0.7]},
       "path_radiance": {"wavelength": _WL, "values": [40.0, 13.0, 5.0, 0.2, 0.3, 1.5, 2.0]},
       "sky_radiance": {"wavelength": _WL, "values": [60.0, 20.0, 8.0, 0.5, 0.6, 3.0, 3.5]}}
BANDS = [{"name": "vis", "min": 0.5, "max": 0.6}, {"name": "lwir", "min": 8.0, "max": 12.0}]


def _scene(atmosphere=None, observer=None, bounces=0):
    nadir = {"name": "map", "type": "orthographic", "center": [0, 0], "gsd": 2.0,
             "shape": [48, 48], "altitude": 1000}
    boxes = [{"name": f"box{i}", "shape": {"type": "box", "size": [8, 6, 5]},
              "position": [-30 + 25 * i, 10 - 12 * i, 0], "rotation": [20 * i, 0, 0],
              "material": "white" if i % 2 else "grey", "temperature": f"{300 + 5 * i} K"}
             for i in range(3)]
    return {
        "name": "real-time boxes",
        "environment": {"sun": {"zenith": 40.0, "azimuth": 135.0},
                        "atmosphere": atmosphere or {"type": "none"}},
        "materials": {"grey": {"reflectance": 0.3}, "white": {"reflectance": 0.8}},
        "objects": [{"name": "ground", "shape": {"type": "plate", "width": 400, "length": 400},
                     "material": "grey", "temperature": "290 K"}, *boxes],
        "bands": BANDS,
        "observers": [observer or nadir],
        "render": {"sky_samples": 8, "seed": 3, "background_bounces": bounces,
                   "background_samples": 4},
    }


def _move(sim, k):
    """Frame k's poses: each box along its own line, turning."""
    sim.set_poses({f"box{i}": ((-30 + 25 * i + 1.5 * k, 10 - 12 * i + 0.7 * k * (i - 1), 0.0),
                               (20 * i + 7 * k, 0.0, 0.0)) for i in range(3)})


def _relative(a, b):
    a, b = np.asarray(a, float), np.asarray(b, float)
    return float(np.nanmax(np.abs(a - b) / np.maximum(np.abs(b), 1e-300)))


def _pair(atmosphere=None, observer=None, frames=4, bounces=0):
    """Frames of the same motion, real-time and full."""
    fast = radscene.Simulation(_scene(atmosphere, observer, bounces), realtime=True)
    full = radscene.Simulation(_scene(atmosphere, observer, bounces))
    out = []
    for k in range(frames):
        _move(fast, k)
        _move(full, k)
        out.append((fast.step(0.04).radiance, full.step(0.04).radiance))
    return out


@pytest.mark.parametrize(("atmosphere", "bounces"), [(None, 0), (SKY, 0), (SKY, 1)],
                         ids=["no atmosphere", "sky", "sky and background"])
def test_the_key_frame_equals_the_full_render(atmosphere, bounces):
    fast, full = _pair(atmosphere, frames=1, bounces=bounces)[0]
    name = next(iter(full))
    assert fast[name].attrs["render_mode"] == "realtime"
    layers = ("background_reflected",) if bounces else ()
    assert ("background_reflected" in fast[name]) == bool(bounces)
    for var in (*TERMS, *layers, "radiance", "path_transmittance", "brightness_temperature"):
        assert _relative(fast[name][var], full[name][var]) <= KEY_FRAME_TOLERANCE, var
    for var in ("object_id", "material_id"):
        np.testing.assert_array_equal(fast[name][var], full[name][var])


def test_moved_boxes_without_sky_equal_the_full_render():
    """No atmosphere: nothing that real-time frames freeze is non-zero."""
    for fast, full in _pair(None)[1:]:
        for var in (*TERMS, "radiance", "brightness_temperature"):
            assert _relative(fast["map"][var], full["map"][var]) <= MOVED_TOLERANCE, var
        np.testing.assert_array_equal(fast["map"].object_id, full["map"].object_id)
        np.testing.assert_array_equal(fast["map"].shadow_fraction, full["map"].shadow_fraction)


def test_with_a_sky_only_the_reflected_sky_differs_near_what_moved():
    """The visible sky is the key frame's: a box reflects the sky with the view of it of the
    surface its pixels saw in the key frame, and the ground beside a box keeps the view it
    had then (the box's shade on the sky moves with it in a full render, not here)."""
    fast, full = _pair(SKY)[-1]
    a, b = fast["map"], full["map"]
    for var in ("sun_diffuse", "sun_specular", "thermal_emission", "path_radiance",
                "path_transmittance"):
        assert _relative(a[var], b[var]) <= MOVED_TOLERANCE, var
    sky_error = a.sky_reflected.values - b.sky_reflected.values
    np.testing.assert_allclose(a.radiance.values - b.radiance.values, sky_error, rtol=0,
                               atol=1e-12 * float(b.radiance.max()))
    # measured (frame 4, boxes moved 4.5 m and turned 21 deg): 13 % of the pixels differ, the
    # radiance by up to 23 % (vis) and 19 % (lwir) where a box's side took the ground's view,
    # the image's by 0.26 % and 0.29 % on average
    error = np.abs(a.radiance.values - b.radiance.values) / b.radiance.values
    assert 0.0 < np.mean(error[0] > 1e-9) < 0.2
    assert 0.0 < error.max() < 0.3
    assert error.mean() < 0.005


@pytest.mark.parametrize("observer", [
    None, {"name": "cam", "type": "perspective", "position": [-60, -150, 90],
           "look_at": [0, 0, 0], "fov": 40, "shape": [40, 56]}], ids=["orthographic", "perspective"])
def test_retracing_only_what_moved_gives_every_pixel_traced_again(observer):
    incremental = radscene.Simulation(_scene(SKY, observer), realtime=True)
    everything = radscene.Simulation(_scene(SKY, observer), realtime=True)
    everything._realtime.incremental = False
    traced = []
    for k in range(5):
        _move(incremental, k)
        _move(everything, k)
        a, b = incremental.step(0.04).radiance, everything.step(0.04).radiance
        name = next(iter(a))
        traced.append(a[name].attrs["pixels_traced"])
        for var in a[name].data_vars:
            np.testing.assert_array_equal(a[name][var].values, b[name][var].values, err_msg=var)
    size = a[name].sizes["x"] * a[name].sizes["y"]
    assert traced[0] == size and 0 < max(traced[1:]) < size


def test_shadows_cast_down_hills_are_traced_again_where_they_fall():
    """Boxes flying over hills under a low sun: their shadows fall far below them, on slopes
    the last frame saw (the sweep's floor); retracing only those pixels still gives every
    pixel traced again, and the shadows are there."""
    def scene():
        out = _scene()
        out["environment"]["sun"] = {"zenith": 65.0, "azimuth": 250.0}
        out["objects"] = out["objects"][1:]
        for box in out["objects"]:
            box["on_ground"] = False
        out["terrain"] = {"type": "procedural", "size": [300, 300], "spacing": 5.0,
                          "relief": 40.0, "seed": 2, "material": "grey", "temperature": 290.0}
        out["observers"][0].update(center=[150, 150], gsd=5.0, shape=[60, 60])
        return out

    def move(sim, k):
        sim.set_poses({f"box{i}": ((110 + 30 * i + 2.0 * k, 120 + 10 * i - 1.5 * k, 45.0 + 5 * i),
                                   (15 * k, 0.0, 0.0)) for i in range(3)})

    incremental = radscene.Simulation(scene(), realtime=True)
    everything = radscene.Simulation(scene(), realtime=True)
    everything._realtime.incremental = False
    for k in range(5):
        move(incremental, k)
        move(everything, k)
        a, b = incremental.step(0.04).radiance["map"], everything.step(0.04).radiance["map"]
        for var in a.data_vars:
            np.testing.assert_array_equal(a[var].values, b[var].values, err_msg=var)
    shade = (a.shadow_fraction.values == 1.0) & (a.object_id.values == 0)
    assert shade.sum() > 20 and a.attrs["pixels_traced"] < a.sizes["x"] * a.sizes["y"] / 2


def test_frame_k_is_the_same_in_every_run():
    runs = []
    for _ in range(2):
        sim = radscene.Simulation(_scene(SKY), realtime=True)
        for k in range(3):
            _move(sim, k)
            frame = sim.step(0.04)
        runs.append(frame.radiance["map"])
    for var in runs[0].data_vars:
        np.testing.assert_array_equal(runs[0][var].values, runs[1][var].values, err_msg=var)


def test_the_background_is_the_key_frames_where_a_pixel_sees_the_same_object():
    fast, full = _pair(SKY, bounces=1)[-1]
    a, b = fast["map"], full["map"]
    key = _pair(SKY, frames=1, bounces=1)[0][0]["map"]
    same = (a.object_id.values == key.object_id.values)
    np.testing.assert_array_equal(a.background_reflected.values[:, same],
                                  key.background_reflected.values[:, same])
    assert not a.background_reflected.values[:, ~same].any()
    # measured (frame 4): the background is 0.23 % (vis) and 0.45 % (lwir) of the radiance on
    # average; with it and the sky frozen the radiance differs by 0.45 % and 0.62 % on average
    # and up to 28 % from the full render's
    share = b.background_reflected.values / b.radiance.values
    assert 0.0 < share.mean() < 0.01
    error = np.abs(a.radiance.values - b.radiance.values) / b.radiance.values
    assert error.mean() < 0.01 and error.max() < 0.4


#: The parts of the reflected sky and background, and the layer each pair sums to.
PARTS = {"sky_reflected": ("sky_reflected_solar", "sky_reflected_thermal"),
         "background_reflected": ("background_reflected_solar", "background_reflected_thermal")}
#: A band whose uniform sky (split at 4 um) holds both sunlight and emission.
MWIR = {"name": "mwir", "min": 3.0, "max": 5.0}


def _parts_pair(frames):
    """Real-time and full frames of the boxes' motion with the sky, the background and a band
    whose sky holds both parts."""
    spec = _scene(SKY, bounces=1)
    spec["bands"] = BANDS + [MWIR]
    fast = radscene.Simulation(spec, realtime=True)
    full = radscene.Simulation(spec)
    out = []
    for k in range(frames):
        _move(fast, k)
        _move(full, k)
        out.append((fast.step(0.04).radiance["map"], full.step(0.04).radiance["map"]))
    return out


def test_the_parts_of_the_reflected_sky_and_background_sum_to_their_layers():
    """Each frame writes the four part layers; each pair sums to its layer (to rounding, the
    solar part being the layer less the thermal one); the key frame's parts are the full
    render's, and later frames keep the background's parts where the layer is kept."""
    frames = _parts_pair(3)
    key, full = frames[0]
    for parts in PARTS.values():
        for name in parts:
            assert key[name].dims == ("band", "y", "x"), name
            assert key[name].attrs["units"] == "W m-2 sr-1"
            assert _relative(key[name], full[name]) <= KEY_FRAME_TOLERANCE, name
    for fast, _ in frames:
        for layer, (solar, thermal) in PARTS.items():
            np.testing.assert_allclose(fast[solar].values + fast[thermal].values,
                                       fast[layer].values, rtol=1e-12,
                                       atol=1e-15 * float(fast[layer].max()), err_msg=layer)
        mwir = fast.sel(band="mwir")
        # the band holds both parts of the sky, the others one each
        assert float(mwir.sky_reflected_solar.max()) > 0.0
        assert float(mwir.sky_reflected_thermal.max()) > 0.0
        assert not fast.sel(band="vis").sky_reflected_thermal.values.any()
        assert not fast.sel(band="lwir").sky_reflected_solar.values.any()
        assert float(fast.sel(band="lwir").background_reflected_thermal.max()) > 0.0
    last = frames[-1][0]
    same = last.object_id.values == key.object_id.values
    assert not same.all()
    for name in PARTS["background_reflected"]:
        np.testing.assert_array_equal(last[name].values[:, same], key[name].values[:, same])
        assert not last[name].values[:, ~same].any()


def test_a_frame_kept_by_the_caller_is_not_changed_by_the_next():
    """The part layers are changed in place from frame to frame only where the caller let go
    of the last frame: frames kept and frames let go have the same values."""
    spec = _scene(SKY, bounces=1)
    spec["bands"] = BANDS + [MWIR]
    runs = {}
    for keep in (True, False):
        sim = radscene.Simulation(spec, realtime=True)
        kept, copies = [], []
        for k in range(4):
            _move(sim, k)
            frame = sim.step(0.04).radiance["map"]
            copies.append({n: frame[n].values.copy() for n in PARTS["background_reflected"]
                           + PARTS["sky_reflected"]})
            if keep:
                kept.append(frame)
            del frame
        if keep:  # each kept frame as it was when made
            for frame, values in zip(kept, copies, strict=True):
                for name, value in values.items():
                    np.testing.assert_array_equal(frame[name].values, value, err_msg=name)
        runs[keep] = copies
    for a, b in zip(runs[True], runs[False], strict=True):
        for name in a:
            np.testing.assert_array_equal(a[name], b[name], err_msg=name)


def test_a_frame_without_the_background_has_the_sky_parts_alone():
    fast, full = _pair(SKY, frames=1)[0]
    assert {"sky_reflected_solar", "sky_reflected_thermal"} <= set(fast["map"].data_vars)
    assert "background_reflected_solar" not in fast["map"].data_vars
    for name in PARTS["sky_reflected"]:
        assert _relative(fast["map"][name], full["map"][name]) <= KEY_FRAME_TOLERANCE, name


def test_a_sensor_records_a_real_time_frame_as_a_full_one():
    scene = _scene()
    scene["bands"] = [{"name": "lwir", "min": "8 um", "max": "14 um"}]
    scene["sensors"] = {"bolometer": {"example": "lwir_microbolometer", "detector": {"shape": [16, 16]}}}
    scene["observers"] = [{"name": "ir", "type": "perspective", "position": [0, -300, 60],
                           "look_at": [0, 0, 0], "sensor": "bolometer"}]
    fast = radscene.Simulation(scene, realtime=True).step(0.04).signal["ir"]
    full = radscene.Simulation(scene).step(0.04).signal["ir"]
    np.testing.assert_array_equal(fast["dn"].values, full["dn"].values)


def test_a_moved_observer_gets_a_new_key_frame_equal_to_the_full_render():
    """The new key frame takes the sun of its own instant (10 min after the first)."""
    scene = _scene(SKY)
    scene["environment"].pop("sun")
    scene["environment"].update(time="2026-06-21T09:00:00Z",
                                location={"latitude": 45.0, "longitude": 5.0})
    fast = radscene.Simulation(scene, realtime=True)
    full = radscene.Simulation(scene)
    for sim in (fast, full):
        _move(sim, 2)
        first = sim.step(0.04).radiance["map"]
        sim.set_pose("map", position=(20.0, -10.0, 1000.0))
    a, b = fast.step(600.0).radiance["map"], full.step(600.0).radiance["map"]
    assert a.attrs["pixels_traced"] == a.sizes["x"] * a.sizes["y"]
    assert a.attrs["sun_zenith_deg"] == b.attrs["sun_zenith_deg"] != first.attrs["sun_zenith_deg"]
    for var in (*TERMS, "radiance"):
        assert _relative(a[var], b[var]) <= KEY_FRAME_TOLERANCE, var


def test_set_poses_moves_as_set_pose_does():
    one, many = radscene.Simulation(_scene()), radscene.Simulation(_scene())
    poses = {"box0": ((5.0, 6.0, 1.0), (30.0, 5.0, -3.0)), "box2": ((-7.0, 2.0, 0.0), None),
             "map": ((10.0, 0.0, 900.0), None)}
    for name, (position, attitude) in poses.items():
        one.set_pose(name, position=position, attitude=attitude)
    many.set_poses(poses)
    for name in ("box0", "box1", "box2", "map"):
        for a, b in zip(one.pose(name), many.pose(name), strict=True):
            np.testing.assert_allclose(a, b, rtol=0, atol=1e-12)
    for a, b in zip(one.scene.objects, many.scene.objects, strict=True):
        np.testing.assert_array_equal(a.mesh.vertices, b.mesh.vertices)
    with pytest.raises(ConfigError, match=r"set_poses\[box0\].position"):
        many.set_poses({"box0": ((1.0, np.nan, 0.0), None)})


def test_what_realtime_frames_do_not_render_is_refused():
    scene = _scene()
    scene["observers"][0]["supersample"] = 2
    with pytest.raises(ConfigError, match="realtime: .*supersample 2"):
        radscene.Simulation(scene, realtime=True)
    # band means resolved on a channel grid are not what real-time frames render
    scene = _scene()
    scene["render"] = dict(scene.get("render") or {},
                           spectral_grid={"min": 0.5, "max": 12.0, "step": 0.1})
    with pytest.raises(ConfigError, match="realtime: .*render.spectral_grid is set"):
        radscene.Simulation(scene, realtime=True)


def test_frames_streamed_to_a_file_read_back_as_they_were(tmp_path):
    import datetime as dt

    import xarray as xr

    from radscene.io import FrameStream

    scene = _scene(SKY)
    scene["environment"]["time"] = "2026-06-21T09:00:00Z"
    sim = radscene.Simulation(scene, realtime=True)
    frames = []
    with FrameStream(tmp_path / "run.nc", variables=("radiance", "object_id")) as out:
        for k in range(3):
            _move(sim, k)
            frames.append(sim.step(0.04).radiance["map"])
            out.write(frames[-1])
    with xr.open_dataset(tmp_path / "run.nc", engine="h5netcdf") as ds:
        assert ds.sizes["time"] == 3 and list(ds.band.values) == ["vis", "lwir"]
        for k, frame in enumerate(frames):
            np.testing.assert_array_equal(ds.radiance[k].values, frame.radiance.values)
            np.testing.assert_array_equal(ds.object_id[k].values, frame.object_id.values)
        np.testing.assert_allclose(ds.elapsed.values, [0.04, 0.08, 0.12], rtol=0, atol=1e-12)
        assert ds.time.values[1] - ds.time.values[0] == np.timedelta64(40, "ms")
        assert ds.time.values[0] == np.datetime64(dt.datetime(2026, 6, 21, 9, 0, 0, 40000), "ns")
    with pytest.raises(ConfigError, match="exists"):
        FrameStream(tmp_path / "run.nc")
    with pytest.raises(ConfigError, match="no variable 'radiant'"):
        FrameStream(tmp_path / "other.nc", variables=("radiant",)).write(frames[0])


def test_the_heat_balance_gives_the_key_frames_temperatures_to_every_frame():
    scene = _scene()
    scene["environment"] = {"time": "2026-06-21T09:00:00Z",
                            "location": {"latitude": 45.0, "longitude": 5.0},
                            "atmosphere": {"type": "none"}}
    scene["bands"] = [{"name": "lwir", "min": 8.0, "max": 12.0}]
    scene["observers"][0].update(gsd=20.0, shape=[4, 4])
    scene["objects"] = scene["objects"][:1]
    del scene["objects"][0]["temperature"]
    scene["objects"][0]["material"] = "asphalt"
    scene["thermal"] = {"enabled": True, "start": "2026-06-20T09:00:00+00:00", "step": "30 min", "spin_up": False,
                        "hemisphere_samples": 4}
    fast = radscene.Simulation(scene, thermal_horizon="2 h", realtime=True)
    full = radscene.Simulation(scene, thermal_horizon="2 h")
    key, later = fast.step("1 h").radiance["map"], fast.step("3 h").radiance["map"]
    want = full.step("1 h").radiance["map"]
    np.testing.assert_array_equal(key.surface_temperature.values, want.surface_temperature.values)
    assert _relative(key.radiance, want.radiance) <= KEY_FRAME_TOLERANCE
    # kept: the full render's noon is more than 2 K warmer (test_simulation.py)
    np.testing.assert_array_equal(later.surface_temperature.values, key.surface_temperature.values)
