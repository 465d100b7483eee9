"""OTF filtering and detector sampling: optimised against the reference, energy, geometry."""

from __future__ import annotations

import numpy as np
import pytest

from radscene.errors import ConfigError
from radscene.sensor.otf import detector_otf, jitter_otf, smear_otf
from radscene.sensor.sampling import (
    apply_otf,
    apply_otf_reference,
    block_centre,
    block_mean,
    detector_grid_shape,
    rfft_frequencies,
)

FLOAT32 = 2e-6  # single-precision FFT of the optimised path, relative to the image scale


def _otf(k, fill=1.0, sigma=0.0, smear=(0.0, 0.0)):
    def h(fy, fx):
        out = detector_otf(fx, fy, k * np.sqrt(fill))
        if sigma:
            out = out * jitter_otf(fx, fy, sigma)
        if any(smear):
            out = out * smear_otf(fx, fy, *smear)
        return out
    return h


@pytest.mark.parametrize(("shape", "k"), [((64, 48), 4), ((63, 45), 3), ((40, 40), 1),
                                           ((66, 44), 2), ((30, 35), 5), ((16, 24), 8)])
def test_optimised_equals_reference(shape, k):
    rng = np.random.default_rng(k)
    image = rng.random(shape) * 10.0
    h = _otf(k, fill=0.8, sigma=0.7, smear=(1.3, -0.4))
    fy, fx = rfft_frequencies(shape)
    fast = apply_otf(image, h(fy, fx), k)
    slow = apply_otf_reference(image, h, k)
    assert fast.shape == (shape[0] // k, shape[1] // k)
    assert fast == pytest.approx(slow, abs=FLOAT32 * 10.0)


@pytest.mark.parametrize("shape", [(64, 48), (63, 45)])
def test_otf_given_for_the_positive_rows_only(shape):
    rng = np.random.default_rng(2)
    image = rng.random(shape)
    h = _otf(3 if shape[0] % 3 == 0 else 4, sigma=0.9)
    k = 3 if shape[0] % 3 == 0 else 4
    fy, fx = rfft_frequencies(shape)
    full = apply_otf(image, h(fy, fx), k)
    half = apply_otf(image, h(np.abs(fy[: shape[0] // 2 + 1]), fx), k)
    assert half == pytest.approx(full, abs=1e-6)


def test_batch_axis_matches_single_images():
    rng = np.random.default_rng(3)
    stack = rng.random((3, 32, 32))
    fy, fx = rfft_frequencies((32, 32))
    h = _otf(4, sigma=1.0)(fy, fx)
    both = apply_otf(stack, h, 4)
    for i in range(3):
        assert both[i] == pytest.approx(apply_otf(stack[i], h, 4), abs=1e-6)


@pytest.mark.parametrize("k", [2, 4, 5])
def test_full_fill_footprint_preserves_the_mean_exactly(k):
    # sinc(k f) vanishes at every multiple of the detector frequency 1/k: no aliasing of the
    # mean, so the sampled image holds the same total radiance (energy) as the fine one.
    rng = np.random.default_rng(k)
    image = rng.random((20 * k, 12 * k)) * 100.0
    fy, fx = rfft_frequencies(image.shape)
    out = apply_otf(image, _otf(k, sigma=0.5)(fy, fx), k)
    assert out.mean() == pytest.approx(image.mean(), rel=1e-6)


def test_uniform_image_is_unchanged():
    fy, fx = rfft_frequencies((32, 48))
    out = apply_otf(np.full((32, 48), 7.25), _otf(4, fill=0.5, sigma=2.0)(fy, fx), 4)
    assert out == pytest.approx(np.full((8, 12), 7.25), rel=1e-6)


def test_footprint_alone_is_the_block_mean_of_a_smooth_image():
    # a band-limited image: the continuous box average equals the discrete block mean to the
    # accuracy of the midpoint rule on a smooth function
    y, x = np.mgrid[0:64, 0:64] + 0.5
    image = 3.0 + np.sin(2 * np.pi * x / 64.0) * np.cos(2 * np.pi * 2 * y / 64.0)
    fy, fx = rfft_frequencies(image.shape)
    out = apply_otf(image, _otf(4)(fy, fx), 4)
    assert out == pytest.approx(block_mean(image, 4), abs=2e-3)


def test_impulse_response_is_centred_on_the_detector():
    # a point in the middle of detector (3, 5) spreads symmetrically about that detector
    k = 4
    image = np.zeros((64, 64))
    image[3 * k + 1 : 3 * k + 3, 5 * k + 1 : 5 * k + 3] = 1.0  # the 2x2 centre samples
    fy, fx = rfft_frequencies(image.shape)
    out = apply_otf(image, _otf(k, sigma=3.0)(fy, fx), k)
    assert np.unravel_index(np.argmax(out), out.shape) == (3, 5)
    assert out[2, 5] == pytest.approx(out[4, 5], rel=1e-5)
    assert out[3, 4] == pytest.approx(out[3, 6], rel=1e-5)


def test_pitch_larger_than_image_names_key():
    with pytest.raises(ConfigError, match=r"detector\.pitch"):
        detector_grid_shape((8, 8), 16)
    with pytest.raises(ConfigError, match="oversample"):
        detector_grid_shape((30, 32), 4)
    with pytest.raises(ConfigError, match="oversample"):
        apply_otf(np.zeros((8, 8)), 1.0, 0)


def test_block_mean_skips_nan_and_block_centre_picks_labels():
    a = np.arange(16.0).reshape(4, 4)
    a[0, 0] = np.nan
    m = block_mean(a, 2)
    assert m[0, 0] == pytest.approx((1 + 4 + 5) / 3)
    assert m[1, 1] == pytest.approx((10 + 11 + 14 + 15) / 4)
    assert np.isnan(block_mean(np.full((2, 2), np.nan), 2)[0, 0])
    labels = np.arange(16).reshape(4, 4)
    assert block_centre(labels, 2).tolist() == [[5, 7], [13, 15]]
    assert block_centre(labels, 2).dtype == labels.dtype
