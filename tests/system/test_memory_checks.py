"""Sizes are checked before work: a terrain grid or an observer too large for the memory limit
is one line naming its key and the figure, exit code 2, before anything is built."""

from __future__ import annotations

import time

import pytest
import yaml
from typer.testing import CliRunner

import radscene
from radscene.cli import app
from radscene.errors import ConfigError
from radscene.scene.memory import estimate, parse_memory


def _scene(size=200.0, spacing=2.0, shape=(64, 64), supersample=1, **render):
    return {
        "name": "sizes",
        "environment": {"sun": {"zenith": 30, "azimuth": 180}, "atmosphere": {"type": "none"}},
        "terrain": {"type": "procedural", "size": [size, size], "spacing": spacing,
                    "material": "soil"},
        "materials": {"soil": {"reflectance": 0.3}},
        "bands": [{"name": "red", "min": "0.6 um", "max": "0.7 um"}],
        "observers": [{"name": "map", "type": "orthographic", "center": [0, 0], "gsd": 1.0,
                       "shape": list(shape), "supersample": supersample, "altitude": 3000}],
        "render": render,
    }


def test_a_terrain_grid_too_large_is_refused_before_it_is_built():
    started = time.perf_counter()
    # 1 000 000 km² at 1 m: 1e12 cells, 400 TB; refused in well under a second
    with pytest.raises(ConfigError, match=r"terrain\.spacing: the terrain grid needs about"):
        radscene.load_scene(_scene(size=1e6, spacing=1.0))
    assert time.perf_counter() - started < 2.0


def test_an_observer_too_large_names_its_shape_and_the_figure():
    with pytest.raises(ConfigError, match=r"observers\[0\]\.shape: rendering it needs about "
                                          r"\d+\.\d GB .*the limit is 2\.0 GB \(--max-memory\)"):
        radscene.load_scene(_scene(shape=(4096, 4096), supersample=4), max_memory="2 GB")


def test_the_scene_files_limit_and_the_estimate_scale():
    with pytest.raises(ConfigError, match=r"render\.max_memory"):
        radscene.load_scene(_scene(shape=(2048, 2048), max_memory="0.5 GB"))
    spec = radscene.load_scene(_scene()).spec
    small = estimate(spec)["observers"][0][0]
    spec4 = radscene.load_scene(_scene(supersample=4)).spec
    assert estimate(spec4)["observers"][0][0] > small


@pytest.mark.parametrize("text, value", [("8 GB", 8e9), ("512MiB", 512 * 2 ** 20), (1e9, 1e9)])
def test_memory_sizes_parse(text, value):
    assert parse_memory(text) == value


@pytest.mark.parametrize("text", ["lots", "-1 GB", "8 parsecs", 0])
def test_bad_memory_sizes_are_refused(text):
    with pytest.raises(ConfigError, match="a memory size"):
        parse_memory(text)


def test_cli_refuses_before_work_and_check_reports_the_estimate(tmp_path, one_line_refusal):
    path = tmp_path / "s.yaml"
    path.write_text(yaml.safe_dump(_scene(shape=(4096, 4096), supersample=4)))
    runner = CliRunner()
    result = runner.invoke(app, ["render", str(path), "-o", str(tmp_path / "out"),
                                 "--max-memory", "1GB"])
    assert result.exit_code == 2, result.output
    one_line_refusal(result.output, "observers[0].shape")
    assert not (tmp_path / "out").exists()
    path.write_text(yaml.safe_dump(_scene()))
    result = runner.invoke(app, ["check", str(path)])
    assert result.exit_code == 0, result.output
    assert "memory: about" in result.output


# -- sizes known from a file's header, a span or a grid: checked before the first step --------

def _dem_scene(name):
    scene = _scene()
    scene["terrain"] = {"type": "dem", "file": name, "spacing": [1, 1], "material": "soil"}
    scene["observers"][0]["shape"] = [8, 8]
    return scene


def test_a_dem_file_is_sized_from_its_header_before_it_is_read(tmp_path):
    """A .npy DEM whose header says 30 000 × 30 000 (its samples absent): refused for its size,
    not for the missing samples, so none was read; a GeoTIFF by its width × height."""
    import numpy as np
    import rasterio
    from rasterio.transform import from_origin

    header = np.lib.format.header_data_from_array_1_0(np.zeros((2, 2)))
    header["shape"] = (30000, 30000)
    with open(tmp_path / "big.npy", "wb") as f:
        np.lib.format.write_array_header_1_0(f, header)
    with pytest.raises(ConfigError, match=r"terrain\.file: the terrain grid needs about 36\d\.\d "
                                          r"GB; .*a DEM resampled coarser or cropped"):
        radscene.load_scene(_dem_scene("big.npy"), base_dir=tmp_path)
    with rasterio.open(tmp_path / "big.tif", "w", driver="GTiff", height=1500, width=1500,
                       count=1, dtype="float32", crs="EPSG:32631",
                       transform=from_origin(6e5, 5e6, 1.0, 1.0)) as dst:
        dst.write(np.zeros((1500, 1500), np.float32), 1)
    with pytest.raises(ConfigError, match=r"terrain\.file: the terrain grid needs about 1\.2 GB"):
        radscene.load_scene(_dem_scene("big.tif"), base_dir=tmp_path, max_memory="1 GB")


def test_too_many_channels_name_the_spectral_step():
    scene = _scene()
    scene["observers"][0]["spectral"] = {"min": "0.4 um", "max": "20 um", "step": "0.001 nm"}
    started = time.perf_counter()
    with pytest.raises(ConfigError, match=r"observers\[0\]\.spectral\.step: .*1\.96e\+07 "
                                          r"channels.*a coarser spectral step"):
        radscene.load_scene(scene, max_memory="16 GB")
    assert time.perf_counter() - started < 5.0


def test_a_spectral_cube_gathered_in_memory_is_sized_before_the_render():
    """render_hyperspectral holds the whole cube (512² pixels × 2101 channels × 4 B = 2.2 GB):
    refused, naming the grid, where the pass-by-pass render fits."""
    scene = _scene(shape=(512, 512))
    scene["observers"][0]["spectral"] = {"min": "0.4 um", "max": "2.5 um", "step": "1 nm"}
    loaded = radscene.load_scene(scene, max_memory="2.2 GB")
    started = time.perf_counter()
    with pytest.raises(ConfigError, match=r"observers\[0\]\.spectral\.step: the spectral cube of "
                                          r"2,101 channels × 262,144 pixels in memory needs about "
                                          r"2\.5 GB; the limit is 2\.2 GB \(--max-memory\)"):
        radscene.render_hyperspectral(loaded, progress=False)
    assert time.perf_counter() - started < 2.0


def _sequence_scene(step="1 ms"):
    scene = _scene(shape=(64, 64))
    scene["time"] = {"start": "2026-06-21T10:00:00Z", "end": "2026-06-22T10:00:00Z", "step": step}
    return scene


def test_a_sequence_too_long_for_memory_is_refused_before_its_first_frame(tmp_path, one_line_refusal):
    import datetime as dt

    started = time.perf_counter()
    with pytest.raises(ConfigError, match=r"time\.step: the sequence of 86,400,001 frames .* "
                                          r"needs about \d+\.\d GB"):
        radscene.render_sequence(_sequence_scene(), progress=False)
    with pytest.raises(ConfigError, match=r"time\.step: the sequence of 31,536,001 frames"):
        radscene.render_sequence(_scene(), start=dt.datetime(2026, 1, 1, tzinfo=dt.UTC),
                                 end=dt.datetime(2027, 1, 1, tzinfo=dt.UTC), step=1.0,
                                 progress=False)
    assert time.perf_counter() - started < 5.0
    path = tmp_path / "s.yaml"
    path.write_text(yaml.safe_dump(_sequence_scene()))
    runner = CliRunner()
    result = runner.invoke(app, ["check", str(path)])
    assert result.exit_code == 2 and one_line_refusal(result.output, "time.step: the sequence of 86,400,001")
    out = tmp_path / "out"
    path.write_text(yaml.safe_dump(_sequence_scene(step="10 min")))
    result = runner.invoke(app, ["render", str(path), "-o", str(out), "--step", "1 ms"])
    assert result.exit_code == 2, result.output
    one_line_refusal(result.output, "error: --step: the sequence of 86,400,001 frames")
    assert not out.exists()
    result = runner.invoke(app, ["check", str(path)])
    assert result.exit_code == 0 and "sequence: 145 frames" in result.output, result.output


def _thermal_scene(step="1 s"):
    scene = _scene(size=100.0, spacing=1.0, shape=(8, 8))
    scene["environment"] = {"sun": {"zenith": 30, "azimuth": 180},
                            "atmosphere": {"type": "none"}, "time": "2026-06-21T12:00:00Z",
                            "location": {"latitude": 45.0, "longitude": 5.0}}
    scene["terrain"] = {"type": "flat", "size": [100, 100], "spacing": 1, "material": "concrete"}
    scene["bands"].append({"name": "lwir", "min": "8 um", "max": "12 um"})
    scene["thermal"] = {"start": "2025-06-21T00:00:00Z", "step": step}
    return scene


def test_a_heat_balance_too_large_is_refused_before_its_first_step(tmp_path, one_line_refusal):
    """10 000 elements × a year of 1 s steps: refused at once, never a MemoryError after
    minutes of work (it took 162 s to fail so)."""
    started = time.perf_counter()
    with pytest.raises(ConfigError, match=r"thermal\.step: the heat balance of 10,000 elements × "
                                          r"31,579,201 time steps × 20 nodes needs about"):
        radscene.solve_thermal(_thermal_scene(), progress=False)
    with pytest.raises(ConfigError, match=r"thermal\.step: the heat balance"):
        radscene.render(_thermal_scene(), progress=False)
    assert time.perf_counter() - started < 20.0
    path = tmp_path / "s.yaml"
    path.write_text(yaml.safe_dump(_thermal_scene()))
    runner = CliRunner()
    for args in (["check", str(path)], ["render", str(path), "-o", str(tmp_path / "out")]):
        result = runner.invoke(app, args)
        assert result.exit_code == 2, result.output
        one_line_refusal(result.output, "error: thermal.step: the heat balance of 10,000")
    assert not (tmp_path / "out").exists()
    path.write_text(yaml.safe_dump(_thermal_scene(step="10 min")))
    nc = tmp_path / "t.nc"
    result = runner.invoke(app, ["thermal", str(path), "-o", str(nc), "--step", "1 s"])
    assert result.exit_code == 2 and one_line_refusal(result.output, "error: --step: the heat balance")
    result = runner.invoke(app, ["thermal", str(path), "-o", str(nc), "--max-memory", "0.5GB"])
    assert result.exit_code == 2 and one_line_refusal(result.output, "(--max-memory)")
    assert not nc.exists()


# -- images a scene names: sized from their headers, none of their pixels read ---------------

def _png_header(path, width, height, colour=0):
    """A PNG whose header says ``width`` × ``height`` (8-bit; colour type 0 grey, 2 RGB) with
    four rows of pixels: a few hundred bytes, whatever the size it claims."""
    import struct
    import zlib

    def chunk(kind, data):
        return (struct.pack(">I", len(data)) + kind + data
                + struct.pack(">I", zlib.crc32(kind + data)))

    channels = {0: 1, 2: 3}[colour]
    rows = zlib.compress(bytes(width * channels + 1) * 4)
    path.write_bytes(b"\x89PNG\r\n\x1a\n"
                     + chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 8, colour, 0, 0, 0))
                     + chunk(b"IDAT", rows) + chunk(b"IEND", b""))


def _npy_header(path, shape, dtype="float64"):
    """A .npy file of only a header that says ``shape``: its values are absent."""
    import numpy as np

    header = np.lib.format.header_data_from_array_1_0(np.zeros((2, 2), dtype))
    header["shape"] = tuple(shape)
    with open(path, "wb") as f:
        np.lib.format.write_array_header_1_0(f, header)


def _sparse_geotiff(path, width, height):
    """A tiled GeoTIFF of ``width`` × ``height`` float32 pixels none of whose tiles is written."""
    import rasterio
    from rasterio.transform import from_origin

    with rasterio.open(path, "w", driver="GTiff", height=height, width=width, count=1,
                       dtype="float32", tiled=True, sparse_ok=True, crs="EPSG:32631",
                       transform=from_origin(6e5, 5e6, 1.0, 1.0)):
        pass


def _with_texture(scene, name):
    scene["objects"] = [{"name": "plate", "shape": {"type": "plate", "width": 20, "length": 20},
                         "material": "soil", "temperature": "300 K",
                         "textures": {"reflectance": {"file": name, "size": [10, 10]}}}]


#: image → (how the scene names it, how to write a huge one, the key the refusal names,
#: the figure: GB to read it with the default 300 MB base and the terrain's 4 MB)
IMAGES = {
    "object texture PNG": (_with_texture, lambda p: _png_header(p, 30000, 30000, colour=2),
                           "objects[0].textures.reflectance.file", "50.7"),
    "terrain tile texture .npy": (
        lambda s, f: s["terrain"].update(textures={"emissivity": {
            "type": "tile", "file": f, "texel_size": 1}}),
        lambda p: _npy_header(p, (30000, 30000)), "terrain.textures.emissivity.file", "43.5"),
    "material map PNG": (
        lambda s, f: s["terrain"].update(material_map={"type": "file", "file": f,
                                                       "classes": {0: "soil"}}),
        lambda p: _png_header(p, 30000, 30000), "terrain.material_map.file", "36.3"),
    "temperature map GeoTIFF": (
        lambda s, f: s["terrain"].update(temperature_map=f),
        lambda p: _sparse_geotiff(p, 30000, 30000), "terrain.temperature_map", "36.3"),
    "temperature map .npy": (
        lambda s, f: s["terrain"].update(temperature_map=f),
        lambda p: _npy_header(p, (30000, 30000), "float32"), "terrain.temperature_map", "36.3"),
}


@pytest.mark.parametrize("case", IMAGES)
def test_an_image_is_sized_from_its_header_before_it_is_read(tmp_path, case):
    """30 000 × 30 000 pixels (900 M, more than Pillow's own limit of 179 M), their values
    absent: refused for their size with radscene's message, not for the missing pixels, so none
    was read, and never with Pillow's."""
    put, make, key, figure = IMAGES[case]
    suffix = {"PNG": ".png", ".npy": ".npy", "GeoTIFF": ".tif"}[case.rsplit(" ", 1)[1]]
    make(tmp_path / f"big{suffix}")
    scene = _scene()
    put(scene, f"big{suffix}")
    started = time.perf_counter()
    with pytest.raises(ConfigError) as err:
        radscene.load_scene(scene, base_dir=tmp_path, max_memory="1 GB")
    assert time.perf_counter() - started < 5.0
    assert str(err.value).startswith(f"{key}: the image big{suffix} (30,000 × 30,000 pixels) "
                                     f"needs about {figure} GB to read, with the terrain; the "
                                     "limit is 1.0 GB (--max-memory): an image resampled "
                                     "coarser or cropped"), str(err.value)
    assert err.value.key == key
    assert "decompression" not in str(err.value).lower()
    # without --max-memory the machine's memory is the limit, or the scene's own
    scene["render"] = {"max_memory": "2 GB"}
    with pytest.raises(ConfigError, match=r"the limit is 2\.0 GB \(render\.max_memory\)"):
        radscene.load_scene(scene, base_dir=tmp_path)


def _plate_scene(texture):
    return {
        "name": "plate",
        "environment": {"sun": {"zenith": 30, "azimuth": 180}, "atmosphere": {"type": "none"}},
        "materials": {"paint": {"reflectance": 0.4}},
        "objects": [{"name": "plate", "shape": {"type": "plate", "width": 50, "length": 50},
                     "material": "paint", "temperature": "300 K",
                     "textures": {"reflectance": {"file": texture, "size": [10, 10]}}}],
        "bands": [{"name": "vis", "min": "0.5 um", "max": "0.6 um"}],
        "observers": [{"name": "nadir", "type": "orthographic", "center": [0, 0], "gsd": 1,
                       "shape": [4, 4], "altitude": 1000}],
    }


def test_cli_refuses_a_huge_texture_before_work(tmp_path, one_line_refusal):
    """`radscene check` and `radscene render`: exit code 2, one line naming the key and the
    figures, nothing written; the same scene with a small texture passes the same limit."""
    import numpy as np
    from PIL import Image

    _png_header(tmp_path / "huge.png", 40000, 40000)
    Image.fromarray(np.full((16, 16), 200, np.uint8)).save(tmp_path / "small.png")
    path = tmp_path / "s.yaml"
    path.write_text(yaml.safe_dump(_plate_scene("huge.png")))
    runner = CliRunner()
    out = tmp_path / "out"
    for args in (["check", str(path), "--max-memory", "2GB"],
                 ["render", str(path), "-o", str(out), "--max-memory", "2GB"]):
        result = runner.invoke(app, args)
        assert result.exit_code == 2, result.output
        one_line_refusal(result.output, "error: objects[0].textures.reflectance.file: the image "
                         "huge.png (40,000 × 40,000 pixels) needs about 64.3 GB to read; the limit "
                         "is 2.0 GB (--max-memory)")
        assert "decompression" not in result.output.lower()
    assert not out.exists()
    assert sorted(p.name for p in tmp_path.iterdir()) == ["huge.png", "s.yaml", "small.png"]
    path.write_text(yaml.safe_dump(_plate_scene("small.png")))
    result = runner.invoke(app, ["check", str(path), "--max-memory", "2GB"])
    assert result.exit_code == 0, result.output


def test_images_over_pillows_limit_within_the_memory_limit_are_read(tmp_path, monkeypatch):
    """Pillow's pixel-count limit (here lowered to 300 so that a 32 × 32 image passes it
    three times over; Pillow applies it to a JPEG it opens, and to any image
    radscene.materials.MaterialMap opens) neither refuses nor warns: radscene sized the images
    itself, and the limit is Pillow's again afterwards."""
    import warnings

    import numpy as np
    from PIL import Image

    from radscene.materials import MaterialMap

    monkeypatch.setattr(Image, "MAX_IMAGE_PIXELS", 300)
    Image.fromarray(np.full((32, 32), 200, np.uint8)).save(tmp_path / "grey.jpg")
    Image.fromarray(np.full((32, 32), 1, np.uint8)).save(tmp_path / "classes.jpg")
    Image.fromarray(np.full((32, 32), 1, np.uint8)).save(tmp_path / "classes.png")
    scene = _scene(shape=(8, 8))
    scene["terrain"].update(material_map={"type": "file", "file": "classes.jpg",
                                          "classes": {0: "soil", 1: "soil", 2: "soil"}},
                            textures={"reflectance": {"file": "grey.jpg", "size": [10, 10]}})
    with warnings.catch_warnings():
        warnings.simplefilter("error", Image.DecompressionBombWarning)
        loaded = radscene.load_scene(scene, base_dir=tmp_path, max_memory="2 GB")
        classes = MaterialMap.from_image(tmp_path / "classes.png", {1: "soil"}, size=(1, 1))
    terrain = loaded.objects[0]
    assert terrain.textures["reflectance"].values.shape == (32, 32)
    assert np.allclose(terrain.textures["reflectance"].values, 200 / 255, atol=2 / 255)
    assert classes.shape == (32, 32)
    assert Image.MAX_IMAGE_PIXELS == 300


# -- volumes' density grids: sized from their headers, none of their values read -------------

def _netcdf_header(path, shape, dtype="f4"):
    """A NetCDF-4 file whose variable ``density`` is declared ``shape`` (dims z, y, x) and
    never written: its chunks are not stored, the file holds a few kB."""
    import h5netcdf

    with h5netcdf.File(path, "w") as f:
        f.dimensions = dict(zip(("z", "y", "x"), shape, strict=True))
        f.create_variable("density", ("z", "y", "x"), dtype, chunks=(50, 50, 50))


def _grid_scene(name):
    scene = _plate_scene("small.png")
    scene["objects"][0].pop("textures")
    scene["volumes"] = [{"name": "smoke", "shape": {"type": "box", "size": [20, 20, 10]},
                         "position": [0, 0, 8], "extinction": 0.05, "temperature": "320 K",
                         "profile": {"type": "grid", "file": name}}]
    return scene


@pytest.mark.parametrize("name, make, figure", [
    ("big.npy", lambda p: _npy_header(p, (2000, 2000, 2000), "float32"), "104.3"),
    ("big.nc", lambda p: _netcdf_header(p, (2000, 2000, 2000)), "104.3"),
    ("big64.npy", lambda p: _npy_header(p, (1000, 1000, 1000), "float64"), "9.3"),
])
def test_a_density_grid_is_sized_from_its_header_before_it_is_read(tmp_path, name, make,
                                                                   figure):
    """8 000 M nodes (1 000 M of float64), their values absent: refused for their size in
    well under a second, naming the key the loader names for the file, so none was read."""
    make(tmp_path / name)
    assert (tmp_path / name).stat().st_size < 100_000
    scene = _grid_scene(name)
    started = time.perf_counter()
    with pytest.raises(ConfigError) as err:
        radscene.load_scene(scene, base_dir=tmp_path, max_memory="2 GB")
    assert time.perf_counter() - started < 5.0
    side = name.startswith("big64") and "1,000" or "2,000"
    assert str(err.value) == (
        f"volumes[0].profile.file: the density grid {name} ({side} × {side} × {side} nodes) "
        f"needs about {figure} GB to read; the limit is 2.0 GB (--max-memory): a grid "
        "resampled coarser or cropped")
    assert err.value.key == "volumes[0].profile.file"
    scene["render"] = {"max_memory": "3 GB"}
    with pytest.raises(ConfigError, match=r"the limit is 3\.0 GB \(render\.max_memory\)"):
        radscene.load_scene(scene, base_dir=tmp_path)


def test_a_second_grid_counts_the_first_and_the_terrain(tmp_path):
    """Read after the terrain and the grids before it, which stay held: the figure and the
    message say so; the grids count in every observer's estimate."""
    _npy_header(tmp_path / "a.npy", (500, 500, 500), "float32")  # 1.0 GB held
    _npy_header(tmp_path / "b.npy", (500, 500, 400), "float32")
    scene = _grid_scene("a.npy")
    scene["volumes"].append({**scene["volumes"][0], "name": "plume",
                             "profile": {"type": "grid", "file": "b.npy"}})
    scene["terrain"] = {"type": "flat", "size": [100, 100], "spacing": 1, "material": "paint"}
    with pytest.raises(ConfigError) as err:
        radscene.load_scene(scene, base_dir=tmp_path, max_memory="2.5 GB")
    assert str(err.value).startswith(
        "volumes[1].profile.file: the density grid b.npy (500 × 500 × 400 nodes) needs about "
        "2.6 GB to read, with the terrain and the density grids before it; the limit is 2.5 GB")
    from radscene.scene.memory import GRID_HELD_BYTES
    from radscene.scene.schema import SceneSpec

    spec = SceneSpec.model_validate(scene)
    est = estimate(spec, tmp_path)
    assert [key for _, key, _ in est["grids"]] == ["volumes[0].profile.file",
                                                   "volumes[1].profile.file"]
    assert est["grids_held"] == 225e6 * GRID_HELD_BYTES
    bare = estimate(SceneSpec.model_validate({**scene, "volumes": []}), tmp_path)
    assert est["observers"][0][0] == pytest.approx(bare["observers"][0][0] + 1.8e9)
    # grids of 512 MB and 8 MB held: read within 1.2 GB, but not rendered with 1024² pixels
    _npy_header(tmp_path / "c.npy", (400, 400, 400), "float64")
    _npy_header(tmp_path / "d.npy", (100, 100, 100), "float32")
    scene["volumes"][0]["profile"]["file"] = "c.npy"
    scene["volumes"][1]["profile"]["file"] = "d.npy"
    scene["observers"][0]["shape"] = [1024, 1024]
    with pytest.raises(ConfigError, match=r"^observers\[0\]\.shape: rendering it needs about "
                                          r"1\.4 GB \(.*, with the terrain and density grids\)"):
        radscene.load_scene(scene, base_dir=tmp_path, max_memory="1.2 GB")


@pytest.mark.parametrize("huge", ["huge.npy", "huge.nc"])
def test_cli_refuses_a_huge_density_grid_before_work(tmp_path, one_line_refusal, huge):
    """`radscene check` and `radscene render`: exit code 2, one line naming the key and the
    figures, no output folder; the same scene with a small grid renders within that limit."""
    import numpy as np

    if huge.endswith(".npy"):
        _npy_header(tmp_path / huge, (2000, 2000, 2000), "float32")
    else:
        _netcdf_header(tmp_path / huge, (2000, 2000, 2000))
    np.save(tmp_path / "small.npy", np.linspace(0.0, 2.0, 6 * 5 * 4).reshape(6, 5, 4))
    path = tmp_path / "s.yaml"
    path.write_text(yaml.safe_dump(_grid_scene(huge)))
    runner = CliRunner()
    out = tmp_path / "out"
    for args in (["check", str(path), "--max-memory", "2GB"],
                 ["render", str(path), "-o", str(out), "--max-memory", "2GB"]):
        result = runner.invoke(app, args)
        assert result.exit_code == 2, result.output
        one_line_refusal(result.output, "error: volumes[0].profile.file: the density grid "
                         f"{huge} (2,000 × 2,000 × 2,000 nodes) needs about 104.3 GB to read; "
                         "the limit is 2.0 GB (--max-memory)")
    assert not out.exists()
    assert sorted(p.name for p in tmp_path.iterdir()) == sorted([huge, "s.yaml", "small.npy"])
    path.write_text(yaml.safe_dump(_grid_scene("small.npy")))
    result = runner.invoke(app, ["render", str(path), "-o", str(out), "--max-memory", "2GB"])
    assert result.exit_code == 0, result.output
    assert (out / "nadir.nc").is_file()
