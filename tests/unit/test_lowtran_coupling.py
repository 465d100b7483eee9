"""The ``lowtran`` engine's coupling spectra: the albedo fits, TAPE7's ground column, and the
closure of the coupling with LOWTRAN's own radiance mode."""

from __future__ import annotations

import math

import numpy as np
import pytest

from radscene.atmosphere.lowtran import NOT_BUILT, LowtranAtmosphere, lowtran_available
from radscene.atmosphere.lowtran.coupling import albedo_fit
from radscene.atmosphere.lowtran.parser import parse_tape7_ground

needs_lowtran = pytest.mark.skipif(not lowtran_available(), reason=NOT_BUILT)

#: LOWTRAN's radiance mode against the coupling's equation at a spectral sample: measured
#: within 0.3 % (rural 23 and 5 km, top of the atmosphere and 3 km at 40 deg, rho 0.2, 0.5).
CLOSURE = 5e-3


# -- the fits -----------------------------------------------------------------------------------
@pytest.mark.parametrize(("a", "s"), [(2.0, 0.1), (107.8, 0.037), (0.5, 0.0), (3.0, 0.6)])
def test_albedo_fit_recovers_a_and_s(a, s):
    def f(rho):
        return a * rho / (1.0 - s * rho)
    got_a, got_s = albedo_fit(0.5, 1.0, f(0.5), f(1.0))
    assert float(got_a) == pytest.approx(a, rel=1e-12)
    assert float(got_s) == pytest.approx(s, abs=1e-12)


def test_albedo_fit_broadcasts():
    a = np.array([[1.0], [2.0]])
    s = np.array([0.0, 0.1, 0.2])
    got_a, got_s = albedo_fit(0.25, 1.0, a * 0.25 / (1 - s * 0.25), a / (1 - s))
    assert got_a.shape == got_s.shape == (2, 3)
    np.testing.assert_allclose(got_s, np.broadcast_to(s, (2, 3)), atol=1e-12)
    np.testing.assert_allclose(got_a, np.broadcast_to(a, (2, 3)), rtol=1e-12)


def test_albedo_fit_of_a_flat_function_has_no_spherical_albedo():
    got_a, got_s = albedo_fit(0.5, 1.0, np.zeros(2), np.zeros(2))
    assert np.all(got_a == 0.0) and np.all(got_s == 0.0)


@pytest.mark.parametrize("albedos", [(0.5, 0.5), (0.0, 1.0), (0.5, 1.5)])
def test_albedo_fit_refuses_bad_albedos(albedos):
    with pytest.raises(ValueError, match="two different albedos in"):
        albedo_fit(*albedos, 1.0, 2.0)


# -- TAPE7 ----------------------------------------------------------------------------------------
RECORD = (" 18100.  0.6384 0.00E+00 4.16E-07 5.88E-08 9.13E-07 5.93E-07 1.33E-06  0.3803  "
          "0.5105           4.488E-01")


def test_parse_tape7_ground_reads_the_ground_columns():
    text = "  card echo\n  FREQ   TRANS     ATMOS   PATH\n" + RECORD + "\n" + RECORD.replace(
        "9.13E-07", "1.23-100").replace("18100.", "18105.") + "\n -9999.\n"
    out = parse_tape7_ground(text)
    assert out["wavenumber"].tolist() == [18100.0, 18105.0]
    assert out["ground_radiance"].tolist() == [9.13e-7, 1.23e-100]
    assert out["direct_ground_radiance"].tolist() == [5.93e-7, 5.93e-7]


@pytest.mark.parametrize("text", ["", "  FREQ   TRANS\n -9999.\n", RECORD])
def test_parse_tape7_ground_refuses_a_file_without_records(text):
    with pytest.raises(ValueError, match="no spectral record"):
        parse_tape7_ground(text)


# -- the engine -----------------------------------------------------------------------------------
WAVELENGTH = np.array([0.45, 0.55, 0.66, 0.87])


def _engine(visibility=23.0, **kw):
    return LowtranAtmosphere(model="us_standard", aerosol="rural", visibility=visibility,
                             sun_zenith=30.0, sun_azimuth=0.0, view_azimuth=90.0, workers=2,
                             **kw)


@needs_lowtran
def test_coupling_without_the_sun_is_zero_and_broadcasts():
    atm = LowtranAtmosphere(model="us_standard", aerosol="rural", workers=2)
    cp = atm.coupling([[3000.0], [1e5]], 0.0, [0.0, 20.0, 40.0], WAVELENGTH)
    for name in ("diffuse_transmittance", "rayleigh_share", "spherical_albedo",
                 "direct_irradiance", "diffuse_irradiance"):
        values = getattr(cp, name)
        assert values.shape == (2, 3, WAVELENGTH.size), name
        assert np.all(values == 0.0), name


@needs_lowtran
def test_coupling_figures_are_physical_and_lines_looking_up_have_no_diffuse_transmittance():
    atm = _engine()
    cp = atm.coupling([1e5, 3000.0, 0.0], [0.0, 0.0, 3000.0], [0.0, 40.0, 120.0], WAVELENGTH)
    assert np.all((cp.diffuse_transmittance[:2] > 0.0) & (cp.diffuse_transmittance[:2] < 0.5))
    assert np.all(cp.diffuse_transmittance[2] == 0.0)
    assert np.all((cp.spherical_albedo > 0.0) & (cp.spherical_albedo < 0.2))
    assert np.all((cp.rayleigh_share > 0.0) & (cp.rayleigh_share < 1.0))
    # diffuse over direct falls with wavelength; the molecular share too
    ratio = cp.diffuse_irradiance[0] / cp.direct_irradiance[0]
    assert np.all(np.diff(ratio) < 0.0) and np.all(np.diff(cp.rayleigh_share[0]) < 0.0)
    # the direct irradiance is mu_s times LOWTRAN's transmitted solar irradiance
    sun = atm.line_of_sight(1e5, 0.0, 0.0, wavelength=WAVELENGTH)
    np.testing.assert_allclose(cp.direct_irradiance[0], math.cos(math.radians(30.0))
                               * sun["direct_solar_irradiance"].values, rtol=1e-9)


CONDITIONS = [(23.0, 1e5, 0.0), (5.0, 1e5, 0.0), (23.0, 3000.0, 40.0), (5.0, 3000.0, 40.0)]


@needs_lowtran
@pytest.mark.parametrize("condition", [
    pytest.param(c, marks=() if c == CONDITIONS[0] else pytest.mark.slow,
                 id=f"vis{c[0]:g}-h{c[1]:g}-vz{c[2]:g}") for c in CONDITIONS])
def test_the_coupling_equation_gives_lowtrans_own_radiance_of_a_lambertian_ground(condition):
    """L_path(0) + ρ E_0 (τ + t_d) / (π (1 − S ρ)) against LOWTRAN's radiance mode with the
    path ending on a ground of albedo ρ (scattered path radiance plus RFLSOL)."""
    visibility, observer, view_zenith = condition
    atm = _engine(visibility)
    cp = atm.coupling(observer, 0.0, view_zenith, WAVELENGTH)
    path = atm.path(observer, 0.0, view_zenith, WAVELENGTH)
    e0 = cp.direct_irradiance + cp.diffuse_irradiance
    case, _ = atm._path_case(observer, 0.0, view_zenith, atm._window(WAVELENGTH)[1])
    v = 1e4 / WAVELENGTH
    for rho in (0.2, 0.5):
        model = path.scattered_radiance + rho * e0 / math.pi * (
            path.transmittance + cp.diffuse_transmittance) / (1.0 - cp.spherical_albedo * rho)
        run = atm.runner.run([case.replace(h2=0.0, salb=rho)], [f"ground albedo {rho}"])[0]
        own = (atm._interp(run, run.scattered_radiance, v)
               + atm._interp(run, run.ground_radiance, v))
        np.testing.assert_allclose(model, own, rtol=CLOSURE, err_msg=f"rho {rho}")


@needs_lowtran
def test_line_of_sight_apparent_radiance_is_lowtrans_own_radiance_of_the_surface():
    """``radscene atmosphere los --engine lowtran``: the apparent radiance of a Lambertian
    surface now holds the diffuse sky light it reflects and the surroundings' diffusely
    transmitted light, as LOWTRAN's radiance mode does."""
    from radscene.atmosphere.api import line_of_sight

    rho = 0.3
    ds = line_of_sight(1e5, 0.0, 0.0, engine="lowtran", visibility="23 km", sun_zenith=30.0,
                       sun_azimuth=0.0, view_azimuth=90.0, surface_albedo=rho,
                       wavelength=WAVELENGTH)
    atm = _engine()
    case, _ = atm._path_case(1e5, 0.0, 0.0, atm._window(WAVELENGTH)[1])
    run = atm.runner.run([case.replace(h2=0.0, salb=rho)], ["ground albedo 0.3"])[0]
    v = 1e4 / ds["wavelength"].values
    own = atm._interp(run, run.scattered_radiance, v) + atm._interp(run, run.ground_radiance, v)
    np.testing.assert_allclose(ds["apparent_radiance"].values, own, rtol=CLOSURE)
    assert np.all(ds["diffuse_irradiance"].values > 0.0)
    # the path over black ground, as with the other engines
    black = atm.path(1e5, 0.0, 0.0, ds["wavelength"].values).scattered_radiance
    np.testing.assert_allclose(ds["path_scattered_radiance"].values, black, rtol=1e-9)
