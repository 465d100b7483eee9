"""Unit tests of radscene.thermal.conduction against closed forms (Carslaw & Jaeger 1959).

Measured errors of the default grid (30 nodes, growth 1.2, 5 penetration depths) with one-
minute steps, for a sinusoidal surface temperature over a semi-infinite solid: amplitude
within 0.38 % and phase within 0.0043 rad of the closed form down to one penetration depth;
a refined grid (100 nodes, growth 1.05, 8 depths): 0.56 % and 0.0017 rad down to three.
"""

from types import SimpleNamespace

import numpy as np
import pytest

from radscene.errors import ConfigError
from radscene.materials.thermal import Layer, get_thermal_properties
from radscene.thermal import (
    DAY,
    ImplicitConduction,
    build_grid,
    penetration_depth,
    reference_step,
    stack_depth,
)

K, RHO, C = 1.0, 2000.0, 1000.0  # W m-1 K-1, kg m-3, J kg-1 K-1
OMEGA = 2 * np.pi / DAY
PENALTY = 1e9  # W m-2 K-1: q_s = H (T_s - T_0) imposes T_0 = T_s to ~1e-6 K


def _stack(layers, bottom):
    return SimpleNamespace(layers=tuple(layers), bottom=bottom)


def _solid(thickness=None):
    return Layer("solid", thickness, K, RHO, C)


def _periodic_run(n_nodes, growth, depths, dt=60.0, mean=300.0, amplitude=10.0):
    """Impose T_s = mean + A cos ωt on a semi-infinite solid started on the closed form;
    return the depths and the fitted amplitude ratio and phase lag over the second day."""
    d = float(penetration_depth(K, RHO, C))
    grid = build_grid([_stack([_solid()], "semi-infinite")], n_nodes=n_nodes, growth=growth, penetration_depths=depths)
    z = grid.depth[0]
    temperature = (mean + amplitude * np.exp(-z / d) * np.cos(-z / d))[None]
    solver = ImplicitConduction(grid, dt)
    n_steps = int(round(2 * DAY / dt))
    t = np.arange(1, n_steps + 1) * dt
    record = np.empty((n_steps, z.size))
    for i in range(n_steps):
        ts = mean + amplitude * np.cos(OMEGA * t[i])
        temperature = solver.step(temperature, PENALTY * ts, -PENALTY)
        record[i] = temperature[0]
    second = t > DAY
    design = np.column_stack([np.cos(OMEGA * t[second]), np.sin(OMEGA * t[second])])
    a, b = np.linalg.lstsq(design, record[second] - mean, rcond=None)[0]
    return z, d, np.hypot(a, b) / amplitude, np.arctan2(b, a)


@pytest.mark.parametrize(
    ("n_nodes", "growth", "depths", "deepest", "amp_rel", "phase_abs"),
    [(30, 1.2, 5.0, 1.0, 0.006, 0.006), (100, 1.05, 8.0, 3.0, 0.008, 0.003)],
)
def test_semi_infinite_sinusoid_decays_and_lags(n_nodes, growth, depths, deepest, amp_rel, phase_abs):
    z, d, ratio, lag = _periodic_run(n_nodes, growth, depths)
    sel = (z > 0.05 * d) & (z < deepest * d)
    assert sel.sum() >= 10
    np.testing.assert_allclose(ratio[sel], np.exp(-z[sel] / d), rtol=amp_rel)
    np.testing.assert_allclose(lag[sel], z[sel] / d, atol=phase_abs)
    # a wrong penetration depth (sqrt(kappa/omega), the factor 2 dropped) is rejected
    wrong = np.sqrt(K / (RHO * C) / OMEGA)
    near_d = sel & (z > 0.5 * d)
    assert np.all(np.abs(ratio[near_d] / np.exp(-z[near_d] / wrong) - 1) > 0.1)


def test_penetration_depth_closed_form():
    assert penetration_depth(K, RHO, C) == pytest.approx(np.sqrt(2 * K / (RHO * C) / OMEGA), rel=1e-12)
    assert penetration_depth(K, RHO, C, period=4 * DAY) == pytest.approx(2 * penetration_depth(K, RHO, C), rel=1e-12)


@pytest.mark.parametrize("stack", [_stack([_solid(0.05)], "insulated"), get_thermal_properties("asphalt_shingle")])
def test_insulated_slab_heats_at_flux_over_capacity(stack):
    q, dt, n_steps, t0 = 200.0, 300.0, 120, 290.0  # W m-2, s, -, K
    grid = build_grid([stack])
    volumetric = sum(layer.thickness * layer.density * layer.specific_heat for layer in stack.layers)
    assert grid.capacity.sum() == pytest.approx(volumetric, rel=1e-12)
    solver = ImplicitConduction(grid, dt)
    temperature = np.full((1, grid.n_nodes), t0)
    for _ in range(n_steps):
        temperature = solver.step(temperature, q)
    mean = grid.heat_content(temperature)[0] / volumetric
    assert mean == pytest.approx(t0 + q * n_steps * dt / volumetric, abs=1e-9)
    # the surface is warmer than the back face while heating
    assert temperature[0, 0] > temperature[0, -1] + 0.1


def test_two_layer_steady_state_is_piecewise_linear():
    q, t_deep = 100.0, 280.0  # W m-2, K
    top, bottom = Layer("top", 0.03, 0.5, 1200.0, 1400.0), Layer("base", None, 2.0, 2000.0, 1000.0)
    stack = _stack([top, bottom], "semi-infinite")
    grid = build_grid([stack], deep_temperature=t_deep)
    z = grid.depth[0]
    depth = z[-1]
    assert depth == pytest.approx(stack_depth(stack).sum(), rel=1e-12)
    assert np.any(np.isclose(z, 0.03, rtol=0, atol=1e-15)), "the interface is a node"
    solver = ImplicitConduction(grid, 1e15)  # backward Euler with Δt → ∞ is the steady state
    temperature = solver.step(np.full((1, z.size), 300.0), q)[0]
    interface = t_deep + q * (depth - 0.03) / bottom.conductivity
    exact = np.where(z >= 0.03, t_deep + q * (depth - z) / bottom.conductivity, interface + q * (0.03 - z) / top.conductivity)
    np.testing.assert_allclose(temperature, exact, rtol=0, atol=1e-6)
    flux = grid.conductance[0] * -np.diff(temperature)
    np.testing.assert_allclose(flux, q, rtol=1e-8)
    # the wrong (averaged-conductivity) profile is rejected
    k_mean = depth / (0.03 / top.conductivity + (depth - 0.03) / bottom.conductivity) * 0.5 + 0.5 * top.conductivity
    assert abs(temperature[0] - (t_deep + q * depth / k_mean)) > 1.0


def test_vectorised_step_matches_reference_solver():
    names = ["asphalt", "white_paint", "painted_metal", "snow", "bare_soil", "asphalt_shingle", "green_leaf"]
    stacks = [get_thermal_properties(n) for n in names]
    grid = build_grid(stacks, material_index=np.array([0, 1, 2, 3, 4, 5, 6, 2, 0]), deep_temperature=285.0)
    rng = np.random.default_rng(1)
    temperature = 280.0 + 20.0 * rng.random((grid.n_elements, grid.n_nodes))
    constant, slope = 300.0 + 2000.0 * rng.random(grid.n_elements), -30.0 * rng.random(grid.n_elements)
    for dt in (1.0, 60.0, 3600.0):
        fast = ImplicitConduction(grid, dt).step(temperature, constant, slope)
        slow = reference_step(grid, temperature, dt, constant, slope)
        np.testing.assert_allclose(fast, slow, rtol=0, atol=1e-7)  # measured <= 3e-9 K


def test_grid_rule():
    asphalt = get_thermal_properties("asphalt")
    grid = build_grid([asphalt, get_thermal_properties("bare_aluminium")], n_nodes=30, growth=1.2)
    z = grid.depth[0]
    dz = np.diff(z)
    assert z[0] == 0.0 and np.any(np.isclose(z, 0.10, atol=1e-15, rtol=0))
    base = asphalt.layers[1]
    d = float(penetration_depth(base.conductivity, base.density, base.specific_heat))
    assert z[-1] == pytest.approx(0.10 + 5 * d, rel=1e-12)
    assert dz[0] < z[-1] / 500, "refined at the surface"
    assert np.all(dz[1:] > dz[:-1] * 0.99), "spacing grows downwards"
    assert grid.depth[1, -1] == pytest.approx(0.001, rel=1e-12)  # insulated: the sheet itself
    assert np.isnan(grid.deep_temperature).all()


def test_deep_temperature_only_for_semi_infinite():
    grid = build_grid([get_thermal_properties("asphalt"), get_thermal_properties("roof_tile")], deep_temperature=283.0)
    assert grid.deep_temperature[0] == 283.0 and np.isnan(grid.deep_temperature[1])


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"n_nodes": 1}, "n_nodes"),
        ({"n_nodes": 2}, "2 layers need at least 3 nodes"),
        ({"growth": 0.9}, "growth"),
        ({"deep_temperature": -1.0}, "deep_temperature"),
        ({"material_index": np.array([0, 3])}, r"material_index: indices must lie in \[0, 0\]"),
    ],
)
def test_build_grid_rejects_bad_input(kwargs, match):
    with pytest.raises(ConfigError, match=match):
        build_grid([get_thermal_properties("asphalt")], **kwargs)


def test_bad_stack_and_step_rejected():
    with pytest.raises(ConfigError, match="only the last layer may lack a thickness"):
        build_grid([_stack([_solid(), _solid()], "semi-infinite")])
    with pytest.raises(ConfigError, match="insulated stack needs a thickness"):
        build_grid([_stack([_solid()], "insulated")])
    with pytest.raises(ConfigError, match="bottom must be"):
        build_grid([_stack([_solid(1.0)], "adiabatic")])
    with pytest.raises(ConfigError, match="dt"):
        ImplicitConduction(build_grid([get_thermal_properties("asphalt")]), 0.0)


def test_a_steep_growth_over_many_cells_is_bounded():
    """growth 10 over 999 cells would overflow; the template's last cell is bounded to
    MAX_STRETCH times its first, and every cell has a thickness double precision can hold."""
    from radscene.thermal.conduction import MAX_STRETCH

    grid = build_grid([get_thermal_properties("sand")], n_nodes=1000, growth=10.0)
    cells = np.diff(grid.depth[0])
    assert np.all(cells > 0)
    assert cells[-1] / cells[0] == pytest.approx(MAX_STRETCH, rel=1e-6)


def test_semi_infinite_sinusoidal_flux_thermal_inertia():
    """Surface flux q0 cos ωt into a semi-infinite solid: the surface temperature swings by
    q0/√(kρcω) and lags the flux by π/4 (Carslaw & Jaeger 1959 §2.6). Default grid, 1-min steps;
    measured: amplitude -0.21 %, phase -0.0009 rad."""
    q0, mean, dt = 200.0, 300.0, 60.0  # W m-2, K, s
    d = float(penetration_depth(K, RHO, C))
    amplitude = q0 / np.sqrt(K * RHO * C * OMEGA)
    grid = build_grid([_stack([_solid()], "semi-infinite")])
    z = grid.depth[0]
    temperature = (mean + amplitude * np.exp(-z / d) * np.cos(-z / d - np.pi / 4))[None]
    solver = ImplicitConduction(grid, dt)
    t = np.arange(1, int(2 * DAY / dt) + 1) * dt
    surface = np.empty(t.size)
    for i in range(t.size):
        temperature = solver.step(temperature, q0 * np.cos(OMEGA * t[i]))
        surface[i] = temperature[0, 0]
    second = t > DAY
    design = np.column_stack([np.cos(OMEGA * t[second]), np.sin(OMEGA * t[second])])
    a, b = np.linalg.lstsq(design, surface[second] - mean, rcond=None)[0]
    assert np.hypot(a, b) == pytest.approx(amplitude, rel=0.006)
    assert np.arctan2(b, a) == pytest.approx(np.pi / 4, abs=0.006)
    # the amplitude without the √2 (q0 d / k) is rejected
    assert abs(np.hypot(a, b) / (q0 * d / K) - 1) > 0.2


def _interior_slab(t_in=293.15, h_in=7.7, thickness=0.2):
    return _stack([_solid(thickness)], {"interior_air": t_in, "h": h_in})


def test_interior_air_bottom_steady_state():
    """Steady flux q through a slab into room air: T_N = T_in + q/h_in, T_0 = T_N + q L/k."""
    q, t_in, h_in, thickness = 50.0, 293.15, 7.7, 0.2  # W m-2, K, W m-2 K-1, m
    grid = build_grid([_interior_slab(t_in, h_in, thickness)])
    assert grid.bottom_conductance[0] == h_in and grid.interior_temperature[0] == t_in
    solver = ImplicitConduction(grid, 1e15)  # Δt → ∞: the steady state
    temperature = solver.step(np.full((1, grid.n_nodes), 280.0), q)[0]
    back = t_in + q / h_in
    np.testing.assert_allclose(temperature, back + q * (thickness - grid.depth[0]) / K, rtol=0, atol=1e-6)
    assert grid.bottom_flux(temperature[None])[0] == pytest.approx(q, rel=1e-9)
    # an insulated slab under the same flux has no steady state: it would keep warming
    assert abs(temperature[-1] - t_in) > 1.0


def test_interior_air_bottom_matches_reference_and_closes_energy():
    stacks = [_interior_slab(), get_thermal_properties("asphalt"), _interior_slab(300.0, 2.5, 0.05),
              get_thermal_properties("roof_tile")]
    grid = build_grid(stacks, material_index=np.array([0, 1, 2, 3, 2]), deep_temperature=285.0)
    assert np.isfinite(grid.interior_temperature).tolist() == [True, False, True, False, True]
    assert np.isfinite(grid.deep_temperature).tolist() == [False, True, False, False, False]
    rng = np.random.default_rng(5)
    temperature = 280.0 + 20.0 * rng.random((grid.n_elements, grid.n_nodes))
    temperature[1, -1] = 285.0  # the held deep node
    constant, slope = 300.0 * rng.random(grid.n_elements), -20.0 * rng.random(grid.n_elements)
    for dt in (1.0, 600.0, 86400.0):
        fast = ImplicitConduction(grid, dt).step(temperature, constant, slope)
        slow = reference_step(grid, temperature, dt, constant, slope)
        np.testing.assert_allclose(fast, slow, rtol=0, atol=1e-7)
        # ΔΣ C T = (q_s − bottom flux) Δt for every kind of bottom
        surface_flux = constant + slope * fast[:, 0]
        stored = grid.heat_content(fast) - grid.heat_content(temperature)
        np.testing.assert_allclose(stored, (surface_flux - grid.bottom_flux(fast)) * dt, rtol=1e-9, atol=1e-6)
        assert np.all(np.abs(grid.bottom_flux(fast)[[0, 2, 4]]) > 1.0)  # the room takes heat: not vacuous
        assert grid.bottom_flux(fast)[3] == 0.0


@pytest.mark.parametrize(
    ("bottom", "match"),
    [
        ({"interior_air": 293.0}, "exactly the keys 'interior_air'"),
        ({"interior_air": 293.0, "h": 0.0}, r"bottom.h: must be a finite number > 0"),
        ({"interior_air": -1.0, "h": 5.0}, r"bottom.interior_air: must be a finite number > 0"),
        ("room", "bottom must be 'semi-infinite', 'insulated' or"),
    ],
)
def test_interior_air_bottom_rejects_bad_input(bottom, match):
    with pytest.raises(ConfigError, match=match):
        build_grid([_stack([_solid(0.1)], bottom)])


def test_interior_air_bottom_needs_a_thickness():
    with pytest.raises(ConfigError, match="interior-air stack needs a thickness"):
        build_grid([_stack([_solid()], {"interior_air": 293.0, "h": 7.7})])
