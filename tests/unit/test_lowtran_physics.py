"""The ``lowtran`` engine against physics it must obey, through the real LOWTRAN7.

Skipped where LOWTRAN is not built (``make lowtran``, needs gfortran). Each run takes
0.01-0.3 s; results are cached in a per-session folder.
"""

from __future__ import annotations

import numpy as np
import pytest

from radscene.atmosphere import SkyGeometry
from radscene.atmosphere.lowtran import (
    NOT_BUILT,
    LowtranAtmosphere,
    LowtranCase,
    LowtranRunner,
    ProfileLevel,
    lowtran_available,
)
from radscene.errors import EngineError

pytestmark = pytest.mark.skipif(not lowtran_available(), reason=NOT_BUILT)


@pytest.fixture(scope="module")
def cache(tmp_path_factory):
    return tmp_path_factory.mktemp("lowtran-cache")


@pytest.fixture(scope="module")
def rayleigh(cache):
    """US standard atmosphere, no aerosol, single scattering only."""
    return LowtranAtmosphere(model="us_standard", aerosol="none", multiple_scattering=False,
                             cache_dir=cache)


def test_kirchhoff_on_a_short_isothermal_path(cache):
    # 50 m horizontal at 283.8 K, 94 % relative humidity (lowtran_fortran_horiz_thermal_radiance):
    # an isothermal non-scattering path emits (1 - tau) B(T). LOWTRAN works in single
    # precision with its own Planck function: 1e-3.
    from radscene.radiometry import spectral_radiance

    level = ProfileLevel(z=0.05, p=949.0, t=283.8, wmol=(93.96,) + (0.0,) * 11,
                         jchar="AAH" + "E" * 11)
    case = LowtranCase(model=0, itype=1, iemsct=1, im=1, ird1=1, levels=(level,), h1=0.05,
                       range=0.05, v1=750.0, v2=1250.0, dv=5.0)
    result = LowtranRunner(cache_dir=cache).run([case], ["kirchhoff"])[0]
    expected = (1.0 - result.transmittance) * spectral_radiance(result.wavelength, 283.8)
    assert result.thermal_radiance == pytest.approx(expected, rel=1e-3)


def test_beer_lambert_air_mass(rayleigh):
    # where Rayleigh scattering and the ozone continuum dominate, tau(60 deg) = tau(0)^2;
    # the spherical refracted air mass at 60 deg is 1.995, not 2: 3e-3
    wl = np.array([0.40, 0.45, 0.50])
    tau = rayleigh.sun(0.0, [0.0, 60.0], wl, np.ones(3)).transmittance
    assert tau[1] == pytest.approx(tau[0] ** 2, rel=3e-3)


def test_a_path_down_from_space_is_the_sun_path_reversed(rayleigh):
    wl = np.array([0.45, 0.65, 0.85])
    down = rayleigh.path(100000.0, 0.0, [0.0, 60.0], wl).transmittance
    sun = rayleigh.sun(0.0, [0.0, 60.0], wl, np.ones(3)).transmittance
    assert down == pytest.approx(sun, rel=1e-3)  # observer-side angle from our geometry


@pytest.mark.parametrize("wavelength", [0.40, 0.45])
@pytest.mark.parametrize("sun_zenith, view_zenith, relative_azimuth", [
    (30.0, 0.0, 180.0), (60.0, 0.0, 0.0), (30.0, 45.0, 180.0), (30.0, 45.0, 0.0)])
def test_rayleigh_sky_is_single_scattering(rayleigh, wavelength, sun_zenith, view_zenith,
                                           relative_azimuth):
    # Single-scattered skylight seen from the ground in a plane-parallel Rayleigh atmosphere
    # (Chandrasekhar 1960; e.g. Liou, An Introduction to Atmospheric Radiation, 2002, §3.4):
    #   L = E0 P(Θ)/(4π μ) ∫0^τ exp(-t/μ0) exp(-(τ-t)/μ) dt,  P = 3/4 (1 + cos²Θ)
    # with LOWTRAN's own E0 and τ (which carries a little ozone absorption): 3 %.
    wl = np.array([wavelength])
    sky = rayleigh.sky(view_zenith, 0.0, wl, SkyGeometry(0.0, sun_zenith, relative_azimuth))
    los = rayleigh.with_sun(sun_zenith, 0.0).line_of_sight(100000.0, 0.0, 0.0, wavelength=wl)
    e0 = float(los.direct_solar_irradiance[0] / los.sun_transmittance[0])
    tau = -np.log(float(los.transmittance[0]))
    mu0, mu = np.cos(np.radians(sun_zenith)), np.cos(np.radians(view_zenith))
    cos_theta = mu0 * mu + (np.sin(np.radians(sun_zenith)) * np.sin(np.radians(view_zenith))
                            * np.cos(np.radians(relative_azimuth)))
    phase = 0.75 * (1.0 + cos_theta**2)
    a = 1.0 / mu0 - 1.0 / mu
    integral = (tau * np.exp(-tau / mu) if abs(a) < 1e-12
                else np.exp(-tau / mu) * (1.0 - np.exp(-tau * a)) / a)
    expected = e0 * phase / (4.0 * np.pi) * integral / mu
    assert float(sky[0]) == pytest.approx(expected, rel=0.03)


def test_sky_symmetry_and_multiple_scattering(cache):
    wl = np.array([0.45, 0.65])
    geometry = SkyGeometry(0.0, 40.0, 100.0)
    single = LowtranAtmosphere(multiple_scattering=False, cache_dir=cache)
    multiple = LowtranAtmosphere(multiple_scattering=True, cache_dir=cache)
    a, b = single.sky([50.0, 50.0], [60.0, 140.0], wl, geometry)
    assert a == pytest.approx(b, rel=1e-12)  # 40 deg either side of the sun: one run
    assert np.all(multiple.sky(50.0, 60.0, wl, geometry) > a)


def test_path_radiance_grows_with_path_length(cache):
    atm = LowtranAtmosphere(sun_zenith=35.0, sun_azimuth=180.0, cache_dir=cache)
    wl = np.array([0.55, 10.0])
    out = atm.path([500.0, 3000.0, 10000.0], 0.0, 30.0, wl)
    assert np.all(np.diff(out.transmittance, axis=0) < 0)
    assert np.all(np.diff(out.radiance, axis=0) > 0)
    assert np.all(out.scattered_radiance[:, 0] > 10 * out.thermal_radiance[:, 0])
    assert np.all(out.thermal_radiance[:, 1] > 10 * out.scattered_radiance[:, 1])


def test_path_nodes_reproduce_direct_runs(cache):
    # the renderer mixes node spectra with the node weights: within 1 % of a direct run
    # (single scattering and 20 cm-1 steps keep it quick; the node grid depends on neither)
    atm = LowtranAtmosphere(sun_zenith=30.0, sun_azimuth=180.0, multiple_scattering=False,
                            wavenumber_step=20.0, cache_dir=cache)
    rng = np.random.default_rng(11)
    n = 500
    obs, tgt, vz = np.full(n, 3000.0), rng.uniform(0.0, 300.0, n), rng.uniform(0.0, 50.0, n)
    nodes = atm.path_nodes(obs, tgt, vz)
    wl = np.array([0.45, 0.65, 2.2, 10.0])
    at_nodes = atm.path(nodes.observer_altitude, nodes.target_altitude, nodes.view_zenith, wl)
    pick = np.arange(0, n, 100)
    direct = atm.path(obs[pick], tgt[pick], vz[pick], wl)
    for name in ("transmittance", "radiance"):
        table = getattr(at_nodes, name)
        mixed = np.einsum("nk,nkq->nq", nodes.weight[pick], table[nodes.index[pick]])
        assert mixed == pytest.approx(getattr(direct, name), rel=0.01)


def test_a_lowtran_stop_is_an_engine_error(cache):
    # an invalid unit flag makes LOWTRAN STOP (JOU: BAD PARAM); a raw deck gets past our checks
    deck = ("    0    1    0    0    0    0    0    0    0    0    0    1    0   0.000   0.00\n"
            "    0    0    0    0    0    0     0.000     0.000     0.000     0.000     0.000\n"
            "    1    0    0  bad unit\n"
            "     0.000  1000.000   280.000    50.000     0.000     0.000ZZZ\n"
            "     0.000     0.000     0.000     1.000     0.000     0.000    0\n"
            "   900.000  1000.000     5.000\n    0\n")
    with pytest.raises(EngineError, match="'bad unit flag' failed.*INVALID PARAMETER"):
        LowtranRunner(cache=False).run([deck], ["bad unit flag"])


def test_a_skipped_lowtran_case_is_an_engine_error():
    # looking up from 10 km towards 5 km: LOWTRAN's GEOINP refuses and skips the case
    case = LowtranCase(model=6, itype=2, h1=10.0, h2=5.0, angle=0.0, v1=10000.0, v2=10100.0)
    with pytest.raises(EngineError, match="'up to a lower target' failed.*ERROR IN INPUT DATA"):
        LowtranRunner(cache=False).run([case], ["up to a lower target"])


@pytest.mark.parametrize("model", ["tropical", "midlatitude_winter", "us_standard"])
def test_a_model_at_its_own_columns_is_the_model(cache, model):
    """The scaled-column user atmosphere at the model's own columns is LOWTRAN's model to the
    last digit (season, Earth radius and every flagged gas the model's): path, sun and sky,
    water bands and the thermal infrared."""
    from radscene.atmosphere.lowtran.profiles import model_columns

    water, ozone = model_columns(model)
    kw = dict(model=model, aerosol="rural", visibility=23.0, sun_zenith=30.0, sun_azimuth=0.0,
              cache_dir=cache)
    own, same = LowtranAtmosphere(**kw), LowtranAtmosphere(water=water, ozone=ozone, **kw)
    wl = np.concatenate([np.linspace(0.9, 0.98, 9), np.linspace(8.0, 12.5, 10)])
    a, b = own.path(3000.0, 0.0, 40.0, wl), same.path(3000.0, 0.0, 40.0, wl)
    for name in ("transmittance", "thermal_radiance", "scattered_radiance"):
        assert getattr(b, name) == pytest.approx(getattr(a, name), rel=1e-6, abs=1e-12), name
    assert same.sun(0.0, 30.0, wl, np.ones(wl.size)).transmittance == pytest.approx(
        own.sun(0.0, 30.0, wl, np.ones(wl.size)).transmittance, rel=1e-6)
    geometry = SkyGeometry(0.0, 30.0, 0.0)
    assert same.sky([20.0], [90.0], wl, geometry) == pytest.approx(
        own.sky([20.0], [90.0], wl, geometry), rel=1e-6, abs=1e-12)


def test_more_water_and_ozone_absorb_and_emit_more(cache):
    from radscene.atmosphere.lowtran.profiles import model_columns

    water, ozone = model_columns("us_standard")
    kw = dict(model="us_standard", aerosol="none", cache_dir=cache)
    wl = np.linspace(8.0, 12.5, 46)
    path = {s: LowtranAtmosphere(water=s * water, **kw).path(5000.0, 0.0, 0.0, wl)
            for s in (0.5, 1.0, 2.0)}
    window = (wl > 10.5) & (wl < 12.0)  # the water-vapour continuum
    tau = [path[s].transmittance[window].mean() for s in (0.5, 1.0, 2.0)]
    emitted = [path[s].thermal_radiance[window].mean() for s in (0.5, 1.0, 2.0)]
    assert tau[0] > tau[1] > tau[2] and emitted[0] < emitted[1] < emitted[2]
    band = (wl > 9.4) & (wl < 9.9)  # the ozone band, seen from space
    o3 = {s: LowtranAtmosphere(ozone=s * ozone, **kw).path(100000.0, 0.0, 0.0, wl)
          for s in (1.0, 1.5)}
    assert o3[1.5].transmittance[band].mean() < o3[1.0].transmittance[band].mean() - 0.01
