"""System test: material maps with per-class fractions, tiled Δρ maps and procedural noise, set in
the scene file, have their physically expected effect on a rendered band.

A flat terrain under a sun at 30 deg zenith in vacuum, seen from nadir at 1 m GSD; the 'red' band
(0.6-0.7 um) is dominated by the sun_diffuse term, which is linear in the diffuse reflectance.
"""

from __future__ import annotations

import numpy as np
import pytest

from radscene import load_scene, render
from radscene.errors import ConfigError

N = 32  # terrain nodes a side, 1 m apart: a 31 m square


def _scene(terrain_extra: dict | None = None, objects: list | None = None, shape=(24, 24)) -> dict:
    terrain = {"type": "dem", "elevation": np.zeros((N, N)).tolist(), "spacing": [1.0, 1.0],
               "material": "sand"}
    terrain.update(terrain_extra or {})
    return {
        "name": "textures",
        "environment": {"sun": {"zenith": 30.0, "azimuth": 180.0}, "atmosphere": {"type": "none"}},
        "terrain": terrain,
        "objects": objects or [],
        "bands": [{"name": "red", "min": 0.6, "max": 0.7}],
        "observers": [{"name": "nadir", "type": "orthographic", "center": [15.5, 15.5], "gsd": 1.0,
                       "shape": list(shape), "altitude": 1000}],
    }


def _band(ds, term="sun_diffuse") -> np.ndarray:
    return ds[term].sel(band="red").values


def test_class_with_fractions_renders_the_mean_of_its_materials(tmp_path):
    # three stripes west to east: sand, a 50/50 sand/asphalt class, asphalt
    np.save(tmp_path / "classes.npy", np.array([[0, 2, 1]], dtype=np.int16))
    spec = _scene({"material_map": {"type": "file", "file": "classes.npy",
                                    "classes": {0: "sand", 1: "asphalt",
                                                2: {"sand": 0.5, "asphalt": 0.5}}}})
    scene = load_scene(spec, base_dir=tmp_path)
    ds = render(scene)
    ids = ds["material_id"].values
    names = scene.material_names
    value = {}
    for name in ("sand", "asphalt", "0.5 sand + 0.5 asphalt"):
        sel = ids == names.index(name)
        assert sel.sum() >= 24, name  # at least a column of pixels of every class
        pixels = _band(ds)[sel]
        np.testing.assert_allclose(pixels, pixels.mean(), rtol=1e-9)  # flat, unshadowed
        value[name] = pixels.mean()
    assert value["0.5 sand + 0.5 asphalt"] == pytest.approx(
        0.5 * (value["sand"] + value["asphalt"]), rel=1e-9)
    assert value["sand"] > 1.5 * value["asphalt"]  # the mixture is not trivially either one


def _assert_period(row: np.ndarray, period: int):
    """``row`` repeats every ``period`` pixels and no fewer."""
    for shift in range(1, period + 1):
        same = np.allclose(row[shift:], row[:-shift], rtol=1e-9)
        assert same == (shift == period), shift


def test_tiled_reflectance_map_repeats_with_the_stated_period():
    # two texels, multipliers 1 and 0.5, each 2 m on the ground: a 4 m period east-west
    tile = {"type": "tile", "values": [[1.0, 0.5]], "texel_size": "2 m"}
    plain = _band(render(load_scene(_scene())))
    ds = render(load_scene(_scene({"textures": {"reflectance": tile}})))
    image = _band(ds)
    np.testing.assert_allclose(image, np.broadcast_to(image[0], image.shape), rtol=1e-9)  # no N-S
    _assert_period(image[0], 4)
    ratio = image[0] / plain[0]
    assert ratio.max() <= 1.0 + 1e-9 and ratio.min() >= 0.5 - 1e-9
    assert ratio.max() - ratio.min() > 0.2


def test_tiled_map_on_an_object_repeats_with_the_stated_period():
    tile = {"type": "tile", "values": [[1.0, 0.5, 0.75]], "texel_size": [1.0, 1.0]}
    box = {"name": "slab", "shape": {"type": "box", "size": [20.0, 20.0, 1.0]},
           "position": [15.5, 15.5, 0.0], "material": "concrete",
           "textures": {"reflectance": tile}}
    ds = render(load_scene(_scene(objects=[box], shape=(12, 12))))
    assert np.all(ds["object_id"].values > 0)  # every pixel sees the slab's top
    image = _band(ds)
    _assert_period(image[0], 3)


def test_noise_changes_the_variance_but_not_the_mean():
    plain = _band(render(load_scene(_scene(shape=(30, 30)))))
    noise = {"type": "noise", "amplitude": 0.3, "scale": "3 m", "seed": 4}
    image = _band(render(load_scene(_scene({"textures": {"reflectance": noise}}, shape=(30, 30)))))
    assert plain.std() / plain.mean() < 1e-9
    assert image.std() / image.mean() > 0.03
    assert image.mean() == pytest.approx(plain.mean(), rel=0.01)  # seeds 0-5: within 0.2 %


@pytest.mark.parametrize(
    "extra, key",
    [
        ({"textures": {"reflectance": {"type": "tile", "values": [[1.0]]}}},
         "terrain.textures.reflectance"),
        ({"textures": {"emissivity": {"type": "noise", "amplitude": 2.0, "scale": 5}}},
         "terrain.textures.emissivity.amplitude"),
        ({"textures": {"reflectance": {"type": "tile", "values": [[1.0, -0.5]], "texel_size": 1}}},
         "terrain.textures.reflectance.values"),
        ({"textures": {"reflectance": {"type": "marble"}}}, "terrain.textures.reflectance"),
        ({"material_map": {"type": "file", "file": "c.npy",
                           "classes": {0: {"sand": 0.5, "asphalt": 0.4}}}},
         "terrain.material_map.classes"),
    ],
)
def test_bad_texture_or_fraction_names_the_key(extra, key):
    with pytest.raises(ConfigError) as err:
        load_scene(_scene(extra))
    assert err.value.key.startswith(key), err.value.key


def test_unknown_material_in_a_class_mixture_names_the_key(tmp_path):
    np.save(tmp_path / "c.npy", np.zeros((2, 2), dtype=np.int16))
    spec = _scene({"material_map": {"type": "file", "file": "c.npy",
                                    "classes": {0: {"sand": 0.5, "unobtainium": 0.5}}}})
    with pytest.raises(ConfigError, match="unobtainium") as err:
        load_scene(spec, base_dir=tmp_path)
    assert err.value.key == "terrain.material_map.classes.0.unobtainium"
