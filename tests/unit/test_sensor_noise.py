"""Noise generators against their analytic variances; ADC quantisation and saturation."""

from __future__ import annotations

import numpy as np
import pytest

from radscene.errors import ConfigError
from radscene.sensor.electronics import Electronics, digitize
from radscene.sensor.noise import (
    flicker_noise,
    flicker_noise_reference,
    flicker_variance,
    quantization_variance,
    shot_noise,
    white_noise,
)

STAT = 0.03  # relative tolerance of variances estimated from ~1e5 samples (5 sigma)


@pytest.mark.parametrize("method", ["poisson", "gaussian"])
def test_shot_noise_mean_equals_variance(method):
    rng = np.random.default_rng(1)
    mean = np.array([5.0, 300.0, 2.0e5])[:, None] * np.ones((1, 100_000))
    counts = shot_noise(mean, rng, method)
    assert counts.dtype == np.float32
    assert counts.mean(axis=1) == pytest.approx([5.0, 300.0, 2.0e5], rel=STAT / 10)
    assert counts.var(axis=1) == pytest.approx([5.0, 300.0, 2.0e5], rel=STAT)
    if method == "poisson":
        assert np.all(counts == np.round(counts))


def test_shot_noise_bad_input():
    rng = np.random.default_rng(0)
    with pytest.raises(ConfigError, match="shot_noise"):
        shot_noise([1.0], rng, "binomial")
    with pytest.raises(ConfigError, match="mean"):
        shot_noise([-1.0], rng)


def test_white_noise_rms():
    w = white_noise((200_000,), 3.5, np.random.default_rng(2))
    assert w.std() == pytest.approx(3.5, rel=STAT / 3)
    assert abs(w.mean()) < 0.05


def test_flicker_variance_is_a_harmonic_sum():
    # 2 sigma^2 fc dt * H_m with m = ceil(L/2) - 1
    assert flicker_variance(5, 1.0, 0.5, 1.0) == pytest.approx(1.5, rel=1e-15)
    assert flicker_variance(6, 1.0, 0.5, 1.0) == pytest.approx(1.5, rel=1e-15)
    h = sum(1.0 / j for j in range(1, 500))
    assert flicker_variance(1000, 1e-6, 2e3, 3.0) == pytest.approx(2 * 9.0 * 2e3 * 1e-6 * h, rel=1e-12)


def test_flicker_optimised_equals_reference():
    fast = flicker_noise(257, 1e-3, 50.0, 2.0, np.random.default_rng(7), count=3)
    slow = flicker_noise_reference(257, 1e-3, 50.0, 2.0, np.random.default_rng(7), count=3)
    assert fast.shape == (3, 257)
    assert fast == pytest.approx(slow, abs=1e-5)


def test_flicker_statistics_and_spectrum():
    n, dt, fc, sigma = 4096, 1e-5, 1e3, 1.0
    streams = flicker_noise(n, dt, fc, sigma, np.random.default_rng(11), count=400)
    assert streams.var() == pytest.approx(flicker_variance(n, dt, fc, sigma), rel=0.05)
    # periodogram falls as 1/f: a log-log slope of -1
    power = (np.abs(np.fft.rfft(streams, axis=1)) ** 2).mean(axis=0)[1:-1]
    f = np.arange(1, power.size + 1)
    slope = np.polyfit(np.log(f[10:1000]), np.log(power[10:1000]), 1)[0]
    assert slope == pytest.approx(-1.0, abs=0.05)


def test_quantisation_noise_is_gain_squared_over_12():
    rng = np.random.default_rng(5)
    signal = rng.uniform(0.0, 1000.0, 400_000)
    dn, sat = digitize(signal, 2.5, 0.0, 16)
    err = dn * 2.5 - signal
    assert err.var() == pytest.approx(float(quantization_variance(2.5)), rel=STAT)
    assert abs(err.mean()) < 0.01 and not sat.any()


def test_digitize_rounds_clips_and_picks_dtype():
    dn, sat = digitize([-500.0, 0.0, 149.0, 151.0, 1e9], 100.0, 2.0, 8)
    assert dn.tolist() == [0, 2, 3, 4, 255]
    assert sat.tolist() == [True, False, False, False, True]
    assert dn.dtype == np.uint16
    assert digitize([1.0], 1.0, 0.0, 20)[0].dtype == np.uint32
    with pytest.raises(ConfigError, match=r"electronics\.gain"):
        digitize([1.0], 0.0)


def test_electronics_config():
    e = Electronics.from_config({"gain": "150 e-/DN", "offset": 1000, "bits": 14,
                                 "frame_rate": "50 Hz"})
    assert (e.gain, e.offset, e.bits, e.frame_rate, e.max_dn) == (150.0, 1000.0, 14, 50.0, 16383)
    v = Electronics.from_config({"gain": "0.6 uV/DN"}, signal_unit="V")
    assert v.gain == pytest.approx(6e-7, rel=1e-12)
    for cfg, key in (({"gain": 0}, "electronics.gain"), ({"gain": 1, "bits": 40}, "electronics.bits"),
                     ({"gain": 1, "bits": 12.5}, "electronics.bits"),
                     ({"gain": 1, "volume": 11}, "electronics.volume")):
        with pytest.raises(ConfigError, match=key.replace(".", r"\.")):
            Electronics.from_config(cfg)
