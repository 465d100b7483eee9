"""The formats of ``radscene render``: Zarr stores (-o OUT.zarr), Cloud-Optimised GeoTIFFs of a
map product's layers (--geotiff), ENVI of band radiance (--envi), --quiet and --verbose."""

from __future__ import annotations

import json
import textwrap

import numpy as np
import pytest
import rasterio
import xarray as xr
from typer.testing import CliRunner

from radscene.cli import app
from radscene.io import read_netcdf, read_zarr

pytest.importorskip("zarr")
# rasterio/rioxarray's own use of affine's `*` operator
pytestmark = pytest.mark.filterwarnings("ignore::PendingDeprecationWarning")

SCENE = textwrap.dedent("""
    name: formats
    environment:
      location: {latitude: 46.5, longitude: 6.6, altitude: 400}
      sun: {zenith: 30 deg, azimuth: 180 deg}
      atmosphere: {type: none}
    materials:
      paint: {reflectance: 0.4}
      soil: {reflectance: 0.2}
    objects:
      - {name: ground, shape: {type: plate, width: 50 m, length: 50 m}, material: soil,
         temperature: 290 K}
      - {name: box, shape: {type: box, size: [4 m, 6 m, 3 m]}, material: paint,
         temperature: 310 K}
    bands:
      - {name: vis, min: 0.5 um, max: 0.6 um}
      - {name: lwir, min: 8 um, max: 12 um}
    observers:
      - {name: map, type: orthographic, center: [0, 0], gsd: 1 m, shape: [14, 10]}
""")

runner = CliRunner()


def _run(*args):
    result = runner.invoke(app, [str(a) for a in args])
    assert result.exit_code == 0, result.output
    return result


@pytest.fixture(scope="module")
def runs(tmp_path_factory):
    """The scene rendered once to NetCDF (COGs of every layer, ENVI) and once to Zarr."""
    root = tmp_path_factory.mktemp("formats")
    scene = root / "scene.yaml"
    scene.write_text(SCENE)
    _run("render", scene, "-o", root / "nc", "--geotiff", "all", "--envi", "--no-quicklooks")
    _run("render", scene, "-o", root / "out.zarr", "--geotiff", "none", "--no-quicklooks")
    return root


def test_zarr_store_holds_what_the_netcdf_holds(runs):
    nc = read_netcdf(runs / "nc" / "map.nc")
    store = runs / "out.zarr" / "map.zarr"
    zr = read_zarr(store)
    assert set(zr.data_vars) == set(nc.data_vars)
    assert set(zr.coords) == set(nc.coords)
    for name in nc.data_vars:
        np.testing.assert_array_equal(zr[name].values, nc[name].values, err_msg=name)
        assert zr[name].dtype == nc[name].dtype, name
    for name in nc.coords:
        np.testing.assert_array_equal(zr[name].values, nc[name].values, err_msg=name)
    # latitude/longitude stay auxiliary coordinates of the image layers
    assert {"latitude", "longitude"} <= set(zr["radiance"].coords)
    # the global attributes, provenance included, are those of the NetCDF file (bar the render
    # time and the history of two separate runs)
    volatile = {"history", "render_seconds"}
    assert {k: v for k, v in zr.attrs.items() if k not in volatile} == {
        k: v for k, v in nc.attrs.items() if k not in volatile}
    assert zr.attrs["scene_document"] and json.loads(zr.attrs["library_versions"])
    for name in nc.data_vars:
        for key, value in nc[name].attrs.items():
            assert np.atleast_1d(zr[name].attrs[key]).tolist() == \
                np.atleast_1d(value).tolist(), (name, key)
    # the map product's CRS, as rioxarray reads it from the store
    opened = xr.open_zarr(store)
    crs = xr.open_dataset(runs / "nc" / "map.nc").rio.crs
    assert opened.rio.crs is not None and opened.rio.crs == crs
    assert opened["radiance"].attrs["grid_mapping"] == "crs"  # opened plainly: an attribute
    # written whole: no temporaries beside it; the manifest lists the store's files
    assert not [p for p in (runs / "out.zarr").iterdir() if p.name.startswith(".map")]
    manifest = json.loads((runs / "out.zarr" / "manifest.json").read_text())
    listed = {e["file"] for e in manifest["files"]}
    assert "map.zarr/.zmetadata" in listed and "map.zarr/radiance/.zarray" in listed
    assert not list((runs / "out.zarr").glob("*.tif"))  # --geotiff none


def test_zarr_run_is_checked_before_work_and_renders_again_from_a_store(runs, one_line_refusal):
    scene = runs / "scene.yaml"
    refused = runner.invoke(app, ["render", str(scene), "-o", str(runs / "out.zarr")])
    assert refused.exit_code == 2 and one_line_refusal(refused.output, "map.zarr")
    again = runs / "again.zarr"
    _run("render", "--from", runs / "out.zarr" / "map.zarr", "-o", again, "--geotiff", "none",
         "--no-quicklooks", "--quiet")
    np.testing.assert_array_equal(read_zarr(again / "map.zarr")["radiance"].values,
                                  read_zarr(runs / "out.zarr" / "map.zarr")["radiance"].values)


def test_map_layers_are_cloud_optimised_geotiffs(runs):
    nc = read_netcdf(runs / "nc" / "map.nc")
    crs = xr.open_dataset(runs / "nc" / "map.nc").rio.crs
    thermal = nc["wavelength_center"].values >= 2.5
    expected = {
        "radiance": nc["radiance"].values,
        "brightness_temperature": nc["brightness_temperature"].values[thermal],
        "surface_temperature": nc["surface_temperature"].values[None],
        "object_id": nc["object_id"].values[None],
        "material_id": nc["material_id"].values[None],
        "range": nc["range"].values[None],
        "shadow_fraction": nc["shadow_fraction"].values[None],
        "sky_view_fraction": nc["sky_view_fraction"].values[None],
        "sun_diffuse": nc["sun_diffuse"].values,  # a per-term layer (--geotiff all)
    }
    for name, values in expected.items():
        with rasterio.open(runs / "nc" / f"map_{name}.tif") as src:
            assert src.tags(ns="IMAGE_STRUCTURE")["LAYOUT"] == "COG", name
            assert src.profile["tiled"], name
            assert src.crs == crs, name
            assert src.res == pytest.approx((1.0, 1.0), rel=1e-9)
            assert src.bounds.left == pytest.approx(float(nc.x[0]) - 0.5, abs=1e-6)
            assert src.bounds.top == pytest.approx(float(nc.y[0]) + 0.5, abs=1e-6)
            data = src.read()
            tags = src.tags()
            if name in ("object_id", "material_id"):
                assert src.dtypes[0] == "int32" and src.nodata == -1
                np.testing.assert_array_equal(data, values)
            else:
                assert src.dtypes[0] == "float32" and np.isnan(src.nodata)
                np.testing.assert_array_equal(data, values.astype(np.float32))
                assert tags["units"] == nc[name].attrs["units"]
                assert src.tags(1)["units"] == nc[name].attrs["units"]
            if values.shape[0] > 1 or name in ("radiance", "brightness_temperature"):
                bands = nc["band"].values if name != "brightness_temperature" \
                    else nc["band"].values[thermal]
                assert src.descriptions == tuple(str(b) for b in bands)
            assert tags["scene_sha256"] == nc.attrs["scene_sha256"]  # provenance


def test_a_large_layer_gets_overviews(tmp_path):
    from radscene.io import write_cog
    from radscene.platform.geolocation import LocalFrame

    n = 1100
    y = (np.arange(n) + 0.5)[::-1]
    da = xr.DataArray(np.add.outer(y, y).astype(float), dims=("y", "x"),
                      coords={"y": y, "x": y[::-1]}, name="range", attrs={"units": "m"})
    path = write_cog(da, tmp_path / "big.tif", LocalFrame(46.5, 6.6, 400.0))
    with rasterio.open(path) as src:
        assert src.tags(ns="IMAGE_STRUCTURE")["LAYOUT"] == "COG"
        assert src.block_shapes[0] == (512, 512)
        assert src.overviews(1) == [2, 4]
        np.testing.assert_array_equal(src.read(1), da.values.astype(np.float32))


def test_band_radiance_as_envi_reads_back_with_the_spectral_package(runs):
    envi = pytest.importorskip("spectral.io.envi")
    nc = read_netcdf(runs / "nc" / "map.nc")
    image = envi.open(str(runs / "nc" / "map.hdr"), str(runs / "nc" / "map.img"))
    np.testing.assert_array_equal(np.moveaxis(np.asarray(image.load()), 2, 0),
                                  nc["radiance"].values.astype(np.float32))
    np.testing.assert_allclose(image.bands.centers, nc["wavelength_center"].values, rtol=1e-6)
    np.testing.assert_allclose(image.bands.bandwidths, nc["equivalent_width"].values, rtol=1e-6)
    assert image.bands.band_unit == "Micrometers"
    assert image.metadata["band names"] == ["vis", "lwir"]
    assert image.metadata["data units"] == "W m-2 sr-1"
    # the provenance, each attribute a JSON string that gives the text back exactly
    assert json.loads(image.metadata["scene_document"]) == nc.attrs["scene_document"]
    assert json.loads(image.metadata["scene_files"]) == nc.attrs["scene_files"]


def _map_info(metadata) -> dict:
    """The fields of an ENVI header's ``map info`` as the spectral package reads it."""
    fields = [f.strip() for f in metadata["map info"]]
    return {"projection": fields[0], "pixel": (float(fields[1]), float(fields[2])),
            "corner": (float(fields[3]), float(fields[4])),
            "size": (float(fields[5]), float(fields[6])), "rest": fields[7:]}


def test_band_envi_is_georeferenced_as_the_geotiffs(runs):
    envi = pytest.importorskip("spectral.io.envi")
    from pyproj import CRS

    image = envi.open(str(runs / "nc" / "map.hdr"), str(runs / "nc" / "map.img"))
    info = _map_info(image.metadata)
    nc = read_netcdf(runs / "nc" / "map.nc")
    nc_crs = xr.open_dataset(runs / "nc" / "map.nc").rio.crs
    with rasterio.open(runs / "nc" / "map_radiance.tif") as cog:
        transform, cog_crs = cog.transform, cog.crs
    # the tie point (1, 1) is the outer corner of the first pixel: the GeoTIFF's origin, and
    # half a pixel beyond the NetCDF file's first pixel centre
    assert info["projection"] == "Orthographic" and info["pixel"] == (1.0, 1.0)
    assert info["corner"] == pytest.approx((transform.c, transform.f), abs=1e-9)
    assert info["size"] == pytest.approx((transform.a, -transform.e), rel=1e-12)
    assert info["corner"] == pytest.approx((float(nc.x[0]) - 0.5, float(nc.y[0]) + 0.5),
                                           abs=1e-9)
    assert info["rest"] == ["WGS-84", "units=Meters"]
    # the coordinate system string (split on its commas by the spectral package) is the CRS
    wkt = ",".join(image.metadata["coordinate system string"])
    assert CRS.from_wkt(wkt).equals(CRS.from_wkt(nc_crs.to_wkt()), ignore_axis_order=True)
    # and GDAL reads the ENVI image onto the grid of the GeoTIFFs
    with rasterio.open(runs / "nc" / "map.img") as gdal_envi:
        assert gdal_envi.transform.almost_equals(transform, precision=1e-9)
        assert CRS.from_wkt(gdal_envi.crs.to_wkt()).equals(CRS.from_wkt(cog_crs.to_wkt()),
                                                           ignore_axis_order=True)


def test_a_perspective_view_in_envi_has_no_map_info(tmp_path):
    scene = tmp_path / "scene.yaml"
    scene.write_text(SCENE + "  - {name: cam, type: perspective, position: [0, -60, 40], "
                     "look_at: [0, 0, 0], fov: 40 deg, shape: [6, 8]}\n")
    _run("render", scene, "-o", tmp_path / "out", "--observer", "cam", "--envi",
         "--no-quicklooks", "-q")
    header = (tmp_path / "out" / "cam.hdr").read_text()
    assert "samples = 8" in header.splitlines()
    assert "map info" not in header and "coordinate system string" not in header


def test_quiet_prints_nothing_and_verbose_each_stage(tmp_path, one_line_refusal):
    scene = tmp_path / "scene.yaml"
    scene.write_text(SCENE)
    quiet = _run("render", scene, "-o", tmp_path / "q", "--quiet", "--no-quicklooks")
    assert quiet.output == ""
    assert (tmp_path / "q" / "map.nc").is_file() and (tmp_path / "q" / "manifest.json").is_file()
    loud = _run("render", scene, "-o", tmp_path / "v", "--verbose", "--no-quicklooks",
                "--geotiff", "radiance")
    for words in ("loaded", "checked; writing NetCDF, COG (radiance)", "map: rendered 10×14 px",
                  "wrote", "map.nc", "Cloud-Optimised GeoTIFF(s) (radiance, "
                  "brightness_temperature)", "mean L"):
        assert words in loud.output, words
    assert " s)" in loud.output  # the stages' times
    assert _run("check", scene, "-q").output == ""
    assert "loaded and validated" in _run("check", scene, "--verbose").output
    both = runner.invoke(app, ["render", str(scene), "-o", str(tmp_path / "b"), "-q", "-v"])
    assert both.exit_code == 2 and one_line_refusal(both.output, "--quiet")
    bad = runner.invoke(app, ["render", str(scene), "-o", str(tmp_path / "b"), "-q",
                              "--geotiff", "some"])
    assert bad.exit_code == 2 and one_line_refusal(bad.output, "--geotiff", "maps")
    assert not (tmp_path / "b").exists()


def test_thermal_quiet_and_verbose(tmp_path):
    scene = tmp_path / "yard.yaml"
    scene.write_text(textwrap.dedent("""
        name: yard
        environment: {location: {latitude: 35.0, longitude: 0.0}, time: 2026-06-21T12:00:00Z}
        materials:
          soil: {reflectance: 0.2}
        objects:
          - {name: ground, shape: {type: plate, width: 20 m, length: 20 m}, material: asphalt}
        bands:
          - {name: lwir, min: 8 um, max: 12 um}
        observers:
          - {name: map, type: orthographic, center: [0, 0], gsd: 1 m, shape: [4, 4]}
        thermal: {step: 30 min, hemisphere_samples: 4}
    """))
    span = ["--start", "2026-06-21T11:00:00Z", "--end", "2026-06-21T12:00:00Z", "--no-plots"]
    quiet = _run("thermal", scene, "-o", tmp_path / "q.nc", "--quiet", *span)
    assert quiet.output == "" and (tmp_path / "q.nc").is_file()
    loud = _run("thermal", scene, "-o", tmp_path / "v.nc", "--verbose", *span)
    assert "heat balance solved: 3 time step(s)" in loud.output
    assert "wrote" in loud.output and str(tmp_path / "v.nc") in loud.output


def test_a_map_product_opens_in_gdal_terms(runs):
    """The grid mapping carries GDAL's GeoTransform of the pixel edges (rioxarray writes it):
    the transform rioxarray reads from the file equals the one from the x/y coordinates."""
    opened = xr.open_dataset(runs / "nc" / "map.nc")
    x, y = opened["x"].values, opened["y"].values
    got = [float(v) for v in opened["crs"].attrs["GeoTransform"].split()]
    dx, dy = x[1] - x[0], y[1] - y[0]
    np.testing.assert_allclose(got, [x[0] - dx / 2, dx, 0.0, y[0] - dy / 2, 0.0, dy])
    assert opened["radiance"].rio.transform() == opened.rio.transform()
