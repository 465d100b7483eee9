"""The scene loader: terrain material and temperature maps, lakes where asked, key paths."""

from __future__ import annotations

import numpy as np
import pytest

from radscene import load_scene
from radscene.errors import ConfigError


def _base(terrain, **extra):
    scene = {
        "environment": {"sun": {"zenith": 30, "azimuth": 180}},
        "terrain": terrain,
        "bands": [{"name": "vis", "min": 0.5, "max": 0.6}],
        "observers": [{"name": "map", "type": "orthographic", "center": [50, 50], "gsd": 10,
                       "shape": [10, 10]}],
    }
    scene.update(extra)
    return scene


def test_material_and_temperature_maps_from_files(tmp_path):
    classes = np.zeros((20, 20), dtype=np.int64)
    classes[:, 10:] = 1  # east half is class 1
    np.save(tmp_path / "classes.npy", classes)
    temps = np.full((20, 20), 290.0)
    temps[:10, :] = 310.0  # north half is warm
    np.save(tmp_path / "temps.npy", temps)
    scene = load_scene(_base({
        "type": "dem", "elevation": np.zeros((11, 11)).tolist(), "spacing": [10, 10],
        "material_map": {"type": "file", "file": "classes.npy", "classes": {0: "sand", 1: "asphalt"}},
        "temperature_map": "temps.npy"}), base_dir=tmp_path)
    terrain = scene.objects[0]
    centroid = terrain.mesh.vertices[terrain.mesh.faces].mean(axis=1)
    names = np.array(scene.material_names)[terrain.face_material]
    assert set(names[centroid[:, 0] > 60]) == {"asphalt"}
    assert set(names[centroid[:, 0] < 40]) == {"sand"}
    assert set(terrain.face_temperature[centroid[:, 1] > 60]) == {310.0}
    assert set(terrain.face_temperature[centroid[:, 1] < 40]) == {290.0}


def test_unmapped_class_value_is_an_error(tmp_path):
    np.save(tmp_path / "classes.npy", np.array([[0, 7], [0, 0]]))
    with pytest.raises(ConfigError, match=r"terrain.material_map.classes: .*\[7\]"):
        load_scene(_base({"type": "dem", "elevation": np.zeros((11, 11)).tolist(),
                          "spacing": [10, 10],
                          "material_map": {"type": "file", "file": "classes.npy",
                                           "classes": {0: "sand"}}}), base_dir=tmp_path)


@pytest.mark.parametrize("origin", [(0.0, 0.0), (1000.0, -500.0)])
def test_procedural_lake_lies_where_asked(origin):
    ox, oy = origin
    scene = load_scene(_base({"type": "procedural", "size": [400, 400], "spacing": 5,
                              "origin": [ox, oy],
                              "lakes": [{"x": ox + 100, "y": oy + 300, "radius": 60}]}))
    hf = scene.heightfield
    assert hf.extent == pytest.approx((ox, ox + 400, oy, oy + 400))
    terrain = scene.objects[0]
    water = scene.material_names.index("water")
    centroid = terrain.mesh.vertices[terrain.mesh.faces].mean(axis=1)
    wet = centroid[terrain.face_material == water]
    assert np.hypot(wet[:, 0] - (ox + 100), wet[:, 1] - (oy + 300)).max() < 60 + 10


def test_object_outside_terrain_is_refused():
    scene = _base({"type": "procedural", "size": [100, 100], "spacing": 5},
                  objects=[{"name": "hut", "shape": {"type": "box", "size": [2, 2, 2]},
                            "position": [500, 0, 0], "material": "concrete"}])
    with pytest.raises(ConfigError, match=r"objects\[0\].position"):
        load_scene(scene)


def test_unknown_key_is_named():
    scene = _base({"type": "procedural", "size": [100, 100], "spacing": 5, "hills": 3})
    with pytest.raises(ConfigError, match=r"terrain.hills: unknown key"):
        load_scene(scene)


# -- a temperature map holds kelvin, never image levels ---------------------------------------

def _flat(temperature_map):
    return _base({"type": "flat", "size": [100, 100], "spacing": 10,
                  "temperature_map": temperature_map})


@pytest.mark.parametrize("name, levels", [("temps.png", np.uint8), ("temps.png", np.uint16),
                                          ("temps.jpg", np.uint8), ("temps.JPEG", np.uint8)])
def test_a_png_or_jpeg_temperature_map_is_refused_naming_the_key(tmp_path, name, levels):
    """An 8-bit PNG of 200 came out as 0.78 K, a 16-bit one of 300 as 0.0046 K, a JPEG of 200
    as 200 K (its levels): refused before the file is read, whatever it holds."""
    from PIL import Image

    Image.fromarray(np.full((8, 8), 200, levels)).save(tmp_path / name, format=(
        "PNG" if name.endswith(".png") else "JPEG"))
    with pytest.raises(ConfigError) as err:
        load_scene(_flat(name), base_dir=tmp_path)
    assert err.value.key == "terrain.temperature_map"
    assert str(err.value) == (
        "terrain.temperature_map: a temperature map holds kelvin: give a .npy array or a GeoTIFF "
        f"(.tif, .tiff) of temperatures; {name!r} is neither (a PNG or JPEG holds 8- or 16-bit "
        "levels, not temperatures)")
    with pytest.raises(ConfigError, match=r"^terrain\.temperature_map: a temperature map holds"):
        load_scene(_flat("missing.png"), base_dir=tmp_path)


@pytest.mark.parametrize("values, match", [
    (np.full((4, 4), 0.5), r"every value is at most 1 K \(the largest 0\.5\): these are image "
                           r"levels scaled to 0-1, not temperatures"),
    (np.linspace(0.01, 1.0, 16).reshape(4, 4), r"every value is at most 1 K"),
    (np.array([[300.0, 0.0], [300.0, 300.0]]), r"finite and > 0 K everywhere; the map holds 0 K"),
    (np.array([[300.0, -5.0], [300.0, 300.0]]), r"the map holds -5 K"),
    (np.array([[300.0, np.nan], [300.0, 300.0]]), r"values that are not finite"),
    (np.array([[300.0, np.inf], [300.0, 300.0]]), r"values that are not finite"),
])
def test_temperatures_not_above_0_k_or_levels_are_refused(tmp_path, values, match):
    np.save(tmp_path / "temps.npy", values)
    with pytest.raises(ConfigError, match=r"^terrain\.temperature_map: .*" + match) as err:
        load_scene(_flat("temps.npy"), base_dir=tmp_path)
    assert err.value.key == "terrain.temperature_map"


def test_integer_kelvin_in_a_npy_or_a_geotiff_is_read_as_kelvin(tmp_path):
    """Integer kelvin is legitimate; a map with one cold pixel among warm ones (below 1 K, not
    levels) is accepted too: no physical bound is imposed beyond > 0 K."""
    import rasterio
    from rasterio.transform import from_origin

    temps = np.full((10, 10), 290, np.uint16)
    temps[:5] = 310  # the north half
    np.save(tmp_path / "temps.npy", temps)
    with rasterio.open(tmp_path / "temps.tif", "w", driver="GTiff", height=10, width=10,
                       count=1, dtype="uint16", crs="EPSG:32631",
                       transform=from_origin(6e5, 5e6, 10.0, 10.0)) as dst:
        dst.write(temps, 1)
    cold = temps.astype(float)
    cold[9, 9] = 0.5
    np.save(tmp_path / "cold.npy", cold)
    for name in ("temps.npy", "temps.tif", "cold.npy"):
        terrain = load_scene(_flat(name), base_dir=tmp_path).objects[0]
        centroid = terrain.mesh.vertices[terrain.mesh.faces].mean(axis=1)
        assert set(terrain.face_temperature[centroid[:, 1] > 60]) == {310.0}, name
        assert set(terrain.face_temperature[(centroid[:, 1] < 40) & (centroid[:, 0] < 60)]) == {
            290.0}, name
        assert terrain.face_fixed.all()


# -- a material map's class values are the numbers the file stores --------------------------

def _classes(name):
    return _base({"type": "flat", "size": [100, 100], "spacing": 10, "material_map": {
        "type": "file", "file": name, "classes": {0: "sand", 3: "asphalt", 1000: "concrete"}}})


def _east_west(scene):
    terrain = scene.objects[0]
    centroid = terrain.mesh.vertices[terrain.mesh.faces].mean(axis=1)
    names = np.array(scene.material_names)[terrain.face_material]
    return set(names[centroid[:, 0] < 40]), set(names[centroid[:, 0] > 60])


@pytest.mark.parametrize("values", [(0, 3), (3, 1000)])
def test_a_16_bit_png_material_map_gives_its_levels(tmp_path, values):
    """16-bit levels 0 and 3 were read as 0 and 0 (scaled to 0-1, then times 255): every face
    took class 0's material without a word."""
    from PIL import Image

    classes = np.full((10, 10), values[0], np.uint16)
    classes[:, 5:] = values[1]
    Image.fromarray(classes).save(tmp_path / "classes.png")
    names = {0: "sand", 3: "asphalt", 1000: "concrete"}
    scene = load_scene(_classes("classes.png"), base_dir=tmp_path)
    assert _east_west(scene) == ({names[values[0]]}, {names[values[1]]})


def test_8_bit_palette_and_float_material_maps_give_their_class_values(tmp_path):
    """A palette PNG's indices (not its colours), an 8-bit grey PNG's levels, and a float
    array's values (0 and 1 were read as 0 and 255)."""
    from PIL import Image

    classes = np.zeros((10, 10), np.uint8)
    classes[:, 5:] = 3
    palette = Image.fromarray(classes, mode="L").convert("P")
    palette.putpalette([200, 0, 0] * 3 + [10, 10, 10] + [0, 0, 0] * 252)
    palette.save(tmp_path / "palette.png")
    Image.fromarray(classes).save(tmp_path / "grey.png")
    np.save(tmp_path / "float.npy", classes.astype(float))
    for name in ("palette.png", "grey.png", "float.npy"):
        scene = load_scene(_classes(name), base_dir=tmp_path)
        assert _east_west(scene) == ({"sand"}, {"asphalt"}), name
    ones = (classes > 0).astype(float)
    np.save(tmp_path / "ones.npy", ones)
    scene = _classes("ones.npy")
    scene["terrain"]["material_map"]["classes"] = {0: "sand", 1: "asphalt"}
    assert _east_west(load_scene(scene, base_dir=tmp_path)) == ({"sand"}, {"asphalt"})


@pytest.mark.parametrize("value", [0.5, np.nan])
def test_a_material_map_of_other_numbers_than_integers_is_refused(tmp_path, value):
    classes = np.zeros((4, 4))
    classes[0, 0] = value
    np.save(tmp_path / "classes.npy", classes)
    with pytest.raises(ConfigError, match=r"^terrain\.material_map\.file: class values are "
                                          r"integers; the image holds other numbers"):
        load_scene(_classes("classes.npy"), base_dir=tmp_path)
