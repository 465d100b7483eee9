"""A render stopped midway (SIGTERM) leaves a marker, no temporaries and no manifest; --resume
renders only the observers it had not written and then writes the manifest."""

from __future__ import annotations

import json
import signal
import subprocess
import sys
import textwrap
import time

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


def test_sigterm_leaves_a_marker_and_resume_finishes(tmp_path):
    scene = tmp_path / "two.yaml"
    scene.write_text(SCENE)
    out = tmp_path / "out"
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
    assert not (out / "slow.nc").exists()
    assert not [p.name for p in out.iterdir() if p.name.startswith(".") and p.name != MARKER]

    resumed = subprocess.run(_cli("render", scene, "-o", out, "--no-quicklooks", "--resume"),
                             capture_output=True, text=True, timeout=600)
    assert resumed.returncode == 0, resumed.stderr
    assert "resumed: quick" in resumed.stdout
    manifest = json.loads((out / MANIFEST).read_text())
    assert {e["observer"] for e in manifest["files"]} == {"quick", "slow"}
    assert not marker.exists()
