"""The pure functions behind the new balance terms: humidity and latent heat, the aerodynamic
quantities, the view-factor exchange and the lateral conductances."""

import numpy as np
import pytest
import scipy.sparse as sp
from scipy.optimize import root

from radscene.errors import ConfigError
from radscene.materials.thermal import get_thermal_properties, parse_bottom
from radscene.thermal import (
    SIGMA,
    check_view_factors,
    coupled_surface_temperature,
    environment_longwave,
    evaporative_flux,
    grid_conductance,
    laplacian,
    latent_heat_of_vaporisation,
    linearised_evaporative_flux,
    mesh_conductance,
    saturation_vapour_pressure,
    speed_of_sound,
    vapour_transfer_coefficient,
)


def test_saturation_vapour_pressure_against_tables():
    # over liquid water, CRC Handbook of Chemistry and Physics (from IAPWS-95): 0, 20, 30, 40 degC
    table = {273.15: 611.29, 293.15: 2339.3, 303.15: 4246.9, 313.15: 7384.9}
    t = np.array(list(table))
    np.testing.assert_allclose(saturation_vapour_pressure(t), list(table.values()), rtol=0.004)  # Alduchov & Eskridge: < 0.4 %
    step = 1e-4
    from radscene.thermal.weather.humidity import saturation_vapour_pressure_derivative

    numeric = (saturation_vapour_pressure(t + step) - saturation_vapour_pressure(t - step)) / (2 * step)
    np.testing.assert_allclose(saturation_vapour_pressure_derivative(t), numeric, rtol=1e-7)
    assert saturation_vapour_pressure(np.ones((2, 3)) * 290.0).shape == (2, 3)


def test_humidity_and_latent_heat():
    # q = ε e/(p − (1 − ε) e): at e = p the air is all vapour, q = 1
    from radscene.thermal.weather.humidity import specific_humidity_of_vapour_pressure

    assert specific_humidity_of_vapour_pressure(1000.0, 1000.0) == pytest.approx(1.0, rel=1e-12)
    assert specific_humidity_of_vapour_pressure(1500.0, 100000.0) == pytest.approx(
        0.622 * 1500 / (100000 - 0.378 * 1500), rel=1e-12)
    # latent heat: 2.501 MJ kg-1 at 0 degC and 2.454 at 20 degC (Rogers & Yau 1989, Table 2.1)
    np.testing.assert_allclose(latent_heat_of_vaporisation([273.15, 293.15]), [2.501e6, 2.454e6], rtol=1e-3)
    # the Lewis analogy: h / (c_p Le^{2/3})
    assert vapour_transfer_coefficient(10.0) == pytest.approx(10.0 / (1007.0 * (22.5 / 26.0) ** (2 / 3)), rel=1e-12)


def test_evaporation_signs_and_linearisation():
    args = (1.0, 12.0)
    assert evaporative_flux(*args, 300.0, 295.0, 0.5, 101325.0) < 0  # warm wet surface in dry air: cooling
    assert evaporative_flux(*args, 280.0, 295.0, 0.9, 101325.0) > 0  # cold surface under moist air: dew
    assert evaporative_flux(0.0, 12.0, 300.0, 295.0, 0.5, 101325.0) == 0.0
    # the linearisation is exact at its point and tangent there; its error is second order
    c, s = linearised_evaporative_flux(*args, 300.0, 295.0, 0.5, 101325.0)
    exact = evaporative_flux(*args, 300.0, 295.0, 0.5, 101325.0)
    lv = latent_heat_of_vaporisation
    for dt in (0.0, 0.5, 1.0):
        t = 300.0 + dt
        with_fixed_latent_heat = evaporative_flux(*args, t, 295.0, 0.5, 101325.0) * lv(300.0) / lv(t)
        error = abs(c - s * t - with_fixed_latent_heat)
        assert error <= 2.0 * dt**2 + 1e-9  # W m-2: about 1.2 ΔT² at 300 K (module docstring)
    assert abs(c - s * 300.0 - exact) < 1e-9


def test_speed_of_sound():
    assert speed_of_sound(288.15) == pytest.approx(340.29, abs=0.01)  # ISA sea level


def test_longwave_exchange_reflections_converge_to_radiosity():
    rng = np.random.default_rng(2)
    n = 6
    f = rng.random((n, n)) * (1 - np.eye(n))
    f *= 0.7 / f.sum(axis=1, keepdims=True)
    eps = rng.uniform(0.3, 0.9, n)
    exitance = eps * SIGMA * rng.uniform(270.0, 330.0, n) ** 4
    sky = 0.3 * 300.0 * np.ones(n)
    radiosity = np.linalg.solve(np.eye(n) - (1 - eps)[:, None] * f, exitance + (1 - eps) * sky)
    exact = eps * (f @ radiosity)
    fs = check_view_factors(sp.csr_array(f), n)
    errors = [np.max(np.abs(environment_longwave(fs, eps, exitance, sky, m) - exact)) for m in (0, 1, 2, 40)]
    assert errors[0] > errors[1] > errors[2] and errors[3] < 1e-9


def test_grid_conductance_neighbours_and_harmonic_mean():
    g = grid_conductance((2, 3), (0.5, 0.25), 2.0, 0.1)
    assert g.shape == (6, 6) and (g != g.T).nnz == 0
    dense = g.toarray()
    # along a row (dx 0.25): L = dy = 0.5 -> k t L/d = 0.2 * 0.5/0.25 = 0.4; down a column: 0.2 * 0.25/0.5
    assert dense[0, 1] == pytest.approx(0.4, rel=1e-12) and dense[0, 3] == pytest.approx(0.1, rel=1e-12)
    assert dense[0, 4] == 0.0 and dense[0, 2] == 0.0  # no diagonal or distant neighbours
    assert np.count_nonzero(dense) == 2 * (2 * 2 + 3)  # 7 shared edges
    # two conductivities in series: the harmonic mean (Patankar 1980)
    k = np.array([[1.0, 3.0]])
    two = grid_conductance((1, 2), 1.0, k, 0.1).toarray()[0, 1]
    assert two == pytest.approx(0.1 * 2 * 1.0 * 3.0 / (1.0 + 3.0), rel=1e-12)
    with pytest.raises(ConfigError, match="spacing: must be finite and > 0"):
        grid_conductance((2, 2), 0.0, 1.0, 0.1)


def _square_mesh(rows, cols, size):
    """Squares of ``size`` split into two triangles each; element = square, row-major."""
    iy, ix = np.mgrid[0 : rows + 1, 0 : cols + 1]
    vertices = np.column_stack([ix.ravel() * size[1], iy.ravel() * size[0], np.zeros(ix.size)])
    faces, owner = [], []
    for r in range(rows):
        for c in range(cols):
            v0 = r * (cols + 1) + c
            v1, v2, v3 = v0 + 1, v0 + cols + 2, v0 + cols + 1
            faces += [[v0, v1, v2], [v0, v2, v3]]
            owner += [r * cols + c] * 2
    return vertices, np.array(faces), np.array(owner)


def test_mesh_conductance_matches_the_grid_and_folds_over_edges():
    vertices, faces, owner = _square_mesh(3, 4, (0.5, 0.25))
    mesh = mesh_conductance(vertices, faces, owner, 2.0, 0.1)
    grid = grid_conductance((3, 4), (0.5, 0.25), 2.0, 0.1)
    np.testing.assert_allclose(mesh.toarray(), grid.toarray(), rtol=1e-12, atol=0)
    # each triangle its own element: neighbours across the diagonals appear too
    fine = mesh_conductance(vertices, faces, np.arange(len(faces)), 2.0, 0.1)
    assert fine.shape == (24, 24) and fine.nnz == mesh.nnz + 2 * 12
    # two unit squares folded at a right angle: the path runs along the surfaces
    v = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0], [1, 0, -1], [1, 1, -1]], float)
    f = np.array([[0, 1, 2], [0, 2, 3], [1, 4, 5], [1, 5, 2]])
    folded = mesh_conductance(v, f, [0, 0, 1, 1], 2.0, 0.1).toarray()
    assert folded[0, 1] == pytest.approx(0.2 * 1.0 / 1.0, rel=1e-12)
    with pytest.raises(ConfigError, match="face_element: expected 4 integer element indices"):
        mesh_conductance(v, f, [0, 1], 2.0, 0.1)


def test_coupled_surface_temperature_matches_a_general_root_finder():
    rng = np.random.default_rng(4)
    n = 12
    g = sp.random(n, n, density=0.4, random_state=rng)
    g = (g + g.T) * 50.0
    lap = laplacian(g)
    np.testing.assert_allclose(lap @ np.ones(n), 0.0, atol=1e-12)  # uniform temperatures exchange nothing
    c, m = 2000.0 + 8000.0 * rng.random(n), 5.0 + 30.0 * rng.random(n)
    eps, area = rng.random(n), 0.1 + rng.random(n)
    t = coupled_surface_temperature(c, m, eps, lap, area, np.full(n, 300.0))

    def residual(x):
        return area * (c - eps * SIGMA * x**4 - m * x) - lap @ x

    reference = root(residual, np.full(n, 300.0), tol=1e-13).x
    np.testing.assert_allclose(t, reference, rtol=0, atol=1e-8)
    assert np.max(np.abs(residual(t))) < 1e-6


def test_parse_bottom_and_moisture_availability_data():
    assert parse_bottom("insulated") == "insulated"
    assert parse_bottom({"interior_air": 293, "h": 7}) == {"interior_air": 293.0, "h": 7.0}
    with pytest.raises(ConfigError, match="bottom: bottom must be 'semi-infinite', 'insulated' or"):
        parse_bottom("adiabatic")
    # beta = r_a / (r_a + r_s), r_a = 104 s m-1, r_s = 100 / (0.5 LAI) (FAO-56), for the canopies
    for name in ("green_vegetation", "grass_canopy", "deciduous_canopy", "conifer_canopy", "sparse_canopy"):
        tp = get_thermal_properties(name)
        expected = 104.0 / (104.0 + 100.0 / (0.5 * tp.canopy["lai"]))
        assert tp.moisture_availability == pytest.approx(expected, abs=0.006), name
    assert get_thermal_properties("water").moisture_availability == 1.0
    assert get_thermal_properties("asphalt").moisture_availability == 0.0
    assert get_thermal_properties("snow").moisture_availability == 0.0  # sublimation is not modelled
