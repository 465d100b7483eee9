"""CF form of the written outputs: geolocation as auxiliary coordinates, a grid mapping for map
products that rioxarray reads back, constant angles as scalars."""

from __future__ import annotations

import h5netcdf
import numpy as np
import pytest
import xarray as xr
import yaml
from typer.testing import CliRunner

from radscene.cli import app
from radscene.platform.geolocation import LocalFrame

SCENE = {
    "name": "cf",
    "environment": {"time": "2026-06-21T10:00:00Z",
                    "location": {"latitude": 45.0, "longitude": 5.0, "altitude": 200.0},
                    "atmosphere": {"type": "none"}},
    "materials": {"grey": {"reflectance": 0.3}},
    "objects": [{"name": "ground", "shape": {"type": "plate", "width": 400, "length": 400},
                 "material": "grey", "temperature": "290 K"}],
    "bands": [{"name": "vis", "min": "0.5 um", "max": "0.6 um"}],
    "observers": [
        {"name": "map", "type": "orthographic", "center": [0, 0], "gsd": 20, "shape": [8, 10],
         "altitude": 1000},
        {"name": "cam", "type": "perspective", "position": [0, -150, 80], "look_at": [0, 0, 0],
         "fov": 30, "shape": [8, 8]},
    ],
}


@pytest.fixture(scope="module")
def written(tmp_path_factory):
    folder = tmp_path_factory.mktemp("cf")
    (folder / "scene.yaml").write_text(yaml.safe_dump(SCENE))
    result = CliRunner().invoke(app, ["render", str(folder / "scene.yaml"), "-o",
                                      str(folder / "out"), "--no-quicklooks"])
    assert result.exit_code == 0, result.output
    return folder / "out"


def test_map_product_has_a_grid_mapping_rioxarray_reads(written):
    import rioxarray  # noqa: F401

    with xr.open_dataset(written / "map.nc") as ds:
        assert ds.rio.crs is not None
        assert ds.rio.crs == LocalFrame(45.0, 5.0, 200.0).crs()
        var = ds["radiance"]  # the crs among the coordinates: grid_mapping stays an attribute
        assert var.attrs.get("grid_mapping", var.encoding.get("grid_mapping")) == "crs"
        assert "crs" in var.coords
        # the grid's centres are the scene frame's easting and northing
        assert ds.rio.resolution() == pytest.approx((20.0, -20.0))
        assert ds.rio.bounds() == pytest.approx((-100.0, -80.0, 100.0, 80.0))


@pytest.mark.parametrize("name", ["map", "cam"])
def test_geolocation_is_auxiliary_coordinates(written, name):
    with xr.open_dataset(written / f"{name}.nc") as ds:
        for coord in ("latitude", "longitude", "height"):
            assert coord in ds.coords and coord not in ds.data_vars, coord
        assert ds["latitude"].attrs["standard_name"] == "latitude"
        lat = ds["latitude"].values
        assert np.nanmin(lat) > 44.99 and np.nanmax(lat) < 45.01
    with h5netcdf.File(written / f"{name}.nc", "r") as raw:  # what another CF reader sees
        assert set(raw["radiance"].attrs["coordinates"].split()) >= {"latitude", "longitude"}


def test_cf_xarray_finds_the_coordinates(written):
    cfxr = pytest.importorskip("cf_xarray", reason="cf_xarray is in the dev extra")
    assert cfxr is not None
    with xr.open_dataset(written / "cam.nc") as ds:
        assert ds.cf["latitude"].name == "latitude"
        assert ds.cf["longitude"].name == "longitude"
        assert set(ds.cf.coordinates["latitude"]) == {"latitude"}


@pytest.mark.parametrize("name", ["map", "cam"])
def test_constant_angles_are_scalars(written, name):
    with xr.open_dataset(written / f"{name}.nc") as ds:
        for angle in ("sun_zenith", "sun_azimuth"):
            assert ds[angle].ndim == 0, angle
        assert float(ds["sun_zenith"]) == pytest.approx(ds.attrs["sun_zenith_deg"], abs=1e-9)
        if name == "map":  # a nadir map looks straight down everywhere
            assert ds["view_zenith"].ndim == 0 and float(ds["view_zenith"]) == pytest.approx(0.0, abs=1e-9)
        else:  # a perspective camera's lines of sight spread
            assert ds["view_zenith"].dims == ("y", "x")


@pytest.mark.parametrize("variable, none", [("object_id", "no_object"), ("material_id", "no_material")])
def test_every_id_in_a_map_has_a_cf_flag_meaning(written, variable, none):
    """CF flags: each value of the id maps, -1 (nothing hit) included, has its meaning."""
    files = sorted(written.glob("*.nc"))
    assert files
    for path in files:
        with xr.open_dataset(path) as ds:
            flags = ds[variable]
            meanings = dict(zip(np.atleast_1d(flags.attrs["flag_values"]).tolist(),
                                flags.attrs["flag_meanings"].split(), strict=True))
            assert meanings[-1] == none
            assert set(np.unique(flags.values).tolist()) <= set(meanings)


def test_a_maps_cells_have_cf_axes_and_bounds(written):
    """cf-xarray writes the map's axes and its pixels' edges; a camera's pixel indices get
    neither."""
    import cf_xarray  # noqa: F401

    with xr.open_dataset(written / "map.nc") as ds:
        assert ds["x"].attrs["axis"] == "X" and ds["y"].attrs["axis"] == "Y"
        assert ds.cf.axes == {"X": ["x"], "Y": ["y"]}
        x_edges, y_edges = ds.cf.get_bounds("x").values, ds.cf.get_bounds("y").values
        np.testing.assert_allclose(x_edges[:, 1] - x_edges[:, 0], 20.0)
        np.testing.assert_allclose(x_edges.mean(axis=1), ds["x"].values)
        np.testing.assert_allclose(y_edges.mean(axis=1), ds["y"].values)
        assert x_edges.min() == pytest.approx(ds.rio.bounds()[0])
    with h5netcdf.File(written / "map.nc", "r") as raw:  # bounds are not auxiliary coordinates
        assert raw["x"].attrs["bounds"] == "x_bounds"
        assert "x_bounds" not in raw["radiance"].attrs["coordinates"].split()
    with xr.open_dataset(written / "cam.nc") as ds:
        assert "axis" not in ds["x"].attrs and "x_bounds" not in ds.variables
