"""``radscene render -o OUT.zarr`` beyond single frames: spectral cubes and sequences as Zarr
stores holding what the NetCDF files hold, and a run stopped while it writes a store resumed
with --resume."""

from __future__ import annotations

import hashlib
import json
import os
import subprocess
import sys
import textwrap

import numpy as np
import pytest
import yaml
from typer.testing import CliRunner

from radscene.cli import app
from radscene.io import read_netcdf, read_zarr
from radscene.io.run_record import MANIFEST, MARKER

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

START = "2026-06-21T07:00:00+00:00"
SEQUENCE = {
    "name": "field",
    "environment": {"time": START, "location": {"latitude": 45.0, "longitude": 5.0},
                    "atmosphere": {"type": "none"}},
    "materials": {"grey": {"reflectance": 0.3}},
    "objects": [{"name": "ground", "shape": {"type": "plate", "width": 200, "length": 200},
                 "material": "grey", "temperature": "290 K"},
                {"name": "box", "shape": {"type": "box", "size": [10, 10, 8]},
                 "material": "grey", "temperature": "300 K"}],
    "bands": [{"name": "vis", "min": 0.5, "max": 0.6}, {"name": "lwir", "min": 8, "max": 12}],
    "observers": [{"name": "map", "type": "orthographic", "center": [0, 0], "gsd": 8.0,
                   "shape": [8, 8], "altitude": 1000}],
    "render": {"sky_samples": 4, "seed": 2},
    "time": {"start": START, "end": "2026-06-21T09:00:00+00:00", "step": "1 h"},
}

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
    opened = xr.open_zarr(out / "hsi_spectral.zarr")
    assert opened.rio.crs is not None
    assert opened["radiance"].attrs["grid_mapping"] == "crs"  # opened plainly: an attribute
    assert opened.rio.crs == xr.open_dataset(tmp_path / "nc" / "hsi_spectral.nc").rio.crs
    # opened plainly, the cube itself carries the grid mapping as a coordinate
    assert opened["radiance"].rio.crs == opened.rio.crs
    listed = {e["file"] for e in json.loads((out / MANIFEST).read_text())["files"]}
    assert {"hsi_spectral.zarr/.zmetadata", "hsi_spectral.zarr/radiance/.zarray",
            "hsi_spectral.img"} <= listed
    # checked before any work like the other outputs; rendered again from the store
    refused = runner.invoke(app, ["render", str(scene), "-o", str(out)])
    assert refused.exit_code == 2 and "hsi_spectral.zarr" in refused.output
    _run("render", "--from", out / "hsi_spectral.zarr", "-o", tmp_path / "again.zarr", "-q")
    np.testing.assert_array_equal(read_zarr(tmp_path / "again.zarr" / "hsi_spectral.zarr")[
        "radiance"].values, store["radiance"].values)


def test_a_sequence_goes_into_a_zarr_store(tmp_path):
    scene = tmp_path / "field.yaml"
    scene.write_text(yaml.safe_dump(SEQUENCE))
    _run("render", scene, "-o", tmp_path / "nc", "-q", "--no-quicklooks")
    _run("render", scene, "-o", tmp_path / "out.zarr", "-q", "--no-quicklooks")
    store = read_zarr(tmp_path / "out.zarr" / "map_sequence.zarr")
    nc = read_netcdf(tmp_path / "nc" / "map_sequence.nc")
    assert store["radiance"].dims == ("time", "band", "y", "x")
    assert store.sizes["time"] == 3
    assert [str(t)[:19] for t in store["time"].values] == [
        "2026-06-21T07:00:00", "2026-06-21T08:00:00", "2026-06-21T09:00:00"]
    _same_content(store, nc)
    import zarr

    radiance = zarr.open_group(tmp_path / "out.zarr" / "map_sequence.zarr", mode="r")["radiance"]
    assert radiance.chunks == (1, 1, 8, 8)  # a frame and a band per chunk
    # a complete sequence store has nothing to resume
    again = runner.invoke(app, ["render", str(scene), "-o", str(tmp_path / "out.zarr"),
                                "--resume", "--no-quicklooks"])
    assert again.exit_code == 2 and "\n" not in again.output.strip()

TWO = textwrap.dedent("""
    name: two
    environment:
      sun: {zenith: 30 deg, azimuth: 180 deg}
      atmosphere: {type: none}
    materials:
      paint: {reflectance: 0.4}
    objects:
      - {name: plate, shape: {type: plate, width: 500 m, length: 500 m}, material: paint,
         temperature: 300 K}
      - {name: box, shape: {type: box, size: [20, 20, 10]}, material: paint, temperature: 300 K}
    bands:
      - {name: vis, min: 0.5 um, max: 0.6 um}
    observers:
      - {name: quick, type: orthographic, center: [0, 0], gsd: 10 m, shape: [4, 4]}
      - {name: second, type: orthographic, center: [0, 0], gsd: 5 m, shape: [12, 10]}
""")

#: ``radscene render`` that sends itself SIGTERM once the store of observer ``second`` is
#: written in full under its temporary name, before it is moved into place.
STOPPED_WHILE_WRITING = textwrap.dedent("""
    import os, signal, sys
    import xarray as xr
    write = xr.Dataset.to_zarr
    def to_zarr(self, store, *args, **kwargs):
        result = write(self, store, *args, **kwargs)
        if os.path.basename(str(store)).startswith(".second.zarr."):
            os.kill(os.getpid(), signal.SIGTERM)
        return result
    xr.Dataset.to_zarr = to_zarr
    from radscene.cli import app
    sys.argv[0] = "radscene"
    app()
""")


def _digest(folder):
    return {p.relative_to(folder).as_posix(): hashlib.sha256(p.read_bytes()).hexdigest()
            for p in sorted(folder.rglob("*")) if p.is_file()}


def test_a_run_stopped_while_writing_a_store_resumes(tmp_path):
    scene = tmp_path / "two.yaml"
    scene.write_text(TWO)
    out = tmp_path / "out.zarr"
    args = ["render", str(scene), "-o", str(out), "--no-quicklooks", "--geotiff", "none"]
    env = {**os.environ, "PYTHONPATH": os.pathsep.join(sys.path)}
    stopped = subprocess.run([sys.executable, "-c", STOPPED_WHILE_WRITING, *args], env=env,
                             capture_output=True, text=True, timeout=600)
    assert stopped.returncode != 0, stopped.stdout
    # no half store, no temporary, the marker lists the observer finished, no manifest
    assert sorted(p.name for p in out.iterdir()) == [MARKER, "quick.zarr"]
    assert json.loads((out / MARKER).read_text())["finished"] == ["quick"]
    quick = _digest(out / "quick.zarr")

    resumed = subprocess.run([sys.executable, "-m", "radscene", *args, "--resume"], env=env,
                             capture_output=True, text=True, timeout=600)
    assert resumed.returncode == 0, resumed.stderr
    assert "resumed: quick already written" in resumed.stdout
    assert sorted(p.name for p in out.iterdir()) == [MANIFEST, "quick.zarr", "second.zarr"]
    assert _digest(out / "quick.zarr") == quick  # not written again
    manifest = json.loads((out / MANIFEST).read_text())
    assert {e["observer"] for e in manifest["files"]} == {"quick", "second"}
    assert "second.zarr/.zmetadata" in {e["file"] for e in manifest["files"]}
    second = read_zarr(out / "second.zarr")
    assert second["radiance"].shape == (1, 12, 10)
    assert np.isfinite(second["radiance"].values).all()
