"""Engines: a hung run is stopped at the user's timeout with the case named; a configured
executable that is not one is refused, never passed over for another build."""

from __future__ import annotations

import os
import stat

import pytest

from radscene.atmosphere import make_atmosphere
from radscene.atmosphere import sixs_runner as sr
from radscene.errors import ConfigError, EngineError


def _stand_in(tmp_path, body):
    script = tmp_path / "engine.sh"
    script.write_text(f"#!/bin/sh\n{body}\n")
    script.chmod(script.stat().st_mode | stat.S_IXUSR)
    return str(script)


def test_a_hung_6s_run_is_stopped_at_the_timeout_naming_the_case(tmp_path, monkeypatch):
    monkeypatch.setattr(sr, "_binary", lambda: _stand_in(tmp_path, "exec sleep 30"))
    runner = sr.SixSRunner(workers=1, cache_dir=False, timeout="0.5 s")
    case = sr.SixSCase(0.55, profile="none", aerosol="none", sun_zenith=30.0)
    with pytest.raises(EngineError, match=r"timeout of 0\.5 s for the case .*0\.55"):
        runner.run_one(case)


@pytest.mark.parametrize("timeout", [0, -1, "soon"])
def test_a_bad_timeout_is_refused_by_name(timeout):
    with pytest.raises(ConfigError, match="timeout"):
        make_atmosphere({"type": "sixs", "timeout": timeout})


def test_the_timeout_reaches_the_runner():
    assert make_atmosphere({"type": "sixs", "timeout": "2 min"}).runner.timeout == 120.0


@pytest.mark.parametrize("what", ["missing", "not executable", "a folder"])
def test_a_named_lowtran_executable_that_is_not_one_is_refused(tmp_path, monkeypatch, what):
    from radscene.atmosphere.lowtran.runner import find_executable

    path = tmp_path / "lowtran"
    if what == "not executable":
        path.write_text("x")
        os.chmod(path, 0o644)
    elif what == "a folder":
        path.mkdir()
    monkeypatch.setenv("RADSCENE_LOWTRAN", str(path))
    with pytest.raises(ConfigError, match="RADSCENE_LOWTRAN.*not an executable file"):
        find_executable()


@pytest.mark.parametrize("timeout, seconds", [("2 min", 120.0), (45, 45.0)])
def test_the_lowtran_timeout_takes_a_duration_and_reaches_the_runner(timeout, seconds):
    engine = make_atmosphere({"type": "lowtran", "timeout": timeout, "cache": False})
    assert engine.runner.timeout == seconds


@pytest.mark.parametrize("timeout", [0, -1, "soon", True])
def test_a_bad_lowtran_timeout_is_refused_by_name(timeout):
    with pytest.raises(ConfigError, match="timeout"):
        make_atmosphere({"type": "lowtran", "timeout": timeout, "cache": False})


SCENE = {
    "name": "hung",
    "environment": {"sun": {"zenith": 30, "azimuth": 180}},
    "materials": {"paint": {"reflectance": 0.4}},
    "objects": [{"name": "plate", "shape": {"type": "plate", "width": 50, "length": 50},
                 "material": "paint", "temperature": "300 K"}],
    "bands": [{"name": "vis", "min": "0.5 um", "max": "0.6 um"}],
    "observers": [{"name": "nadir", "type": "orthographic", "center": [0, 0], "gsd": 1,
                   "shape": [4, 4], "altitude": 1000}],
}


@pytest.mark.parametrize("engine", ["lowtran", "sixs"])
def test_a_hung_engine_stops_a_render_at_the_scene_timeout(tmp_path, monkeypatch, engine):
    """A stand-in engine that never answers: `radscene render` ends at the scene's
    atmosphere.timeout with one line naming the case, exit code 1, and leaves its output
    folder marked incomplete."""
    import time

    import yaml
    from typer.testing import CliRunner

    from radscene.cli import app
    from radscene.io.run_record import MANIFEST, MARKER

    hung = _stand_in(tmp_path, "exec sleep 60")
    atmosphere = {"type": engine, "timeout": "0.5 s", "cache": False} if engine == "lowtran" \
        else {"type": engine, "timeout": "0.5 s", "cache": False}
    if engine == "lowtran":
        atmosphere["executable"] = hung
    else:
        monkeypatch.setattr(sr, "_binary", lambda: hung)
    scene = {**SCENE, "environment": {**SCENE["environment"], "atmosphere": atmosphere}}
    path = tmp_path / "scene.yaml"
    path.write_text(yaml.safe_dump(scene))
    started = time.monotonic()
    result = CliRunner().invoke(app, ["render", str(path), "-o", str(tmp_path / "out"), "-q"])
    assert result.exit_code == 1, result.output
    lines = result.output.strip().splitlines()
    assert len(lines) == 1 and "atmosphere.timeout" in lines[0] and "0.5 s" in lines[0], lines
    assert "case" in lines[0] and "Traceback" not in result.output
    assert time.monotonic() - started < 50  # stopped at the timeout, not at the stand-in's end
    assert (tmp_path / "out" / MARKER).is_file() and not (tmp_path / "out" / MANIFEST).exists()


@pytest.mark.parametrize("where", ["scene", "environment"])
def test_check_refuses_an_engine_executable_that_is_not_one(tmp_path, monkeypatch, where):
    """`radscene check` finds the program the engine runs, as the render would: a named file
    that is not executable is one line naming its key, exit 2 (it passed check before). The
    scene names it relative to its own folder, as it names every file."""
    import yaml
    from typer.testing import CliRunner

    from radscene.cli import app

    (tmp_path / "engine.sh").write_text("#!/bin/sh\n")  # not executable
    atmosphere = {"type": "lowtran", "cache": False}
    if where == "scene":
        atmosphere["executable"] = "engine.sh"
    else:
        monkeypatch.setenv("RADSCENE_LOWTRAN", str(tmp_path / "engine.sh"))
    scene = {**SCENE, "environment": {**SCENE["environment"], "atmosphere": atmosphere}}
    path = tmp_path / "scene.yaml"
    path.write_text(yaml.safe_dump(scene))
    monkeypatch.chdir("/")
    result = CliRunner().invoke(app, ["check", str(path)])
    key = "environment.atmosphere.executable" if where == "scene" else "RADSCENE_LOWTRAN"
    assert result.exit_code == 2, result.output
    assert result.output.startswith(f"error: {key}: not an executable file: {tmp_path}"), result.output
    assert len(result.output.strip().splitlines()) == 1 and "Traceback" not in result.output
