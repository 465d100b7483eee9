"""Key frames (radscene.render.key_frames): the frames between key frames shade only the pixels
something moved through and extrapolate the others in time — within KEY_FRAME of the frames
shaded in full at their own instant, the labels and positions exactly."""

from __future__ import annotations

import copy
import sys
from pathlib import Path

import numpy as np
import pytest

import radscene

sys.path.insert(0, str(Path(__file__).parent))
from test_incremental_frames import _terrain_scene  # noqa: E402

#: Frames between key frames against frames shaded in full, relative to the pixel's radiance
#: [-]: the scene below (uniform atmosphere, fixed temperatures, the sun of its date, a moving
#: truck, 0.2 s between key frames) measured at most 2.3e-9 (2026-11-26). The demo with the
#: heat balance differs by more, through the emission's 1 mK temperature grouping of the frames
#: shaded in full (docs/simulation.md, "Key frames").
KEY_FRAME = 1e-7
#: Truth maps compared exactly: what a pixel sees does not change between key frames.
EXACT = ("object_id", "material_id", "range", "latitude", "longitude", "height", "view_zenith",
         "view_azimuth")
STEP = 0.04


def _scene(**render):
    scene = _terrain_scene()
    scene["render"].update({"key_frames": True, "key_frame_interval": 0.2, **render})
    return scene


def _compare(want, got, rtol=KEY_FRAME):
    """The labels exactly; the radiance and its terms to ``rtol`` of the pixel's radiance;
    every other number (the truth maps, brightness temperatures) to ``rtol`` of itself."""
    for name, a in want.radiance.items():
        b = got.radiance[name]
        scale, units = np.abs(a.radiance.values), a.radiance.attrs.get("units")
        for var in a.data_vars:
            x, y = a[var].values, b[var].values
            if var in EXACT:
                np.testing.assert_array_equal(y, x, err_msg=f"{name}.{var}")
            elif a[var].dims == a.radiance.dims and a[var].attrs.get("units") == units:
                same = (np.abs(y - x) <= rtol * scale) | (np.isnan(x) & np.isnan(y))
                assert same.all(), f"{name}.{var}: {np.nanmax(np.abs(y - x) / scale):.2e}"
            elif x.dtype.kind == "f":
                np.testing.assert_allclose(y, x, rtol=rtol, atol=0.0, err_msg=f"{name}.{var}")


def _simulations(scene):
    """A simulation with key frames and one without (the default)."""
    off = copy.deepcopy(scene)
    off["render"]["key_frames"] = False
    return [radscene.Simulation(radscene.load_scene(copy.deepcopy(s))) for s in (scene, off)]


def test_frames_between_key_frames_match_frames_shaded_in_full():
    keyed, every = _simulations(_scene())
    for k in range(10):
        frames = [sim.render() if k == 0 else sim.step(STEP) for sim in (keyed, every)]
        _compare(frames[1], frames[0])
    keys = keyed._caches["map"].keys
    # key frames 0 and 5 (0.2 s apart); 1 to 4 shaded in full; 6 to 9 between
    assert keys.between == 4
    assert [key.elapsed for key in keys.keys] == pytest.approx([0.0, 0.2])
    assert 0 < keys.shaded < 64 * 64 / 2  # the truck's pixels, its shadow's, fans through it
    assert every._caches["map"].keys is None


def test_frame_k_matches_a_single_render_at_its_instant():
    scene = _scene()
    keyed = radscene.Simulation(radscene.load_scene(copy.deepcopy(scene)))
    keyed.render()
    for _ in range(8):
        frame = keyed.step(STEP)
    assert keyed._caches["cam"].keys.between == 3
    single = radscene.Simulation(radscene.load_scene(copy.deepcopy(scene)), incremental=False)
    _compare(single.step(8 * STEP), frame)


def test_a_sun_that_jumps_makes_every_frame_a_key_frame():
    """Frames an hour apart: the sun turns by about 15 deg a frame, more than MAX_SUN_STEP,
    so nothing is extrapolated and the frames equal the frames shaded in full."""
    scene = _scene(key_frame_interval=7200.0)
    del scene["objects"][0]["trajectory"]  # the truck stands: its path lasts 10 s
    keyed, every = _simulations(scene)
    for k in range(4):
        frames = [sim.render() if k == 0 else sim.step(3600.0) for sim in (keyed, every)]
        _compare(frames[1], frames[0], rtol=1e-12)
    assert keyed._caches["map"].keys.between == 0


def test_a_moved_camera_starts_its_key_frames_again():
    keyed, every = _simulations(_scene())
    for k in range(10):
        for sim in (keyed, every):
            if k == 7:
                sim.set_pose("cam", position=(42.0, 10.0, 50.0))
        frames = [sim.render() if k == 0 else sim.step(STEP) for sim in (keyed, every)]
        _compare(frames[1], frames[0])
    # key frames 0 and 5, 6 between; the move: a key frame at 7, 8 and 9 shaded in full
    assert keyed._caches["cam"].keys.between == 1
    assert keyed._caches["map"].keys.between == 4


def test_fans_meet_spheres_matches_the_fans_directions():
    """The probe of key frames against the fans' own directions tested one by one."""
    from radscene.render import kernels
    from radscene.render.illumination import _fan_setup
    from radscene.render.kept_fans import fans_meet_spheres, meets_spheres

    rng = np.random.default_rng(1)
    n, m = 500, 16
    origins = rng.uniform(-20.0, 20.0, (n, 3))
    normals = rng.normal(size=(n, 3))
    normals /= np.linalg.norm(normals, axis=1)[:, None]
    shift = rng.random((n, 2))
    spheres = np.array([[5.0, 3.0, 8.0, 4.0], [-10.0, 0.0, -2.0, 2.5]])
    got = fans_meet_spheres(origins, normals, m, shift, spheres)
    shift, base, side, pos, nrm = _fan_setup(origins, normals, m, None, shift)
    o32, d32 = kernels.empty_fan(n * m)
    kernels.cosine_fan(pos, nrm, np.zeros(3), 0.0, shift, base, side, o32, d32)
    want = meets_spheres(np.repeat(origins, m, axis=0), d32.astype(float), spheres)
    np.testing.assert_array_equal(got, want.reshape(n, m).any(axis=1))
    assert 0 < got.sum() < n
