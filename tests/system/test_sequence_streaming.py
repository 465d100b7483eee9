"""Frame sequences written to disk frame by frame (``render_sequence(..., output=...)``,
``radscene render`` of a ``time:`` span): the files equal the in-memory sequence written whole,
the memory needed does not grow with the number of frames, a stopped run leaves no file, and a
disk too small is refused before the first frame."""

from __future__ import annotations

import datetime as dt
import itertools
import json
import signal
import subprocess
import sys
import textwrap
import time

import numpy as np
import pytest
import xarray as xr
import yaml
from typer.testing import CliRunner

import radscene
from radscene.cli import app
from radscene.errors import ConfigError
from radscene.io import write_netcdf, write_zarr
from radscene.io.run_record import MANIFEST, MARKER
from radscene.pipeline.simulation import render_sequence
from radscene.scene import memory

START = "2026-06-21T09:00:00+00:00"
#: Variables that time the render: they differ from run to run.
TIMINGS = ("frame_render_seconds",)


def _scene(frames=3):
    """A box driven across a nadir map and a perspective camera with a sensor, 40 ms frames."""
    end = (dt.datetime.fromisoformat(START) + dt.timedelta(milliseconds=40 * (frames - 1))).isoformat()
    return {
        "name": "stream",
        "environment": {"time": START, "location": {"latitude": 45.0, "longitude": 5.0},
                        "atmosphere": {"type": "none"}},
        "materials": {"grey": {"reflectance": 0.3}, "white": {"reflectance": 0.8}},
        "objects": [
            {"name": "ground", "shape": {"type": "plate", "width": 400, "length": 400},
             "position": [0, 0, 0], "material": "grey", "temperature": "290 K"},
            {"name": "box", "shape": {"type": "box", "size": [10, 10, 4]}, "material": "white",
             "temperature": "300 K",
             "trajectory": {"waypoints": [[0, -20, 0, 0], [10, 80, 0, 0]]}},
        ],
        "bands": [{"name": "vis", "min": 0.5, "max": 0.6}, {"name": "lwir", "min": "8 um", "max": "12 um"}],
        "sensors": {"bolometer": {"example": "lwir_microbolometer", "detector": {"shape": [12, 12]}}},
        "observers": [
            {"name": "map", "type": "orthographic", "center": [0, 0], "gsd": 2.0, "shape": [20, 24],
             "altitude": 1000},
            {"name": "ir", "type": "perspective", "position": [0, -300, 60], "look_at": [0, 0, 0],
             "sensor": "bolometer", "bands": ["lwir"]},
        ],
        "render": {"sky_samples": 4, "seed": 3},
        "time": {"start": START, "end": end, "step": "40 ms"},
    }


def _same_attrs(got: dict, want: dict) -> bool:
    return got.keys() == want.keys() and all(
        np.array_equal(np.asarray(got[k]), np.asarray(want[k])) for k in want)


def _assert_same(got: xr.Dataset, want: xr.Dataset):
    """Every variable and coordinate equal to 0 difference (NaN where NaN), every attribute
    equal; the render's timings excepted."""
    assert set(got.variables) == set(want.variables)
    assert set(got.coords) == set(want.coords)
    assert dict(got.sizes) == dict(want.sizes)
    assert _same_attrs(got.attrs, want.attrs)
    for name, var in want.variables.items():
        if name in TIMINGS:
            continue
        other = got[name].variable
        assert other.dims == var.dims, name
        assert other.dtype == var.dtype, name
        assert _same_attrs(other.attrs, var.attrs), (name, other.attrs, var.attrs)
        if var.dtype.kind in "fc":
            np.testing.assert_array_equal(other.values, var.values, err_msg=name)
        else:
            assert np.array_equal(other.values, var.values), name


@pytest.mark.parametrize("folder, writer, ext", [("out", write_netcdf, ".nc"),
                                                 ("out.zarr", write_zarr, ".zarr")])
def test_a_streamed_sequence_equals_the_one_held_in_memory(tmp_path, folder, writer, ext):
    held = render_sequence(_scene(), progress=False)
    seen = []
    streamed = render_sequence(_scene(), progress=lambda done, total: seen.append(done),
                               output=tmp_path / folder)
    assert seen == [1, 2, 3]
    assert sorted(p.name for p in (tmp_path / folder).iterdir()) == sorted(
        [f"map_sequence{ext}", f"ir_sequence{ext}", f"ir_signal_sequence{ext}"])
    assert set(streamed.radiance) == {"map", "ir"} and set(streamed.signal) == {"ir"}
    for kind, name, stem in (("radiance", "map", "map_sequence"), ("radiance", "ir", "ir_sequence"),
                             ("signal", "ir", "ir_signal_sequence")):
        want_path = writer(getattr(held, kind)[name], tmp_path / "whole" / f"{stem}{ext}")
        with xr.open_dataset(want_path, engine="zarr" if ext == ".zarr" else "h5netcdf") as want:
            got = getattr(streamed, kind)[name]
            _assert_same(got, want)
            # and the values held in memory, as the file stores them (float32 image layers)
            memory_ds = getattr(held, kind)[name]
            for var in ("radiance", "dn", "elapsed", "frame_sun_zenith_deg", "latitude"):
                if var in memory_ds.variables:
                    stored = got[var].values
                    np.testing.assert_array_equal(
                        stored, memory_ds[var].values.astype(stored.dtype), err_msg=var)
            got.close()
    assert streamed.radiance["map"].sizes["time"] == 3
    assert streamed.radiance["map"].attrs["frames"] == 3


def test_an_angle_map_after_one_value_rewrites_the_frames_so_far(tmp_path):
    """A view angle that the first frames hold as one value and a later one as a map (an image
    that sees nothing but sky in that frame, say): the file holds the map in every frame, the
    value spread over it, as the stack in memory does."""
    from radscene.io.sequence_file import SequenceWriter
    from radscene.pipeline.simulation import _sequence_attrs, _stack

    def layer(k, as_map):
        value = 10.0 + k
        angle = (("time", "y", "x"), np.where(np.eye(3, 4, dtype=bool), np.nan, value)[None],
                 {"units": "degree", "m": 1}) if as_map else (("time",), [value], {"units": "degree"})
        return xr.Dataset({"radiance": (("time", "y", "x"), np.full((1, 3, 4), float(k))),
                           "view_zenith": angle, "elapsed": (("time",), [float(k)])},
                          coords={"time": [np.datetime64("2026-01-01T00:00:00", "ns") + k],
                                  "y": [0.0, 1.0, 2.0], "x": [0.0, 1.0, 2.0, 3.0]},
                          attrs={"title": "t"})

    for pattern, (ext, writer, engine) in itertools.product(
            ((False, False, True, False), (True, False, True, False)),
            ((".nc", write_netcdf, "h5netcdf"), (".zarr", write_zarr, "zarr"))):
        layers = [layer(k, m) for k, m in enumerate(pattern)]
        want = _stack([ds.copy() for ds in layers])
        if not pattern[0]:  # the value over the map
            assert np.all(want.view_zenith.isel(time=0).values == 10.0)
        path = tmp_path / f"{'-'.join(map(str, pattern))}{ext}"
        times = np.array([ds["time"].values[0] for ds in layers])
        with SequenceWriter(path, times) as out:
            for ds in layers:
                ds = ds.copy()
                _sequence_attrs(ds)  # as the stack gives them
                out.append(ds)
        with xr.open_dataset(writer(want, tmp_path / f"whole{ext}"), engine=engine) as whole, \
                xr.open_dataset(path, engine=engine) as got:
            _assert_same(got, whole)
        assert not [p for p in tmp_path.iterdir() if p.name.startswith(".")]


def test_a_failed_stream_leaves_no_file(tmp_path):
    from radscene.io.sequence_file import SequenceWriter

    ds = xr.Dataset({"a": (("time", "x"), [[1.0, 2.0]])}, coords={"time": [0.0]})
    for name in ("s.nc", "s.zarr"):
        with pytest.raises(RuntimeError, match="stop"), SequenceWriter(tmp_path / name) as out:
            out.append(ds)
            raise RuntimeError("stop")
    assert list(tmp_path.iterdir()) == []


def test_the_streamed_memory_estimate_does_not_grow_with_the_frames():
    observers = [((480, 640), 3, 480 * 640 * 4), ((800, 800), 3, 800 * 800)]
    limit = (1e15, "test")
    streamed = [memory.check_sequence_memory(n, observers, limit, streamed=True)
                for n in (1, 100, 100_000)]
    assert streamed[0] == streamed[1] == streamed[2]
    held = [memory.check_sequence_memory(n, observers, limit) for n in (1, 100)]
    assert held[1] > 50 * held[0] / 2
    # one frame of each observer and the frame caches, over the base
    per_frame = sum(r * c * (memory.FRAME_PIXEL_BYTES + 3 * memory.FRAME_PIXEL_BAND_BYTES)
                    for (r, c), _, _ in observers)
    cache = memory.FRAME_CACHE_SAMPLE_BYTES * sum(s for *_, s in observers)
    assert streamed[0] == pytest.approx(memory.BASE_BYTES + memory.STREAMED_FRAMES * per_frame + cache)
    render = memory.BASE_BYTES + 2e9  # beside the largest render
    assert memory.check_sequence_memory(7, observers, limit, streamed=True, render=render) == \
        pytest.approx(render + memory.STREAMED_FRAMES * per_frame + cache)


def _cli_scene(tmp_path, frames, shape=(64, 64)):
    scene = _scene(frames)
    scene["observers"] = [dict(scene["observers"][0], shape=list(shape))]
    path = tmp_path / f"scene{frames}.yaml"
    path.write_text(yaml.safe_dump(scene))
    return path


def test_a_sequence_refused_in_memory_is_streamed_by_the_cli(tmp_path):
    """A limit that holds about four 64 x 64 frames: six frames held in memory are refused,
    and ``radscene render`` streams them (its render, two frames and the frame cache)."""
    per_frame = 64 * 64 * (memory.FRAME_PIXEL_BYTES + 2 * memory.FRAME_PIXEL_BAND_BYTES)
    limit = memory.BASE_BYTES + 4 * per_frame
    path = _cli_scene(tmp_path, 6)
    scene = radscene.load_scene(path, max_memory=limit)
    with pytest.raises(ConfigError, match=r"time\.step: the sequence of 6 frames .* all held"):
        render_sequence(scene, progress=False)
    out = tmp_path / "out"
    result = CliRunner().invoke(app, ["render", str(path), "-o", str(out), "--max-memory",
                                      f"{limit:.0f}", "--video", "gif"])
    assert result.exit_code == 0, result.output
    with xr.open_dataset(out / "map_sequence.nc", engine="h5netcdf") as ds:
        assert ds.sizes["time"] == 6 and ds.attrs["frames"] == 6
    assert (out / "map_sequence" / "vis.gif").is_file() and (out / MANIFEST).is_file()


PEAK = textwrap.dedent("""
    import resource, sys
    from radscene.cli import app
    try:
        app(["render", *sys.argv[1:]])
    except SystemExit as end:
        assert end.code in (0, None), end.code
    print(resource.getrusage(resource.RUSAGE_SELF).ru_maxrss)
""")


def _peak_rss(tmp_path, frames) -> float:
    """Peak resident memory [kB] of a streamed ``radscene render`` of ``frames`` frames of a
    256 x 256 map."""
    path = _cli_scene(tmp_path, frames, shape=(256, 256))
    run = subprocess.run([sys.executable, "-c", PEAK, str(path), "-o", str(tmp_path / f"out{frames}"),
                          "--no-quicklooks", "-q"], capture_output=True, text=True, timeout=600)
    assert run.returncode == 0, run.stderr
    return float(run.stdout.split()[-1])


def test_the_peak_memory_of_a_streamed_cli_run_does_not_grow_with_its_frames(tmp_path):
    """12 frames of a 256 x 256 map (each 26 MB in memory) against 3: held in memory they
    would add 9 frames (236 MB; measured 476 against 827 MB); streamed, the peak stays within
    20 % (measured 399 against 407 MB, 2026-11-26: see docs/benchmarks.md)."""
    short, long = _peak_rss(tmp_path, 3), _peak_rss(tmp_path, 12)
    per_frame = 256 * 256 * (memory.FRAME_PIXEL_BYTES + 2 * memory.FRAME_PIXEL_BAND_BYTES) / 1e3
    assert long < 1.2 * short, (short, long)
    assert long - short < 3 * per_frame, (short, long)


def _temporaries(folder):
    return [p.name for p in folder.rglob("*") if p.name.startswith(".") and p.name != MARKER]


def _stop_when(proc, ready, sig, seconds=240):
    deadline = time.monotonic() + seconds
    while time.monotonic() < deadline and proc.poll() is None:
        if ready():
            break
        time.sleep(0.02)
    assert proc.poll() is None, "the run ended before it could be stopped"
    proc.send_signal(sig)
    proc.communicate(timeout=120)
    return proc.returncode


@pytest.mark.parametrize("how", [signal.SIGTERM, signal.SIGKILL])
def test_a_stopped_stream_leaves_no_file_and_the_next_run_cleans_up(tmp_path, how):
    """Stopped while its frames are written: SIGTERM removes the growing files on the way out;
    SIGKILL leaves them, hidden, and the next run into the folder removes them and writes the
    whole sequence."""
    path = _cli_scene(tmp_path, 40, shape=(128, 128))
    out = tmp_path / "out"
    proc = subprocess.Popen([sys.executable, "-m", "radscene", "render", str(path), "-o", str(out),
                             "--no-quicklooks"], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    growing = lambda: out.is_dir() and any(p.name.startswith(".map_sequence.nc.~")  # noqa: E731
                                           for p in out.iterdir())
    assert _stop_when(proc, growing, how) != 0
    assert not (out / "map_sequence.nc").exists() and not (out / MANIFEST).exists()
    left = _temporaries(out)
    assert (left == []) if how == signal.SIGTERM else any(n.startswith(".map_sequence.nc.~") for n in left)
    path.write_text(yaml.safe_dump(_scene(3) | {"observers": [_scene()["observers"][0]]}))
    again = subprocess.run([sys.executable, "-m", "radscene", "render", str(path), "-o", str(out),
                            "--no-quicklooks", "--overwrite"], capture_output=True, text=True, timeout=600)
    assert again.returncode == 0, again.stderr
    assert _temporaries(out) == []
    with xr.open_dataset(out / "map_sequence.nc", engine="h5netcdf") as ds:
        assert ds.sizes["time"] == 3
    assert json.loads((out / MANIFEST).read_text())["files"]


def test_a_disk_too_small_is_refused_before_the_first_frame(tmp_path, monkeypatch, one_line_refusal):
    path = _cli_scene(tmp_path, 6)
    monkeypatch.setattr(memory, "free_disk_space", lambda folder: 1e5)
    out = tmp_path / "out"
    result = CliRunner().invoke(app, ["render", str(path), "-o", str(out)])
    assert result.exit_code == 2
    line = one_line_refusal(result.output, "time.step: the sequence of 6 frames needs up to",
                            "GB of disk", "has 0.0 GB free")
    assert str(out) in line
    assert not out.exists()
    given = CliRunner().invoke(app, ["render", str(path), "-o", str(out), "--step", "20 ms"])
    assert given.exit_code == 2 and one_line_refusal(given.output, "--step: the sequence of 11 frames")
    with pytest.raises(ConfigError, match=r"time\.step: the sequence of 6 frames needs up to"):
        render_sequence(_scene(6), output=tmp_path / "api", progress=False)
    assert not (tmp_path / "api").exists()
