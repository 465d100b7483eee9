"""A volume's density grid sized from its file's header (radscene.scene.memory.grid_header)
and its place in the memory estimate."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import xarray as xr

from radscene.scene.memory import (
    GRID_HELD_BYTES,
    GRID_NODE_BYTES,
    estimate,
    grid_files,
    grid_header,
)
from radscene.scene.schema import SceneSpec


@pytest.mark.parametrize("dtype, read", [("float32", 4.0), ("float64", 0.0), ("int16", 2.0),
                                         ("uint8", 1.0)])
def test_a_npy_header_gives_the_shape_and_the_bytes_read_before_the_grid(tmp_path, dtype, read):
    """The stored values, unless they are float64 already: they are the grid then."""
    np.save(tmp_path / "g.npy", np.zeros((6, 5, 4), dtype))
    assert grid_header(tmp_path / "g.npy") == ((6, 5, 4), read)


def test_a_netcdf_variable_gives_its_shape_and_stored_and_decoded_bytes(tmp_path):
    grid = np.zeros((3, 4, 5))
    ds = xr.Dataset({"density": (("z", "y", "x"), grid.astype(np.float32)),
                     "smoke": (("z", "y", "x"), grid),
                     "packed": (("z", "y", "x"), grid)})
    encoding = {"packed": {"dtype": "int16", "scale_factor": np.float32(0.01), "_FillValue": -1}}
    ds.to_netcdf(tmp_path / "g.nc", engine="h5netcdf", encoding=encoding)
    assert grid_header(tmp_path / "g.nc") == ((3, 4, 5), 4.0)
    assert grid_header(tmp_path / "g.nc", "smoke") == ((3, 4, 5), 0.0)
    assert grid_header(tmp_path / "g.nc", "packed") == ((3, 4, 5), 2.0 + 4.0)  # int16, float32
    assert grid_header(tmp_path / "g.nc", "absent") is None
    ds.to_netcdf(tmp_path / "classic.nc", engine="scipy")  # NetCDF-3
    assert grid_header(tmp_path / "classic.nc") == ((3, 4, 5), 4.0)


@pytest.mark.parametrize("name, content", [("g.npy", b"\x93NUMPY junk"), ("g.nc", b"CDF junk"),
                                           ("g.nc", b"")])
def test_a_header_that_cannot_be_read_is_left_to_the_reader(tmp_path, name, content):
    (tmp_path / name).write_bytes(content)
    assert grid_header(tmp_path / name) is None
    assert grid_header(tmp_path / "missing.npy") is None
    assert grid_header(tmp_path / "missing.nc") is None


def _spec(*profiles):
    return SceneSpec.model_validate({
        "name": "grids",
        "environment": {"sun": {"zenith": 30, "azimuth": 180}, "atmosphere": {"type": "none"}},
        "materials": {"soil": {"reflectance": 0.3}},
        "objects": [{"name": "plate", "shape": {"type": "plate", "width": 2, "length": 2},
                     "material": "soil", "temperature": "300 K"}],
        "volumes": [{"name": f"v{i}", "shape": {"type": "box", "size": [4, 4, 2]},
                     "position": [0, 0, 5], "extinction": 0.1, "temperature": "300 K",
                     "profile": profile} for i, profile in enumerate(profiles)],
        "bands": [{"name": "red", "min": "0.6 um", "max": "0.7 um"}],
        "observers": [{"name": "map", "type": "orthographic", "center": [0, 0], "gsd": 1.0,
                       "shape": [8, 8], "altitude": 3000}],
    })


def test_the_grids_a_scene_names_and_their_place_in_the_estimate(tmp_path):
    """Each grid's key as the loader names it; read with the grids before it held; held, with
    the textures, in every observer's estimate."""
    spec = _spec({"type": "grid", "file": "a.npy"}, {"type": "uniform"},
                 {"type": "grid", "file": "/abs/b.nc", "variable": "smoke"})
    assert grid_files(spec, tmp_path) == [("volumes[0].profile.file", tmp_path / "a.npy", "density"),
                                          ("volumes[2].profile.file", Path("/abs/b.nc"), "smoke")]
    assert grid_files(spec, None) == []
    bare = estimate(_spec({"type": "uniform"}), tmp_path)
    assert bare["grids"] == [] and bare["grids_held"] == 0.0
    np.save(tmp_path / "a.npy", np.zeros((10, 20, 30), np.float32))
    np.save(tmp_path / "c.npy", np.zeros((4, 5, 6)))
    est = estimate(_spec({"type": "grid", "file": "a.npy"}, {"type": "grid", "file": "c.npy"},
                         {"type": "grid", "file": "missing.npy"}), tmp_path)
    base = bare["terrain"][0]
    assert est["grids"] == [
        (pytest.approx(base + 6000 * (GRID_NODE_BYTES + 4.0)), "volumes[0].profile.file",
         "the density grid a.npy (10 × 20 × 30 nodes)"),
        (pytest.approx(base + 6000 * GRID_HELD_BYTES + 120 * GRID_NODE_BYTES),
         "volumes[1].profile.file", "the density grid c.npy (4 × 5 × 6 nodes)")]
    assert est["grids_held"] == 6120 * GRID_HELD_BYTES
    assert est["observers"][0][0] == pytest.approx(bare["observers"][0][0] + est["grids_held"])
