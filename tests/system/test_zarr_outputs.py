"""``radscene render -o OUT.zarr`` beyond single frames: spectral cubes as Zarr stores holding
what the NetCDF files hold."""

from __future__ import annotations

import json
import textwrap

import numpy as np
import pytest
from typer.testing import CliRunner

from radscene.cli import app
from radscene.io import read_netcdf, read_zarr
from radscene.io.run_record import MANIFEST

pytest.importorskip("zarr")
# rasterio/rioxarray's own use of affine's `*` operator
pytestmark = pytest.mark.filterwarnings("ignore::PendingDeprecationWarning")

SPECTRAL = textwrap.dedent("""
    name: tiny_hsi
    environment:
      sun: {zenith: 30 deg, azimuth: 180 deg}
      atmosphere: {type: uniform, transmittance: 0.9, path_radiance: 2.0, sky_radiance: 3.0}
    materials:
      paint: {reflectance: 0.4}
      soil: {reflectance: 0.2}
    objects:
      - {name: ground, shape: {type: plate, width: 50 m, length: 50 m}, material: soil,
         temperature: 300 K}
      - {name: box, shape: {type: box, size: [4 m, 6 m, 3 m]}, material: paint,
         temperature: 310 K}
    observers:
      - {name: hsi, type: orthographic, center: [0, 0], gsd: 1 m, shape: [8, 6],
         spectral: {min: 400 nm, max: 1000 nm, step: 20 nm}}
""")

runner = CliRunner()


def _run(*args):
    result = runner.invoke(app, [str(a) for a in args])
    assert result.exit_code == 0, result.output
    return result


def _same_content(store, nc, volatile=("history", "render_seconds", "frame_render_seconds")):
    """The store's variables, coordinates and attributes are the NetCDF file's (bar the render
    times and the history of two separate runs)."""
    assert set(store.data_vars) == set(nc.data_vars)
    assert set(store.coords) == set(nc.coords)
    for name in set(nc.variables) - set(volatile):
        np.testing.assert_array_equal(store[name].values, nc[name].values, err_msg=name)
        assert store[name].dtype == nc[name].dtype, name
    assert {k: v for k, v in store.attrs.items() if k not in volatile} == \
        {k: v for k, v in nc.attrs.items() if k not in volatile}


def test_a_spectral_cube_goes_into_a_zarr_store(tmp_path):
    import rioxarray  # noqa: F401 - the .rio accessor
    import xarray as xr

    scene = tmp_path / "hsi.yaml"
    scene.write_text(SPECTRAL)
    _run("render", scene, "-o", tmp_path / "nc", "-q")
    _run("render", scene, "-o", tmp_path / "out.zarr", "-q")
    out = tmp_path / "out.zarr"
    assert sorted(p.name for p in out.iterdir()) == [
        "hsi_spectral.hdr", "hsi_spectral.img", "hsi_spectral.zarr", MANIFEST]
    store = read_zarr(out / "hsi_spectral.zarr")
    nc = read_netcdf(tmp_path / "nc" / "hsi_spectral.nc")
    assert store["radiance"].dims == ("wavelength", "y", "x")
    assert store["radiance"].shape == (31, 8, 6)
    _same_content(store, nc)
    # the ENVI image beside it is the same cube
    image = np.fromfile(out / "hsi_spectral.img", dtype="<f4").reshape(31, 8, 6)
    np.testing.assert_array_equal(image, store["radiance"].values)
    # a map product: rioxarray finds the CRS, the cube's and the maps' alike
    opened = xr.open_zarr(out / "hsi_spectral.zarr", decode_coords="all")
    assert opened.rio.crs is not None
    assert opened["radiance"].encoding["grid_mapping"] == "crs"
    assert opened.rio.crs == xr.open_dataset(tmp_path / "nc" / "hsi_spectral.nc",
                                             decode_coords="all").rio.crs
    listed = {e["file"] for e in json.loads((out / MANIFEST).read_text())["files"]}
    assert {"hsi_spectral.zarr/.zmetadata", "hsi_spectral.zarr/radiance/.zarray",
            "hsi_spectral.img"} <= listed
    # checked before any work like the other outputs; rendered again from the store
    refused = runner.invoke(app, ["render", str(scene), "-o", str(out)])
    assert refused.exit_code == 2 and "hsi_spectral.zarr" in refused.output
    _run("render", "--from", out / "hsi_spectral.zarr", "-o", tmp_path / "again.zarr", "-q")
    np.testing.assert_array_equal(read_zarr(tmp_path / "again.zarr" / "hsi_spectral.zarr")[
        "radiance"].values, store["radiance"].values)
