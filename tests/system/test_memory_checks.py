"""Sizes are checked before work: a terrain grid or an observer too large for the memory limit
is one line naming its key and the figure, exit code 2, before anything is built."""

from __future__ import annotations

import time

import pytest
import yaml
from typer.testing import CliRunner

import radscene
from radscene.cli import app
from radscene.errors import ConfigError
from radscene.scene.memory import estimate, parse_memory


def _scene(size=200.0, spacing=2.0, shape=(64, 64), supersample=1, **render):
    return {
        "name": "sizes",
        "environment": {"sun": {"zenith": 30, "azimuth": 180}, "atmosphere": {"type": "none"}},
        "terrain": {"type": "procedural", "size": [size, size], "spacing": spacing,
                    "material": "soil"},
        "materials": {"soil": {"reflectance": 0.3}},
        "bands": [{"name": "red", "min": "0.6 um", "max": "0.7 um"}],
        "observers": [{"name": "map", "type": "orthographic", "center": [0, 0], "gsd": 1.0,
                       "shape": list(shape), "supersample": supersample, "altitude": 3000}],
        "render": render,
    }


def test_a_terrain_grid_too_large_is_refused_before_it_is_built():
    started = time.perf_counter()
    # 1 000 000 km² at 1 m: 1e12 cells, 400 TB; refused in well under a second
    with pytest.raises(ConfigError, match=r"terrain\.spacing: the terrain grid needs about"):
        radscene.load_scene(_scene(size=1e6, spacing=1.0))
    assert time.perf_counter() - started < 2.0


def test_an_observer_too_large_names_its_shape_and_the_figure():
    with pytest.raises(ConfigError, match=r"observers\[0\]\.shape: rendering it needs about "
                                          r"\d+\.\d GB .*the limit is 2\.0 GB \(--max-memory\)"):
        radscene.load_scene(_scene(shape=(4096, 4096), supersample=4), max_memory="2 GB")


def test_the_scene_files_limit_and_the_estimate_scale():
    with pytest.raises(ConfigError, match=r"render\.max_memory"):
        radscene.load_scene(_scene(shape=(2048, 2048), max_memory="0.5 GB"))
    spec = radscene.load_scene(_scene()).spec
    small = estimate(spec)["observers"][0][0]
    spec4 = radscene.load_scene(_scene(supersample=4)).spec
    assert estimate(spec4)["observers"][0][0] > small


@pytest.mark.parametrize("text, value", [("8 GB", 8e9), ("512MiB", 512 * 2 ** 20), (1e9, 1e9)])
def test_memory_sizes_parse(text, value):
    assert parse_memory(text) == value


@pytest.mark.parametrize("text", ["lots", "-1 GB", "8 parsecs", 0])
def test_bad_memory_sizes_are_refused(text):
    with pytest.raises(ConfigError, match="a memory size"):
        parse_memory(text)


def test_cli_refuses_before_work_and_check_reports_the_estimate(tmp_path):
    path = tmp_path / "s.yaml"
    path.write_text(yaml.safe_dump(_scene(shape=(4096, 4096), supersample=4)))
    runner = CliRunner()
    result = runner.invoke(app, ["render", str(path), "-o", str(tmp_path / "out"),
                                 "--max-memory", "1GB"])
    assert result.exit_code == 2, result.output
    assert "observers[0].shape" in result.output and not (tmp_path / "out").exists()
    path.write_text(yaml.safe_dump(_scene()))
    result = runner.invoke(app, ["check", str(path)])
    assert result.exit_code == 0, result.output
    assert "memory: about" in result.output
