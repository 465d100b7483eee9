"""Surface–atmosphere coupling: 6S's environment function, the PSF and the coupling terms."""

from __future__ import annotations

import numpy as np
import pytest

from radscene.render import coupling


def test_environment_function_satellite_values_by_hand():
    # 6S ENVIRO, satellite: F_R = 1 - 0.930 e^{-0.08 r} - 0.070 e^{-1.10 r},
    # F_A = 1 - 0.448 e^{-0.27 r} - 0.552 e^{-2.83 r}; at r = 1 km, nadir:
    assert coupling.environment_function(1.0, 700.0, 1.0, 1.0) == pytest.approx(0.118201,
                                                                                abs=2e-6)
    assert coupling.environment_function(1.0, 700.0, 1.0, 0.0) == pytest.approx(0.625431,
                                                                                abs=2e-6)
    # mixed by the molecular share of t_d
    assert coupling.environment_function(1.0, 700.0, 1.0, 0.25) == pytest.approx(
        0.25 * 0.118201 + 0.75 * 0.625431, abs=2e-6)


def test_environment_function_aircraft_interpolates_the_height_table():
    # at 3 km: F_R = 1 - 0.606 e^{-0.634 r} - 0.394 e^{-0.08 r}; F_A = 1 - 0.626 e^{-0.86 r}
    # - 0.374 e^{-5.16 r}; at r = 0.5 km:
    f_r = 1 - 0.606 * np.exp(-0.317) - 0.394 * np.exp(-0.04)
    f_a = 1 - 0.626 * np.exp(-0.43) - 0.374 * np.exp(-2.58)
    assert coupling.environment_function(0.5, 3.0, 1.0, 1.0) == pytest.approx(f_r, rel=1e-12)
    assert coupling.environment_function(0.5, 3.0, 1.0, 0.0) == pytest.approx(f_a, rel=1e-12)
    # half way between the 3 and 4 km rows
    mid = coupling.environment_function(0.5, 3.5, 1.0, 0.0)
    lo, hi = (coupling.environment_function(0.5, h, 1.0, 0.0) for h in (3.0, 4.0))
    assert min(lo, hi) < mid < max(lo, hi)


@pytest.mark.parametrize("height", [0.5, 3.0, 700.0])
@pytest.mark.parametrize("cos_view", [1.0, np.cos(np.radians(40.0))])
def test_environment_function_is_a_distribution(height, cos_view):
    r = np.linspace(0.0, 400.0, 40001)
    for share in (0.0, 1.0):
        f = coupling.environment_function(r, height, cos_view, share)
        assert f[0] == pytest.approx(0.0, abs=1e-12)
        assert f[-1] == pytest.approx(1.0, abs=1e-6)
        assert np.all(np.diff(f) >= -1e-12)


def test_oblique_views_see_farther_surroundings():
    nadir = coupling.environment_function(1.0, 700.0, 1.0, 0.3)
    oblique = coupling.environment_function(1.0, 700.0, np.cos(np.radians(50.0)), 0.3)
    assert oblique < nadir


@pytest.mark.parametrize("share", [0.0, 1.0])
def test_psf_kernel_holds_the_environment_function_of_its_window(share):
    cell, half = 50.0, 40
    k = coupling.psf_kernel_fast(cell, half, 700.0, 1.0, share)
    assert np.all(k >= 0.0)
    # the kernel's sum within a disc of radius R is F(R) (cells inside the disc)
    n = 2 * half + 1
    c = (np.arange(n) - half) * cell
    r = np.hypot(*np.meshgrid(c, c, indexing="ij"))
    for radius in (500.0, 1000.0, 1900.0):
        inside = k[r <= radius].sum()
        assert inside == pytest.approx(
            coupling.environment_function(radius / 1000.0, 700.0, 1.0, share), rel=0.03)
    # the centre cell: the disc of the same area, exactly
    assert k[half, half] == pytest.approx(coupling.environment_function(
        cell / np.sqrt(np.pi) / 1000.0, 700.0, 1.0, share), rel=1e-12)


def test_uniform_grid_is_unchanged_by_the_blur():
    grid = np.full((2, 30, 40), 3.5)
    grid[1] = 0.25
    kernels = [coupling.psf_kernel_fast(100.0, 40, 700.0, 1.0, s) for s in (1.0, 0.0)]
    out = coupling.blur_environment(grid, kernels, np.array([0.3, 0.8]))
    assert out == pytest.approx(grid, rel=1e-12)


def _disc_points(radius, cell=50.0, half=80, inner=0.05, outer=0.4):
    c = (np.arange(2 * half + 1) - half) * cell
    x, y = (a.ravel() for a in np.meshgrid(c, c, indexing="ij"))
    values = np.where(np.hypot(x, y) <= radius, inner, outer)[None, :]
    return x, y, values


@pytest.mark.parametrize("radius", [500.0, 1000.0, 2000.0])
def test_dark_disc_centre_sees_the_environment_function_mix(radius):
    """At a disc's centre the surroundings are F(r) of the disc and 1 - F(r) of the rest."""
    x, y, values = _disc_points(radius)
    share = 0.3
    env = coupling.surroundings(x, y, values, np.ones(x.size), 700.0, 1.0, np.array([share]))
    centre = np.flatnonzero((x == 0) & (y == 0))[0]
    f = coupling.environment_function(radius / 1000.0, 700.0, 1.0, share)
    expected = f * 0.05 + (1.0 - f) * 0.4
    assert env[0, centre] == pytest.approx(expected, rel=0.02)
    # brighter towards the disc's edge, darkest at its centre
    on_axis = np.flatnonzero((y == 0) & (x >= 0) & (x < radius))
    order = np.argsort(x[on_axis])
    assert np.all(np.diff(env[0, on_axis[order]]) >= -1e-12)


def test_coupling_terms_of_a_uniform_lambertian_surface_are_6s():
    """L = ρ E_0 (τ + t_d) / (π (1 − S ρ)) over uniform surroundings (6S), with a PSF or not."""
    rho, tau, t_d, s, e_dir, e_dif = 0.3, 0.8, 0.12, 0.15, 900.0, 150.0
    n = 50
    e0 = e_dir + e_dif
    reflected_sun = np.full((1, n), rho / np.pi * e_dir * tau)
    sky = np.full((1, n), rho / np.pi * e_dif * tau)
    args = (reflected_sun + sky, np.zeros((1, n)), sky, np.ones(n), np.full((1, n), tau),
            np.full((1, n), t_d), np.array([s]), np.array([e0]), np.array([e_dif]))
    for environment in (None, lambda v: v.copy()):
        out = coupling.coupling_terms(*args, environment=environment)
        total = reflected_sun + sky + sum(out.values())
        expected = rho * e0 * (tau + t_d) / (np.pi * (1.0 - s * rho))
        assert total == pytest.approx(np.full((1, n), expected), rel=1e-12)
        assert out["adjacency"] == pytest.approx(np.zeros((1, n)), abs=1e-12)
        assert out["multiple_reflection"] == pytest.approx(
            np.full((1, n), rho * e0 * tau / np.pi * s * rho / (1 - s * rho)), rel=1e-12)


def test_coupling_terms_leave_uncovered_pixels_and_black_surfaces_alone():
    args = (np.array([[0.0, 1.0]]), np.zeros((1, 2)), np.array([[0.0, 0.5]]),
            np.array([0.0, 1.0]), np.full((1, 2), 0.8), np.full((1, 2), 0.1), np.array([0.2]),
            np.array([1000.0]), np.array([100.0]))
    out = coupling.coupling_terms(*args)
    for layer in out.values():
        assert layer[0, 0] == 0.0
        assert np.all(np.isfinite(layer))


@pytest.mark.parametrize("half", [2, 5, 12])
def test_blur_equals_a_direct_linear_convolution(half):
    """The FFT blur (padded only as far as the grid's window needs) is the linear convolution
    of the deviation from the border mean, plus that mean, for kernels narrower and wider
    than the grid."""
    rng = np.random.default_rng(4)
    grid = rng.random((2, 9, 6))
    w = 2 * half + 1
    kernels = [rng.random((w, w)) * 0.004, rng.random((w, w)) * 0.006]
    shares = np.array([0.3, 0.8])
    out = coupling.blur_environment(grid, kernels, shares)
    for b, s in enumerate(shares):
        k = s * kernels[0] + (1.0 - s) * kernels[1]
        border = np.concatenate([grid[b, 0], grid[b, -1], grid[b, 1:-1, 0],
                                 grid[b, 1:-1, -1]]).mean()
        dev = np.pad(grid[b] - border, half)
        direct = np.array([[np.sum(dev[i:i + w, j:j + w] * k[::-1, ::-1])
                            for j in range(6)] for i in range(9)])
        assert out[b] == pytest.approx(border + direct, rel=1e-12, abs=1e-14)


@pytest.mark.parametrize("blurred", [False, True])
def test_image_layers_equal_the_coupling_terms_of_the_mixed_quantities(blurred):
    """The compiled image pass gives coupling_terms's layers of the same pixels, with the
    transmittances mixed from path nodes and the PSF surroundings, and adds them to a total."""
    rng = np.random.default_rng(7)
    n_b, side, n_j = 3, 24, 4
    n = side * side
    sun_d, sun_s, sky, emitted = (rng.random((n_b, n)) * f for f in (20.0, 0.5, 4.0, 1.0))
    sun_s[:, ::3] = 0.0
    coverage = rng.uniform(0.5, 1.0, n)
    coverage[5] = 0.0
    tau_nodes, t_d_nodes = rng.uniform(0.5, 0.9, (n_b, n_j)), rng.uniform(0.0, 0.2, (n_b, n_j))
    index = rng.integers(0, n_j, (n + 3, 2))
    weight = rng.random((n + 3, 2))
    weight[::4, 1] = 0.0
    weight /= weight.sum(axis=1, keepdims=True)
    rank = rng.permutation(n + 3)[:n]
    tau = np.array([[weight[h] @ tau_nodes[b, index[h]] for h in rank] for b in range(n_b)])
    t_d = np.array([[weight[h] @ t_d_nodes[b, index[h]] for h in rank] for b in range(n_b)])
    s, e0, e_dif = rng.uniform(0.05, 0.2, n_b), rng.uniform(10, 60, n_b), rng.uniform(2, 20, n_b)
    e_dif[-1] = 0.0
    x, y = (a.ravel() * 30.0 for a in np.meshgrid(np.arange(side), np.arange(side),
                                                 indexing="ij"))
    shares = rng.random(n_b)
    environment = None
    psf = None
    if blurred:
        psf = (x, y, 8.0, 0.9, shares)

        def environment(values):
            return coupling.surroundings(x, y, values, coverage, 8.0, 0.9, shares)
    pixel = rng.permutation(n + 5)[:n]
    names = ("multiple_reflection", "diffuse_transmitted", "adjacency")
    expected = {k: np.zeros((n_b, n + 5)) for k in names}
    coupling.coupling_terms(sun_d + sun_s + sky, emitted, sky, coverage, tau, t_d, s, e0, e_dif,
                            environment, out=expected, pixel=pixel)
    out = {k: np.zeros((n_b, n + 5)) for k in names}
    total = rng.random((n_b, n + 5))
    before = total.copy()
    nodes = coupling.NodeTransmittances(tau_nodes, t_d_nodes, index, weight, rank)
    coupling.image_layers(sun_d, sun_s, sky, emitted, coverage, nodes, s, e0, e_dif, out, pixel,
                          psf, total)
    for k in names:
        assert out[k] == pytest.approx(expected[k], rel=1e-12, abs=1e-15)
    assert np.any(out["adjacency"] != 0.0) == blurred
    assert total == pytest.approx(before + sum(out.values()), rel=1e-15)


@pytest.mark.parametrize(("args", "key"), [
    ((-0.1, 700.0, 1.0, 0.5), "r_km"), ((np.nan, 700.0, 1.0, 0.5), "r_km"),
    ((1.0, 0.0, 1.0, 0.5), "height_km"), ((1.0, 700.0, 0.0, 0.5), "cos_view"),
    ((1.0, 700.0, 1.2, 0.5), "cos_view"), ((1.0, 700.0, 1.0, 1.5), "rayleigh_share"),
])
def test_environment_function_refuses_bad_input(args, key):
    with pytest.raises(ValueError, match=key):
        coupling.environment_function(*args)


def test_environment_function_below_the_table_uses_its_lowest_row():
    assert coupling.environment_function(0.3, 0.2, 1.0, 0.4) == pytest.approx(
        coupling.environment_function(0.3, 0.5, 1.0, 0.4), rel=1e-12)
