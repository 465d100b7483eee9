"""Shared by the validation tests: a scene rendered through the ``radscene render`` command."""

from __future__ import annotations

import subprocess
import sys

import pytest
import xarray as xr
import yaml


def _render_scene(folder, scene, observer="cam") -> xr.Dataset:
    """Write ``scene`` (a dict) as YAML into ``folder``, run ``radscene render`` on it in a
    subprocess and return the observer's Dataset, loaded."""
    folder.mkdir(parents=True, exist_ok=True)
    path = folder / "scene.yaml"
    path.write_text(yaml.safe_dump(scene))
    out = folder / "out"
    run = subprocess.run([sys.executable, "-m", "radscene", "render", str(path), "-o", str(out),
                          "--no-quicklooks"], capture_output=True, text=True)
    assert run.returncode == 0, run.stderr
    with xr.open_dataset(out / f"{observer}.nc", engine="h5netcdf") as ds:
        return ds.load()


@pytest.fixture(scope="session")
def render_scene():
    """:func:`_render_scene`: ``render_scene(folder, scene_dict) -> Dataset``."""
    return _render_scene
