"""Unit tests of radscene.radiometry.grids."""

import numpy as np
import pytest

from radscene.errors import ConfigError
from radscene.radiometry import resample, wavelength_grid

REL = 1e-12


def test_wavelength_grid_is_inclusive():
    grid = wavelength_grid(0.4, 2.5, 0.01)
    assert grid.size == 211
    assert grid[0] == 0.4 and grid[-1] == 2.5
    assert np.diff(grid) == pytest.approx(np.full(210, 0.01), rel=1e-9)


def test_wavelength_grid_stops_below_a_non_integral_stop():
    assert wavelength_grid(8.0, 12.5, 1.0) == pytest.approx([8.0, 9.0, 10.0, 11.0, 12.0], rel=REL)
    assert wavelength_grid(10.0, 10.0, 0.1) == pytest.approx([10.0], rel=REL)


@pytest.mark.parametrize(
    ("args", "key"),
    [
        ((0.0, 1.0, 0.1), "start"),
        ((1.0, 2.0, 0.0), "step"),
        ((1.0, 2.0, -0.1), "step"),
        ((2.0, 1.0, 0.1), "stop"),
        ((1.0, float("inf"), 0.1), "stop"),
        (("1", 2.0, 0.1), "start"),
    ],
)
def test_wavelength_grid_bad_input(args, key):
    with pytest.raises(ConfigError, match=f"^{key}: "):
        wavelength_grid(*args)


def test_linear_resample_is_exact_for_linear_spectra_and_keeps_leading_axes():
    wl = np.linspace(1.0, 3.0, 5)
    values = np.stack([2.0 * wl + 1.0, -wl, np.ones_like(wl)])[None]  # (1, 3, 5)
    new = np.array([1.0, 1.3, 2.71, 3.0])
    out = resample(wl, values, new)
    assert out.shape == (1, 3, 4)
    assert out[0, 0] == pytest.approx(2.0 * new + 1.0, rel=REL)
    assert out[0, 1] == pytest.approx(-new, rel=REL)


def test_average_resample_is_the_cell_mean():
    wl = np.linspace(0.0, np.pi, 100001) + 1.0  # fine sampling of sin(λ - 1)
    values = np.sin(wl - 1.0)
    new = np.linspace(1.0, 1.0 + np.pi, 11)
    out = resample(wl, values, new, method="average")
    edges = np.concatenate(([new[0]], 0.5 * (new[1:] + new[:-1]), [new[-1]]))
    # exact mean of sin over each cell: (cos a - cos b) / (b - a)
    expected = (np.cos(edges[:-1] - 1.0) - np.cos(edges[1:] - 1.0)) / np.diff(edges)
    assert out == pytest.approx(expected, rel=1e-8)
    # the cells tile the range, so the integral is conserved
    assert np.sum(out * np.diff(edges)) == pytest.approx(2.0, rel=1e-9)


def test_average_of_piecewise_linear_is_exact():
    wl = np.array([1.0, 2.0, 4.0])
    values = np.array([[0.0, 2.0, 0.0]])
    out = resample(wl, values, [1.5, 3.0], method="average")
    # cells [1.0, 2.25] (half a spacing below 1.5 is cut at the source start) and
    # [2.25, 3.75]; S = 2(λ - 1) on [1, 2], 4 - λ on [2, 4]. By hand:
    # (1 + 0.46875) / 1.25 = 1.175 and 1.5 / 1.5 = 1.
    assert out.shape == (1, 2)
    assert out[0] == pytest.approx([1.175, 1.0], rel=REL)


def test_nan_in_values_propagates_locally():
    out = resample([1.0, 2.0, 3.0], [np.nan, 1.0, 1.0], [1.5, 2.5])
    assert np.isnan(out[0]) and out[1] == 1.0


@pytest.mark.parametrize(
    ("new", "method", "match"),
    [
        ([0.5, 2.0], "linear", "outside the source range"),
        ([2.0, 3.5], "average", "outside the source range"),
        ([2.0, 2.5], "cubic", "unknown resampling method 'cubic'; known: linear, average"),
        ([2.5, 2.0], "average", "strictly increasing"),
        ([2.0], "average", "at least 2"),
        ([[2.0]], "linear", "1-D"),
    ],
)
def test_resample_bad_input(new, method, match):
    with pytest.raises(ConfigError, match=match):
        resample([1.0, 2.0, 3.0], [1.0, 2.0, 3.0], new, method=method)


def test_resample_bad_source():
    with pytest.raises(ConfigError, match="^wavelength: "):
        resample([1.0, 1.0, 3.0], [1.0, 2.0, 3.0], [2.0])
    with pytest.raises(ConfigError, match="^values: "):
        resample([1.0, 2.0, 3.0], [1.0, 2.0], [2.0])
