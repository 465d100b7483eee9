"""Unit tests of the heat-balance flux terms: radscene.thermal.radiation and .convection."""

import numpy as np
import pytest
from scipy import constants as sc

from radscene.errors import ConfigError
from radscene.thermal import (
    CONVECTION_MODELS,
    SIGMA,
    absorbed_shortwave,
    absorbed_sky_longwave,
    convection_coefficient,
    convective_flux,
    emitted_longwave,
    emitted_longwave_derivative,
)


def test_sigma_from_planck_constants():
    expected = 2 * np.pi**5 * sc.k**4 / (15 * sc.h**3 * sc.c**2)
    assert SIGMA == pytest.approx(expected, rel=1e-9)


def test_absorbed_shortwave_reference_values():
    # 0.9 (800 * 0.5 * 1 + 100 * 0.8) = 432
    assert absorbed_shortwave(0.9, 800.0, 0.5, 100.0, lit=1.0, sky_view_fraction=0.8) == pytest.approx(432.0, rel=1e-12)
    # in shadow only the diffuse term; sun behind the surface likewise
    assert absorbed_shortwave(0.5, 800.0, 0.5, 100.0, lit=0.0) == pytest.approx(50.0, rel=1e-12)
    assert absorbed_shortwave(0.5, 800.0, -0.3, 100.0) == pytest.approx(50.0, rel=1e-12)
    # half lit
    assert absorbed_shortwave(1.0, 1000.0, 1.0, 0.0, lit=0.5) == pytest.approx(500.0, rel=1e-12)


def test_shortwave_and_sky_broadcast():
    alpha = np.array([0.2, 0.9])[:, None]
    cos_i = np.linspace(-1, 1, 5)[None, :]
    q = absorbed_shortwave(alpha, 900.0, cos_i, 50.0)
    assert q.shape == (2, 5)
    np.testing.assert_allclose(q[:, :3], np.broadcast_to(alpha * 50.0, (2, 3)), rtol=1e-12)
    assert absorbed_sky_longwave(np.ones((3, 1)), np.full(4, 320.0), 0.5).shape == (3, 4)
    assert absorbed_sky_longwave(0.95, 300.0, 0.5) == pytest.approx(142.5, rel=1e-12)


def test_emission_and_its_derivative():
    assert emitted_longwave(1.0, 300.0) == pytest.approx(459.30, abs=0.01)
    t = np.array([250.0, 300.0, 350.0])
    step = 1e-3
    numeric = (emitted_longwave(0.9, t + step) - emitted_longwave(0.9, t - step)) / (2 * step)
    np.testing.assert_allclose(emitted_longwave_derivative(0.9, t), numeric, rtol=1e-8)
    assert np.isnan(emitted_longwave(1.0, np.nan))


def test_convection_correlations():
    assert convection_coefficient(0.0) == pytest.approx(5.7, rel=1e-12)
    assert convection_coefficient(2.0, "McAdams") == pytest.approx(13.3, rel=1e-12)
    assert convection_coefficient(2.0, "watmuff") == pytest.approx(8.8, rel=1e-12)
    np.testing.assert_allclose(convection_coefficient(np.array([0.0, 1.0, 5.0])), [5.7, 9.5, 24.7], rtol=1e-12)
    assert convective_flux(10.0, 300.0, 310.0) == pytest.approx(-100.0, rel=1e-12)
    assert set(CONVECTION_MODELS) == {"mcadams", "mixed", "none", "watmuff"}
    assert convection_coefficient(2.0, "mixed", 8.0, 1.0) == pytest.approx(6.0 + 9.482 * 2.0 / 6.238, rel=1e-12)


def test_convection_rejects_bad_input():
    with pytest.raises(ConfigError, match="unknown convection model 'jurges'; known: mcadams, mixed, none, watmuff"):
        convection_coefficient(1.0, "jurges")
    with pytest.raises(ConfigError, match="wind_speed: wind speed must be >= 0"):
        convection_coefficient(np.array([1.0, -0.5]))
