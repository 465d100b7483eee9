"""Spectral cubes written pass by pass: the NetCDF file (or Zarr store) and the ENVI image hold
the passes in grid order, and a run that fails or does not fill the grid leaves no file
behind."""

from __future__ import annotations

import numpy as np
import pytest
import xarray as xr

from radscene.errors import ConfigError
from radscene.io import read_netcdf, read_zarr, write_spectral
from radscene.radiometry import channel_grid
from radscene.render.hyperspectral import spectral_attributes


def _passes(grid, sizes, shape=(3, 5), seed=0):
    rng = np.random.default_rng(seed)
    start = 0
    for k in sizes:
        part = slice(start, start + k)
        yield xr.Dataset(
            {"radiance": (("wavelength", "y", "x"), rng.random((k,) + shape),
                          spectral_attributes(grid)),
             "range": (("y", "x"), np.full(shape, 1000.0), {"units": "m"})},
            coords={"wavelength": ("wavelength", grid.wavelength[part], {"units": "um"}),
                    "fwhm": ("wavelength", grid.width[part], {"units": "um"}),
                    "y": np.arange(shape[0]), "x": np.arange(shape[1])},
            attrs={"scene": "s", "observer": "o"})
        start += k


def test_passes_land_in_grid_order(tmp_path):
    grid = channel_grid(1.0, 1.9, 0.1)
    expected = np.concatenate([p["radiance"].values for p in _passes(grid, [4, 4, 2])])
    files = write_spectral(_passes(grid, [4, 4, 2]), tmp_path / "c.nc", grid,
                           envi=tmp_path / "c.img")
    assert [f.name for f in files] == ["c.nc", "c.img", "c.hdr"]
    cube = read_netcdf(tmp_path / "c.nc")
    np.testing.assert_array_equal(cube["radiance"].values, expected.astype(np.float32))
    np.testing.assert_allclose(cube["fwhm"].values, grid.width, rtol=1e-15)
    assert cube["radiance"].attrs["units"] == "W m-2 sr-1 um-1"
    assert float(cube["range"].mean()) == 1000.0
    image = np.fromfile(tmp_path / "c.img", dtype="<f4").reshape(10, 3, 5)
    np.testing.assert_array_equal(image, expected.astype(np.float32))


def test_a_zarr_store_holds_what_the_netcdf_file_holds(tmp_path):
    pytest.importorskip("zarr")
    grid = channel_grid(1.0, 1.9, 0.1)
    files = write_spectral(_passes(grid, [3, 3, 3, 1], shape=(40, 30)), tmp_path / "c.zarr",
                           grid, envi=tmp_path / "c.img")
    assert [f.name for f in files] == ["c.zarr", "c.img", "c.hdr"]
    write_spectral(_passes(grid, [10], shape=(40, 30)), tmp_path / "c.nc", grid)
    store, nc = read_zarr(tmp_path / "c.zarr"), read_netcdf(tmp_path / "c.nc")
    assert set(store.variables) == set(nc.variables)
    for name in nc.variables:
        np.testing.assert_array_equal(store[name].values, nc[name].values, err_msg=name)
        assert store[name].dtype == nc[name].dtype, name
        assert store[name].attrs == nc[name].attrs, name
    assert store.attrs == nc.attrs == {"scene": "s", "observer": "o",
                                       "spectral_mode": "hyperspectral"}
    assert "fwhm" in store["radiance"].coords
    import zarr

    cube = zarr.open_group(tmp_path / "c.zarr", mode="r")["radiance"]
    assert cube.chunks == (1, 40, 30) and cube.dtype == np.float32
    image = np.fromfile(tmp_path / "c.img", dtype="<f4").reshape(10, 40, 30)
    np.testing.assert_array_equal(image, store["radiance"].values)


@pytest.mark.parametrize("name", ["c.nc", "c.zarr"])
@pytest.mark.parametrize("sizes, message", [([4, 4], "hold 8 of the grid's 10 channels"),
                                            ([4, 4, 4], "does not match the grid")])
def test_passes_that_do_not_fill_the_grid_leave_nothing(tmp_path, sizes, message, name):
    if name.endswith(".zarr"):
        pytest.importorskip("zarr")
    grid = channel_grid(1.0, 1.9, 0.1)
    long = channel_grid(1.0, 2.5, 0.1)
    with pytest.raises(ConfigError, match=message):
        write_spectral(_passes(long, sizes), tmp_path / name, grid, envi=tmp_path / "c.img")
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize("name", ["c.nc", "c.zarr"])
def test_a_failing_render_leaves_nothing(tmp_path, name):
    if name.endswith(".zarr"):
        pytest.importorskip("zarr")
    grid = channel_grid(1.0, 1.9, 0.1)

    def failing():
        yield from _passes(grid, [4])
        raise RuntimeError("the render failed")

    with pytest.raises(RuntimeError, match="the render failed"):
        write_spectral(failing(), tmp_path / name, grid, envi=tmp_path / "c.img")
    assert list(tmp_path.iterdir()) == []
