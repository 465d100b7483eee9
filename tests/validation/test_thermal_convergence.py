"""The conduction solver against closed forms and its promised orders of accuracy: a step of
surface temperature on a semi-infinite solid (the erfc solution, Carslaw & Jaeger 1959 §2.5),
second order under refinement of the layers, first order in time (backward Euler); a periodic
surface temperature on a semi-infinite solid against the figures of reference case
``heat_semi_infinite_periodic_surface_T`` (Carslaw & Jaeger 1959 §2.6); and a thin plate
cooling by convection and radiation against an independent ODE solve."""

from types import SimpleNamespace

import numpy as np
import pytest
from scipy.integrate import solve_ivp
from scipy.special import erf

from radscene.materials.thermal import Layer
from radscene.thermal import (
    SIGMA,
    HeatBalance,
    ImplicitConduction,
    ThermalForcing,
    build_grid,
    penetration_depth,
)

K, RHO, C = 1.0, 2000.0, 1000.0  # W m-1 K-1, kg m-3, J kg-1 K-1
KAPPA = K / (RHO * C)
PENALTY = 1e9  # W m-2 K-1: imposes the surface temperature


def _slab(thickness=1.0, bottom="insulated"):
    return SimpleNamespace(layers=(Layer("solid", thickness, K, RHO, C),), bottom=bottom)


def _step_response(n_nodes, dt, duration=6 * 3600.0, t0=280.0, ts=300.0):
    """A 1 m slab (insulated below: semi-infinite for 6 h, the wave reaches ~0.2 m) at t0 whose
    surface is held at ts from t = 0; uniform nodes. Returns depths and the profile at the end."""
    grid = build_grid([_slab()], n_nodes=n_nodes, growth=1.0)
    solver = ImplicitConduction(grid, dt)
    temperature = np.full((1, n_nodes), t0)
    for _ in range(int(round(duration / dt))):
        temperature = solver.step(temperature, PENALTY * ts, -PENALTY)
    return grid.depth[0], temperature[0]


def _erfc_profile(z, t, t0=280.0, ts=300.0):
    return ts + (t0 - ts) * erf(z / (2.0 * np.sqrt(KAPPA * t)))


def test_step_of_surface_temperature_matches_the_erfc_solution():
    z, temperature = _step_response(n_nodes=401, dt=10.0)
    exact = _erfc_profile(z, 6 * 3600.0)
    inside = z < 0.3
    # measured: 0.0013 K at most over the 20 K step (dt 10 s, 2.5 mm cells)
    assert np.max(np.abs(temperature[inside] - exact[inside])) < 0.03


def _error_at(n_nodes, dt, depth=0.04, duration=6 * 3600.0):
    z, temperature = _step_response(n_nodes, dt, duration)
    return abs(np.interp(depth, z, temperature) - _erfc_profile(depth, duration))


def test_second_order_in_space():
    """Time error made small (dt 1 s, two hours); cells 1/25, 1/50, 1/100 m: the error at 4 cm
    (a node of every grid) falls by about 4 per halving (measured over six hours: 0.0123,
    0.0031, 0.00082 K, ratios 4.0 and 3.8)."""
    errors = [_error_at(n, dt=1.0, duration=2 * 3600.0) for n in (26, 51, 101)]
    ratios = [errors[0] / errors[1], errors[1] / errors[2]]
    assert all(3.0 < r < 5.5 for r in ratios), (errors, ratios)


def test_second_order_in_space_on_the_default_layered_grid():
    """The asphalt stack (10 cm of asphalt concrete over semi-infinite sand) on the default
    geometric grid (growth 1.2, whose template is one grid from 30 nodes on), a sunny day at
    one-minute steps from a uniform start: the largest error of the surface temperature over the
    day, against 640 nodes at the same steps, falls by about 4 per doubling of the nodes
    (measured: 0.0125, 0.0029, 0.00067 K at 40, 80, 160 nodes; ratios 4.3 and 4.3)."""
    from radscene.materials.thermal import get_thermal_properties
    from radscene.thermal import DAY, ThermalForcing

    stack = get_thermal_properties("asphalt")
    assert len(stack.layers) == 2
    time = np.arange(0.0, DAY + 1, 60.0)
    phase = 2 * np.pi * time / DAY
    sun = np.maximum(0.0, -np.cos(phase))
    air = 288.0 + 5.0 * np.sin(phase - 2 * np.pi / 3)
    forcing = ThermalForcing(time, (800.0 * sun)[:, None], sun[:, None], (100.0 * sun)[:, None], 300.0,
                             air[:, None], 2.0)
    surface = {n: HeatBalance([stack], n_nodes=n).run(forcing, initial_temperature=288.0).surface_temperature[:, 0]
               for n in (40, 80, 160, 640)}
    errors = [float(np.max(np.abs(surface[n] - surface[640]))) for n in (40, 80, 160)]
    ratios = [errors[0] / errors[1], errors[1] / errors[2]]
    assert all(3.3 < r < 5.5 for r in ratios), (errors, ratios)


def test_many_nodes_keep_a_balanced_grid():
    """200 nodes (the scene file's limit) on a stack of the default growth give what 100 give,
    to the second-order error (before the template's stretch was bounded, 200 nodes made the
    first cell 3e-17 m and the surface fell to 209 K)."""
    from radscene.materials.thermal import get_thermal_properties
    from radscene.thermal import DAY, ThermalForcing

    stack = get_thermal_properties("asphalt")
    time = np.arange(0.0, DAY / 2 + 1, 300.0)
    forcing = ThermalForcing(time, 800.0, 0.8, 100.0, 300.0, 290.0, 2.0)
    end = [HeatBalance([stack], n_nodes=n).run(forcing, initial_temperature=290.0).surface_temperature[-1, 0]
           for n in (100, 200)]
    assert abs(end[0] - end[1]) < 0.01, end


def test_first_order_in_time():
    """Fine grid (1 mm cells); steps 240, 120, 60 s: the error at 4 cm halves per halving
    (measured: 0.0171, 0.0085, 0.0043 K)."""
    errors = [_error_at(1001, dt) for dt in (240.0, 120.0, 60.0)]
    ratios = [errors[0] / errors[1], errors[1] / errors[2]]
    assert all(1.7 < r < 2.3 for r in ratios), (errors, ratios)



#: Reference case heat_semi_infinite_periodic_surface_T (Carslaw & Jaeger, *Conduction of Heat
#: in Solids*, 2nd ed. 1959, §2.6): T(z, t) = T_m + A exp(-z/d) cos(ωt - z/d), d = sqrt(2α/ω),
#: a concrete-like solid. Inputs and expected figures as the case gives them.
PERIODIC_CASE = {
    "mean": 290.0,  # T_m [K]
    "amplitude": 10.0,  # A [K]
    "period": 86400.0,  # [s]
    "diffusivity": 7e-7,  # α [m2 s-1]
    "conductivity": 1.4,  # k [W m-1 K-1]
    "damping_depth": 0.138749,  # d [m]
    "amplitude_at_depth": {0.0: 10.0, 0.05: 6.97424, 0.1: 4.864, 0.2: 2.36585, 0.3: 1.15075},  # [m]: [K]
    "lag_at_depth": {0.0: 0.0, 0.05: 1.37648, 0.1: 2.75296, 0.2: 5.50593, 0.3: 8.25889},  # [m]: [h]
    "surface_flux_amplitude": 142.6961,  # q_0 = k A sqrt(ω/α) [W m-2]
    "flux_lead": 3.0,  # [h]: π/4 of the period
}
#: The case's tolerance: relative 1 % for a 1-D finite-volume solver with dz <= d/10, dt <= P/500.
PERIODIC_REL = 0.01
#: The rounding of the case's damping depth (six figures).
DEPTH_ROUNDING_REL = 1e-5


def _periodic_surface_run(dz=0.005, depth=0.75, dt=60.0, periods=7):
    """The case's solid on a uniform grid (dz = d/28, every depth of the case a node; held at
    T_m at 0.75 m = 5.4 d) from T_m everywhere, its surface held at T_m + A cos ωt by a penalty
    (q_s = H (T_s - T_0)) for ``periods`` periods, one-minute steps (P/1440). Returns the node
    depths [m], and fitted over the last period the amplitude [K] and lag [h] of every node,
    and the amplitude [W m-2] and lead [h] of the flux into the surface."""
    case = PERIODIC_CASE
    heat_capacity = case["conductivity"] / case["diffusivity"]  # ρ c [J m-3 K-1]
    density = 2000.0  # [kg m-3]; only ρ c enters
    layer = Layer("concrete-like", None, case["conductivity"], density, heat_capacity / density)
    d = float(penetration_depth(layer.conductivity, layer.density, layer.specific_heat,
                                period=case["period"]))
    stack = SimpleNamespace(layers=(layer,), bottom="semi-infinite")
    grid = build_grid([stack], n_nodes=int(round(depth / dz)) + 1, growth=1.0, period=case["period"],
                      penetration_depths=depth / d, deep_temperature=case["mean"])
    solver = ImplicitConduction(grid, dt)
    omega = 2 * np.pi / case["period"]
    steps = int(round(case["period"] / dt))
    temperature = np.full((1, grid.n_nodes), case["mean"])
    t = np.arange(1, periods * steps + 1) * dt
    record, flux = np.empty((steps, grid.n_nodes)), np.empty(steps)
    for i, now in enumerate(t):
        surface = case["mean"] + case["amplitude"] * np.cos(omega * now)
        temperature = solver.step(temperature, PENALTY * surface, -PENALTY)
        if i >= (periods - 1) * steps:
            record[i - (periods - 1) * steps] = temperature[0]
            flux[i - (periods - 1) * steps] = PENALTY * (surface - temperature[0, 0])
    last = t[(periods - 1) * steps:]
    design = np.column_stack([np.cos(omega * last), np.sin(omega * last)])
    (a, b), *_ = np.linalg.lstsq(design, record - case["mean"], rcond=None)
    (fa, fb), *_ = np.linalg.lstsq(design, flux, rcond=None)
    hours = 1.0 / (omega * 3600.0)
    return (grid.depth[0], d, np.hypot(a, b), np.arctan2(b, a) * hours, np.hypot(fa, fb),
            -np.arctan2(fb, fa) * hours)


def test_periodic_surface_temperature_matches_the_reference_case():
    """Reference case heat_semi_infinite_periodic_surface_T: damping depth, amplitude and lag
    at five depths, and the surface flux's amplitude and lead, within the case's 1 %. Measured
    (seven periods from a uniform start): amplitude -0.04 % at 5 cm to -0.41 % at 30 cm, lag
    -0.12 % to -0.15 %, flux amplitude -9e-6, lead 2.9972 h."""
    case = PERIODIC_CASE
    z, d, amplitude, lag, flux_amplitude, flux_lead = _periodic_surface_run()
    assert d == pytest.approx(case["damping_depth"], rel=DEPTH_ROUNDING_REL)
    for depth, expected in case["amplitude_at_depth"].items():
        node = int(np.argmin(np.abs(z - depth)))
        assert z[node] == pytest.approx(depth, abs=1e-12), "each depth of the case is a node"
        assert amplitude[node] == pytest.approx(expected, rel=PERIODIC_REL), depth
        # at the surface, held by the penalty, the lag is 0 to within 1e-6 h
        assert lag[node] == pytest.approx(case["lag_at_depth"][depth], rel=PERIODIC_REL, abs=1e-6), depth
    assert flux_amplitude == pytest.approx(case["surface_flux_amplitude"], rel=PERIODIC_REL)
    assert flux_lead == pytest.approx(case["flux_lead"], rel=PERIODIC_REL)


def test_thin_plate_cooling_matches_an_ode_solve():
    """A 2 mm aluminium plate (insulated back, Biot number ~1e-4: lumped), 350 K at the start,
    under a black sky (no long-wave in) in air at 290 K with McAdams' h at 1 m/s (9.5 W m-2 K-1),
    emissivity 0.8: ρ c d dT/dt = −ε σ T⁴ − h (T − T_air), solved by scipy's LSODA to 1e-10."""
    d, rho, c, eps, h, t_air = 0.002, 2700.0, 900.0, 0.8, 5.7 + 3.8 * 1.0, 290.0
    stack = SimpleNamespace(layers=(Layer("aluminium", d, 237.0, rho, c),), bottom="insulated")
    balance = HeatBalance([stack], absorptance=0.0, emissivity=eps, n_nodes=5, growth=1.0)
    dt = 1.0
    time = np.arange(0.0, 3600.0 + dt, dt)
    forcing = ThermalForcing(time, 0.0, 0.0, 0.0, 0.0, t_air, 1.0)
    result = balance.run(forcing, initial_temperature=350.0)

    def rate(_, t):
        return [-(eps * SIGMA * t[0] ** 4 + h * (t[0] - t_air)) / (rho * c * d)]

    ode = solve_ivp(rate, (0.0, 3600.0), [350.0], t_eval=time, method="LSODA", rtol=1e-10, atol=1e-10)
    # backward Euler's lag at 1 s steps: measured 0.05 K at most while the plate cools 84 K
    assert np.max(np.abs(result.surface_temperature[:, 0] - ode.y[0])) < 0.1
    assert ode.y[0][-1] < 300.0  # it has cooled most of the way
