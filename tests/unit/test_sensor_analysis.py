"""Analysis: 3-D noise, slanted-edge MTF, noise budget and NEΔT."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy import constants as sc

from radscene.errors import ConfigError
from radscene.radiometry import RectangularResponse, band_radiance
from radscene.sensor import make_sensor, netd, noise_3d, noise_budget, slanted_edge_mtf
from radscene.sensor.analysis import COMPONENTS, noise_3d_reference

AXES = {"t": 0, "v": 1, "h": 2}


def synthetic_cube(shape, sigma: dict, mean: float, seed: int = 0) -> np.ndarray:
    """A cube whose 3-D noise components are orthogonal with exactly the given std (ddof=1)."""
    rng = np.random.default_rng(seed)
    cube = np.full(shape, mean)
    for comp, s in sigma.items():
        size = [shape[i] if name in comp else 1 for name, i in AXES.items()]
        a = rng.standard_normal(size)
        for name in comp:
            a = a - a.mean(axis=AXES[name], keepdims=True)
        a *= s / np.std(a, ddof=1)
        cube = cube + a
    return cube


def test_noise_3d_recovers_known_components():
    sigma = {"t": 0.5, "v": 1.5, "h": 2.5, "tv": 0.7, "th": 1.1, "vh": 3.0, "tvh": 4.0}
    cube = synthetic_cube((12, 40, 50), sigma, 500.0)
    r = noise_3d(cube)
    assert r.mean == pytest.approx(500.0, rel=1e-12)
    for c in COMPONENTS:
        assert getattr(r, c) == pytest.approx(sigma[c], rel=1e-10), c
    assert r.total == pytest.approx(math.sqrt(sum(s * s for s in sigma.values())), rel=1e-10)
    # the components add back up to the cube
    assert sum(r.maps.values()) + r.mean == pytest.approx(cube, rel=1e-12)


def test_noise_3d_equals_the_sequential_operator_reference():
    cube = np.random.default_rng(3).gamma(4.0, 10.0, (6, 17, 23))
    fast, slow = noise_3d(cube), noise_3d_reference(cube)
    for c in (*COMPONENTS, "mean"):
        assert fast.as_dict()[c] == pytest.approx(slow.as_dict()[c], rel=1e-10)
    assert noise_3d(cube, ddof=0).tvh < fast.tvh


def test_noise_3d_bad_input():
    with pytest.raises(ConfigError, match="cube"):
        noise_3d(np.zeros((4, 4)))
    with pytest.raises(ConfigError, match="cube"):
        noise_3d(np.zeros((1, 4, 4)))


def _gaussian_edge(n=80, angle=5.0, sigma=0.6, sub=8):
    """Edge image: a Gaussian-blurred step (std `sigma` px) integrated over square pixels."""
    from scipy.special import erf

    a = math.radians(angle)
    img = np.zeros((n, n))
    offs = (np.arange(sub) + 0.5) / sub
    for dy in offs:
        for dx in offs:
            y = np.arange(n)[:, None] + dy
            x = np.arange(n)[None, :] + dx
            d = ((x - n / 2) - math.tan(a) * (y - n / 2)) * math.cos(a)
            img += 0.5 * (1 + erf(d / (sigma * math.sqrt(2))))
    return 10.0 + 90.0 * img / sub**2


@pytest.mark.parametrize("transpose", [False, True])
def test_slanted_edge_recovers_gaussian_times_pixel_mtf(transpose):
    sigma = 0.6
    img = _gaussian_edge(sigma=sigma)
    result = slanted_edge_mtf(img.T if transpose else img)
    assert result.orientation == ("horizontal" if transpose else "vertical")
    assert abs(result.angle) == pytest.approx(5.0, abs=0.05)
    f = np.linspace(0.05, 0.8, 16)
    th = math.radians(5.0)
    expected = (np.exp(-2 * np.pi**2 * sigma**2 * f**2)
                * np.abs(np.sinc(f * math.cos(th)) * np.sinc(f * math.sin(th))))
    assert result(f) == pytest.approx(expected, abs=0.01)
    assert result.mtf[0] == pytest.approx(1.0, abs=1e-12)


def test_slanted_edge_rejects_unusable_images():
    with pytest.raises(ConfigError, match="image"):
        slanted_edge_mtf(np.zeros((4, 4)))
    flat_rows = np.zeros((32, 32))
    flat_rows[:, 16:] = 1.0  # an edge exactly along the columns: no sub-pixel phase spread
    with pytest.raises(ConfigError, match="image"):
        slanted_edge_mtf(flat_rows)
    with pytest.raises(ConfigError, match="oversampling"):
        slanted_edge_mtf(_gaussian_edge(), oversampling=0)


SENSOR = {
    "optics": {"focal_length": 0.05, "f_number": 2.0, "transmittance": 0.9},
    "detector": {"type": "photon", "pitch": 20e-6, "responsivity": 2.0,
                 "integration_time": 0.001, "temperature": 77.0, "read_noise": 300,
                 "dark_current": 1e-12, "prnu": 0.01, "dsnu": 0.1, "cold_shield_f_number": 2.0},
    "electronics": {"gain": 100.0, "bits": 16},
    "bands": {"mwir": {"response": {"type": "rectangular", "wavelength_min": 3.0,
                                    "wavelength_max": 5.0}}},
}


def test_noise_budget_by_hand():
    s = make_sensor(SENSOR)
    b = noise_budget(s, "mwir", radiance=[1.0, 2.0])
    g = (20e-6) ** 2 * math.pi / 16
    t_q = 0.001 / sc.e
    signal = np.array([1.0, 2.0]) * g * 0.9 * 2.0 * t_q
    optics = g * 0.1 * band_radiance(3.0, 5.0, 293.15) * 2.0 * t_q  # emissivity 1 - tau
    background = optics + 1e-12 * t_q
    quant = 100.0**2 / 12
    assert b.unit == "e-"
    assert b.signal == pytest.approx(signal, rel=1e-9)
    assert b.background == pytest.approx(np.full(2, background), rel=1e-9)
    assert b.temporal_rms == pytest.approx(np.sqrt(signal + background + 300.0**2 + quant), rel=1e-9)
    assert b.fixed_pattern_rms == pytest.approx(
        np.sqrt((0.01 * (signal + background)) ** 2 + (0.1 * 1e-12 * t_q) ** 2), rel=1e-9)
    assert b.snr == pytest.approx(b.signal / b.temporal_rms, rel=1e-15)


def test_netd_is_noise_over_the_blackbody_slope():
    s = make_sensor(SENSOR)
    t = 300.0
    value = float(netd(s, "mwir", t))
    # independent: finite difference of the blackbody signal, exact Planck band integrals
    dt = 0.01
    g = (20e-6) ** 2 * math.pi / 16 * 0.9 * 2.0 * 0.001 / sc.e
    slope = g * (band_radiance(3.0, 5.0, t + dt) - band_radiance(3.0, 5.0, t - dt)) / (2 * dt)
    noise = float(noise_budget(s, "mwir", temperature=t).temporal_rms)
    assert value == pytest.approx(noise / slope, rel=1e-6)
    assert noise_budget(s, "mwir", temperature=t).signal == pytest.approx(
        g * band_radiance(3.0, 5.0, t), rel=1e-9)
    # hotter scenes: more shot noise but a steeper slope; NETD falls
    assert netd(s, "mwir", [280.0, 320.0]).tolist() == sorted(
        netd(s, "mwir", [280.0, 320.0]).tolist(), reverse=True)


def test_budget_bad_input():
    s = make_sensor(SENSOR)
    with pytest.raises(ConfigError, match="radiance"):
        noise_budget(s, "mwir")
    with pytest.raises(ConfigError, match="response"):
        noise_budget(s, radiance=1.0)  # the base channel has no response
    b = noise_budget(s, radiance=1.0, response=RectangularResponse(3.0, 5.0))
    assert float(b.snr) > 0
