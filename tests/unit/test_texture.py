"""Tests of radscene.materials.texture."""

import numpy as np
import pytest
from PIL import Image

from radscene.errors import ConfigError
from radscene.materials import Texture
from radscene.materials.texture import LUMINANCE_WEIGHTS

# 2 x 3 image on a 30 m x 20 m rectangle from (100, 200): pixels 10 m square.
VALUES = np.array([[1.0, 2.0, 3.0], [4.0, 5.0, 6.0]])


def _texture(wrap=True):
    return Texture(VALUES, size=(30.0, 20.0), origin=(100.0, 200.0), wrap=wrap)


def test_pixel_centres_and_orientation():
    t = _texture()
    # row 0 is the north row (y = 215 is its centre), column 0 the west column (x = 105)
    assert t.sample(105.0, 215.0) == pytest.approx(1.0, abs=1e-14)
    assert t.sample(125.0, 215.0) == pytest.approx(3.0, abs=1e-14)
    assert t.sample(105.0, 205.0) == pytest.approx(4.0, abs=1e-14)
    assert t.pixel_size == (10.0, 10.0)


def test_bilinear_reference():
    t = _texture()
    # midway between the four centres (105,215),(115,215),(105,205),(115,205)
    assert t.sample(110.0, 210.0) == pytest.approx((1 + 2 + 4 + 5) / 4, abs=1e-14)
    # a quarter of the way east from (105, 215), on the north row
    assert t.sample(107.5, 215.0) == pytest.approx(1.25, abs=1e-14)
    # a fifth of the way south from (115, 215)
    assert t.sample(115.0, 213.0) == pytest.approx(2.0 + 0.2 * 3.0, abs=1e-14)


def test_broadcasting_and_nan():
    t = _texture()
    x = np.array([105.0, 115.0, np.nan])[:, None]
    y = np.array([215.0, 205.0])
    out = t.sample(x, y)
    assert out.shape == (3, 2)
    assert out[:2] == pytest.approx(np.array([[1.0, 4.0], [2.0, 5.0]]), abs=1e-14)
    assert np.all(np.isnan(out[2]))


def test_wrap_is_periodic_and_interpolates_across_the_seam():
    t = _texture(wrap=True)
    rng = np.random.default_rng(0)
    x = rng.uniform(-500, 500, 50)
    y = rng.uniform(-500, 500, 50)
    np.testing.assert_allclose(t.sample(x + 30.0, y - 40.0), t.sample(x, y), rtol=1e-12)
    # the west edge x = 100 is midway between column 2 (tile to the west) and column 0
    assert t.sample(100.0, 215.0) == pytest.approx((3.0 + 1.0) / 2, abs=1e-14)
    # the north edge y = 220 is midway between row 0 and row 1 of the next tile north
    assert t.sample(105.0, 220.0) == pytest.approx((1.0 + 4.0) / 2, abs=1e-14)


def test_no_wrap_holds_edges_and_refuses_outside():
    t = _texture(wrap=False)
    assert t.sample(100.0, 220.0) == pytest.approx(1.0, abs=1e-14)  # north-west corner
    assert t.sample(130.0, 200.0) == pytest.approx(6.0, abs=1e-14)  # south-east corner
    with pytest.raises(ConfigError, match=r"\(130\.5, 210\) m is outside the texture"):
        t.sample([110.0, 130.5], 210.0)
    with pytest.raises(ConfigError, match="outside"):
        t.sample(110.0, 199.0)


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"values": [1.0, 2.0]}, "2-D"),
        ({"values": [[1.0, -0.5]]}, ">= 0"),
        ({"values": [[1.0, np.inf]]}, "finite"),
        ({"size": (0.0, 1.0)}, "positive"),
        ({"size": (1.0,)}, "pair"),
        ({"origin": (np.nan, 0.0)}, "finite"),
        ({"wrap": "yes"}, "wrap must be"),
    ],
)
def test_invalid_construction(kwargs, match):
    args = {"values": [[1.0]], "size": (1.0, 1.0)} | kwargs
    with pytest.raises(ConfigError, match=match):
        Texture(**args)


def test_from_image_grey_png_values_are_multipliers(tmp_path):
    pixels = np.array([[0, 51], [102, 255]], dtype=np.uint8)
    path = tmp_path / "g.png"
    Image.fromarray(pixels, mode="L").save(path)
    t = Texture.from_image(path, size=(2.0, 2.0))
    np.testing.assert_allclose(t.values, pixels / 255.0, rtol=0, atol=1e-7)


def test_from_image_rgb_jpeg_uses_bt709_luminance(tmp_path):
    rgb = np.zeros((8, 8, 3), dtype=np.uint8)
    rgb[..., 1] = 200  # pure green: large flat areas survive JPEG nearly unchanged
    path = tmp_path / "c.jpg"
    Image.fromarray(rgb, mode="RGB").save(path, quality=100)
    t = Texture.from_image(path, size=(1.0, 1.0))
    assert t.values.mean() == pytest.approx(LUMINANCE_WEIGHTS[1] * 200 / 255, abs=0.01)


def test_from_image_contrast(tmp_path):
    rng = np.random.default_rng(1)
    image = rng.uniform(0.0, 1.0, (16, 16))
    path = tmp_path / "pattern.npy"
    np.save(path, image)
    t = Texture.from_image(path, size=(16.0, 16.0), contrast=0.2)
    assert t.values.mean() == pytest.approx(1.0, abs=1e-12)
    assert t.values.max() - t.values.min() == pytest.approx(0.2, rel=1e-12)
    expected = 1.0 + 0.2 * (image - image.mean()) / (image.max() - image.min())
    np.testing.assert_allclose(t.values, expected, rtol=1e-12)


def test_from_image_errors_name_the_file(tmp_path):
    neg = tmp_path / "neg.npy"
    np.save(neg, np.array([[1.0, -0.1], [0.5, 0.2]]))
    with pytest.raises(ConfigError, match=r"neg\.npy.*>= 0"):
        Texture.from_image(neg, size=(1.0, 1.0))
    skew = tmp_path / "skew.npy"
    np.save(skew, np.array([[0.0, 1.0, 1.0, 1.0]]))  # mean 0.75: contrast > 1/0.75 goes negative
    with pytest.raises(ConfigError, match=r"skew\.npy.*negative.*1\.333"):
        Texture.from_image(skew, size=(1.0, 1.0), contrast=2.0)
    flat = tmp_path / "flat.npy"
    np.save(flat, np.ones((3, 3)))
    with pytest.raises(ConfigError, match=r"flat\.npy.*no variation"):
        Texture.from_image(flat, size=(1.0, 1.0), contrast=0.5)
    with pytest.raises(ConfigError, match="unknown texture format '.tif'"):
        Texture.from_image(tmp_path / "x.tif", size=(1.0, 1.0))
    with pytest.raises(ConfigError, match=r"missing\.png.*cannot read"):
        Texture.from_image(tmp_path / "missing.png", size=(1.0, 1.0))
