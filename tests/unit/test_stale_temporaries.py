"""Temporaries left by a run killed outright (SIGKILL) are removed by the next run into the
folder: those of this host whose writing process is gone, and only those."""

from __future__ import annotations

import os
import socket
import subprocess
import sys
import textwrap

from radscene.io.files import atomic_output, atomic_output_dir, remove_stale_temporaries
from radscene.io.run_record import MANIFEST


def _dead_pid():
    proc = subprocess.run([sys.executable, "-c", "import os; print(os.getpid())"],
                          capture_output=True, text=True, check=True)
    return int(proc.stdout)


def test_temporaries_name_their_host_and_process(tmp_path):
    owner = f"~{socket.gethostname()}~{os.getpid()}~"
    with atomic_output(tmp_path / "a.nc") as tmp:
        assert os.path.basename(tmp).startswith(f".a.nc.{owner}")
    with atomic_output_dir(tmp_path / "b.zarr") as tmp:
        assert os.path.basename(tmp).startswith(f".b.zarr.{owner}")


def test_only_the_temporaries_of_gone_processes_of_this_host_go(tmp_path):
    host, dead = socket.gethostname(), _dead_pid()
    stale_file = tmp_path / f".cam.nc.~{host}~{dead}~x1y2.tmp"
    stale_dir = tmp_path / "cam_sequence" / f".store.zarr.~{host}~{dead}~abc.tmp"
    live = tmp_path / f".cam.nc.~{host}~{os.getpid()}~q.tmp"
    other_host = tmp_path / f".cam.nc.~another-host~{dead}~q.tmp"
    ordinary = [tmp_path / ".radscene-incomplete.json", tmp_path / "cam.nc",
                tmp_path / ".hidden~notes"]
    stale_dir.mkdir(parents=True)
    (stale_dir / "part").write_text("x")
    for path in (stale_file, live, other_host, *ordinary):
        path.write_text("x")
    removed = remove_stale_temporaries(tmp_path)
    assert set(removed) == {stale_file, stale_dir}
    assert not stale_file.exists() and not stale_dir.exists()
    assert live.exists() and other_host.exists() and all(p.exists() for p in ordinary)


def test_names_restrict_the_search_to_those_files(tmp_path):
    host, dead = socket.gethostname(), _dead_pid()
    mine = tmp_path / f".day.nc.~{host}~{dead}~a.tmp"
    theirs = tmp_path / f".other.nc.~{host}~{dead}~b.tmp"
    below = tmp_path / "sub" / f".day.nc.~{host}~{dead}~c.tmp"
    below.parent.mkdir()
    for path in (mine, theirs, below):
        path.write_text("x")
    assert remove_stale_temporaries(tmp_path, ["day.nc"]) == [mine]
    assert theirs.exists() and below.exists()


def test_a_render_after_a_killed_one_leaves_no_temporary(tmp_path):
    """The folder of a run killed by SIGKILL while it wrote: its marker and a temporary; the
    next render into it (``--resume``) finishes it and leaves no temporary."""
    scene = tmp_path / "plate.yaml"
    scene.write_text(textwrap.dedent("""
        name: plate
        environment: {sun: {zenith: 30 deg, azimuth: 180 deg}, atmosphere: {type: none}}
        materials: {paint: {reflectance: 0.4}}
        objects:
          - {name: plate, shape: {type: plate, width: 50 m, length: 50 m}, material: paint,
             temperature: 300 K}
        bands: [{name: vis, min: 0.5 um, max: 0.6 um}]
        observers: [{name: cam, type: orthographic, center: [0, 0], gsd: 1 m, shape: [8, 8]}]
    """))
    out = tmp_path / "out"
    cli = [sys.executable, "-m", "radscene", "render", str(scene), "-o", str(out),
           "--no-quicklooks"]
    killed = subprocess.Popen([*cli])
    killed.kill()
    killed.wait()
    out.mkdir(exist_ok=True)
    left = out / f".cam.nc.~{socket.gethostname()}~{killed.pid}~r4nd.tmp"
    left.write_text("half a file")
    run = subprocess.run([*cli, "--overwrite"], capture_output=True, text=True, timeout=300)
    assert run.returncode == 0, run.stderr
    assert (out / "cam.nc").is_file() and not left.exists()
    assert not [p.name for p in out.rglob(".*") if p.name != MANIFEST]
