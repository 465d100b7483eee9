"""Unit tests of radscene.radiometry.planck and the radiation constants."""

import math
import warnings

import numpy as np
import pytest
from scipy import constants as sc
from scipy.integrate import quad
from scipy.optimize import brentq

from radscene.errors import ConfigError
from radscene.radiometry import (
    C1,
    C1L,
    C2,
    SIGMA,
    GaussianResponse,
    RectangularResponse,
    TabulatedResponse,
    band_brightness_temperature,
    band_radiance,
    brightness_temperature,
    exitance,
    peak_wavelength,
    radiance_temperature_derivative,
    spectral_radiance,
    spectral_radiance_wavenumber,
)

QUAD_REL = 1e-10  # band integrals vs adaptive quadrature
ROUND_TRIP_ABS = 1e-6  # [K], brightness temperature round trips


def planck_frequency(frequency, temperature):
    """Independent oracle: Planck per unit frequency [W m-2 sr-1 Hz-1], from h, c, k."""
    return 2 * sc.h * frequency**3 / sc.c**2 / np.expm1(sc.h * frequency / (sc.k * temperature))


def quad_band(lo, hi, temperature):
    return quad(
        lambda wl: spectral_radiance(wl, temperature), lo, hi, epsabs=0, epsrel=1e-13, limit=200
    )[0]


def test_constants_formulae():
    assert C1 == pytest.approx(2 * math.pi * sc.h * sc.c**2, rel=1e-15)
    assert C1L == pytest.approx(C1 / math.pi, rel=1e-15)
    assert C2 == pytest.approx(sc.h * sc.c / sc.k, rel=1e-15)
    # σ = 2 π⁵ k⁴ / (15 h³ c²) = π⁴ c1L / (15 c2⁴) · π
    assert SIGMA == pytest.approx(math.pi**5 * C1L / (15 * C2**4), rel=1e-12)


@pytest.mark.parametrize("wavelength", [0.3, 0.55, 4.0, 10.0, 15.0])
@pytest.mark.parametrize("temperature", [77.0, 300.0, 1000.0, 5778.0])
def test_spectral_radiance_matches_frequency_form(wavelength, temperature):
    # L_λ = L_ν c / λ², λ in m, then per um.
    lam = wavelength * 1e-6
    expected = planck_frequency(sc.c / lam, temperature) * sc.c / lam**2 * 1e-6
    assert spectral_radiance(wavelength, temperature) == pytest.approx(expected, rel=1e-12)


def test_spectral_radiance_broadcasts():
    wl = np.array([[1.0], [4.0], [10.0]])
    t = np.array([200.0, 300.0, 400.0, 1000.0])
    out = spectral_radiance(wl, t)
    assert out.shape == (3, 4)
    assert out[1, 2] == pytest.approx(float(spectral_radiance(4.0, 400.0)), rel=1e-15)


def test_zero_temperature_and_tiny_lambda_t_give_zero_without_warnings():
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert np.all(spectral_radiance([0.01, 10.0], 0.0) == 0.0)
        assert spectral_radiance(0.01, 1.0) == 0.0  # c2/λT ~ 1.4e6
        assert spectral_radiance_wavenumber(1e5, 1.0) == 0.0
        assert np.all(radiance_temperature_derivative([0.01, 10.0], [0.0, 1.0]) == 0.0)
        assert band_radiance(0.4, 0.7, 0.0) == 0.0
        assert band_radiance(0.4, 0.7, 1.0) == 0.0
        assert brightness_temperature(10.0, 0.0) == 0.0
        assert peak_wavelength(0.0) == np.inf


def test_nan_propagates():
    assert np.isnan(spectral_radiance(10.0, np.nan))
    assert np.isnan(band_radiance(8.0, 12.0, np.nan))
    assert np.isnan(brightness_temperature(10.0, np.nan))
    assert np.isnan(radiance_temperature_derivative(10.0, np.nan))


@pytest.mark.parametrize(
    "call",
    [
        lambda: spectral_radiance(10.0, -1.0),
        lambda: spectral_radiance_wavenumber(1000.0, [300.0, -0.1]),
        lambda: radiance_temperature_derivative(10.0, -5.0),
        lambda: band_radiance(8.0, 12.0, -300.0),
        lambda: exitance(-1.0),
        lambda: peak_wavelength(-1.0),
    ],
)
def test_negative_temperature_raises(call):
    with pytest.raises(ConfigError, match="temperature must be >= 0 K"):
        call()


@pytest.mark.parametrize(
    ("call", "key"),
    [
        (lambda: spectral_radiance(0.0, 300.0), "wavelength"),
        (lambda: spectral_radiance([-1.0, 10.0], 300.0), "wavelength"),
        (lambda: spectral_radiance_wavenumber(0.0, 300.0), "wavenumber"),
        (lambda: radiance_temperature_derivative(-4.0, 300.0), "wavelength"),
        (lambda: band_radiance(0.0, 12.0, 300.0), "wavelength_min"),
        (lambda: band_radiance(12.0, 8.0, 300.0), "wavelength_max"),
        (lambda: brightness_temperature(0.0, 1.0), "wavelength"),
        (lambda: brightness_temperature(10.0, -1.0), "radiance"),
    ],
)
def test_bad_spectral_input_raises(call, key):
    with pytest.raises(ConfigError, match=f"^{key}: "):
        call()


def test_wavenumber_form_is_the_wavelength_form_times_dlambda_dnu():
    wl = np.array([2.0, 5.0, 10.0, 14.0])
    nu = 1e4 / wl
    expected = spectral_radiance(wl, 300.0) * wl**2 / 1e4
    assert spectral_radiance_wavenumber(nu, 300.0) == pytest.approx(expected, rel=1e-12)


@pytest.mark.parametrize(
    ("wavelength", "temperature"), [(0.5, 5778.0), (4.0, 300.0), (10.0, 250.0)]
)
def test_temperature_derivative_matches_central_difference(wavelength, temperature):
    h = 1e-5 * temperature  # truncation ~ (x h / T)² / 6 < 1e-8
    diff = (
        spectral_radiance(wavelength, temperature + h)
        - spectral_radiance(wavelength, temperature - h)
    ) / (2 * h)
    assert radiance_temperature_derivative(wavelength, temperature) == pytest.approx(diff, rel=1e-7)


@pytest.mark.parametrize(
    ("lo", "hi", "temperature"),
    [
        (8.0, 12.0, 300.0),
        (0.4, 0.7, 5778.0),
        (0.4, 0.7, 300.0),
        (3.0, 5.0, 1500.0),
        (1.0, 20.0, 50.0),
        (15.0, 100.0, 300.0),
        (10.0, 10.01, 300.0),
        (0.2, 3.0, 5000.0),
    ],
)
def test_band_radiance_matches_adaptive_quadrature(lo, hi, temperature):
    assert band_radiance(lo, hi, temperature) == pytest.approx(
        quad_band(lo, hi, temperature), rel=QUAD_REL
    )


def test_band_radiance_whole_spectrum_is_stefan_boltzmann_over_pi():
    t = np.array([10.0, 300.0, 6000.0])
    assert band_radiance(1e-4, np.inf, t) == pytest.approx(SIGMA * t**4 / math.pi, rel=1e-12)


def test_band_radiance_is_additive_and_broadcasts():
    t = np.array([[250.0], [300.0], [350.0]])
    edges = np.array([8.0, 9.0, 10.5, 12.0])
    parts = band_radiance(edges[:-1], edges[1:], t)
    assert parts.shape == (3, 3)
    assert parts.sum(axis=1) == pytest.approx(band_radiance(8.0, 12.0, t[:, 0]), rel=1e-13)


def test_very_narrow_band_is_width_times_spectral_radiance():
    width = 1e-6
    value = band_radiance(10.0, 10.0 + width, 300.0)
    assert value == pytest.approx(spectral_radiance(10.0 + width / 2, 300.0) * width, rel=1e-12)
    assert band_radiance(10.0, 10.0, 300.0) == 0.0


def test_exitance_and_peak_wavelength():
    assert exitance([0.0, 300.0]) == pytest.approx([0.0, SIGMA * 300.0**4], rel=1e-15)
    peak = float(peak_wavelength(300.0))
    # the peak is the maximum: neighbours are lower
    values = spectral_radiance(peak * np.array([0.999, 1.0, 1.001]), 300.0)
    assert values[1] > values[0] and values[1] > values[2]
    # Wien: x = c2/(λT) solves x = 5 (1 - e^-x)
    x = C2 / (peak * 1e-6 * 300.0)
    assert x == pytest.approx(5 * (1 - math.exp(-x)), rel=1e-12)


def test_brightness_temperature_round_trip_shape_3x4():
    rng = np.random.default_rng(1)
    t = rng.uniform(150.0, 3000.0, (3, 4))
    wl = np.array([0.5, 3.9, 10.0, 12.0])
    radiance = spectral_radiance(wl, t)
    assert brightness_temperature(wl, radiance) == pytest.approx(t, abs=ROUND_TRIP_ABS, rel=0)
    assert brightness_temperature(wl, radiance).shape == (3, 4)


def band_temperature_oracle(radiance, response):
    """Slow reference: root finding on the quadrature-integrated band radiance."""

    def band(t):
        return response.integrate_function(lambda wl: spectral_radiance(wl, t))

    return brentq(lambda t: band(t) - radiance, 1.0, 1e5, xtol=1e-12, rtol=1e-15)


RESPONSES_UNDER_TEST = [
    RectangularResponse(8.0, 12.0),
    RectangularResponse(3.0, 5.0),
    GaussianResponse(10.5, 1.0),
    TabulatedResponse([0.45, 0.5, 0.6, 0.65], [0.0, 1.0, 0.8, 0.0]),
]


@pytest.mark.parametrize("response", RESPONSES_UNDER_TEST, ids=lambda r: r.name)
def test_band_brightness_temperature_round_trip_shape_3x4(response):
    rng = np.random.default_rng(2)
    t = rng.uniform(180.0, 2500.0, (3, 4))
    radiance = response.integrate_function(lambda wl: spectral_radiance(wl, t[..., None]))
    assert radiance.shape == (3, 4)
    got = band_brightness_temperature(radiance, response)
    assert got.shape == (3, 4)
    assert got == pytest.approx(t, abs=ROUND_TRIP_ABS, rel=0)


@pytest.mark.parametrize("response", RESPONSES_UNDER_TEST[:3], ids=lambda r: r.name)
@pytest.mark.parametrize("radiance_scale", [1e-3, 1.0, 1e3])
def test_band_brightness_temperature_matches_root_finding_oracle(response, radiance_scale):
    radiance = radiance_scale * response.equivalent_width()
    expected = band_temperature_oracle(radiance, response)
    assert float(band_brightness_temperature(radiance, response)) == pytest.approx(
        expected, abs=ROUND_TRIP_ABS, rel=0
    )


def test_band_brightness_temperature_special_values_and_errors():
    band = RectangularResponse(8.0, 12.0)
    got = band_brightness_temperature([0.0, np.nan, np.inf], band)
    assert got[0] == 0.0 and np.isnan(got[1]) and got[2] == np.inf
    with pytest.raises(ConfigError, match="radiance: band radiance must be >= 0"):
        band_brightness_temperature([1.0, -1.0], band)
    with pytest.raises(ConfigError, match="1e\\+06 K"):
        band_brightness_temperature(1e12, band)


def test_band_brightness_temperature_table_is_built_once_per_response():
    from radscene.radiometry.planck import _brightness_table

    band = RectangularResponse(8.0, 12.0)
    radiance = band.integrate_function(lambda wl: spectral_radiance(wl, np.array([[250.0],
                                                                                  [320.0]])))
    first = band_brightness_temperature(radiance, band)
    table = band.__dict__["_brightness_table"]
    assert _brightness_table(band) is table
    assert np.array_equal(band_brightness_temperature(radiance, band), first)
    assert first == pytest.approx([250.0, 320.0], abs=ROUND_TRIP_ABS, rel=0)
    with pytest.raises(ValueError):
        table[0][0] = 0.0  # read-only: no caller can spoil it
    # another response gets its own table
    other = RectangularResponse(3.0, 5.0)
    band_brightness_temperature(1.0, other)
    assert other.__dict__["_brightness_table"][0][0] != table[0][0]


def test_band_brightness_temperature_of_an_image_does_not_depend_on_pixel_order():
    # each value's table interval is looked for from the last one's: sorted, shuffled and
    # repeated values must all come out as when inverted one by one
    band = GaussianResponse(10.0, 1.0)
    image = np.random.default_rng(3).uniform(5.0, 60.0, (1024, 1024))
    result = band_brightness_temperature(image, band)
    assert result.shape == image.shape
    flat = image.ravel()
    order = np.argsort(flat)
    assert np.array_equal(band_brightness_temperature(flat[order], band), result.ravel()[order])
    single = np.array([float(band_brightness_temperature(v, band)) for v in flat[:200]])
    assert np.array_equal(single, result.ravel()[:200])
    again = band_brightness_temperature(np.repeat(flat[:50], 3), band)
    assert np.array_equal(again, np.repeat(result.ravel()[:50], 3))
