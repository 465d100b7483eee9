"""--confine: a scene of unknown origin reads no file outside its own folder."""

from __future__ import annotations

import numpy as np
import pytest
import yaml
from typer.testing import CliRunner

import radscene
from radscene.cli import app
from radscene.errors import ConfigError


def _scene(band_file):
    return {
        "name": "confined",
        "environment": {"sun": {"zenith": 30, "azimuth": 180}, "atmosphere": {"type": "none"}},
        "materials": {"grey": {"reflectance": 0.3}},
        "objects": [{"name": "plate", "shape": {"type": "plate", "width": 50, "length": 50},
                     "material": "grey", "temperature": "300 K"}],
        "bands": [{"name": "red", "file": band_file}],
        "observers": [{"name": "map", "type": "orthographic", "center": [0, 0], "gsd": 5,
                       "shape": [4, 4], "altitude": 1000}],
    }


@pytest.fixture
def folders(tmp_path):
    inside, outside = tmp_path / "scene", tmp_path / "elsewhere"
    inside.mkdir()
    outside.mkdir()
    srf = np.c_[np.linspace(0.6, 0.7, 11), np.ones(11)]
    for folder in (inside, outside):
        np.savetxt(folder / "red.csv", srf, delimiter=",")
    (inside / "link.csv").symlink_to(outside / "red.csv")
    return inside, outside


def test_a_file_inside_the_folder_is_read(folders):
    inside, _ = folders
    scene = radscene.load_scene(_scene("red.csv"), base_dir=inside, confine=True)
    assert scene.bands[0].name == "red"


@pytest.mark.parametrize("name", ["../elsewhere/red.csv", "link.csv", "ABSOLUTE"])
def test_a_file_outside_is_refused_naming_its_key(folders, name):
    inside, outside = folders
    name = str(outside / "red.csv") if name == "ABSOLUTE" else name
    with pytest.raises(ConfigError, match=r"bands\[0\]\.file: .*outside the scene's folder"):
        radscene.load_scene(_scene(name), base_dir=inside, confine=True)
    # without --confine the same scene loads (the test can fail)
    radscene.load_scene(_scene(name), base_dir=inside)


def test_cli_confine_exits_2(folders, one_line_refusal):
    inside, _ = folders
    path = inside / "s.yaml"
    path.write_text(yaml.safe_dump(_scene("../elsewhere/red.csv")))
    result = CliRunner().invoke(app, ["check", str(path), "--confine"])
    assert result.exit_code == 2 and one_line_refusal(result.output, "bands[0].file")


@pytest.mark.parametrize("key, value", [("executable", "/bin/true"), ("cache_dir", "/tmp")])
def test_a_confined_scene_runs_no_program_and_writes_no_folder_it_names(folders, key, value):
    inside, _ = folders
    scene = _scene("red.csv")
    scene["environment"]["atmosphere"] = {"type": "lowtran", key: value}
    with pytest.raises(ConfigError, match=rf"environment\.atmosphere\.{key}: --confine"):
        radscene.load_scene(scene, base_dir=inside, confine=True)
