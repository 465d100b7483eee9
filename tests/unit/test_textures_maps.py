"""Material maps with per-class fractions, areal mixing, tiled and procedural textures."""

import numpy as np
import pytest

from radscene.errors import ConfigError
from radscene.materials import (
    MaterialFractions,
    MaterialMap,
    NoiseTexture,
    Texture,
    TextureSet,
    fractal_noise,
    get_material,
    gradient_noise,
    make_texture,
    mix_materials,
    noise_elevation,
)

CLASSES = np.array([[1, 1, 2, 2], [1, 1, 2, 7], [3, 3, 2, 2], [3, 3, 3, 2]])
NAMES = {1: "asphalt", 2: "dry_grass", 3: "water", 7: "Dry_Grass", 9: "sand"}


def test_material_map_indexes_and_places_like_textures():
    mm = MaterialMap(CLASSES, NAMES, size=(40.0, 40.0), origin=(100.0, 200.0))
    assert mm.materials == ["asphalt", "dry_grass", "water"]  # 7 maps to dry_grass too; 9 unused
    # row 0 is the north edge, column 0 the west edge: pixel (0, 0) is at the north-west corner
    idx = mm.material_index([105.0, 135.0, 105.0, 135.0], [235.0, 235.0, 205.0, 205.0])
    assert idx.tolist() == [0, 1, 2, 1]
    assert mm.material_index(np.nan, 210.0).tolist() == -1
    with pytest.raises(ConfigError, match=r"point \(99, 210\) m is outside the map"):
        mm.material_index(99.0, 210.0)


def test_unmapped_class_values_are_listed():
    with pytest.raises(ConfigError, match=r"class values \[3, 7\] that have no material; mapped: \[1, 2\]"):
        MaterialMap(CLASSES, {1: "asphalt", 2: "dry_grass"}, size=(4, 4))
    with pytest.raises(ConfigError, match="must be integers"):
        MaterialMap(np.array([[1.5]]), {1: "asphalt"}, size=(1, 1))


def test_fractions_for_sub_pixel_mixing():
    mm = MaterialMap(CLASSES, NAMES, size=(4.0, 4.0))
    fr = mm.fractions(2)
    assert fr.values.shape == (3, 2, 2)
    np.testing.assert_allclose(fr.values.sum(axis=0), 1.0, rtol=0, atol=1e-15)
    # north-east block: 3 grass pixels of 4 (class 2 x3 and class 7 -> grass): all grass
    np.testing.assert_allclose(fr.values[:, 0, 1], [0.0, 1.0, 0.0], atol=0)
    # south-east block: classes 2, 2, 3, 2 -> 3/4 grass, 1/4 water
    np.testing.assert_allclose(fr.values[:, 1, 1], [0.0, 0.75, 0.25], atol=0)
    np.testing.assert_allclose(fr.sample(3.5, 0.5), [0.0, 0.75, 0.25], atol=0)
    assert fr.dominant().tolist() == [[0, 1], [2, 1]]
    np.testing.assert_allclose(mm.fractions(1).values.sum(axis=0), 1.0, atol=0)
    with pytest.raises(ConfigError, match="factor 3 does not divide the map shape 4 x 4"):
        mm.fractions(3)
    with pytest.raises(ConfigError, match=r"fractions of cell \(0, 0\) sum to 0.9"):
        MaterialFractions(np.array([[[0.4]], [[0.5]]]), ["a", "b"], size=(1, 1))


def test_from_image_png_and_npy(tmp_path):
    from PIL import Image

    Image.fromarray(CLASSES.astype(np.uint8), mode="L").save(tmp_path / "classes.png")
    np.save(tmp_path / "classes.npy", CLASSES)
    for f in ("classes.png", "classes.npy"):
        mm = MaterialMap.from_image(tmp_path / f, NAMES, size=(4.0, 4.0))
        assert mm.index.tolist() == MaterialMap(CLASSES, NAMES, size=(4, 4)).index.tolist()
    Image.fromarray(np.zeros((2, 2, 3), np.uint8)).save(tmp_path / "rgb.png")
    with pytest.raises(ConfigError, match=r"rgb\.png: a classified image must be single-band"):
        MaterialMap.from_image(tmp_path / "rgb.png", NAMES, size=(1, 1))
    with pytest.raises(ConfigError, match=r"unknown material-map format '\.tif'"):
        MaterialMap.from_image(tmp_path / "x.tif", NAMES, size=(1, 1))


def test_mix_materials_is_area_weighted_and_kirchhoff_closed():
    a, g = get_material("asphalt"), get_material("dry_grass")
    mix = mix_materials([(0.25, a), (0.75, g)], name="verge")
    wl = np.array([0.55, 0.85, 4.0, 10.0])
    for attr in ("reflectance", "emissivity", "transmittance"):
        np.testing.assert_allclose(getattr(mix, attr)(wl),
                                   0.25 * getattr(a, attr)(wl) + 0.75 * getattr(g, attr)(wl), rtol=1e-12)
    c = mix.components(np.linspace(0.4, 20, 300))
    np.testing.assert_allclose(sum(c.values()), 1.0, rtol=1e-12)
    with pytest.raises(ConfigError, match="fractions sum to 0.9, not 1"):
        mix_materials([(0.4, a), (0.5, g)])
    with pytest.raises(ConfigError, match="different exponents"):
        mix_materials([(0.5, get_material("water")), (0.5, get_material("painted_metal"))])


def test_tiled_texture_repeats_at_its_scale():
    tile = [[0.8, 1.2], [1.0, 1.4]]
    t = Texture.tiled(tile, tile_size=(2.0, 4.0), origin=(1.0, 0.0))
    x = np.array([1.5, 2.5, 3.5, 21.5, -8.5])
    y = np.full_like(x, 3.0)
    expected = [0.8, 1.2, 0.8, 0.8, 0.8]
    np.testing.assert_allclose(t.sample(x, y), expected, rtol=1e-12)
    np.testing.assert_allclose(t.sample(x + 2.0, y + 4.0), t.sample(x, y), rtol=1e-12)  # period


def test_make_texture_registry_and_texture_set(tmp_path):
    np.save(tmp_path / "t.npy", np.array([[2.0, 4.0]]))
    img = make_texture({"type": "image", "file": "t.npy", "size": [2, 1]}, base_dir=tmp_path)
    assert float(img.sample(0.5, 0.5)) == pytest.approx(2.0)
    tile = make_texture({"type": "TILE", "file": "t.npy", "tile_size": [2, 1]}, base_dir=tmp_path)
    assert float(tile.sample(10.5, 7.5)) == pytest.approx(2.0)
    with pytest.raises(ConfigError, match="unknown texture type 'perlin'; known: image, noise, tile"):
        make_texture({"type": "perlin"}, key="terrain.textures.emissivity")
    with pytest.raises(ConfigError, match=r"unknown keys \['colour'\] for a noise texture"):
        make_texture({"type": "noise", "amplitude": 0.1, "scale": 5, "colour": 1})
    with pytest.raises(ConfigError, match="emissivity: missing 'scale'"):
        TextureSet(emissivity={"type": "noise", "amplitude": 0.1})
    ts = TextureSet(reflectance={"type": "noise", "amplitude": 0.3, "scale": 4.0, "seed": 2},
                    transmittance=Texture([[0.5]], size=(1, 1)))
    out = ts.sample(np.linspace(0, 50, 7), 1.0)
    assert set(out) == {"reflectance", "emissivity", "transmittance"}
    np.testing.assert_allclose(out["emissivity"], 1.0, atol=0)
    np.testing.assert_allclose(out["transmittance"], 0.5, atol=0)
    assert out["reflectance"].shape == (7,) and np.all(np.abs(out["reflectance"] - 1.0) <= 0.3)


def test_gradient_noise_properties():
    rng = np.random.default_rng(0)
    x, y = rng.uniform(-300, 300, (2, 50_000))
    n = gradient_noise(x, y, seed=4)
    assert np.all(np.abs(n) <= 1.0)
    assert abs(float(n.mean())) < 0.01 and float(n.std()) > 0.2
    # zero at lattice points, continuous, deterministic, seed-dependent
    np.testing.assert_allclose(gradient_noise(np.arange(-5.0, 5.0), 3.0, seed=4), 0.0, atol=1e-15)
    eps = 1e-6
    assert np.max(np.abs(gradient_noise(x + eps, y, seed=4) - n)) < 1e-4
    np.testing.assert_array_equal(gradient_noise(x, y, seed=4), n)
    assert not np.allclose(gradient_noise(x, y, seed=5), n)
    assert np.isnan(gradient_noise(np.nan, 0.0))


def test_fractal_noise_scale_and_errors():
    x = np.linspace(0.0, 1000.0, 20001)
    coarse = fractal_noise(x, 0.0, scale=200.0, octaves=1, seed=1)
    fine = fractal_noise(x, 0.0, scale=10.0, octaves=1, seed=1)
    # the feature size is the scale: rougher (larger mean gradient) at small scale
    assert np.mean(np.abs(np.diff(fine))) > 10 * np.mean(np.abs(np.diff(coarse)))
    assert np.all(np.abs(fractal_noise(x, 3.0, scale=25.0, octaves=6)) <= 1.0)
    with pytest.raises(ConfigError, match="octaves: must be in \\[1, 16\\]; got 0"):
        fractal_noise(x, 0.0, scale=1.0, octaves=0)
    with pytest.raises(ConfigError, match="scale: must be > 0"):
        fractal_noise(x, 0.0, scale=0.0)
    z = noise_elevation(x, 5.0, amplitude=2.5, scale=50.0, seed=3)
    assert np.all(np.abs(z) <= 2.5) and float(np.ptp(z)) > 0.5


def test_noise_texture_multipliers_and_rasterize():
    t = NoiseTexture(amplitude=0.25, scale=8.0, octaves=3, seed=9)
    x, y = np.meshgrid(np.linspace(0, 64, 65), np.linspace(0, 64, 65))
    m = t.sample(x, y)
    assert m.shape == x.shape and np.all((m >= 0.75) & (m <= 1.25))
    r = t.rasterize(size=(64.0, 64.0), shape=(32, 32))
    assert isinstance(r, Texture) and r.values.shape == (32, 32)
    # pixel centres hold the procedural values exactly (row 0 is north)
    assert r.values[0, 0] == pytest.approx(float(t.sample(1.0, 63.0)), rel=1e-12)
    with pytest.raises(ConfigError, match=r"amplitude: must be <= 1; got 1.5"):
        NoiseTexture(amplitude=1.5, scale=1.0)


def test_make_material_mixture_type():
    from radscene.materials import make_material

    m = make_material({"type": "mixture", "parts": [{"fraction": 0.5, "material": "asphalt"},
                                                    {"fraction": 0.5, "material": {"type": "custom", "reflectance": 0.2}}]},
                      key="materials.verge")
    expected = 0.5 * get_material("asphalt").reflectance(0.55) + 0.5 * 0.2
    assert float(m.reflectance(0.55)) == pytest.approx(float(expected), rel=1e-12)
    with pytest.raises(ConfigError, match=r"materials.v.parts\[0\]: each part is"):
        make_material({"type": "mixture", "parts": [{"fraction": 1.0}]}, key="materials.v")
