"""The formulas shared by the 6S engine and the database (no 6S run needed)."""

from __future__ import annotations

import numpy as np
import pytest
from scipy import integrate

from radscene.atmosphere import sixs_model as m
from radscene.errors import ConfigError

REL = 1e-9


def test_loglog_interp_is_exact_for_power_laws_and_extrapolates():
    nodes = np.array([0.4, 0.55, 0.86, 1.65])
    values = 0.1 * nodes ** -4.08  # Rayleigh-like
    wl = np.array([0.3, 0.45, 0.7, 1.2, 3.0])
    assert m.loglog_interp(wl, nodes, values) == pytest.approx(0.1 * wl ** -4.08, rel=REL)
    # several spectra at once, wavelength on the last axis
    both = m.loglog_interp(wl, nodes, np.stack([values, 2 * values]))
    assert both.shape == (2, 5)
    assert both[1] == pytest.approx(2 * both[0], rel=REL)


def test_loglog_interp_falls_back_to_linear_where_a_value_is_zero():
    out = m.loglog_interp([0.5], [0.4, 0.6], [0.0, 1.0])
    t = np.log(0.5 / 0.4) / np.log(0.6 / 0.4)
    assert out == pytest.approx([t], rel=REL)


def test_scattering_angle_matches_6s_report():
    # 6S printed "scattering angle: 146.90 deg" for θs = 32, θv = 23, Δφ = 74 deg
    # (the Py6S default geometry; case py6s_satellite_level of shared/reference/cases.json)
    assert m.scattering_angle_view(32.0, 23.0, 264.0 - 190.0) == pytest.approx(146.90, abs=0.01)
    # the sky: looking at the sun is forward scattering, away from it 180 - 2 θs
    assert m.scattering_angle_sky(40.0, 40.0, 0.0) == pytest.approx(0.0, abs=1e-6)
    assert m.scattering_angle_sky(40.0, 40.0, 180.0) == pytest.approx(80.0, abs=1e-9)


def test_azimuth_fourier_reproduces_a_three_term_series_and_its_mean():
    a0, a1, a2 = 0.3, 0.1, -0.04
    f = lambda p: a0 + a1 * np.cos(np.radians(p)) + a2 * np.cos(np.radians(2 * p))  # noqa: E731
    phi = np.array([0.0, 37.0, 90.0, 141.0, 180.0, 250.0])
    assert m.azimuth_fourier(phi, f(0), f(90), f(180)) == pytest.approx(f(phi), rel=REL)
    assert m.azimuth_fourier(np.nan, f(0), f(90), f(180)) == pytest.approx(a0, rel=REL)


def test_direct_transmittance_is_beer_lambert():
    assert m.direct_transmittance(0.3, 60.0) == pytest.approx(np.exp(-0.6), rel=REL)
    assert m.direct_transmittance(np.array([0.1, 0.2]), 0.0).shape == (2,)


def test_path_reflectance_keeps_water_off_the_molecules():
    # 6S (Vermote et al. 1997): T_g^nw rho_R + T_g (rho_R+A - rho_R)
    assert m.path_reflectance(0.10, 0.04, 0.5, 0.9) == pytest.approx(0.9 * 0.04 + 0.5 * 0.06,
                                                                     rel=REL)


def test_earth_sun_factor_follows_6s_varsol():
    assert m.earth_sun_factor_6s(1, 4) == pytest.approx(1.0 / (1.0 - 0.01673) ** 2, rel=REL)
    assert m.earth_sun_factor_6s(4, 5) == pytest.approx(1.0, abs=3e-4)


def test_single_scattering_reflectance_thin_limit_and_top():
    # optically thin: rho = tau P / (4 mu_s mu_v) (Chandrasekhar 1960)
    rho = m.single_scattering_reflectance(30.0, 45.0, 1.2, 0.3, 1e-6, 0.0, 1.0)
    mu_s, mu_v = np.cos(np.radians(30.0)), np.cos(np.radians(45.0))
    assert rho == pytest.approx(1e-6 * 1.2 / (4 * mu_s * mu_v), rel=1e-5)
    # an observer at the ground sees no layer: zero; a partial layer is in between
    assert m.single_scattering_reflectance(30.0, 45.0, 1.2, 0.3, 0.2, 0.3, 0.9, 0.0, 0.0) == 0.0
    part = m.single_scattering_reflectance(30.0, 45.0, 1.2, 0.3, 0.2, 0.3, 0.9, 0.4, 0.5)
    full = m.single_scattering_reflectance(30.0, 45.0, 1.2, 0.3, 0.2, 0.3, 0.9)
    assert 0.0 < part < full


def test_single_scattering_below_an_observer_weighs_the_layers_own_mixture():
    # thin layer: rho = (f_R tau_R P_R + f_A omega tau_A P_A) / (4 mu_s mu_v), the phase
    # function of what lies below the observer, not of the whole column
    tau_r, tau_a, om, pr, pa, f_r, f_a = 2e-6, 3e-6, 0.9, 1.2, 0.3, 0.3, 0.8
    mu_s, mu_v = np.cos(np.radians(30.0)), np.cos(np.radians(45.0))
    got = m.single_scattering_reflectance(30.0, 45.0, pr, pa, tau_r, tau_a, om, f_r, f_a)
    want = (f_r * tau_r * pr + f_a * om * tau_a * pa) / (4 * mu_s * mu_v)
    assert got == pytest.approx(want, rel=1e-5)
    # at the top of the atmosphere the layer is the column
    top = m.single_scattering_reflectance(30.0, 45.0, pr, pa, tau_r, tau_a, om, 1.0, 1.0)
    assert top == pytest.approx((tau_r * pr + om * tau_a * pa) / (4 * mu_s * mu_v), rel=1e-5)


def test_layer_share_is_one_at_the_top_zero_at_the_ground_and_the_isotropic_ratio_between():
    args = (30.0, 45.0, 0.2, 0.3)
    assert m.layer_share(*args, 1.0, 1.0) == pytest.approx(1.0, rel=1e-12)
    assert m.layer_share(*args, 0.0, 0.0) == 0.0
    part = m.layer_share(*args, 0.4, 0.8)
    iso = m.single_scattering_reflectance(30.0, 45.0, 1.0, 1.0, 0.2, 0.3, 1.0, 0.4, 0.8)
    top = m.single_scattering_reflectance(30.0, 45.0, 1.0, 1.0, 0.2, 0.3, 1.0)
    assert part == pytest.approx(iso / top, rel=1e-12)


def test_single_scattering_sky_matches_a_numerical_layer_integral():
    # L(mu) = E0/(4 pi mu) ∫0^τ ω P e^{-t/μs} e^{-(τ-t)/μ} dt, integrated independently
    e0, tau_r, tau_a, om, pr, pa = 1800.0, 0.1, 0.3, 0.9, 1.1, 0.4
    zen, rel, sz = 50.0, 120.0, 35.0
    theta = float(m.scattering_angle_sky(sz, zen, rel))
    nodes = np.array([0.0, 180.0])
    mu, mu_s = np.cos(np.radians(zen)), np.cos(np.radians(sz))
    tau = tau_r + tau_a

    def integrand(t):
        return (tau_r * pr + om * tau_a * pa) / tau * np.exp(-t / mu_s) * np.exp(-(tau - t) / mu)

    ref = e0 / (4 * np.pi * mu) * integrate.quad(integrand, 0.0, tau)[0]
    got = m.single_scattering_sky(zen, rel, sz, np.array([e0]), np.array([1.0]),
                                  np.array([tau_r]), np.array([tau_a]), np.array([om]), nodes,
                                  np.array([[pr], [pr]]), np.array([[pa], [pa]]))
    assert theta > 0
    assert got.shape == (1,)
    assert got[0] == pytest.approx(ref, rel=1e-9)


def test_sky_radiance_integrates_to_the_diffuse_and_environment_irradiance():
    e0 = np.array([1800.0, 900.0])
    args = dict(sun_zenith=40.0, toa_irradiance=e0, gas_down=np.array([0.97, 0.9]),
                tau_rayleigh=np.array([0.1, 0.02]), tau_aerosol=np.array([0.25, 0.12]),
                omega_aerosol=np.array([0.93, 0.9]), angle_nodes=np.array([0.0, 90.0, 180.0]),
                phase_rayleigh=np.array([[1.5, 1.5], [0.75, 0.75], [1.5, 1.5]]),
                phase_aerosol=np.array([[30.0, 20.0], [0.3, 0.4], [0.2, 0.3]]),
                total_down=np.array([0.85, 0.92]), spherical_albedo=np.array([0.15, 0.08]),
                background_albedo=0.2)
    # independent midpoint rule over the hemisphere
    nz, na = 300, 360
    zen = (np.arange(nz) + 0.5) * 90.0 / nz
    az = (np.arange(na) + 0.5) * 360.0 / na
    zz, aa = np.meshgrid(zen, az, indexing="ij")
    radiance = m.sky_radiance(zz, aa, **args)
    dw = np.radians(90.0 / nz) * np.radians(360.0 / na)
    weight = np.cos(np.radians(zz)) * np.sin(np.radians(zz)) * dw
    e_sky = np.einsum("za,zan->n", weight, radiance)
    mu_s = np.cos(np.radians(40.0))
    tau = args["tau_rayleigh"] + args["tau_aerosol"]
    direct = e0 * mu_s * np.exp(-tau / mu_s) * args["gas_down"]
    diffuse = e0 * mu_s * (args["total_down"] - np.exp(-tau / mu_s)) * args["gas_down"]
    rb = 0.2 * args["spherical_albedo"]
    expected = diffuse + (direct + diffuse) * rb / (1 - rb)
    assert e_sky == pytest.approx(expected, rel=2e-3)
    # the aureole: brighter towards the sun than away from it
    toward, away = m.sky_radiance(np.array([40.0, 40.0]), np.array([0.0, 180.0]), **args)
    assert np.all(toward > away)
    # night
    assert np.all(m.sky_radiance(10.0, 0.0, **{**args, "sun_zenith": 95.0}) == 0.0)


def test_multilinear_nodes_reproduce_a_trilinear_function():
    rng = np.random.default_rng(1)
    pts = [rng.uniform(0, 3, 50), rng.uniform(10, 20, 50), rng.uniform(0, 80, 50)]
    axes = [np.array([0.0, 1.0, 3.0]), np.array([10.0, 20.0]), np.arange(0.0, 90.0, 10.0)]
    coords, index, weight = m.multilinear_nodes(pts, axes)
    assert index.shape == weight.shape == (50, 8)
    assert weight.sum(axis=1) == pytest.approx(np.ones(50), rel=REL)

    def f(a, b, c):
        return 2.0 + 0.5 * a - 0.1 * b + 0.03 * c

    node_values = f(*coords)
    assert (node_values[index] * weight).sum(axis=1) == pytest.approx(f(*pts), rel=1e-12)


def test_check_path_geometry_turns_upward_paths_round_and_refuses_bad_ones():
    upper, lower, zen = m.check_path_geometry([100.0, 5000.0], [3000.0, 0.0], [120.0, 30.0])
    assert upper == pytest.approx([3000.0, 5000.0])
    assert lower == pytest.approx([100.0, 0.0])
    assert zen == pytest.approx([60.0, 30.0])
    with pytest.raises(ConfigError, match="below the ground"):
        m.check_path_geometry(1000.0, -10.0, 0.0)
    with pytest.raises(ConfigError, match="above the atmosphere"):
        m.check_path_geometry(200_000.0, 150_000.0, 0.0)
    with pytest.raises(ConfigError, match="contradicts the altitudes"):
        m.check_path_geometry(1000.0, 0.0, 100.0)
    with pytest.raises(ConfigError, match=r"\[0, 180\]"):
        m.check_path_geometry(1000.0, 0.0, -5.0)
    with pytest.raises(ConfigError, match="finite"):
        m.check_path_geometry(np.nan, 0.0, 0.0)


def test_check_path_geometry_puts_ends_within_noise_below_the_ground_on_it():
    # float32 ray hits on a surface at the engine's lowest altitude land a little below it
    upper, lower, zen = m.check_path_geometry(7e5, [-5.8e-11, -4.7e-10, 3.0], 30.0)
    assert np.array_equal(lower, [0.0, 0.0, 3.0]) and np.all(upper == 7e5)
    upper, lower, _ = m.check_path_geometry([1500.0, 1199.99], 1199.9999, [0.0, 95.0],
                                            min_target=1200.0)
    assert np.array_equal(lower, [1200.0, 1200.0]) and np.array_equal(upper, [1500.0, 1200.0])
    for below in (-1.0, -m.GROUND_TOLERANCE - 1e-6):
        with pytest.raises(ConfigError, match="target_altitude: a path below the ground"):
            m.check_path_geometry(7e5, below, 30.0)
    with pytest.raises(ConfigError, match="a path below the ground: 1199 m is under the "
                                          "engine's lowest altitude 1200 m"):
        m.check_path_geometry(1199.0, 1500.0, 120.0, min_target=1200.0)


def test_phase_functions_6s_printed_as_nan_are_filled_from_larger_angles():
    from radscene.atmosphere.sixs import PHASE_ANGLES

    angles = np.asarray(PHASE_ANGLES)
    exact = np.exp(-0.05 * angles)[:, None] * np.array([[2.0, 3.0]])  # log-linear in angle
    printed = exact.copy()
    printed[0, 0] = np.nan
    printed[:2, 1] = [np.nan, -1.0]
    filled = m.fill_phase_function(PHASE_ANGLES, printed)
    np.testing.assert_allclose(filled, exact, rtol=1e-12)
    assert np.isnan(printed[0, 0])  # a copy
    again = m.fill_phase_function(PHASE_ANGLES, exact)
    assert again is not exact and np.array_equal(again, exact)
    # a gap at the largest angle: from the two below it
    printed = exact.copy()
    printed[-1, 1] = np.nan
    np.testing.assert_allclose(m.fill_phase_function(angles, printed), exact, rtol=1e-12)


def test_phase_functions_without_two_valid_angles_are_an_engine_error():
    from radscene.atmosphere.sixs import PHASE_ANGLES
    from radscene.errors import EngineError

    printed = np.full((len(PHASE_ANGLES), 2), 2.0)
    printed[1:, 1] = np.nan
    with pytest.raises(EngineError, match="fewer than two valid phase-function values at "
                                          "wavelength index 1"):
        m.fill_phase_function(PHASE_ANGLES, printed)


def test_phase_interp_holds_its_ends_and_is_log_linear():
    nodes = np.array([10.0, 20.0])
    table = np.array([[4.0], [1.0]])
    assert m.phase_interp([5.0, 15.0, 30.0], nodes, table)[:, 0] == pytest.approx(
        [4.0, 2.0, 1.0], rel=REL)


def test_aerosol_asymmetry_of_tabulated_phase_functions():
    nodes = np.linspace(0.0, 180.0, 361)
    c = np.cos(np.radians(nodes))
    table = np.stack([(1 - g * g) / (1 + g * g - 2 * g * c) ** 1.5 for g in (0.0, 0.3, 0.7)],
                     axis=1)
    assert m.aerosol_asymmetry(nodes, table) == pytest.approx([0.0, 0.3, 0.7], abs=2e-3)
    # the molecular phase function is symmetric
    assert m.aerosol_asymmetry(nodes, 0.75 * (1 + c * c)[:, None])[0] == pytest.approx(
        0.0, abs=1e-9)


def test_multiple_scattering_shape():
    tau, share, g = np.array([0.3, 1e-9]), np.array([0.7, 0.7]), np.array([0.65, 0.65])
    zenith = np.array([0.0, 60.0, 85.0])
    assert m.multiple_scattering_shape(zenith, 180.0, 30.0, tau, share, g).shape == (3, 2)
    # without aerosol: brighter towards the horizon; a thin layer gives tau / (2 mu)
    mu = np.cos(np.radians(zenith))
    isotropic = m.multiple_scattering_shape(zenith, 0.0, 30.0, tau, np.zeros(2), g)
    assert np.all(np.diff(isotropic[:, 0]) > 0.0)
    np.testing.assert_allclose(isotropic[:, 1], 1e-9 / (2 * mu), rtol=1e-6)
    # the aerosol's memory of the sun: Henyey-Greenstein of g^3 (0 and 60 deg from the sun)
    toward, away = m.multiple_scattering_shape(np.array([30.0, 30.0]), np.array([0.0, 180.0]),
                                               30.0, tau[:1], np.ones(1), g[:1])[:, 0]
    g3 = 0.65**3
    depth = 1 - np.cos(np.radians(30)) / 0.3 * (1 - np.exp(-0.3 / np.cos(np.radians(30))))
    assert toward == pytest.approx(depth * (1 + g3) / (1 - g3) ** 2, rel=1e-9)
    assert away == pytest.approx(depth * (1 - g3 * g3) / (1 + g3 * g3 - 2 * g3 * np.cos(
        np.radians(60.0))) ** 1.5, rel=1e-9)


def test_aerosol_asymmetry_is_the_trapezoidal_mean_cosine_of_the_interpolated_phase():
    """The compiled pass (geometric steps within a node interval) equals the trapezoidal rule
    over phase_interp's values at the 1 801 angles, to rounding."""
    nodes = np.array([0.0, 1.0, 2.0, 3.0, 4.0, 5.0, 7.5, 10.0, 15.0, 20.0, 30.0, 40.0, 60.0,
                      80.0, 100.0, 120.0, 130.0, 135.0, 140.0, 145.0, 150.0, 155.0, 160.0,
                      165.0, 170.0, 175.0, 180.0])
    rng = np.random.default_rng(3)
    c = np.cos(np.radians(nodes))[:, None]
    g = np.array([0.2, 0.6, 0.8])
    table = (1 - g * g) / (1 + g * g - 2 * g * c) ** 1.5 * rng.uniform(0.8, 1.2, (nodes.size, 3))
    fine = np.linspace(0.0, 180.0, 1801)
    theta = np.radians(fine)[:, None]
    dens = m.phase_interp(fine, nodes, table) * np.sin(theta)
    expected = (np.trapezoid(dens * np.cos(theta), theta, axis=0)
                / np.trapezoid(dens, theta, axis=0))
    np.testing.assert_allclose(m.aerosol_asymmetry(nodes, table), expected, rtol=1e-13)


def test_sky_terms_do_not_depend_on_the_order_of_the_directions():
    """The sky and shape kernels reuse each zenith's layer factor along a run of directions
    of that zenith: shuffled directions give the same values."""
    qz, qp, _ = m.hemisphere_quadrature(6, 8)
    order = np.random.default_rng(5).permutation(qz.size)
    nodes = np.linspace(0.0, 180.0, 19)
    pr = 0.75 * (1 + np.cos(np.radians(nodes)) ** 2)[:, None] * np.ones((1, 2))
    pa = np.exp(-nodes / 40.0)[:, None] * np.array([[1.0, 2.0]])
    args = (35.0, np.array([1800.0, 1500.0]), np.array([0.95, 0.9]), np.array([0.1, 0.05]),
            np.array([0.3, 0.2]), np.array([0.9, 0.92]), nodes, pr, pa)
    sky = m.single_scattering_sky(qz, qp, *args)
    assert np.array_equal(m.single_scattering_sky(qz[order], qp[order], *args), sky[order])
    tau, share, g = np.array([0.4, 0.25]), np.array([0.6, 0.7]), np.array([0.7, 0.65])
    shape = m.multiple_scattering_shape(qz, qp, 35.0, tau, share, g)
    assert np.array_equal(m.multiple_scattering_shape(qz[order], qp[order], 35.0, tau, share, g),
                          shape[order])
    # the closed form, evaluated by numpy
    mu = np.cos(np.radians(qz))[:, None]
    x = tau / mu
    c = np.cos(np.radians(m.scattering_angle_sky(35.0, qz, qp)))[:, None]
    g3 = g**3
    expected = ((1 - mu / tau * (1 - np.exp(-x)))
                * ((1 - share) + share * (1 - g3 * g3) / (1 + g3 * g3 - 2 * g3 * c) ** 1.5))
    np.testing.assert_allclose(shape, expected, rtol=1e-12)
