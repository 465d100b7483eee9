"""Bad files a scene names: one line naming the scene key, exit code 2, never a traceback."""

from __future__ import annotations

import copy

import numpy as np
import pytest
import yaml
from typer.testing import CliRunner

from radscene.cli import app

BASE = {
    "name": "files",
    "environment": {"sun": {"zenith": 30, "azimuth": 180}, "atmosphere": {"type": "none"}},
    "materials": {"paint": {"reflectance": 0.4}},
    "objects": [{"name": "plate", "shape": {"type": "plate", "width": 50, "length": 50},
                 "material": "paint", "temperature": "300 K"}],
    "bands": [{"name": "vis", "min": "0.5 um", "max": "0.6 um"}],
    "observers": [{"name": "nadir", "type": "orthographic", "center": [0, 0], "gsd": 1,
                   "shape": [4, 4], "altitude": 1000}],
}


def _binary(path):
    path.write_bytes(bytes(range(256)) * 2)


def _pickled(path):
    np.save(path, np.array([{"a": 1}], dtype=object), allow_pickle=True)


def _empty(path):
    path.write_bytes(b"")


def _corrupt_png(path):
    path.write_bytes(b"\x89PNG\r\n\x1a\n" + bytes(50))


def _geotiff(path, crs):
    import rasterio
    from rasterio.transform import from_origin

    with rasterio.open(path, "w", driver="GTiff", height=3, width=4, count=1, dtype="float32",
                       crs=crs, transform=from_origin(5.0, 45.0, 0.001, 0.001)) as dst:
        dst.write(np.zeros((3, 4), np.float32), 1)


def _text(content):
    return lambda path: path.write_text(content)


def _texture(scene, name):
    scene["objects"][0]["textures"] = {"reflectance": {"file": name, "size": [10, 10]}}


def _sensor(scene, name):
    scene["sensors"] = {"cam": {"file": name}}
    scene["observers"][0]["sensor"] = "cam"


def _weather(scene, name):
    """The heat balance runs (a thermal band, a surface without a fixed temperature) and reads
    the weather file: `radscene check` reads it too."""
    scene["environment"] = {**scene["environment"], "time": "2026-06-21T10:00:00Z",
                            "location": {"latitude": 45.0, "longitude": 5.0}}
    scene["objects"][0].pop("temperature")
    scene["bands"].append({"name": "lwir", "min": "8 um", "max": "12 um"})
    scene["thermal"] = {"weather": {"file": name}}


CASES = {
    "binary DEM": ("junk.npy", _binary, lambda s, f: s.update(
        terrain={"type": "dem", "file": f, "spacing": [1, 1], "material": "paint"}),
        "terrain.file"),
    "pickled DEM": ("obj.npy", _pickled, lambda s, f: s.update(
        terrain={"type": "dem", "file": f, "spacing": [1, 1], "material": "paint"}),
        "terrain.file"),
    "binary mesh": ("junk.obj", _binary, lambda s, f: s["objects"].append(
        {"name": "m", "shape": {"type": "mesh", "file": f}, "material": "paint",
         "temperature": "300 K"}), "objects[1].shape.file"),
    "binary band response": ("junk.csv", _binary, lambda s, f: s["bands"].append(
        {"name": "j", "file": f}), "bands[1]"),
    "binary reflectance": ("junk.csv", _binary, lambda s, f: s["materials"].update(
        paint={"reflectance": {"file": f}}), "materials.paint.reflectance"),
    "corrupt texture PNG": ("junk.png", _corrupt_png, lambda s, f: _texture(s, f),
                            "objects[0].textures.reflectance"),
    "empty texture .npy": ("empty.npy", _empty, lambda s, f: _texture(s, f),
                           "objects[0].textures.reflectance"),
    "empty sensor file": ("cam.yaml", _empty, lambda s, f: _sensor(s, f), "sensors.cam.file"),
    "binary sensor file": ("cam.yaml", _binary, lambda s, f: _sensor(s, f), "sensors.cam.file"),
    "sensor file of a list": ("cam.yaml", _text("- 1\n- 2\n"), lambda s, f: _sensor(s, f),
                              "sensors.cam.file"),
    "malformed sensor YAML": ("cam.yaml", _text("a: [1, 2\n"), lambda s, f: _sensor(s, f),
                              "sensors.cam.file"),
    "binary weather CSV": ("wx.csv", _binary, lambda s, f: _weather(s, f), "thermal.weather.file"),
    "empty weather CSV": ("wx.csv", _empty, lambda s, f: _weather(s, f), "thermal.weather.file"),
    "weather CSV of other columns": ("wx.csv", _text("a,b\n1,2\n"), lambda s, f: _weather(s, f),
                                     "thermal.weather.file"),
    "weather NetCDF of text": ("wx.nc", _text("hello"), lambda s, f: _weather(s, f),
                               "thermal.weather.file"),
    "missing weather file": ("wx.csv", None, lambda s, f: _weather(s, f), "thermal.weather.file"),
    "DEM in geographic degrees": ("deg.tif", lambda p: _geotiff(p, "EPSG:4326"), lambda s, f: s.update(
        terrain={"type": "dem", "file": f, "material": "paint"}), "terrain.file"),
}


@pytest.mark.parametrize("case", CASES)
def test_a_bad_file_is_one_line_naming_its_key(tmp_path, case):
    name, make, put, key = CASES[case]
    if make is not None:
        make(tmp_path / name)
    scene = copy.deepcopy(BASE)
    put(scene, name)
    path = tmp_path / "scene.yaml"
    path.write_text(yaml.safe_dump(scene))
    result = CliRunner().invoke(app, ["check", str(path)])
    lines = [ln for ln in result.output.splitlines() if ln.strip()]
    assert result.exit_code == 2, result.output
    assert len(lines) == 1 and key in lines[0], result.output
    assert "Traceback" not in result.output


# -- the matrix: every reader of a scene × every kind of bad file --------------------------

#: Text of a file that is not what it should be; no error message may quote it.
SECRET = "hunter2-SECRET"


def _trajectory(scene, name):
    scene["objects"][0]["trajectory"] = {"file": name}


def _volume_grid(scene, name):
    scene["volumes"] = [{"name": "smoke", "shape": {"type": "box", "size": [4, 4, 2]},
                         "position": [0, 0, 5], "density": 1, "optical_depth": 0.5,
                         "temperature": "350 K", "profile": {"type": "grid", "file": name}}]


def _flat(scene, **extra):
    scene["terrain"] = {"type": "flat", "size": [10, 10], "spacing": 1, "material": "paint",
                        **extra}


def _wth(scene, name):
    _weather(scene, name)
    scene["thermal"]["weather"]["start"] = "2026-06-21T00:00:00Z"


#: reader → (file suffix, how the scene names the file, the key the error names)
READERS = {
    "DEM .npy": (".npy", lambda s, f: s.update(terrain={"type": "dem", "file": f, "spacing": [1, 1],
                                                         "material": "paint"}), "terrain.file"),
    "DEM GeoTIFF": (".tif", lambda s, f: s.update(terrain={"type": "dem", "file": f,
                                                            "material": "paint"}), "terrain.file"),
    "mesh OBJ": (".obj", lambda s, f: s["objects"].append(
        {"name": "m", "shape": {"type": "mesh", "file": f}, "material": "paint",
         "temperature": "300 K"}), "objects[1].shape.file"),
    "mesh PLY": (".ply", lambda s, f: s["objects"].append(
        {"name": "m", "shape": {"type": "mesh", "file": f}, "material": "paint",
         "temperature": "300 K"}), "objects[1].shape.file"),
    "band response": (".csv", lambda s, f: s["bands"].append({"name": "j", "file": f}), "bands[1]"),
    "spectrum": (".csv", lambda s, f: s["materials"].update(paint={"reflectance": {"file": f}}),
                 "materials.paint.reflectance"),
    "texture PNG": (".png", _texture, "objects[0].textures.reflectance"),
    "texture .npy": (".npy", _texture, "objects[0].textures.reflectance"),
    "sensor file": (".yaml", _sensor, "sensors.cam"),
    "weather CSV": (".csv", _weather, "thermal.weather.file"),
    "weather NetCDF": (".nc", _weather, "thermal.weather.file"),
    "weather .wth": (".wth", _wth, "thermal.weather.file"),
    "track CSV": (".csv", _trajectory, "objects[0].trajectory.file"),
    "track NetCDF": (".nc", _trajectory, "objects[0].trajectory.file"),
    "temperature map": (".tif", lambda s, f: _flat(s, temperature_map=f),
                        "terrain.temperature_map"),
    "material map": (".npy", lambda s, f: _flat(s, material_map={"type": "file", "file": f,
                                                                 "classes": {1: "paint"}}),
                     "terrain.material_map.file"),
    "temperature map PNG": (".png", lambda s, f: _flat(s, temperature_map=f),
                            "terrain.temperature_map"),
    "material map PNG": (".png", lambda s, f: _flat(s, material_map={
        "type": "file", "file": f, "classes": {1: "paint"}}), "terrain.material_map.file"),
    "density grid .npy": (".npy", _volume_grid, "volumes[0].profile.file"),
    "density grid NetCDF": (".nc", _volume_grid, "volumes[0].profile.file"),
    "spectral library": (".txt", lambda s, f: s["materials"].update(
        paint={"type": "file", "path": f}), "materials.paint"),
    "tabulated BRDF": (".csv", lambda s, f: s["materials"]["paint"].update(
        brdf={"type": "tabulated", "file": f}), "materials.paint.brdf"),
}


def _folder(path):
    path.mkdir()


def _npy(array, allow_pickle=False):
    """Write ``array`` in .npy format under the exact name given, whatever its suffix."""
    def write(path):
        with open(path, "wb") as f:
            np.save(f, array, allow_pickle=allow_pickle)
    return write


#: kind of bad file → how to make it (None: the file is missing)
KINDS = {
    "missing": None,
    "empty": _empty,
    "a folder": _folder,
    "binary": _binary,
    "words": _text(f"{SECRET} {SECRET}\n{SECRET}\n"),
    "a header then words": _text(f"time [s], x [m], y [m], z [m]\n{SECRET},1,2,3\n"),
    "ragged rows": _text(f"0.5,0.1\n0.6\n0.7,0.3,{SECRET}\n"),
    "YAML of other values": _text(f"optics: {SECRET}\nsensor: {{a: {SECRET}}}\n"),
    "a .npy of one dimension": _npy(np.arange(5.0)),
    "a .npy of NaN": _npy(np.full((4, 4, 4), np.nan)),
    "a pickled .npy": _npy(np.array([{"a": 1}], dtype=object), allow_pickle=True),
}


@pytest.mark.parametrize("kind", KINDS)
@pytest.mark.parametrize("reader", READERS)
def test_the_bad_file_matrix(tmp_path, reader, kind):
    """Each reader × each kind of bad file: exit code 2, one line naming the scene key, no
    traceback, and nothing of the file's content quoted."""
    suffix, put, key = READERS[reader]
    name = "input" + suffix
    if KINDS[kind] is not None:
        KINDS[kind](tmp_path / name)
    scene = copy.deepcopy(BASE)
    put(scene, name)
    path = tmp_path / "scene.yaml"
    path.write_text(yaml.safe_dump(scene))
    result = CliRunner().invoke(app, ["check", str(path)])
    lines = [ln for ln in result.output.splitlines() if ln.strip()]
    assert result.exit_code == 2, result.output
    assert len(lines) == 1 and key in lines[0], result.output
    assert "Traceback" not in result.output
    assert "SECRET" not in result.output.upper(), result.output


def test_an_atmosphere_database_is_named_relative_to_the_scene_folder(tmp_path, monkeypatch, one_line_refusal):
    """As every file of a scene: `file: mine.nc` beside the scene, run from elsewhere."""
    import shutil

    from radscene.atmosphere.database import shipped_databases

    shutil.copy(shipped_databases()["default"], tmp_path / "mine.nc")
    scene = copy.deepcopy(BASE)
    scene["environment"]["atmosphere"] = {"type": "database", "file": "mine.nc"}
    (tmp_path / "scene.yaml").write_text(yaml.safe_dump(scene))
    monkeypatch.chdir("/")
    result = CliRunner().invoke(app, ["check", str(tmp_path / "scene.yaml")])
    assert result.exit_code == 0, result.output
    (tmp_path / "mine.nc").write_bytes(bytes(range(256)))
    result = CliRunner().invoke(app, ["check", str(tmp_path / "scene.yaml")])
    assert result.exit_code == 2
    assert one_line_refusal(result.output).startswith(
        f"error: environment.atmosphere.file: cannot read the database {tmp_path / 'mine.nc'}")
