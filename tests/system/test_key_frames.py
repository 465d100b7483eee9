"""Key frames (radscene.render.key_frames): the frames between key frames shade only the pixels
something moved through and extrapolate the others in time — or, in a sequence, interpolate
them between the key frame behind and one rendered ahead (radscene.pipeline.look_ahead) —
within KEY_FRAME of the frames shaded in full at their own instant, the labels and positions
exactly."""

from __future__ import annotations

import copy
import sys
from pathlib import Path
from types import SimpleNamespace

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


@pytest.mark.parametrize("lobe", [False, True])
@pytest.mark.parametrize("m", [16, 9, 12])
@pytest.mark.parametrize("far", [False, True])
def test_fans_meet_spheres_matches_the_fans_directions(lobe, m, far):
    """The probe of key frames against the fans' own directions tested one by one: cosine
    and lobe fans, regular grids (16, 9) and another pattern (12), spheres near and far (the
    polar-angle bound that skips most far points, kept_fans._may_meet)."""
    from radscene.render import kernels
    from radscene.render.illumination import _fan_setup
    from radscene.render.kept_fans import fans_meet_spheres, meets_spheres

    rng = np.random.default_rng(1)
    n = 4000
    origins = rng.uniform(-20.0, 20.0, (n, 3))
    normals = rng.normal(size=(n, 3))
    normals /= np.linalg.norm(normals, axis=1)[:, None]
    shift = rng.random((n, 2))
    spheres = np.array([[5.0, 3.0, 8.0, 4.0], [-10.0, 0.0, -2.0, 2.5]])
    if far:
        spheres = np.array([[300.0, -40.0, 25.0, 4.0], [-150.0, 220.0, 3.0, 6.0]])
    axis = rng.normal(size=(n, 3))
    axis /= np.linalg.norm(axis, axis=1)[:, None]
    exponent = rng.uniform(1.0, 80.0, n)
    got = fans_meet_spheres(origins, normals, m, shift, spheres,
                            lobe=(axis, exponent) if lobe else None)
    shift, base, side, pos, nrm = _fan_setup(origins, normals, m, None, shift)
    o32, d32 = kernels.empty_fan(n * m)
    if lobe:
        kernels.lobe_fan(pos, nrm, axis, exponent, np.zeros(3), 0.0, shift, base, side, o32,
                         d32)
    else:
        kernels.cosine_fan(pos, nrm, np.zeros(3), 0.0, shift, base, side, o32, d32)
    want = meets_spheres(np.repeat(origins, m, axis=0), d32.astype(float), spheres)
    np.testing.assert_array_equal(got, want.reshape(n, m).any(axis=1))
    assert 0 < got.sum() < n


# -- a sequence: key frames rendered ahead, the frames between interpolated ------------------

#: Frames interpolated between a key frame and one rendered ahead against frames shaded in
#: full [-]: the scene above measured at most 3.1e-9 for the radiance and 1.1e-8 for cos θ_i
#: (2026-11-26) — the ephemeris's own jitter from frame to frame (its Julian date in float64:
#: 5e-5 s), which the frames shaded in full carry and a line through two key frames does not.
INTERPOLATED = KEY_FRAME


def _sequence(scene, frames, step=STEP):
    """render_sequence of ``scene`` over ``frames`` frames ``step`` [s] apart."""
    import datetime as dt

    start = dt.datetime(2026, 6, 21, 9, tzinfo=dt.UTC)
    return radscene.render_sequence(radscene.load_scene(copy.deepcopy(scene)), start=start,
                                    end=start + dt.timedelta(seconds=step * (frames - 1)),
                                    step=step, progress=False)


def _rendered(ds):
    """A sequence's maps without the frames' wall times."""
    return ds.drop_vars([v for v in ds.data_vars if v == "frame_render_seconds"])


def test_a_sequence_interpolates_between_key_frames_rendered_ahead():
    """render_sequence with key frames (0.2 s apart: frames 0, 5 and the last, 7, rendered
    ahead) against every frame shaded in full; and again, the same to the bit."""
    scene = _scene()
    off = copy.deepcopy(scene)
    off["render"]["key_frames"] = False
    want = _sequence(off, 8)
    got = _sequence(scene, 8)
    for k in range(8):
        frames = [SimpleNamespace(radiance={n: _rendered(ds.isel(time=k))
                                            for n, ds in seq.radiance.items()})
                  for seq in (want, got)]
        _compare(*frames, rtol=INTERPOLATED)
    again = _sequence(scene, 8)
    for name, ds in got.radiance.items():
        for var in _rendered(ds).data_vars:
            np.testing.assert_array_equal(again.radiance[name][var].values, ds[var].values,
                                          err_msg=f"{name}.{var}")


def _wall_scene():
    """A truck driving along a white wall; the sky fan (4 directions) smaller than the
    background's paths (32 a pixel), so that most of a pixel's first rays are drawn beyond
    it and only the key frames' records (radscene.render.background_record) see what moved
    through them."""
    return {
        "name": "wall",
        "environment": {"time": "2026-06-21T09:00:00Z",
                        "location": {"latitude": 45.0, "longitude": 5.0},
                        "atmosphere": {"type": "uniform"}},
        "materials": {"grey": {"reflectance": 0.3}, "white": {"reflectance": 0.8}},
        "terrain": {"type": "flat", "size": [200, 200], "material": "grey",
                    "temperature": "290 K"},
        "objects": [
            {"name": "wall", "shape": {"type": "box", "size": [2, 60, 15]},
             "position": [100, 100, 0], "material": "white", "temperature": "295 K"},
            {"name": "truck", "shape": {"type": "box", "size": [3, 6, 4]},
             "position": [104, 95, 0], "material": "grey", "temperature": "305 K",
             "trajectory": {"waypoints": [[0, 104, 95, 0], [10, 104, 145, 0]],
                            "attitude": "path"}}],
        "bands": [{"name": "vis", "min": 0.5, "max": 0.6}],
        "observers": [{"name": "map", "type": "orthographic", "center": [100, 100],
                       "gsd": 0.75, "shape": [64, 64], "altitude": 1000}],
        "render": {"sky_samples": 4, "specular_samples": 4, "seed": 3,
                   "background_bounces": 1, "background_samples": 32, "key_frames": True,
                   "key_frame_interval": 0.2},
    }


def test_the_background_is_interpolated_where_nothing_moved_through_its_paths():
    """The pixels not shaded take their reflected background interpolated too; those whose
    paths something moved through are shaded (without the records, 0.2 of the radiance
    off)."""
    scene = _wall_scene()
    off = copy.deepcopy(scene)
    off["render"]["key_frames"] = False
    want, got = _sequence(off, 8), _sequence(scene, 8)
    for k in range(8):
        frames = [SimpleNamespace(radiance={n: _rendered(ds.isel(time=k))
                                            for n, ds in seq.radiance.items()})
                  for seq in (want, got)]
        _compare(*frames, rtol=INTERPOLATED)
    keyed = radscene.Simulation(radscene.load_scene(scene))
    keyed.schedule([k * STEP for k in range(8)])
    keyed.render()
    keyed.step(STEP)
    keys = keyed._caches["map"].keys
    assert keys.between == keys.between_background == 1
    assert all(len(key.paths.sample) for key in keys.keys)
    assert 0 < keys.shaded < 64 * 64 / 2


def test_the_record_checksum_tells_which_vertices_the_sun_lit():
    from radscene.render.background_record import PathRecord

    sums = []
    for lit in ([True, False, True], [True, False, True], [False, True, True]):
        record = PathRecord(6)
        bound = record.bind(np.array([5, 1]))  # the call's points 0 and 1: samples 5 and 1
        bound.lit(np.array([0, 0, 1]), np.array([0, 1, 0]), np.array(lit))
        sums.append(record.finish().checksum)
    np.testing.assert_array_equal(sums[0], sums[1])
    assert sums[0][5] != sums[2][5] and sums[0][1] == sums[2][1]
    # sets of lit paths whose keys sum alike ({0, 3} and {1, 2}) are told apart
    pair = []
    for paths in ([0, 3], [1, 2]):
        record = PathRecord(1)
        record.bind(np.array([0])).lit(np.zeros(2, int), np.array(paths), np.ones(2, bool))
        pair.append(int(record.finish().checksum[0]))
    assert pair[0] != pair[1]


def test_the_records_spheres_widen_with_the_suns_turn():
    """A shadow ray recorded along the key frame's sun misses a small sphere just beside it;
    widened by the angle the sun turns, the sphere is met."""
    from types import SimpleNamespace as NS

    from radscene.render.background_record import meeting_samples

    record = NS(origin=np.zeros((1, 3)), direction=np.array([[0.0, 0.0, 1.0]]),
                sample=np.array([7]))
    sphere = np.array([[0.5, 0.0, 1000.0, 0.3]])  # 0.5 m off the ray, 1 km up
    assert len(meeting_samples(record, sphere)) == 0
    assert list(meeting_samples(record, sphere, np.radians(0.05))) == [7]


def test_key_frames_ahead_are_the_frames_at_their_instants():
    """A scheduled simulation: the key frame ahead is rendered once (with its key frame
    behind) and is the frame at its instant; the frames between are interpolated."""
    keyed = radscene.Simulation(radscene.load_scene(_scene()))
    keyed.schedule([k * STEP for k in range(7)])
    keyed.render()
    keys = keyed._caches["map"].keys
    assert [key.elapsed for key in keys.keys] == pytest.approx([0.0, 0.2])
    for _ in range(4):
        keyed.step(STEP)
    assert keys.between == 4 and 0 < keys.shaded < 64 * 64 / 2
    keyed.step(STEP)  # the key frame ahead reached: taken as it was rendered, the next ahead
    assert keys.between == 4
    assert [key.elapsed for key in keys.keys] == pytest.approx([0.2, 0.24])


def test_with_look_ahead_a_sun_that_jumps_makes_every_frame_a_key_frame():
    """Frames an hour apart: no key frame ahead within MAX_SUN_STEP of the sun, so every frame
    is shaded in full, once, at its own instant."""
    scene = _scene(key_frame_interval=7200.0)
    del scene["objects"][0]["trajectory"]
    keyed, every = _simulations(scene)
    keyed.schedule([3600.0 * k for k in range(3)])
    for k in range(3):
        frames = [sim.render() if k == 0 else sim.step(3600.0) for sim in (keyed, every)]
        _compare(frames[1], frames[0], rtol=1e-12)
        assert [key.elapsed for key in keyed._caches["map"].keys.keys] == [3600.0 * k]
    assert keyed._caches["map"].keys.between == 0
    assert not keyed._ahead.stored


def test_with_look_ahead_moved_things_start_the_key_frames_again():
    """A moved camera lets its key frames go, the one ahead with them; a moved object every
    observer's: the frames still match those shaded in full."""
    keyed, every = _simulations(_scene())
    keyed.schedule([k * STEP for k in range(8)])
    for k in range(8):
        for sim in (keyed, every):
            if k == 2:
                sim.set_pose("cam", position=(42.0, 10.0, 50.0))
            if k == 4:
                sim.set_pose("drone", position=(97.0, 95.0, 21.0))
        frames = [sim.render() if k == 0 else sim.step(STEP) for sim in (keyed, every)]
        _compare(frames[1], frames[0], rtol=INTERPOLATED)
        cam = keyed._caches["cam"].keys
        if k == 2:  # the camera moved: a key frame behind, the next rendered ahead
            assert [key.elapsed for key in cam.keys] == pytest.approx([2 * STEP, 7 * STEP])
        if k == 4:  # the drone moved: every observer's key frames from here, and the last
            for cache in keyed._caches.values():
                assert [key.elapsed for key in cache.keys.keys] == pytest.approx(
                    [4 * STEP, 7 * STEP])
    assert keyed._caches["map"].keys.between == 5


def test_the_key_frame_ahead_stays_within_the_heat_balance_step():
    """The key frame ahead: an interval on, brought back within the heat balance's time step
    of the key frame behind; none where the next frame lies in another."""
    from radscene.pipeline.look_ahead import LookAhead

    def segment(t):
        return 0 if t < 0.3 - 1e-9 else 1

    sim = SimpleNamespace(_caches={}, _thermal_segment=segment, _instant=lambda t: None,
                          scene=SimpleNamespace(sun=None))
    ahead = LookAhead(sim, [k * STEP for k in range(20)])
    key = SimpleNamespace(segment=0)
    assert ahead._next_key(0.0, key, 0.2) == pytest.approx(0.2)
    assert ahead._next_key(0.2, key, 0.2) == pytest.approx(0.28)
    assert ahead._next_key(0.28, key, 0.2) is None
    key.segment = 1
    assert ahead._next_key(0.6, key, 0.2) == pytest.approx(0.76)  # the last frame


def test_the_memory_check_counts_the_key_frame_held_ahead():
    from radscene.scene.memory import check_sequence_memory

    observers = [((64, 64), 2, 64 * 64 * 4)]
    limit = (1e15, "test")
    for streamed in (False, True):
        held = [check_sequence_memory(10, observers, limit, streamed=streamed, ahead=ahead)
                for ahead in (False, True)]
        per_frame = check_sequence_memory(11, observers, limit) - check_sequence_memory(
            10, observers, limit)
        assert held[1] - held[0] == pytest.approx(per_frame)
