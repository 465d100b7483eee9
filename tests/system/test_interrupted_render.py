"""A run stopped midway (SIGTERM) leaves a marker, no temporaries and no manifest — a render into
NetCDF or Zarr, a sequence, a spectral cube — or no output at all (radscene thermal); --resume
renders only the observers it had not written and then writes the manifest."""

from __future__ import annotations

import json
import signal
import subprocess
import sys
import textwrap
import time

import pytest

from radscene.io.run_record import MANIFEST, MARKER

SCENE = textwrap.dedent("""
    name: two
    environment:
      sun: {zenith: 30 deg, azimuth: 180 deg}
      atmosphere: {type: none}
    materials:
      paint: {reflectance: 0.4}
    objects:
      - {name: plate, shape: {type: plate, width: 500 m, length: 500 m}, material: paint,
         temperature: 300 K}
      - {name: box, shape: {type: box, size: [20, 20, 10]}, material: paint, temperature: 300 K}
    bands:
      - {name: vis, min: 0.5 um, max: 0.6 um}
    observers:
      - {name: quick, type: orthographic, center: [0, 0], gsd: 10 m, shape: [4, 4]}
      - {name: slow, type: orthographic, center: [0, 0], gsd: 1 m, shape: [300, 300],
         supersample: 2}
    render: {sky_samples: 32}
""")


def _cli(*args):
    return [sys.executable, "-m", "radscene", *map(str, args)]


def _temporaries(folder):
    """Hidden files and folders left under ``folder`` (a temporary is '.NAME.<random><suffix>'),
    but the marker and the metadata files inside Zarr stores."""
    return [p.name for p in folder.rglob("*") if p.name.startswith(".") and p.name != MARKER
            and not any(q.suffix == ".zarr" for q in p.relative_to(folder).parents)]


def _stop_when(proc, ready, seconds=240, delay=0.0):
    """SIGTERM ``proc`` as soon as ``ready()`` holds (and ``delay`` [s] later); its return
    code."""
    deadline = time.monotonic() + seconds
    while time.monotonic() < deadline and proc.poll() is None:
        try:
            if ready():
                break
        except (OSError, ValueError, KeyError):
            pass
        time.sleep(0.05)
    time.sleep(delay)
    assert proc.poll() is None, "the run ended before it could be stopped"
    proc.send_signal(signal.SIGTERM)
    proc.communicate(timeout=120)
    return proc.returncode


@pytest.mark.parametrize("folder", ["out", "out.zarr"])
def test_sigterm_leaves_a_marker_and_resume_finishes(tmp_path, folder):
    scene = tmp_path / "two.yaml"
    scene.write_text(SCENE)
    out = tmp_path / folder
    ext = ".zarr" if folder.endswith(".zarr") else ".nc"
    proc = subprocess.Popen(_cli("render", scene, "-o", out, "--no-quicklooks"),
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    deadline = time.monotonic() + 240
    marker = out / MARKER
    while time.monotonic() < deadline and proc.poll() is None:
        try:
            if "quick" in json.loads(marker.read_text())["finished"]:
                break
        except (OSError, ValueError, KeyError):
            pass
        time.sleep(0.2)
    assert proc.poll() is None, "the render ended before it could be stopped"
    proc.send_signal(signal.SIGTERM)
    proc.communicate(timeout=120)
    assert proc.returncode != 0
    assert marker.is_file() and not (out / MANIFEST).exists()
    record = json.loads(marker.read_text())
    assert record["finished"] == ["quick"]
    assert (out / f"quick{ext}").exists() and not (out / f"slow{ext}").exists()
    assert not _temporaries(out)

    resumed = subprocess.run(_cli("render", scene, "-o", out, "--no-quicklooks", "--resume"),
                             capture_output=True, text=True, timeout=600)
    assert resumed.returncode == 0, resumed.stderr
    assert "resumed: quick" in resumed.stdout
    manifest = json.loads((out / MANIFEST).read_text())
    assert {e["observer"] for e in manifest["files"]} == {"quick", "slow"}
    assert any(e["file"].startswith(f"slow{ext}") for e in manifest["files"])
    assert not marker.exists() and not _temporaries(out)


SEQUENCE = textwrap.dedent("""
    name: frames
    environment:
      sun: {zenith: 30 deg, azimuth: 180 deg}
      atmosphere: {type: none}
    materials:
      paint: {reflectance: 0.4}
    objects:
      - {name: plate, shape: {type: plate, width: 500 m, length: 500 m}, material: paint,
         temperature: 300 K}
      - {name: box, shape: {type: box, size: [20, 20, 10]}, material: paint, temperature: 300 K,
         trajectory: {waypoints: [[0, 0, 0, 0], [60, 50, 0, 0]]}}
    bands:
      - {name: vis, min: 0.5 um, max: 0.6 um}
    observers:
      - {name: a, type: orthographic, center: [0, 0], gsd: 1 m, shape: [200, 200], supersample: 2}
      - {name: b, type: orthographic, center: [5, 0], gsd: 1 m, shape: [200, 200], supersample: 2}
    time: {start: 2026-06-21T10:00:00Z, end: 2026-06-21T10:01:00Z, step: 20 s}
    render: {sky_samples: 32, video: gif}
""")


def test_a_stopped_sequence_leaves_a_marker_and_resume_finishes(tmp_path, one_line_refusal):
    scene = tmp_path / "frames.yaml"
    scene.write_text(SEQUENCE)
    out = tmp_path / "out"
    proc = subprocess.Popen(_cli("render", scene, "-o", out), stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True)
    assert _stop_when(proc, lambda: (out / MARKER).is_file()) != 0
    assert (out / MARKER).is_file() and not (out / MANIFEST).exists()
    assert not list(out.glob("*_sequence.nc")) and not _temporaries(out)
    resumed = subprocess.run(_cli("render", scene, "-o", out, "--resume"), capture_output=True,
                             text=True, timeout=600)
    assert resumed.returncode == 0, resumed.stderr
    manifest = json.loads((out / MANIFEST).read_text())
    files = {e["file"] for e in manifest["files"]}
    assert {"a_sequence.nc", "b_sequence.nc", "a_sequence/vis.gif", "b_sequence/vis.gif"} <= files
    assert not (out / MARKER).exists() and not _temporaries(out)
    again = subprocess.run(_cli("render", scene, "-o", out, "--resume", "--step", "30 s"),
                           capture_output=True, text=True, timeout=600)
    assert again.returncode == 2 and one_line_refusal(again.stderr, "nothing to resume")


# the render, with SIGTERM sent from inside a ctypes callback first: there Python drops the
# exception its handler raises (as when the signal lands while numba compiles a kernel)
DROPPED = textwrap.dedent("""
    import ctypes, os, signal, sys
    import radscene.cli
    import radscene.pipeline.simulation as simulation

    render_sequence = simulation.render_sequence

    def signalled(*args, **kwargs):
        ctypes.CFUNCTYPE(None)(lambda: os.kill(os.getpid(), signal.SIGTERM))()
        return render_sequence(*args, **kwargs)

    simulation.render_sequence = signalled
    sys.argv = ["radscene", *sys.argv[1:]]
    radscene.cli.run()
""")


def test_a_sigterm_whose_exception_was_dropped_still_stops_the_run(tmp_path):
    scene = tmp_path / "frames.yaml"
    scene.write_text(SEQUENCE)
    out = tmp_path / "out"
    run = subprocess.run([sys.executable, "-c", DROPPED, "render", scene, "-o", out],
                         capture_output=True, text=True, timeout=600)
    assert "Exception ignored" in run.stderr  # the handler's exception was dropped ...
    assert run.returncode == 130  # ... and the run stopped all the same
    assert (out / MARKER).is_file() and not (out / MANIFEST).exists()
    assert not list(out.glob("*_sequence.nc")) and not _temporaries(out)


def test_a_stopped_spectral_cube_leaves_no_temporaries(tmp_path):
    scene = tmp_path / "cube.yaml"
    scene.write_text(SCENE.replace("supersample: 2}", "supersample: 2,\n"
                                   "         spectral: {min: 0.4 um, max: 2.5 um, step: 2 nm}}"))
    out = tmp_path / "out"
    proc = subprocess.Popen(_cli("render", scene, "-o", out, "--observer", "slow"),
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    assert _stop_when(proc, lambda: any(p.name.startswith(".slow_spectral.nc.")
                                        for p in out.iterdir())) != 0
    assert (out / MARKER).is_file() and not (out / MANIFEST).exists()
    assert not (out / "slow_spectral.nc").exists() and not _temporaries(out)


def test_a_stopped_heat_balance_leaves_no_output(tmp_path):
    """radscene thermal writes its plots, then OUTPUT: stopped while it writes the plots, it
    leaves no OUTPUT and no temporaries."""
    scene = tmp_path / "day.yaml"
    scene.write_text(textwrap.dedent("""
        name: day
        environment:
          time: 2026-06-21T12:00:00Z
          location: {latitude: 45.0, longitude: 5.0}
          atmosphere: {type: none}
        terrain: {type: flat, size: [30, 30], spacing: 1, material: concrete}
        bands:
          - {name: lwir, min: 8 um, max: 12 um}
        observers:
          - {name: map, type: orthographic, center: [15, 15], gsd: 1 m, shape: [8, 8]}
        thermal: {step: 10 min}
    """))
    out = tmp_path / "out"
    nc = out / "day.nc"
    proc = subprocess.Popen(_cli("thermal", scene, "-o", nc), stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True)
    # stopped as soon as the first plot's temporary (or the plot) appears: the earliest moment
    # of the writing, so that the rest of it (the maps, then OUTPUT) is still to come
    assert _stop_when(proc, lambda: any(p.name.startswith((".day_diurnal", "day_diurnal"))
                                        for p in out.iterdir())) != 0
    assert not nc.exists() and not _temporaries(out)
