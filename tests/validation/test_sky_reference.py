"""The visible sky radiance map against a Monte Carlo of the same atmosphere, and LOWTRAN's sky.

References (``sky_references.py``, made by ``scripts/make_sky_references.py``): a scalar
backward Monte Carlo (``scripts/sky_monte_carlo.py``) of the sky at 0.55 um seen from the
ground — the zenith, the almucantar (zenith angle of the sun, 20-180 deg from it) and the
principal plane, for the sun at 30 and 60 deg — solved for

* 6S's atmosphere (US Standard 1962, continental aerosol at 23 and 5 km visibility: τ_R, τ_A,
  ω_A and the phase functions printed by 6S itself), whose diffuse irradiance agrees with 6S's
  own within 0.3 % (checked below);
* LOWTRAN's rural aerosol at 23 km with a Henyey-Greenstein phase function (g = 0.7), which
  LOWTRAN can take too (``phase_function: henyey_greenstein``).

What they showed: radscene's sky model (``sixs_model.sky_radiance``, shared by the ``database``
and ``sixs`` engines) spread the multiply scattered rest of 6S's diffuse irradiance
isotropically, which made the zenith 3-6 % (sun at 30 deg) to 33-37 % (60 deg) too bright,
the anti-solar sky up to 51 % (23 km) and 76 % (5 km) too bright and the horizon under the
sun 20 % too dark; with the angular shape of multiply scattered light (module notes of
``sixs_model``) every direction up to 75 deg from the zenith and 20 deg or more from the sun
is within 9.5 % (23 km) and 11.6 % (5 km) with the database, the zenith within +1.3 to
+10.9 %.
The database's zenith was never "far below" LOWTRAN's for the same atmosphere: LOWTRAN's rural
aerosol at 23 km visibility has τ_A(0.55 um) = 0.325 against 6S's continental 0.235, and
LOWTRAN's zenith sky is within 6 % of the Monte Carlo of its own atmosphere. LOWTRAN's sky is
nevertheless suspect elsewhere: its two-stream multiple scattering (an isotropic-like source
from the flux profiles) makes the anti-solar sky up to 24 % too bright and the sky near the
horizon on the sun's side up to 19 % too dark (the known gap below).

Tolerance: 12 % of the Monte Carlo radiance (its standard error is 0.2 %; neglecting
polarisation costs a few per cent of the molecular part).
"""

from __future__ import annotations

import importlib.util
from pathlib import Path

import numpy as np
import pytest

from radscene.atmosphere import sixs_model
from radscene.atmosphere.base import SkyGeometry


def _load_references():
    path = Path(__file__).with_name("sky_references.py")
    spec = importlib.util.spec_from_file_location("sky_references", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


ref = _load_references()

TOLERANCE = 0.12
#: The Monte Carlo's diffuse irradiance against 6S's (measured within 0.3 %).
IRRADIANCE_TOLERANCE = 0.01
WAVELENGTH = np.array([ref.WAVELENGTH_UM])
CONDITIONS = [(vis, sz) for vis in ref.VISIBILITIES_KM for sz in ref.SUN_ZENITHS]


def _cases(source, visibility, sun_zenith):
    return {k: c for k, c in ref.CASES.items()
            if k.startswith(f"{source}-") and c["visibility_km"] == visibility
            and c["sun_zenith"] == sun_zenith}


def _compare(sky, cases, tolerance):
    """Failures of ``sky(zenith, relative azimuth)`` against the cases' Monte Carlo radiance."""
    failures = []
    for case_id, c in cases.items():
        got = float(sky(c["zenith"], c["relative_azimuth"]))
        error = got / c["radiance"] - 1.0
        if abs(error) > tolerance:
            failures.append(f"{case_id}: {got:.2f}, Monte Carlo {c['radiance']:.2f} W m-2 sr-1 "
                            f"um-1 ({100 * error:+.1f} %)")
    return failures


@pytest.mark.parametrize("check", sorted(ref.CHECKS))
def test_the_monte_carlo_diffuse_irradiance_is_6s(check):
    c = ref.CHECKS[check]
    assert c["mc_diffuse_irradiance"] == pytest.approx(c["sixs_diffuse_irradiance"],
                                                       rel=IRRADIANCE_TOLERANCE)


def _database(visibility, sun_zenith):
    from radscene.atmosphere.database import DatabaseAtmosphere

    return DatabaseAtmosphere(profile="us_standard", aerosol="rural",
                              visibility=visibility * 1e3, sun_zenith=sun_zenith,
                              sun_azimuth=0.0)


@pytest.mark.parametrize(("visibility", "sun_zenith"), CONDITIONS)
def test_database_sky_equals_the_monte_carlo(visibility, sun_zenith):
    atm = _database(visibility, sun_zenith)
    # the same atmosphere as the reference's: 6S's optical depths
    c = atm.components(sixs_model.TOP_OF_ATMOSPHERE, 0.0, 0.0, WAVELENGTH,
                       sun_zenith=sun_zenith, relative_azimuth=0.0)
    optics = ref.SIXS_OPTICS[f"vis{visibility:02.0f}"]
    assert float(c["optical_depth_aerosol"][0, 0]) == pytest.approx(optics["tau_aerosol"],
                                                                    rel=0.01)
    geometry = SkyGeometry(0.0, sun_zenith, 0.0)
    failures = _compare(lambda z, a: atm.sky(z, a, WAVELENGTH, geometry)[0],
                        _cases("sixs", visibility, sun_zenith), TOLERANCE)
    assert not failures, "\n".join(failures)


@pytest.mark.parametrize(("visibility", "sun_zenith"), CONDITIONS)
def test_database_sky_integrates_to_its_diffuse_irradiance_and_that_is_6s(visibility,
                                                                          sun_zenith):
    """The hemispheric integral of the sky times cos θ is the engine's diffuse irradiance
    (by construction, 0.1 %), which is 6S's within 3 % (measured −2.4 % to +0.3 %: the
    database's interpolation between its nodes)."""
    atm = _database(visibility, sun_zenith)
    qz, qp, qw = sixs_model.hemisphere_quadrature(24, 48)
    e_sky = float(qw @ atm.sky(qz, qp, WAVELENGTH, SkyGeometry(0.0, sun_zenith, 0.0))[:, 0])
    e_dif = float(atm.coupling(1e5, 0.0, 0.0, WAVELENGTH).diffuse_irradiance[0])
    assert e_sky == pytest.approx(e_dif, rel=1e-3)
    sixs = ref.CHECKS[f"sixs-vis{visibility:02.0f}-sz{sun_zenith:02.0f}"]
    assert e_dif == pytest.approx(sixs["sixs_diffuse_irradiance"], rel=0.03)


@pytest.mark.slow
@pytest.mark.parametrize(("visibility", "sun_zenith"), CONDITIONS)
def test_sixs_engine_sky_equals_the_monte_carlo(tmp_path, visibility, sun_zenith):
    from radscene.atmosphere import sixs_runner
    from radscene.atmosphere.sixs import SixSAtmosphere

    available, reason = sixs_runner.sixs_available()
    if not available:
        pytest.skip(f"6S cannot run here: {reason}")
    atm = SixSAtmosphere(profile="us_standard", aerosol="rural", visibility=visibility * 1e3,
                         sun_zenith=sun_zenith, sun_azimuth=0.0, cache=tmp_path, workers=2)
    geometry = SkyGeometry(0.0, sun_zenith, 0.0)
    failures = _compare(lambda z, a: atm.sky(z, a, WAVELENGTH, geometry)[0],
                        _cases("sixs", visibility, sun_zenith), TOLERANCE)
    assert not failures, "\n".join(failures)


# -- LOWTRAN -----------------------------------------------------------------------------------
def _lowtran(sun_zenith):
    from radscene.atmosphere.lowtran import NOT_BUILT, LowtranAtmosphere, lowtran_available

    if not lowtran_available():
        pytest.skip(NOT_BUILT)
    return LowtranAtmosphere(model="us_standard", aerosol="rural",
                             visibility=ref.LOWTRAN_VISIBILITY_KM,
                             phase_function="henyey_greenstein",
                             asymmetry=ref.LOWTRAN_ASYMMETRY, workers=2)


def _lowtran_shapes(sun_zenith):
    """(case id, engine, LOWTRAN's own, Monte Carlo) sky over the zenith sky, each."""
    atm = _lowtran(sun_zenith)
    cases = _cases("lowtran", ref.LOWTRAN_VISIBILITY_KM, sun_zenith)
    z = np.array([c["zenith"] for c in cases.values()])
    a = np.array([c["relative_azimuth"] for c in cases.values()])
    wl = np.array([1e4 / ref.WAVENUMBER_CM1])
    engine = atm.sky(z, a, wl, SkyGeometry(0.0, sun_zenith, 0.0))[:, 0]
    own = np.array([c["lowtran_radiance_per_irradiance"] for c in cases.values()])
    mc = np.array([c["mc_radiance_per_irradiance"] for c in cases.values()])
    zenith = list(cases).index(next(k for k, c in cases.items() if c["zenith"] == 0.0))
    return list(cases), engine / engine[zenith], own / own[zenith], mc / mc[zenith], \
        own[zenith] / mc[zenith]


@pytest.mark.parametrize("sun_zenith", ref.SUN_ZENITHS)
def test_lowtran_engine_sky_is_lowtrans_own(sun_zenith):
    """The engine's sky queries (directions, azimuth convention) give LOWTRAN's own sky."""
    _, engine, own, _, _ = _lowtran_shapes(sun_zenith)
    np.testing.assert_allclose(engine, own, rtol=5e-3)


@pytest.mark.parametrize("sun_zenith", ref.SUN_ZENITHS)
def test_lowtrans_zenith_sky_is_the_monte_carlos(sun_zenith):
    """LOWTRAN's zenith radiance of its own atmosphere: measured -1.5 % (sun at 30 deg) and
    +6.2 % (60 deg) from the Monte Carlo's."""
    *_, zenith_ratio = _lowtran_shapes(sun_zenith)
    assert zenith_ratio == pytest.approx(1.0, rel=0.08)


@pytest.mark.xfail(strict=True, reason="known gap: LOWTRAN's two-stream multiple scattering "
                   "makes the anti-solar sky up to 24 % too bright and the horizon on the "
                   "sun's side up to 19 % too dark against the Monte Carlo of the same "
                   "atmosphere")
@pytest.mark.parametrize("sun_zenith", ref.SUN_ZENITHS)
def test_lowtrans_sky_shape_is_the_monte_carlos(sun_zenith):
    names, _, own, mc, zenith_ratio = _lowtran_shapes(sun_zenith)
    error = own * zenith_ratio / mc - 1.0
    assert np.all(np.abs(error) <= TOLERANCE), dict(zip(names, np.round(100 * error, 1), strict=True))
