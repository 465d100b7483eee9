"""The channels of a hyperspectral grid: triangles that sum to one, their widths, and the
weights that turn channel values into band radiances."""

from __future__ import annotations

import numpy as np
import pytest

from radscene.errors import ConfigError
from radscene.radiometry import (
    GaussianResponse,
    TabulatedResponse,
    channel_grid,
    spectral_radiance,
)

EXACT = 1e-12


def test_grid_centres_widths_and_names():
    grid = channel_grid(0.4, 2.5, 0.01)
    assert len(grid) == 211
    assert grid.wavelength[0] == 0.4 and grid.wavelength[-1] == 2.5
    assert grid.width[0] == pytest.approx(0.005, rel=EXACT)
    assert grid.width[1] == pytest.approx(0.01, rel=EXACT)
    assert grid.width.sum() == pytest.approx(2.1, rel=EXACT)
    assert grid.names[:2] == ["0.4000 um", "0.4100 um"]
    assert len(set(channel_grid(3.0, 14.0, 0.05).names)) == 221


def test_responses_partition_unity_and_have_their_widths():
    grid = channel_grid(8.0, 12.0, 0.25)
    responses = grid.responses()
    wl = np.linspace(8.0, 12.0, 4001)
    assert np.abs(sum(r(wl) for r in responses) - 1.0).max() < EXACT
    outside = np.array([7.9, 12.1])
    assert all(np.all(r(outside) == 0.0) for r in responses)
    widths = [r.equivalent_width() for r in responses]
    np.testing.assert_allclose(widths, grid.width, rtol=EXACT)
    # a channel's response peaks at its centre and is half at half a step from it
    r = responses[5]
    assert r(grid.wavelength[5]) == 1.0
    assert r(grid.wavelength[5] + 0.125) == pytest.approx(0.5, rel=EXACT)


def test_band_weights_integrate_channel_values_exactly():
    """Σ S(λ_c) w_c L_c = ∫ S L dλ for S linear between the centres, with L_c the channels'
    response-weighted means of a Planck spectrum (each integral by the responses' own rule)."""
    grid = channel_grid(8.0, 12.0, 0.25)
    spectrum = lambda wl: spectral_radiance(wl, 300.0)  # noqa: E731
    values = np.array([r.integrate_function(spectrum) for r in grid.responses()]) / grid.width
    band = TabulatedResponse([8.0, 8.5, 9.25, 11.0, 12.0], [0.3, 0.0, 1.0, 0.6, 0.2])
    want = band.integrate_function(spectrum)
    assert grid.band_weights(band) @ values == pytest.approx(want, rel=1e-12)
    # a response with knots between the centres is integrated through its interpolant only
    gaussian = GaussianResponse(10.0, 0.5)
    got = grid.band_weights(gaussian) @ values
    assert abs(got / gaussian.integrate_function(spectrum) - 1.0) > 1e-4


def test_band_weights_refuse_a_response_beyond_the_grid():
    grid = channel_grid(8.0, 12.0, 0.25)
    with pytest.raises(ConfigError, match="spans 11–12.5 µm, beyond the grid's 8–12 µm"):
        grid.band_weights(TabulatedResponse([11.0, 12.5], [1.0, 1.0]))


@pytest.mark.parametrize("args, key, message", [
    ((0.4, 2.5, 0.0), "spectral.step", "must be > 0"),
    ((0.4, 2.5, -0.01), "spectral.step", "must be > 0"),
    ((0.4, 0.4, 0.01), "spectral.max", "the grid is empty"),
    ((0.4, 0.3, 0.01), "spectral.max", "the grid is empty"),
    ((0.0, 2.5, 0.01), "spectral.min", "must be > 0"),
    ((0.4, 2.5, 3.0), "spectral.step", "fewer than two channels"),
    ((0.4, float("nan"), 0.01), "spectral.max", "finite"),
    ((0.4, "x", 0.01), "spectral.max", "must be a wavelength"),
])
def test_bad_grids_name_their_key(args, key, message):
    with pytest.raises(ConfigError, match=message) as info:
        channel_grid(*args)
    assert info.value.key == key
