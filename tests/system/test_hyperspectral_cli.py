"""Hyperspectral mode on the command line: the cube in NetCDF and ENVI, and bad grids refused
with one line naming the key, exit code 2, nothing written."""

from __future__ import annotations

import textwrap
from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

from radscene.cli import app
from radscene.io import read_netcdf

GOOD = textwrap.dedent("""
    name: tiny_hsi
    environment:
      sun: {zenith: 30 deg, azimuth: 180 deg}
      atmosphere: {type: uniform, transmittance: {wavelength: [0.35, 3.0], values: [0.8, 0.9]},
                   path_radiance: 2.0, sky_radiance: 3.0}
    materials:
      paint: {reflectance: 0.4}
    objects:
      - {name: plate, shape: {type: plate, width: 50 m, length: 50 m}, material: paint,
         temperature: 300 K}
    observers:
      - {name: hsi, type: orthographic, center: [0, 0], gsd: 1 m, shape: [4, 6],
         spectral: {min: 400 nm, max: 1000 nm, step: 10 nm}}
""")

runner = CliRunner()


def _run(tmp_path: Path, text: str):
    scene = tmp_path / "scene.yaml"
    scene.write_text(text)
    out = tmp_path / "out"
    return runner.invoke(app, ["render", str(scene), "-o", str(out)]), out


def test_spectral_observer_writes_netcdf_and_envi(tmp_path):
    result, out = _run(tmp_path, GOOD)
    assert result.exit_code == 0, result.output
    assert "61 channels 0.4–1 µm" in result.output
    cube = read_netcdf(out / "hsi_spectral.nc")
    assert cube["radiance"].dims == ("wavelength", "y", "x")
    assert cube["radiance"].shape == (61, 4, 6)
    assert cube["radiance"].attrs["units"] == "W m-2 sr-1 um-1"
    np.testing.assert_allclose(cube["wavelength"].values, np.linspace(0.4, 1.0, 61), rtol=1e-12)
    image = np.fromfile(out / "hsi_spectral.img", dtype="<f4").reshape(61, 4, 6)
    np.testing.assert_array_equal(image, cube["radiance"].values)
    header = (out / "hsi_spectral.hdr").read_text()
    for line in ("samples = 6", "lines = 4", "bands = 61", "interleave = bsq", "data type = 4",
                 "byte order = 0", "wavelength units = Micrometers"):
        assert line in header.splitlines()
    assert "fwhm = {0.005000, 0.010000," in header


def test_terms_true_writes_each_term_as_a_spectral_variable(tmp_path):
    result, out = _run(tmp_path, GOOD.replace("step: 10 nm}", "step: 10 nm, terms: true}"))
    assert result.exit_code == 0, result.output
    cube = read_netcdf(out / "hsi_spectral.nc")
    names = ["sun_diffuse", "sun_specular", "thermal_emission", "sky_reflected",
             "path_radiance", "background_reflected", "multiple_reflection",
             "diffuse_transmitted", "adjacency"]
    assert set(names) <= set(cube.data_vars)
    total = sum(cube[n].values.astype(float) for n in names)
    for name in names:
        assert cube[name].dims == ("wavelength", "y", "x") and cube[name].shape == (61, 4, 6)
        assert cube[name].dtype == np.float32
        assert cube[name].attrs["units"] == "W m-2 sr-1 um-1"
    assert float(cube["sun_diffuse"].min()) > 0.0 and float(cube["path_radiance"].min()) > 0.0
    size = sum(np.abs(cube[n].values.astype(float)) for n in names)
    np.testing.assert_array_less(np.abs(total - cube["radiance"].values),
                                 float(np.finfo(np.float32).eps) * size)
    # the ENVI image stays the radiance alone
    image = np.fromfile(out / "hsi_spectral.img", dtype="<f4")
    np.testing.assert_array_equal(image.reshape(61, 4, 6), cube["radiance"].values)
    # without terms, none
    (tmp_path / "plain").mkdir()
    result, out = _run(tmp_path / "plain", GOOD)
    assert result.exit_code == 0, result.output
    assert "sun_diffuse" not in read_netcdf(out / "hsi_spectral.nc").data_vars


def test_envi_file_reads_back_with_the_spectral_package(tmp_path):
    envi = pytest.importorskip("spectral.io.envi")
    result, out = _run(tmp_path, GOOD)
    assert result.exit_code == 0, result.output
    image = envi.open(str(out / "hsi_spectral.hdr"), str(out / "hsi_spectral.img"))
    cube = read_netcdf(out / "hsi_spectral.nc")
    np.testing.assert_array_equal(np.moveaxis(np.asarray(image.load()), 2, 0),
                                  cube["radiance"].values)
    np.testing.assert_allclose(image.bands.centers, cube["wavelength"].values, rtol=1e-6)
    np.testing.assert_allclose(image.bands.bandwidths, cube["fwhm"].values, rtol=1e-6)
    # an orthographic observer: georeferenced, the tie point (1, 1) at the outer corner of
    # the first pixel, in the CRS of the NetCDF file's grid mapping
    import rioxarray  # noqa: F401 - the .rio accessor
    import xarray as xr
    from pyproj import CRS

    info = [f.strip() for f in image.metadata["map info"]]
    assert info[:3] == ["Orthographic", "1", "1"] and info[7:] == ["WGS-84", "units=Meters"]
    x, y = cube["x"].values, cube["y"].values
    assert [float(v) for v in info[3:7]] == pytest.approx(
        [x[0] - 0.5, y[0] + 0.5, x[1] - x[0], y[0] - y[1]], abs=1e-9)
    crs = xr.open_dataset(out / "hsi_spectral.nc").rio.crs
    wkt = ",".join(image.metadata["coordinate system string"])
    assert CRS.from_wkt(wkt).equals(CRS.from_wkt(crs.to_wkt()), ignore_axis_order=True)


BAD = {
    "zero step": (GOOD.replace("step: 10 nm", "step: 0 nm"), "observers[0].spectral.step"),
    "negative step": (GOOD.replace("step: 10 nm", "step: -10 nm"),
                      "observers[0].spectral.step: must be > 0 µm"),
    "empty grid": (GOOD.replace("max: 1000 nm", "max: 400 nm"),
                   "observers[0].spectral.max: must be above min"),
    "one channel": (GOOD.replace("step: 10 nm", "step: 1 um"),
                    "observers[0].spectral.step"),
    "beyond the atmosphere": (GOOD.replace("max: 1000 nm", "max: 4 um"),
                              "observers[0].spectral: the 'uniform' atmosphere covers 0.35–3 µm"),
    "bands and a grid": (GOOD.replace("spectral:", "bands: [vis], spectral:").replace(
        "observers:", "bands: [{name: vis, min: 0.5, max: 0.6}]\nobservers:"),
        "observers[0].bands: a spectral observer renders its grid"),
    "terms not a boolean": (GOOD.replace("step: 10 nm}", "step: 10 nm, terms: sometimes}"),
                            "observers[0].spectral.terms"),
    "no bands and no grid": (GOOD.replace(",\n     spectral: {min: 400 nm, max: 1000 nm, "
                                          "step: 10 nm}", ""), "bands: give at least one band"),
}


@pytest.mark.parametrize("case", sorted(BAD))
def test_bad_grid_is_one_line_exit_2_and_writes_nothing(tmp_path, case):
    text, expected = BAD[case]
    assert text != GOOD
    result, out = _run(tmp_path, text)
    assert result.exit_code == 2, result.output
    message = result.output.strip()
    assert expected in message, message
    assert "Traceback" not in message
    assert len(message.splitlines()) == 1, message
    assert not out.exists()
