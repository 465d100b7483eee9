"""Provenance in every output, and ``radscene render --from`` rendering it again bit-identically."""

from __future__ import annotations

import hashlib
import json

import numpy as np
import pytest
import xarray as xr
import yaml
from typer.testing import CliRunner

import radscene
from radscene.cli import app
from radscene.pipeline.provenance import PROVENANCE_ATTRS

runner = CliRunner()


def _scene(tmp_path):
    """A DEM from a file, a reflectance spectrum from a file, the shipped atmosphere database,
    sampled sky and background light, a sensor with noise: everything that could differ."""
    yy, xx = np.mgrid[0:24, 0:24]
    np.save(tmp_path / "dem.npy", 3.0 * np.sin(xx / 4.0) * np.cos(yy / 5.0))
    (tmp_path / "paint.csv").write_text("wavelength_um,reflectance\n0.4,0.1\n0.7,0.5\n2.5,0.3\n14,0.05\n")
    scene = {
        "name": "provenance",
        "environment": {"time": "2026-06-21T10:00:00Z",
                        "location": {"latitude": 45.0, "longitude": 5.0},
                        "atmosphere": {"type": "database", "aerosol": "maritime",
                                       "aot550": 0.2}},
        "materials": {"paint": {"reflectance": {"file": "paint.csv"}}},
        "terrain": {"type": "dem", "file": "dem.npy", "spacing": [2, 2], "material": "paint",
                    "temperature": "295 K"},
        "objects": [{"name": "box", "shape": {"type": "box", "size": [6, 6, 4]},
                     "material": "paint", "temperature": "300 K"}],
        "bands": [{"name": "red", "min": "0.6 um", "max": "0.7 um"},
                  {"name": "lwir", "min": "8 um", "max": "14 um"}],
        "sensors": {"bolometer": {"example": "lwir_microbolometer",
                                  "detector": {"shape": [6, 6]}}},
        "observers": [{"name": "cam", "type": "perspective", "position": [0, -40, 30],
                       "look_at": [0, 0, 0], "bands": ["lwir"], "sensor": "bolometer"},
                      {"name": "vis", "type": "perspective", "position": [10, -40, 30],
                       "look_at": [0, 0, 0], "fov": 40, "shape": [12, 12]}],
        "render": {"sky_samples": 4, "background_samples": 4, "seed": 7},
    }
    path = tmp_path / "scene.yaml"
    path.write_text(yaml.safe_dump(scene, sort_keys=False))
    return path


def _render(args):
    result = runner.invoke(app, ["render", *map(str, args), "--no-quicklooks"])
    assert result.exit_code == 0, result.output
    return result


def _same_numbers(a: xr.Dataset, b: xr.Dataset):
    assert sorted(a.data_vars) == sorted(b.data_vars)
    for name in a.data_vars:
        assert np.array_equal(a[name].values, b[name].values, equal_nan=a[name].dtype.kind == "f"), name


def test_every_output_carries_its_provenance(tmp_path):
    path = _scene(tmp_path)
    _render([path, "-o", tmp_path / "out"])
    for name in ("cam.nc", "cam_signal.nc", "vis.nc"):
        with xr.open_dataset(tmp_path / "out" / name) as ds:
            attrs = dict(ds.attrs)
        missing = [k for k in PROVENANCE_ATTRS if k not in attrs]
        assert not missing, (name, missing)
        text = attrs["scene_document"]
        assert hashlib.sha256(text.encode()).hexdigest() == attrs["scene_sha256"]
        assert yaml.safe_load(text) == yaml.safe_load(path.read_text())
        assert attrs["scene_file"] == str(path.resolve())
        # the scene as read: every default filled in, quantities in SI
        resolved = yaml.safe_load(attrs["scene_resolved"])
        assert resolved == radscene.load_scene(path).spec.model_dump(mode="json")
        assert resolved["bands"][0]["min"] == pytest.approx(0.6)  # "0.6 um" read as um
        assert "supersample" in resolved["observers"][1]  # a default the file left out
        files = {f["key"]: f for f in json.loads(attrs["scene_files"])}
        assert set(files) == {"terrain.file", "materials.paint.reflectance.file"}
        dem = files["terrain.file"]
        assert dem["sha256"] == hashlib.sha256((tmp_path / "dem.npy").read_bytes()).hexdigest()
        engine = json.loads(attrs["atmosphere_engine"])
        assert engine["type"] == "database" and engine["settings"]["aerosol"] == "maritime"
        assert len(engine["database"]["sha256"]) == 64
        assert "maritime" in engine["description"]["aerosol_condition"]
        geometry = json.loads(attrs["observer_geometry"])
        assert geometry["settings"]["look_at"] == [0.0, 0.0, 0.0]
        if name.startswith("cam"):
            assert geometry["shape"] == [24, 24] and 0.0 < geometry["fov_deg"] < 90.0  # sensor's
        else:
            assert geometry["shape"] == [12, 12] and geometry["fov_deg"] == 40.0
        assert attrs["random_seed"] == 7
        versions = json.loads(attrs["library_versions"])
        assert versions["numpy"] == np.__version__ and "embreex" in versions
        assert attrs["radscene_version"] == radscene.__version__


def test_render_from_an_output_gives_the_same_numbers(tmp_path):
    path = _scene(tmp_path)
    _render([path, "-o", tmp_path / "out"])
    _render(["--from", tmp_path / "out" / "cam.nc", "-o", tmp_path / "again"])
    _render(["--from", tmp_path / "out" / "vis.nc", "-o", tmp_path / "again", "--overwrite"])
    for name in ("cam.nc", "cam_signal.nc", "vis.nc"):
        with xr.open_dataset(tmp_path / "out" / name) as a, \
                xr.open_dataset(tmp_path / "again" / name) as b:
            _same_numbers(a, b)
            for key in PROVENANCE_ATTRS:
                assert a.attrs[key] == b.attrs[key], key


def test_render_from_the_file_alone(tmp_path):
    """The output carries the files its scene names: moved elsewhere with the scene's folder
    gone (or with the files changed), it renders the same numbers from its own copies."""
    (tmp_path / "project").mkdir()
    path = _scene(tmp_path / "project")
    _render([path, "-o", tmp_path / "out"])
    with xr.open_dataset(tmp_path / "out" / "vis.nc") as ds:
        assert ds.attrs["scene_files_embedded"].startswith("yes: 2 file(s)")
        assert not any(n.startswith("file_") for n in ds.variables)  # not in the image's group
    sent = tmp_path / "colleague" / "vis.nc"
    sent.parent.mkdir()
    (tmp_path / "out" / "vis.nc").rename(sent)
    for f in (tmp_path / "project").iterdir():
        f.unlink()
    result = _render(["--from", sent, "-o", tmp_path / "again"])
    assert "terrain.file: taken from vis.nc" in result.output
    taken = tmp_path / "again" / "scene_files" / "terrain.file" / "dem.npy"
    assert taken.is_file()
    with xr.open_dataset(sent) as a, xr.open_dataset(tmp_path / "again" / "vis.nc") as b:
        _same_numbers(a, b)
        files = {f["key"]: f for f in json.loads(b.attrs["scene_files"])}
        assert files["terrain.file"]["path"] == str(taken.resolve())
        assert b.attrs["scene_files_embedded"].startswith("yes")


def test_render_from_refuses_a_changed_file_it_does_not_carry(tmp_path, one_line_refusal,
                                                              monkeypatch):
    from radscene.io import scene_files

    monkeypatch.setattr(scene_files, "EMBED_LIMIT", 100)
    path = _scene(tmp_path)
    _render([path, "-o", tmp_path / "out"])
    with xr.open_dataset(tmp_path / "out" / "cam.nc") as ds:
        assert ds.attrs["scene_files_embedded"].startswith("no: ")
    np.save(tmp_path / "dem.npy", np.zeros((24, 24)))
    result = runner.invoke(app, ["render", "--from", str(tmp_path / "out" / "cam.nc"),
                                 "-o", str(tmp_path / "again")])
    assert result.exit_code == 2
    one_line_refusal(result.output, "terrain.file", "changed since cam.nc")
    assert "does not carry it" in result.output
    assert not (tmp_path / "again" / "cam.nc").exists()


@pytest.mark.parametrize("case", ["both", "neither", "not netcdf", "no provenance", "edited"])
def test_render_from_bad_input_is_one_line(tmp_path, case):
    out = tmp_path / "out"
    if case == "both":
        args = [str(_scene(tmp_path)), "--from", "x.nc"]
    elif case == "neither":
        args = []
    elif case == "not netcdf":
        (tmp_path / "x.nc").write_text("hello")
        args = ["--from", str(tmp_path / "x.nc")]
    else:
        ds = xr.Dataset({"a": ("x", [1.0])})
        if case == "edited":
            ds.attrs = {"scene_document": "name: x\n", "scene_sha256": "0" * 64,
                        "scene_base_dir": str(tmp_path), "scene_files": "[]"}
        ds.to_netcdf(tmp_path / "x.nc", engine="h5netcdf")
        args = ["--from", str(tmp_path / "x.nc")]
    result = runner.invoke(app, ["render", *args, "-o", str(out)])
    lines = [ln for ln in result.output.splitlines() if ln.strip()]
    assert result.exit_code == 2, result.output
    assert len(lines) == 1 and "Traceback" not in result.output, result.output
    assert not out.exists()


def test_python_api_outputs_carry_it_too(tmp_path, monkeypatch):
    scene = yaml.safe_load(_scene(tmp_path).read_text())
    monkeypatch.chdir(tmp_path)
    scene["environment"]["atmosphere"] = {"type": "none"}
    scene["materials"]["paint"] = {"reflectance": 0.3}
    ds = radscene.render(scene, "cam")
    assert ds.attrs["scene_file"] == ""
    assert yaml.safe_load(ds.attrs["scene_document"]) == scene
    assert ds.attrs["scene_base_dir"] == str(tmp_path.resolve())  # a dict's files: from here
    assert {f["key"] for f in json.loads(ds.attrs["scene_files"])} == {"terrain.file"}


def _plate_view(tmp_path):
    """A flat 400 m plate seen by a perspective camera 100 m west of and 100 m above the point
    it looks at, and by a map camera."""
    scene = {
        "name": "plate_view",
        "environment": {"sun": {"zenith": 30.0, "azimuth": 180.0},
                        "atmosphere": {"type": "none"}},
        "materials": {"grey": {"reflectance": 0.3}},
        "objects": [{"name": "plate", "shape": {"type": "plate", "width": 400, "length": 400},
                     "material": "grey", "temperature": "300 K"}],
        "bands": [{"name": "red", "min": "0.6 um", "max": "0.7 um"}],
        "observers": [{"name": "oblique", "type": "perspective", "position": [-100, 20, 100],
                       "look_at": [0, 20, 0], "fov": 10, "shape": [8, 10]},
                      {"name": "map", "type": "orthographic", "center": [0, 0], "gsd": 2.0,
                       "shape": [4, 4], "altitude": 1000}],
        "render": {"sky_samples": 4},
    }
    path = tmp_path / "scene.yaml"
    path.write_text(yaml.safe_dump(scene, sort_keys=False))
    return path


def test_perspective_output_records_its_attitude_and_boresight_gsd(tmp_path):
    """A look-at camera's output records the attitude it was turned to (yaw = the azimuth of
    the boresight, east 90 deg; pitch = its elevation, 45 deg down; roll 0) and the GSD where
    the boresight meets the plate: the slant range sqrt(2) 100 m times the angular pitch
    2 tan(5 deg) / 10 across the line of sight, sqrt(2) times that on the plate seen at 45 deg."""
    path = _plate_view(tmp_path)
    _render([path, "-o", tmp_path / "out"])
    with xr.open_dataset(tmp_path / "out" / "oblique.nc") as ds:
        geometry = json.loads(ds.attrs["observer_geometry"])
    assert geometry["attitude_deg"] == pytest.approx([90.0, -45.0, 0.0], abs=1e-9)
    slant = 100.0 * np.sqrt(2.0)
    pitch = 2.0 * np.tan(np.radians(5.0)) / 10
    assert geometry["boresight_range_m"] == pytest.approx(slant, rel=1e-9)
    assert geometry["gsd_boresight_m"] == pytest.approx(slant * pitch, rel=1e-9)
    assert geometry["gsd_boresight_surface_m"] == pytest.approx(np.sqrt(2.0) * slant * pitch,
                                                                rel=1e-9)
    # a map camera's GSD is its own setting: no boresight to trace, no attitude derived
    with xr.open_dataset(tmp_path / "out" / "map.nc") as ds:
        geometry = json.loads(ds.attrs["observer_geometry"])
    assert geometry["gsd_m"] == 2.0
    assert "attitude_deg" not in geometry and "gsd_boresight_m" not in geometry


def test_a_boresight_that_meets_nothing_records_no_gsd(tmp_path):
    from radscene.pipeline.provenance import provenance

    scene = yaml.safe_load(_plate_view(tmp_path).read_text())
    scene["observers"][0].pop("look_at")
    scene["observers"][0]["attitude"] = [30.0, 10.0, 5.0]  # above the horizon, rolled
    geometry = json.loads(provenance(radscene.load_scene(scene), "oblique")["observer_geometry"])
    assert geometry["attitude_deg"] == [30.0, 10.0, 5.0]
    assert geometry["boresight_range_m"] is None and geometry["gsd_boresight_m"] is None
    assert geometry["gsd_boresight_surface_m"] is None


def test_a_zarr_store_carries_the_files_too(tmp_path):
    pytest.importorskip("zarr", reason="Zarr output needs the zarr extra")
    from radscene.io import scene_files

    path = _scene(tmp_path)
    _render([path, "-o", tmp_path / "out.zarr", "--observer", "vis"])
    store = tmp_path / "out.zarr" / "vis.zarr"
    held = scene_files.embedded(store)
    assert set(held) == {"terrain.file", "materials.paint.reflectance.file"}
    assert held["terrain.file"][1] == (tmp_path / "dem.npy").read_bytes()
    assert xr.open_zarr(store).attrs["scene_files_embedded"].startswith("yes")
