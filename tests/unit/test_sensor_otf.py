"""OTF factors: closed forms, the pupil-autocorrelation oracle, broadcasting, bad input."""

from __future__ import annotations

import numpy as np
import pytest

from radscene.errors import ConfigError
from radscene.sensor.otf import (
    MAX_WAVEFRONT_ERROR,
    defocus_otf,
    detector_otf,
    diffraction_otf,
    jitter_otf,
    pupil_otf,
    smear_otf,
    wavefront_error_otf,
)

X = np.linspace(0.0, 1.0, 41)


def _clear(x):
    """Goodman eq. 6-32, written out independently of radscene."""
    x = np.minimum(np.abs(x), 1.0)
    return 2.0 / np.pi * (np.arccos(x) - x * np.sqrt(1.0 - x * x))


def test_diffraction_clear_pupil_is_goodman_closed_form():
    # 10 um at F/2: cut-off 1 / (lambda N) = 0.05 cycles/um
    nu = X * 0.05
    assert diffraction_otf(nu, 10.0, 2.0) == pytest.approx(_clear(X), abs=1e-12)
    assert diffraction_otf([0.05, 0.06, 1.0], 10.0, 2.0) == pytest.approx([0, 0, 0], abs=0)


@pytest.mark.parametrize("eta", [0.0, 0.2, 0.35, 0.5, 0.7])
def test_annular_diffraction_matches_pupil_autocorrelation(eta):
    analytic = diffraction_otf(X, 1.0, 1.0, eta)
    numeric = pupil_otf(X, eta, samples=512)
    assert analytic == pytest.approx(numeric, abs=1e-3)


def test_annular_known_values():
    # eta -> at x <= (1 - eta)/2 the cross term is -2 eta^2 (O'Neill 1956); for eta = 0.5,
    # x = 0.2: (A(0.2) + eta^2 A(0.2/eta) - 2 eta^2) / (1 - eta^2)
    eta, x = 0.5, 0.2
    expected = (_clear(x) + eta**2 * _clear(x / eta) - 2 * eta**2) / (1 - eta**2)
    assert float(diffraction_otf(x, 1.0, 1.0, eta)) == pytest.approx(expected, abs=1e-12)
    # an annulus passes more of the high frequencies than a clear pupil
    assert diffraction_otf(0.8, 1.0, 1.0, 0.5) > diffraction_otf(0.8, 1.0, 1.0, 0.0)


def test_diffraction_broadcasts_over_wavelength_and_obscuration():
    out = diffraction_otf(np.full((4, 1, 1), 0.02), np.array([3.0, 4.0, 5.0])[None, :, None],
                          2.0, np.array([0.0, 0.3])[None, None, :])
    assert out.shape == (4, 3, 2)
    assert out[0, 1, 0] == pytest.approx(_clear(0.02 * 4.0 * 2.0), abs=1e-12)


@pytest.mark.parametrize(("kwargs", "key"), [
    ({"wavelength": 0.0}, "wavelength"),
    ({"f_number": 0.0}, "f_number"),
    ({"f_number": -2.0}, "f_number"),
    ({"obscuration": 1.0}, "obscuration"),
    ({"obscuration": -0.1}, "obscuration"),
])
def test_diffraction_bad_input_names_key(kwargs, key):
    args = {"frequency": 0.01, "wavelength": 4.0, "f_number": 2.0, "obscuration": 0.0, **kwargs}
    with pytest.raises(ConfigError, match=key):
        diffraction_otf(**args)


def test_wavefront_error_shannon_factor():
    # W = 0.09 waves: 1 - (0.5)^2 [1 - 4 (x - 0.5)^2]
    w = 0.09 * 4.0
    h = wavefront_error_otf(X / 8.0, 4.0, 2.0, w)
    assert h == pytest.approx(1.0 - 0.25 * (1.0 - 4.0 * (X - 0.5) ** 2), abs=1e-12)
    assert h[0] == 1.0 and h[-1] == pytest.approx(1.0, abs=1e-12)
    with pytest.raises(ConfigError, match="wavefront_error"):
        wavefront_error_otf(0.01, 1.0, 2.0, (MAX_WAVEFRONT_ERROR + 0.01) * 1.0)


@pytest.mark.parametrize("w020", [0.1, 0.25, 0.5, 1.0])
def test_defocus_product_close_to_exact_pupil_otf(w020):
    approx = diffraction_otf(X, 1.0, 1.0) * defocus_otf(X, 1.0, 1.0, w020)
    exact = pupil_otf(X, 0.0, w020, samples=512)
    assert approx == pytest.approx(exact, abs=0.02)


def test_defocus_limits():
    assert defocus_otf(X, 4.0, 2.0, 0.0) == pytest.approx(np.ones_like(X), abs=0)
    # geometric limit at small x: 2 J1(a)/a with a = 8 pi (W/lambda) x; first zero a = 3.8317
    x0 = 3.8317059702 / (8 * np.pi * 5.0)
    assert float(defocus_otf(x0 / 4.0, 1.0, 4.0, 5.0)) == pytest.approx(0.0, abs=0.03)


def test_jitter_gaussian():
    f = np.array([0.0, 0.1, 0.5])
    assert jitter_otf(f, 0.0, 2.0) == pytest.approx(np.exp(-2 * np.pi**2 * 4.0 * f**2), rel=1e-12)
    # separable in x and y
    assert float(jitter_otf(0.3, 0.2, 1.0, 2.0)) == pytest.approx(
        float(jitter_otf(0.3, 0, 1.0) * jitter_otf(0, 0.2, 2.0)), rel=1e-12)
    with pytest.raises(ConfigError, match="jitter"):
        jitter_otf(0.1, 0.1, -1.0)


def test_smear_and_footprint_are_sinc():
    assert float(smear_otf(0.25, 0.0, 2.0)) == pytest.approx(2 / np.pi, rel=1e-12)
    # diagonal smear projects on the frequency direction
    assert float(smear_otf(0.1, 0.1, 3.0, 2.0)) == pytest.approx(np.sinc(0.5), rel=1e-12)
    # negative lobe kept (phase reversal)
    assert float(smear_otf(0.75, 0.0, 2.0)) < 0
    assert detector_otf(np.array([0.25, 0.5, 1.0]), 0.0, 1.0) == pytest.approx(
        [np.sin(np.pi / 4) / (np.pi / 4), 2 / np.pi, 0.0], abs=1e-15)
    with pytest.raises(ConfigError, match="pitch"):
        detector_otf(0.1, 0.1, 0.0)


def test_nan_frequency_propagates():
    assert np.isnan(jitter_otf(np.nan, 0.0, 1.0))
    assert np.isnan(detector_otf(np.nan, 0.0, 1.0))
