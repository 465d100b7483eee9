"""Motion blur (docs/simulation.md#motion-blur): a bright box moving across a dark plate under
a nadir map camera, against the closed form — a streak of speed × exposure, the energy of the
unblurred frame — through ``radscene.Simulation`` and ``radscene.render_sequence``."""

from __future__ import annotations

import copy

import numpy as np
import pytest

import radscene
from radscene.errors import ConfigError

#: The box's speed along +x [m s-1] and the exposure [s]: a streak of 8 m, 8 pixels of 1 m.
SPEED = 200.0
EXPOSURE = 0.04
SAMPLES = 16
#: The box (3 m × 3 m seen from above) is at x = 0.1 m at t = 0.5 s; y = 0.2 m. Its edges never
#: fall on a pixel centre at any sub-instant, so each render sees exactly 9 box pixels.
WIDTH = 3.0
FRAME_T = 0.5
#: The mean of 16 images of the same energy, against one: float64 rounding [-].
ENERGY_REL = 1e-6
#: The streak's length from whole lit pixels, against speed × exposure [px].
STREAK_PX = 1.0


def _scene(blur=None):
    x0 = 0.1 - SPEED * FRAME_T
    scene = {
        "name": "blur",
        "environment": {"sun": {"zenith": 0.0}, "atmosphere": {"type": "none"}},
        "materials": {"dark": {"reflectance": 0.05}, "bright": {"reflectance": 0.9}},
        "objects": [
            {"name": "plate", "shape": {"type": "plate", "width": 600, "length": 600},
             "material": "dark", "temperature": "290 K"},
            {"name": "box", "shape": {"type": "box", "size": [WIDTH, WIDTH, 1.0]}, "material": "bright",
             "temperature": "290 K", "on_ground": False,
             # from 1 s before the start: the first frame's exposure begins before it
             "trajectory": {"waypoints": [[-1.0, x0 - SPEED, 0.2, 0.0], [1.0, x0 + SPEED, 0.2, 0.0]]}},
        ],
        "bands": [{"name": "vis", "min": 0.5, "max": 0.6}],
        "observers": [{"name": "map", "type": "orthographic", "center": [0, 0], "gsd": 1.0,
                       "shape": [32, 32], "altitude": 100}],
        "render": {"sky_samples": 1, "shadows": False, "background_bounces": 0, "adjacency": False},
    }
    if blur is not None:
        scene["render"]["motion_blur"] = blur
    return scene


def _frame(scene):
    return radscene.Simulation(scene).step(FRAME_T).radiance["map"]


@pytest.fixture(scope="module")
def frames():
    sharp = _frame(_scene())
    blurred = _frame(_scene({"samples": SAMPLES, "exposure": f"{EXPOSURE * 1e3:g} ms"}))
    return sharp, blurred


def test_streak_is_speed_times_exposure(frames):
    sharp, blurred = frames
    background = float(sharp.radiance.values[0, 0, 0])
    excess = blurred.radiance.values[0] - background
    lit = np.abs(excess) > 1e-9 * background
    rows = np.flatnonzero(lit.any(axis=1))
    cols = np.flatnonzero(lit.any(axis=0))
    assert len(rows) == WIDTH  # blur along the motion only
    streak = (cols[-1] - cols[0] + 1) - WIDTH  # [px] of 1 m
    assert abs(streak - SPEED * EXPOSURE) <= STREAK_PX
    # the unblurred box: 3 × 3 pixels
    assert np.count_nonzero(np.abs(sharp.radiance.values[0] - background) > 1e-9 * background) == 9
    # the streak is centred on the box at the frame's instant (x = 0.1 m)
    x = blurred.x.values
    centre = float((excess.sum(axis=0) * x).sum() / excess.sum())
    assert centre == pytest.approx(0.1, abs=0.5)


def test_energy_is_kept(frames):
    sharp, blurred = frames
    background = float(sharp.radiance.values[0, 0, 0])
    for name in ("radiance", "sun_diffuse"):
        before = float((sharp[name].values - sharp[name].values[0, 0, 0]).sum())
        after = float((blurred[name].values - blurred[name].values[0, 0, 0]).sum())
        assert before > 100 * background
        assert after == pytest.approx(before, rel=ENERGY_REL)


def test_one_sample_is_the_unblurred_frame(frames):
    sharp, _ = frames
    one = _frame(_scene({"samples": 1, "exposure": "40 ms"}))
    for name in ("radiance", "sun_diffuse", "object_id", "brightness_temperature"):
        np.testing.assert_array_equal(one[name].values, sharp[name].values)


def test_deterministic(frames):
    _, blurred = frames
    again = _frame(_scene({"samples": SAMPLES, "exposure": "40 ms"}))
    np.testing.assert_array_equal(again.radiance.values, blurred.radiance.values)
    assert again.attrs["motion_blur_samples"] == SAMPLES


def test_poses_back_at_the_frame_instant():
    sim = radscene.Simulation(_scene({"samples": 4, "exposure": "40 ms"}))
    sim.step(FRAME_T)
    position, _ = sim.pose("box")
    assert position[0] == pytest.approx(0.1, abs=1e-9)


def test_sequence_blurs_like_the_simulation(frames):
    _, blurred = frames
    scene = _scene({"samples": SAMPLES, "exposure": "40 ms"})
    scene["environment"] = {"time": "2026-06-21T12:00:00Z", "atmosphere": {"type": "none"},
                            "location": {"latitude": 0.0, "longitude": 0.0}}
    scene["time"] = {"start": "2026-06-21T12:00:00Z", "end": "2026-06-21T12:00:00.5Z", "step": 0.25}
    sequence = radscene.render_sequence(copy.deepcopy(scene))
    last = sequence.radiance["map"].radiance.isel(time=-1).values[0]
    background = float(last[0, 0])
    lit = np.abs(last - background) > 1e-9 * background
    cols = np.flatnonzero(lit.any(axis=0))
    assert abs((cols[-1] - cols[0] + 1) - WIDTH - SPEED * EXPOSURE) <= STREAK_PX
    # the last frame, 0.5 s after the first: the box at x = 0.1 m, as in the fixture
    assert cols.mean() == pytest.approx(np.flatnonzero(
        (np.abs(blurred.radiance.values[0] - blurred.radiance.values[0, 0, 0]) > 0).any(axis=0)).mean())


def test_exposure_from_the_sensor_or_given():
    from radscene.pipeline.motion_blur import exposure_offsets

    np.testing.assert_allclose(exposure_offsets(4, 0.008), [-0.003, -0.001, 0.001, 0.003], rtol=0, atol=1e-15)
    assert exposure_offsets(1, 0.01).tolist() == [0.0]
    with pytest.raises(ConfigError, match=r"render.motion_blur.exposure.*no sensor"):
        radscene.Simulation(_scene({"samples": 4}))


def _at_start(blur):
    """The scene with the box at x = 0.1 m at t = 0, the instant of a single render."""
    scene = _scene(blur)
    scene["objects"][1]["trajectory"]["waypoints"] = [[-1.0, 0.1 - SPEED, 0.2, 0.0],
                                                      [1.0, 0.1 + SPEED, 0.2, 0.0]]
    return scene


def test_a_single_render_is_blurred_as_the_first_frame():
    """``radscene.render`` of a scene with ``render.motion_blur`` gives the image a
    simulation's frame at the same instant gives (to 1e-6), a streak, not the sharp box."""
    blur = {"samples": SAMPLES, "exposure": f"{EXPOSURE * 1e3:g} ms"}
    single = radscene.render(_at_start(blur))
    frame = radscene.Simulation(_at_start(blur)).render().radiance["map"]
    np.testing.assert_allclose(single.radiance.values, frame.radiance.values, rtol=1e-6)
    sharp = radscene.render(_at_start(None))
    background = float(sharp.radiance.values[0, 0, 0])
    lit = np.abs(single.radiance.values[0] - background) > 1e-9 * background
    cols = np.flatnonzero(lit.any(axis=0))
    assert abs((cols[-1] - cols[0] + 1) - WIDTH - SPEED * EXPOSURE) <= STREAK_PX
    assert np.count_nonzero(np.abs(sharp.radiance.values[0] - background)
                            > 1e-9 * background) == 9
    assert single.radiance.values.sum() == pytest.approx(sharp.radiance.values.sum(),
                                                         rel=ENERGY_REL)
