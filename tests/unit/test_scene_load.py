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
