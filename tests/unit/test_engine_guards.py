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
    monkeypatch.setattr(sr, "_binary", lambda: _stand_in(tmp_path, "sleep 30"))
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
