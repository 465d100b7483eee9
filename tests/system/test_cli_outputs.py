"""The output of ``radscene render`` and ``radscene thermal`` is checked before any work: a
file, a folder under a file, a folder that cannot be written and earlier results (without
--overwrite) are refused with one line naming --output, exit code 2."""

from __future__ import annotations

import os
import textwrap
import time
from pathlib import Path

import pytest
from typer.testing import CliRunner

from radscene.cli import app

GOOD = textwrap.dedent("""
    name: tiny
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
      - {name: nadir, type: orthographic, center: [0, 0], gsd: 1 m, shape: [4, 4]}
""")

runner = CliRunner()


def _render(tmp_path, out, *extra):
    scene = tmp_path / "scene.yaml"
    scene.write_text(GOOD)
    return runner.invoke(app, ["render", str(scene), "-o", str(out), *extra])


def _refused(result, words):
    assert result.exit_code == 2, result.output
    lines = [ln for ln in result.output.splitlines() if ln.strip()]
    assert len(lines) == 1 and "--output" in lines[0] and words in lines[0], result.output


def test_an_output_that_is_a_file_is_refused(tmp_path):
    target = tmp_path / "taken"
    target.write_text("x")
    _refused(_render(tmp_path, target), "is a file")
    assert target.read_text() == "x"


def test_an_output_under_a_file_is_refused(tmp_path):
    (tmp_path / "taken").write_text("x")
    _refused(_render(tmp_path, tmp_path / "taken" / "out"), "is a file")


@pytest.mark.skipif(os.geteuid() == 0, reason="root writes into read-only folders")
def test_an_output_that_cannot_be_written_is_refused(tmp_path):
    locked = tmp_path / "locked"
    locked.mkdir()
    locked.chmod(0o500)
    try:
        _refused(_render(tmp_path, locked / "out"), "not writable")
    finally:
        locked.chmod(0o700)


@pytest.mark.skipif(not os.path.isdir("/proc/self"), reason="needs Linux's /proc")
@pytest.mark.parametrize("command", ["render", "thermal"])
def test_an_output_no_one_can_create_is_refused_even_for_root(tmp_path, command):
    """/proc passes every permission check for root, yet nothing can be created in it: the
    output is refused before any work, not by a traceback at the end."""
    if command == "render":
        _refused(_render(tmp_path, Path("/proc/radscene-out")), "cannot write /proc/radscene-out")
        return
    scene = tmp_path / "scene.yaml"
    scene.write_text(GOOD)
    result = runner.invoke(app, ["thermal", str(scene), "-o", "/proc/radscene-out.nc"])
    _refused(result, "cannot write /proc/radscene-out.nc")


def test_earlier_results_are_kept_unless_overwrite(tmp_path):
    out = tmp_path / "out"
    assert _render(tmp_path, out).exit_code == 0
    first = (out / "nadir.nc").stat().st_mtime_ns
    started = time.perf_counter()
    _refused(_render(tmp_path, out), "nadir.nc")
    assert time.perf_counter() - started < 5.0  # refused before rendering
    assert (out / "nadir.nc").stat().st_mtime_ns == first
    again = _render(tmp_path, out, "--overwrite")
    assert again.exit_code == 0, again.output
    assert (out / "nadir.nc").stat().st_mtime_ns != first


def test_another_observer_into_the_same_folder_is_not_an_overwrite(tmp_path):
    out = tmp_path / "out"
    (out).mkdir()
    (out / "other.nc").write_text("x")
    assert _render(tmp_path, out).exit_code == 0


def test_thermal_output_checked_before_work(tmp_path):
    scene = tmp_path / "scene.yaml"
    scene.write_text(GOOD)
    folder = tmp_path / "a_folder.nc"
    folder.mkdir()
    result = runner.invoke(app, ["thermal", str(scene), "-o", str(folder)])
    _refused(result, "is a folder")
    existing = tmp_path / "t.nc"
    existing.write_text("x")
    _refused(runner.invoke(app, ["thermal", str(scene), "-o", str(existing)]), "exists")
    assert existing.read_text() == "x"


def test_check_reports_what_each_observer_sees_and_warns_about_nothing(tmp_path):
    path = tmp_path / "s.yaml"
    path.write_text(GOOD)
    result = runner.invoke(app, ["check", str(path)])
    assert result.exit_code == 0, result.output
    assert ("field of view: parallel rays over 4 × 4 m; GSD 1 m; ground footprint 3 × 3 m "
            "(pixel centres; 100 % of pixels on the scene)") in " ".join(result.output.split())
    # the same camera beside the plate sees nothing
    path.write_text(GOOD.replace("center: [0, 0]", "center: [500, 500]"))
    result = runner.invoke(app, ["check", str(path)])
    assert result.exit_code == 0, result.output
    flat = " ".join(result.output.split())
    # its field of view and GSD first, then the warning
    assert ("field of view: parallel rays over 4 × 4 m; GSD 1 m; ground footprint: none" in flat
            and flat.index("GSD 1 m") < flat.index("warning: observer nadir looks at nothing"))


def test_check_gives_a_perspective_observer_its_gsd_at_the_boresight(tmp_path):
    path = tmp_path / "s.yaml"
    frame = ("{name: frame, type: perspective, position: [0, 0, 100 m], look_at: [0, 0, 0], "
             "fov: 40 deg, shape: [4, 4]}")
    path.write_text(GOOD.replace(
        "{name: nadir, type: orthographic, center: [0, 0], gsd: 1 m, shape: [4, 4]}", frame))
    result = runner.invoke(app, ["check", str(path)])
    assert result.exit_code == 0, result.output
    flat = " ".join(result.output.split())
    # 100 m x 2 tan(20 deg) / 4 columns
    assert ("field of view 40° × 40°; GSD 18.2 m at the boresight's ground point (0, 0, 0) m, "
            "100 m away, across the line of sight; ground footprint ") in flat, flat
    # looking up: its field of view, no GSD, then the warning
    path.write_text(path.read_text().replace("look_at: [0, 0, 0]", "look_at: [0, 0, 200 m]"))
    result = runner.invoke(app, ["check", str(path)])
    assert result.exit_code == 0, result.output
    flat = " ".join(result.output.split())
    assert ("field of view 40° × 40°; GSD: none, the boresight meets no ground; ground "
            "footprint: none") in flat, flat
    assert flat.index("field of view") < flat.index("warning: observer frame looks at nothing")


def test_check_gives_a_pushbroom_its_field_of_view_gsd_and_footprint():
    from radscene import example_path

    result = runner.invoke(app, ["check", str(example_path("landsat_overpass"))])
    assert result.exit_code == 0, result.output
    flat = " ".join(result.output.split())
    line = flat[flat.index("observer landsat: pushbroom"):]
    assert "field of view 0.156° across track (IFOV 0.000813°); GSD 10 m at the boresight's " \
           "ground point" in line, line
    assert "at mid-image, 704,991 m away" in line and "; ground footprint 2,321 × 2,201 m" in line
