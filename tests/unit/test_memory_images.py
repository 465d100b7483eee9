"""An image's size from its header (radscene.scene.memory.image_header) and Pillow's limit
lifted while radscene reads what it has sized (radscene.materials.imagefile)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from PIL import Image

from radscene.materials.imagefile import pil_unlimited
from radscene.scene.memory import (
    IMAGE_TEXEL_BYTES,
    IMAGE_VALUE_COPIES,
    TEXTURE_TEXEL_BYTES,
    estimate,
    image_files,
    image_header,
)
from radscene.scene.schema import SceneSpec


@pytest.mark.parametrize("mode, shape, channels", [("L", (6, 5), 1), ("RGB", (6, 5, 3), 3),
                                                   ("RGBA", (6, 5, 4), 4), ("P", (6, 5), 4)])
def test_png_and_jpeg_headers_give_rows_columns_and_the_decoded_bytes(tmp_path, mode, shape,
                                                                      channels):
    """4 B a channel, as the readers decode them; a palette as four channels (RGBA)."""
    image = Image.fromarray(np.zeros(shape, np.uint8))
    image = image.convert("P") if mode == "P" else image
    assert image.mode == mode
    image.save(tmp_path / "a.png")
    assert image_header(tmp_path / "a.png") == (6, 5, 6 * 5 * channels * 4.0)
    if mode in ("L", "RGB"):
        image.save(tmp_path / "a.jpg")
        assert image_header(tmp_path / "a.jpg") == (6, 5, 6 * 5 * channels * 4.0)


def test_npy_and_geotiff_headers_give_their_dtype_and_every_band(tmp_path):
    import rasterio
    from rasterio.transform import from_origin

    np.save(tmp_path / "a.npy", np.zeros((6, 5, 2), np.float32))
    assert image_header(tmp_path / "a.npy") == (6, 5, 6 * 5 * 2 * 4.0)
    with rasterio.open(tmp_path / "a.tif", "w", driver="GTiff", height=6, width=5, count=3,
                       dtype="int16", crs="EPSG:32631",
                       transform=from_origin(6e5, 5e6, 1.0, 1.0)) as dst:
        dst.write(np.zeros((3, 6, 5), np.int16))
    assert image_header(tmp_path / "a.tif") == (6, 5, 6 * 5 * 3 * 2.0)


@pytest.mark.parametrize("name, content", [("a.png", b"\x89PNG\r\n\x1a\n" + bytes(50)),
                                           ("a.jpg", b""), ("a.npy", b"\x93NUMPY junk"),
                                           ("a.tif", b"II*\x00junk")])
def test_a_header_that_cannot_be_read_is_left_to_the_reader(tmp_path, name, content):
    (tmp_path / name).write_bytes(content)
    assert image_header(tmp_path / name) is None
    assert image_header(tmp_path / "missing.png") is None


def test_pillows_limit_is_lifted_while_reading_and_restored_after(monkeypatch):
    monkeypatch.setattr(Image, "MAX_IMAGE_PIXELS", 1234)
    with pil_unlimited():
        with pil_unlimited():
            assert Image.MAX_IMAGE_PIXELS is None
        assert Image.MAX_IMAGE_PIXELS is None
    assert Image.MAX_IMAGE_PIXELS == 1234
    with pytest.raises(RuntimeError), pil_unlimited():
        raise RuntimeError
    assert Image.MAX_IMAGE_PIXELS == 1234


def _spec(**terrain):
    return SceneSpec.model_validate({
        "name": "images",
        "environment": {"sun": {"zenith": 30, "azimuth": 180}, "atmosphere": {"type": "none"}},
        "terrain": {"type": "flat", "size": [10, 10], "spacing": 1, "material": "soil",
                    **terrain},
        "materials": {"soil": {"reflectance": 0.3}},
        "objects": [{"name": "plate", "shape": {"type": "plate", "width": 2, "length": 2},
                     "material": "soil", "textures": {
                         "emissivity": {"type": "tile", "file": "t.npy", "tile_size": [1, 1]},
                         "reflectance": {"type": "noise", "amplitude": 0.1, "scale": 1}}}],
        "bands": [{"name": "red", "min": "0.6 um", "max": "0.7 um"}],
        "observers": [{"name": "map", "type": "orthographic", "center": [0, 0], "gsd": 1.0,
                       "shape": [8, 8], "altitude": 3000}],
    })


def test_the_images_a_scene_names_and_their_place_in_the_estimate(tmp_path):
    """Every image key; a texture's multipliers count in every observer's estimate, a map's
    (resampled onto the terrain's grid, then dropped) only while it is read."""
    spec = _spec(temperature_map="/abs/temp.tif",
                 material_map={"type": "file", "file": "m.png", "classes": {1: "soil"}},
                 textures={"reflectance": {"file": "r.png", "size": [5, 5]}})
    assert image_files(spec, tmp_path) == [
        ("terrain.textures.reflectance.file", tmp_path / "r.png", True),
        ("terrain.material_map.file", tmp_path / "m.png", False),
        ("terrain.temperature_map", Path("/abs/temp.tif"), False),
        ("objects[0].textures.emissivity.file", tmp_path / "t.npy", True),
    ]
    assert image_files(spec, None) == []
    bare = estimate(_spec(), tmp_path)
    assert bare["images"] == [] and bare["textures"] == 0.0
    np.save(tmp_path / "t.npy", np.zeros((100, 200)))
    Image.fromarray(np.zeros((300, 400), np.uint8)).save(tmp_path / "m.png")
    est = estimate(_spec(material_map={"type": "file", "file": "m.png", "classes": {1: "soil"}}),
                   tmp_path)
    assert [(key, what) for _, key, what in est["images"]] == [
        ("terrain.material_map.file", "the image m.png (400 × 300 pixels)"),
        ("objects[0].textures.emissivity.file", "the image t.npy (200 × 100 pixels)")]
    base = bare["terrain"][0]
    assert est["images"][0][0] == pytest.approx(
        base + 300 * 400 * (IMAGE_TEXEL_BYTES + IMAGE_VALUE_COPIES * 4.0))
    assert est["images"][1][0] == pytest.approx(
        base + 100 * 200 * (IMAGE_TEXEL_BYTES + IMAGE_VALUE_COPIES * 8.0))
    assert est["textures"] == 100 * 200 * TEXTURE_TEXEL_BYTES
    assert est["observers"][0][0] == pytest.approx(bare["observers"][0][0] + est["textures"])


def test_a_resolving_grid_counts_its_channel_passes_in_the_estimate():
    """render.spectral_grid: the band observer's estimate holds a pass of the grid's channels
    besides its bands (its what-line says so)."""
    from radscene.scene.memory import CHANNEL_BYTES

    bare = estimate(_spec())["observers"][0]
    spec = _spec().model_dump(mode="json")
    spec["render"] = {"spectral_grid": {"min": 0.6, "max": 0.7, "step": 0.01}}
    resolving = estimate(SceneSpec.model_validate(spec))["observers"][0]
    assert resolving[0] > bare[0] + 11 * CHANNEL_BYTES
    assert "render.spectral_grid" in resolving[2]
