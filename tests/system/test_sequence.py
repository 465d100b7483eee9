"""Frame sequences (radscene.pipeline.simulation.render_sequence, ``time: {start, end, step}``,
``radscene render --start --end --step``)."""

from __future__ import annotations

import datetime as dt

import numpy as np
import pytest
import xarray as xr
import yaml
from typer.testing import CliRunner

import radscene
from radscene.cli import app
from radscene.errors import ConfigError
from radscene.pipeline.simulation import frame_times, render_sequence

START = "2026-06-21T07:00:00+00:00"
#: Frames and single renders trace the same rays through Embree scenes built differently
#: (two-level against one BVH): the same hits, radiances equal but for float32 rounding [-].
SAME_RENDER = 1e-6


def _scene():
    return {
        "name": "field",
        "environment": {"time": START, "location": {"latitude": 45.0, "longitude": 5.0},
                        "atmosphere": {"type": "none"}},
        "materials": {"grey": {"reflectance": 0.3}},
        "objects": [{"name": "ground", "shape": {"type": "plate", "width": 200, "length": 200},
                     "position": [0, 0, 0], "material": "grey", "temperature": "290 K"},
                    {"name": "box", "shape": {"type": "box", "size": [10, 10, 8]}, "position": [0, 0, 0],
                     "material": "grey", "temperature": "300 K"}],
        "bands": [{"name": "vis", "min": 0.5, "max": 0.6}],
        "observers": [{"name": "map", "type": "orthographic", "center": [0, 0], "gsd": 4.0, "shape": [16, 16],
                       "altitude": 1000}],
        "render": {"sky_samples": 4, "seed": 2},
        "time": {"start": START, "end": "2026-06-21T09:00:00+00:00", "step": "1 h"},
    }


def test_a_sequence_stacks_frames_that_equal_single_renders_at_their_instants():
    seen = []
    out = render_sequence(_scene(), progress=lambda done, total: seen.append((done, total)))
    ds = out.radiance["map"]
    assert out.signal == {}  # no sensor
    assert seen == [(1, 3), (2, 3), (3, 3)]
    assert ds.radiance.dims == ("time", "band", "y", "x")
    assert ds.object_id.dims == ("time", "y", "x")
    np.testing.assert_array_equal(ds.elapsed.values, [0.0, 3600.0, 7200.0])
    assert str(ds.time.values[2]) == "2026-06-21T09:00:00.000000000"
    for k, hour in enumerate((7, 9)):
        single = dict(_scene(), environment=dict(_scene()["environment"], time=f"2026-06-21T0{hour}:00:00+00:00"))
        want = radscene.render(single, "map")
        got = ds.isel(time=2 * k)
        np.testing.assert_allclose(got.radiance.values, want.radiance.values, rtol=SAME_RENDER)
        np.testing.assert_array_equal(got.shadow_fraction.values, want.shadow_fraction.values)
        assert float(got.frame_sun_zenith_deg) == want.attrs["sun_zenith_deg"]
    # the morning sun climbs: the box's shadow shortens from frame to frame
    shadow = (ds.shadow_fraction > 0.5).sum(dim=("y", "x")).values
    assert shadow[0] > shadow[1] > shadow[2]


def test_frame_times_include_the_end_when_a_step_lands_on_it():
    t0 = dt.datetime(2026, 6, 21, tzinfo=dt.UTC)
    assert len(frame_times(t0, t0 + dt.timedelta(seconds=1), 1 / 3)) == 4
    assert len(frame_times(t0, t0 + dt.timedelta(seconds=1), 0.4)) == 3
    assert frame_times(t0, t0, "40 ms") == [t0]


@pytest.mark.parametrize("change, match", [
    ({"end": "2026-06-21T06:00:00+00:00"}, "time: end 2026-06-21T06:00:00"),
    ({"step": "0 s"}, "time.step"),
    ({"step": "-1 min"}, "time.step"),
    ({"start": "2026-06-21T07:00:00"}, "time.start: a time with a UTC offset"),
])
def test_bad_spans_in_the_scene_file_name_the_key(change, match):
    scene = _scene()
    scene["time"] = dict(scene["time"], **change)
    with pytest.raises(ConfigError, match=match):
        render_sequence(scene)


def test_the_cli_renders_a_sequence_into_one_netcdf_per_observer(tmp_path, one_line_refusal):
    scene = _scene()
    del scene["time"]
    path = tmp_path / "field.yaml"
    path.write_text(yaml.safe_dump(scene))
    out = tmp_path / "out"
    result = CliRunner().invoke(app, ["render", str(path), "-o", str(out), "--start", START,
                                      "--end", "2026-06-21T07:00:01+00:00", "--step", "500 ms"])
    assert result.exit_code == 0, result.output
    ds = xr.open_dataset(out / "map_sequence.nc", engine="h5netcdf")
    assert ds.sizes["time"] == 3
    assert ds.radiance.attrs["units"] == "W m-2 sr-1"
    from PIL import Image

    with Image.open(out / "map_sequence" / "vis.gif") as gif:
        assert gif.size == (16, 16)
        total = 0  # Pillow merges identical frames, adding their durations [ms]
        for k in range(gif.n_frames):
            gif.seek(k)
            total += gif.info["duration"]
        assert total == 3 * 100  # three frames at the default 10 per second
    args = ["render", str(path), "-o", str(out), "--start", START, "--end", "2026-06-21T07:00:01+00:00",
            "--step", "500 ms", "--no-quicklooks"]
    again = CliRunner().invoke(app, args)
    assert again.exit_code == 2 and one_line_refusal(again.output, "map_sequence.nc")  # kept
    assert CliRunner().invoke(app, [*args, "--overwrite"]).exit_code == 0
    bad = CliRunner().invoke(app, ["render", str(path), "-o", str(tmp_path / "bad"), "--start", START,
                                   "--end", "2026-06-21T06:00:00+00:00", "--step", "1 s"])
    assert bad.exit_code == 2
    one_line_refusal(bad.output, "--end: 2026-06-21T06:00:00+00:00 lies before the start")
    assert not (tmp_path / "bad").exists()


def test_an_object_on_waypoints_is_where_the_straight_line_puts_it_in_every_frame(tmp_path):
    """5 m/s east in 2 s frames over 1 m pixels: the roof's 10 x 10 pixels, their centre on
    the straight line within 0.1 pixel in every frame."""
    scene = _scene()
    scene["observers"][0].update(gsd=1.0, shape=[24, 64])
    scene["objects"][1]["trajectory"] = {"waypoints": [[0, -20, 0, 0], [4, 0, 0, 0], [8, 20, 0, 0]]}
    scene["time"] = {"start": START, "end": "2026-06-21T07:00:08+00:00", "step": "2 s"}
    ds = render_sequence(scene).radiance["map"]
    for k in range(ds.sizes["time"]):
        box = ds.object_id.isel(time=k).values == 1
        x = np.broadcast_to(ds.x.values, box.shape)[box]
        assert x.mean() == pytest.approx(-20.0 + 10.0 * k, abs=0.1)  # 1 m pixels: 0.1 pixel
        assert box.sum() == 100
    from PIL import Image

    from radscene.io import band_animations

    (path,) = band_animations(ds, tmp_path, fps=25)
    with Image.open(path) as gif:
        assert gif.n_frames == 5  # the box moves: no two frames alike
        assert gif.info["duration"] == 40


def test_waypoints_out_of_order_or_outrun_are_refused_naming_the_object():
    scene = _scene()
    scene["objects"][1]["trajectory"] = {"waypoints": [[0, 0, 0, 0], [5, 1, 0, 0], [5, 2, 0, 0]]}
    with pytest.raises(ConfigError, match=r"objects\[1\].trajectory: waypoints\[2\]: t = 5 s does not follow"):
        render_sequence(scene)
    scene["objects"][1]["trajectory"] = {"waypoints": [[0, 0, 0, 0], [3600, 10, 0, 0]]}
    with pytest.raises(ConfigError, match=r"objects\[1\].trajectory: the clock at 7200 s lies outside"):
        render_sequence(scene)


def test_animations_refuse_a_frame_rate_gif_cannot_play(tmp_path):
    from radscene.io import band_animations

    ds = render_sequence(_scene()).radiance["map"]
    for fps in (0.0, -1.0, 60.0, float("nan")):
        with pytest.raises(ConfigError, match="fps: must lie in"):
            band_animations(ds, tmp_path, fps=fps)
    assert not list(tmp_path.iterdir())


def test_check_accepts_a_thermal_sequence_without_an_instant_of_its_own(tmp_path):
    """A thermal band (heat balance by default) and a ``time:`` span but no
    ``environment.time``: ``radscene check`` sizes the balance over the sequence's span, as the
    render does, instead of asking for an instant (it refused the scene with exit 2 before)."""
    spec = {
        "name": "span",
        "environment": {"sun": {"zenith": 30.0, "azimuth": 180.0}, "atmosphere": {"type": "none"}},
        "terrain": {"type": "flat", "size": [20, 20], "spacing": 2, "material": "asphalt"},
        "bands": [{"name": "lwir", "min": "8 um", "max": "12 um"}],
        "observers": [{"name": "map", "type": "orthographic", "center": [10, 10], "gsd": 2,
                       "shape": [4, 4], "altitude": 500}],
        "time": {"start": "2024-06-21T12:00:00Z", "end": "2024-06-21T14:00:00Z", "step": "1 h"},
    }
    scene = tmp_path / "span.yaml"
    scene.write_text(yaml.safe_dump(spec))
    result = CliRunner().invoke(app, ["check", str(scene)])
    assert result.exit_code == 0, result.output
    assert "sequence: 3 frames" in result.output
