"""The leaf layer of the heat balance (radscene.thermal.canopy): its closed-form limits, energy
closure, and the compiled step against the numpy reference."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
from scipy.integrate import quad

from radscene.errors import ConfigError
from radscene.materials import get_thermal_properties
from radscene.materials.thermal import _canopy
from radscene.thermal import HeatBalance, ThermalForcing
from radscene.thermal.canopy import (
    CANOPY_MIN_WIND,
    aerodynamic_conductance,
    canopy_conductances,
    diffuse_transmittance,
    radiometric_temperature,
    stability_factor,
    stomatal_resistance,
)
from radscene.thermal.conduction import DAY
from radscene.thermal.radiation import SIGMA

CLOSURE = 1e-6  # relative energy closure of a step
LIMIT = 1e-3  # K: LAI 1e-6 against bare soil


def _grass(lai=2.5, **extra):
    """The clay-silt ground of grass_canopy under a leaf layer."""
    soil = get_thermal_properties("bare_soil")
    spec = {"lai": lai, "areal_heat_capacity": 500.0 * lai, "height": 0.15, "leaf_width": 0.01,
            "source": "test"} | extra
    return dataclasses.replace(soil, material="grass", canopy=spec)


def _day(n, wind=2.0, step=600.0, **extra):
    time = np.arange(0.0, DAY + 1, step)
    phase = 2 * np.pi * time / DAY
    sun = np.maximum(0.0, -np.cos(phase))[:, None]
    air = (288.0 + 5.0 * np.sin(phase - 2 * np.pi / 3))[:, None]
    return ThermalForcing(time, 800.0 * sun, np.broadcast_to(sun, (time.size, n)), 100.0 * sun, 300.0, air, wind,
                          relative_humidity=0.6, pressure=95000.0, **extra)


def test_diffuse_transmittance_is_the_hemispherical_integral_of_the_beam():
    for lai in (0.0, 0.5, 2.5, 6.0):
        integral = quad(lambda mu, lai=lai: 2.0 * np.exp(-0.5 * lai / mu) * mu, 0.0, 1.0)[0]
        assert float(diffuse_transmittance(lai)) == pytest.approx(integral, rel=1e-10)


def test_stomata_close_in_the_dark_and_stability_weakens_night_exchange():
    assert float(stomatal_resistance(2.5, 100.0, 0.0)) == pytest.approx(5000.0, rel=1e-12)  # r_max
    assert float(stomatal_resistance(2.5, 100.0, 1e9)) == pytest.approx(80.0, rel=1e-6)  # r_l / (0.5 L)
    assert float(stability_factor(0.0, 100.0)) == 1.0
    assert float(stability_factor(0.2, 100.0)) < 0.3 < 1.0 < float(stability_factor(-0.2, 100.0))
    # the radiometric temperature lies between leaves and soil, leaves dominating at grazing view
    nadir = float(radiometric_temperature(280.0, 290.0, 2.5))
    assert 280.0 < float(radiometric_temperature(280.0, 290.0, 2.5, 70.0)) < nadir < 290.0
    with pytest.raises(ConfigError, match="view_zenith"):
        radiometric_temperature(280.0, 290.0, 2.5, 90.0)


def test_conductances_reach_bare_soil_as_lai_vanishes():
    leaf_air, soil_air, leaf_soil = canopy_conductances(1e-9, 0.15, 0.01, 2.0, 13.3, 290.0, 95000.0)
    assert float(soil_air) == pytest.approx(13.3, rel=1e-6)
    assert float(leaf_air) < 1e-6 and float(leaf_soil) < 1e-6
    # no wind, no convection: nothing couples to the air
    leaf_air, soil_air, _ = canopy_conductances(2.5, 0.15, 0.01, 0.0, 0.0, 290.0, 95000.0)
    assert float(leaf_air) == 0.0 and float(soil_air) == 0.0


def test_vanishing_leaf_area_gives_the_bare_soil_solution():
    """LAI → 0: the leaf layer takes no radiation, holds no heat and the soil meets the air
    through the scene's h, so the element is the bare clay-silt ground."""
    forcing = _day(1)
    bare = HeatBalance([get_thermal_properties("bare_soil")], n_nodes=20).run(forcing, spin_up=True)
    thin = HeatBalance([_grass(lai=1e-6)], n_nodes=20).run(forcing, spin_up=True, record_terms=True)
    np.testing.assert_allclose(thin.surface_temperature, bare.surface_temperature, rtol=0, atol=LIMIT)
    np.testing.assert_allclose(thin.ground_temperature, bare.surface_temperature, rtol=0, atol=LIMIT)
    assert np.max(thin.closure[1:]) <= CLOSURE


def test_leaves_in_the_dark_without_wind_cool_faster_than_bare_soil():
    """Dark, still air, a cold sky: the thin leaf layer, insulated from the soil by the air
    space, falls towards its radiative equilibrium with the sky and the soil
    (ε(1 − τ_d)E_sky + leaf–soil exchange = emission) within the hour; the bare soil, fed from
    its store, cools a quarter as much."""
    time = np.arange(0.0, 3601.0, 60.0)
    forcing = ThermalForcing(time, 0.0, 0.0, 0.0, 250.0, 290.0, 0.0, relative_humidity=0.0, pressure=95000.0)
    start = 290.0
    bare = HeatBalance([get_thermal_properties("bare_soil")], convection="none").run(forcing, initial_temperature=start)
    grass = HeatBalance([_grass()], convection="none").run(forcing, initial_temperature=start, record_terms=True)
    leaf, soil = grass.canopy_temperature[:, 0], grass.ground_temperature[:, 0]
    assert start - leaf[-1] > 3.0 * (start - bare.surface_temperature[-1, 0])  # measured 16.4 K against 4.1 K
    assert grass.surface_temperature[-1, 0] < bare.surface_temperature[-1, 0]
    # the leaves' radiative equilibrium with sky and soil (no air, no transpiration in the dark):
    # (1 − τ_d)(ε E_sky + ε² σ T_s⁴) = (1 − τ_d)(ε + ε²) σ T_c⁴
    eps = get_thermal_properties("bare_soil").longwave_emissivity
    equilibrium = ((eps * 250.0 + eps**2 * SIGMA * soil[-1] ** 4) / (eps * (1 + eps) * SIGMA)) ** 0.25
    assert equilibrium < leaf[-1] < leaf[-2] < start
    assert leaf[-1] - equilibrium < 0.1 * (start - equilibrium)
    assert np.max(grass.closure[1:]) <= CLOSURE


def test_canopy_step_closes_energy_and_matches_the_numpy_reference():
    stacks = [_grass(), get_thermal_properties("asphalt"), _grass(lai=5.0)]
    runs = [HeatBalance(stacks, [0, 1, 2, 0], moisture_availability=[0.3, 0.0, 0.0, 0.3], compiled=c).run(
        _day(4), spin_up=True, record_terms=True) for c in (True, False)]
    fast, slow = runs
    for r in runs:
        assert np.max(r.closure[1:]) <= CLOSURE  # measured 1e-13
        terms = {k: v[1:] for k, v in r.terms.items()}
        np.testing.assert_allclose(sum(v for k, v in terms.items() if k != "q_d"), -terms["q_d"], rtol=0, atol=1e-5)
        assert np.all(np.isnan(r.canopy_temperature[:, 1])) and np.all(np.isfinite(r.canopy_temperature[:, [0, 2, 3]]))
        assert np.min(terms["q_v"][:, 0]) < -100.0  # the leaves transpire by day
    np.testing.assert_allclose(fast.surface_temperature, slow.surface_temperature, rtol=0, atol=1e-8)
    np.testing.assert_allclose(fast.canopy_temperature[:, [0, 2]], slow.canopy_temperature[:, [0, 2]], rtol=0, atol=1e-8)


def test_canopy_needs_humidity_and_a_whole_leaf_layer_entry():
    forcing = ThermalForcing(np.array([0.0, 600.0]), 0.0, 0.0, 0.0, 300.0, 290.0, 1.0)
    with pytest.raises(ConfigError, match="carry leaves.*relative humidity"):
        HeatBalance([_grass()]).run(forcing)
    HeatBalance([_grass()], canopy=False).run(forcing)  # the lumped surface model
    base = {"lai": 2.5, "areal_heat_capacity": 1000.0, "source": "x"}
    assert _canopy(base | {"height": 0.15, "leaf_width": 0.01}, "c")["height"] == 0.15
    assert _canopy(base | {"height": 0.12}, "c")["height"] == 0.12  # lumped, aerodynamic
    with pytest.raises(ConfigError, match="c: a leaf layer needs both 'height' and 'leaf_width'"):
        _canopy(base | {"leaf_width": 0.01}, "c")
    with pytest.raises(ConfigError, match=r"c.height: must be <= 2 m .*got 3"):
        _canopy(base | {"height": 3.0}, "c")
    with pytest.raises(ConfigError, match=r"c.height: must be a finite number > 0"):
        _canopy(base | {"height": -1.0, "leaf_width": 0.01}, "c")
    with pytest.raises(ConfigError, match="expected the keys"):
        _canopy(base | {"lia": 3}, "c")


def test_a_canopy_without_leaves_meets_the_air_through_its_aerodynamic_conductance():
    """A canopy entry with a height and no leaf width: the lumped surface's h is ρ c_p / r_a of
    FAO-56 eq. 4 for that height times the Louis factor at the step's start temperature, in
    place of the scene's flat-plate correlation (recorded q_k = h (T_air − T))."""
    soil = get_thermal_properties("bare_soil")
    spec = {"lai": 2.5, "areal_heat_capacity": 1250.0, "height": 0.12, "source": "test"}
    grass = dataclasses.replace(soil, material="grass", canopy=spec)
    forcing = _day(2, wind=np.linspace(0.5, 4.0, 145)[:, None] * np.ones((1, 2)))
    run = HeatBalance([grass, soil], n_nodes=20).run(forcing, record_terms=True)
    t = run.surface_temperature
    air = np.asarray(forcing.air_temperature)[:, 0]
    wind = np.asarray(forcing.wind_speed)[:, 0]
    for k in (30, 72, 120):  # night, noon, evening
        want = aerodynamic_conductance(0.12, wind[k], air[k], 95000.0, t[k - 1, 0], CANOPY_MIN_WIND)
        got = run.terms["q_k"][k, 0] / (air[k] - t[k, 0])
        assert got == pytest.approx(float(want), rel=1e-9)
        bare = run.terms["q_k"][k, 1] / (air[k] - t[k, 1])  # the scene's McAdams
        assert bare == pytest.approx(5.7 + 3.8 * wind[k], rel=1e-9)
    # calm air: the wind is taken as at least CANOPY_MIN_WIND, not 0 (no exchange at all)
    calm = [HeatBalance([grass], n_nodes=20).run(_day(1, wind=u)).surface_temperature for u in
            (0.0, CANOPY_MIN_WIND)]
    np.testing.assert_array_equal(calm[0], calm[1])
    # no air (convection "none"): no exchange for the canopy either
    vacuum = HeatBalance([grass], n_nodes=20, convection="none").run(_day(1), record_terms=True)
    assert np.all(vacuum.terms["q_k"][1:] == 0.0)  # (the first instant has no step)
