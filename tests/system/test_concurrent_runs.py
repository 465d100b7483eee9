"""Two runs into one output folder at once: neither breaks the other, the folder stays marked
incomplete until the last one ends, and the manifest lists both."""

from __future__ import annotations

import json
import subprocess
import sys
import textwrap

from radscene.io.run_record import MANIFEST, MARKER

SCENE = textwrap.dedent("""
    name: two
    environment:
      sun: {zenith: 30 deg, azimuth: 180 deg}
      atmosphere: {type: none}
    materials:
      paint: {reflectance: 0.4}
    objects:
      - {name: plate, shape: {type: plate, width: 50 m, length: 50 m}, material: paint,
         temperature: 300 K}
    bands:
      - {name: vis, min: 0.5 um, max: 0.6 um}
    observers:
      - {name: a, type: orthographic, center: [0, 0], gsd: 1 m, shape: [24, 24]}
      - {name: b, type: orthographic, center: [5, 0], gsd: 1 m, shape: [24, 24]}
""")


def test_two_runs_into_one_folder_at_once(tmp_path):
    scene = tmp_path / "two.yaml"
    scene.write_text(SCENE)
    out = tmp_path / "out"
    procs = [subprocess.Popen([sys.executable, "-m", "radscene", "render", str(scene), "-o", str(out),
                               "--observer", name], stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                              text=True)
             for name in ("a", "b")]
    results = [p.communicate(timeout=600) for p in procs]
    assert [p.returncode for p in procs] == [0, 0], results
    assert not (out / MARKER).exists()
    manifest = json.loads((out / MANIFEST).read_text())
    observers = {e["observer"] for e in manifest["files"]}
    assert observers == {"a", "b"}
    for name in ("a", "b"):
        assert (out / f"{name}.nc").is_file() and (out / name / "vis.png").is_file()
    # quicklooks and GeoTIFFs of both, no temporaries left
    assert not [p.name for p in out.rglob("*") if p.name.startswith(".")]


def test_a_later_run_for_another_observer_keeps_the_earlier_files_in_the_manifest(tmp_path):
    scene = tmp_path / "two.yaml"
    scene.write_text(SCENE)
    out = tmp_path / "out"
    for name in ("a", "b"):
        done = subprocess.run([sys.executable, "-m", "radscene", "render", str(scene), "-o", str(out),
                               "--observer", name, "--no-quicklooks"], capture_output=True, text=True,
                              timeout=600)
        assert done.returncode == 0, done.stderr
    manifest = json.loads((out / MANIFEST).read_text())
    assert {e["observer"] for e in manifest["files"]} == {"a", "b"}
    assert set(manifest["observers"]) == {"a", "b"}
