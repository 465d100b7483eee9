"""The selectable top-of-atmosphere solar spectra: radscene's default (ASTM G173-03, Gueymard
2004), the TSIS-1 HSRS v2 (``tsis1``) and LOWTRAN7's own (``lowtran``), through radscene.sun and
the atmosphere options."""

from __future__ import annotations

from importlib import resources

import numpy as np
import pytest

from radscene.atmosphere import sixs_model
from radscene.atmosphere.options import ENGINE_SPECTRA, SOLAR_SPECTRA, check_options
from radscene.errors import ConfigError
from radscene.sun import (
    SOLAR_SPECTRUM_NAMES,
    solar_constant,
    sun_radiance,
    toa_solar_irradiance,
    toa_solar_spectrum,
)

#: Total solar irradiance [W m-2] (Kopp & Lean 2011, GRL 38, L01706; TSIS-1 TIM agrees).
TSI = 1360.8
#: The HSRS v2 file's own integral over 202-2730 nm [W m-2]: the sum of its 0.025 nm samples.
HSRS_FILE_INTEGRAL = 1325.76
#: 6S's extraterrestrial irradiance at 0.55 um as 6SV1.1 prints it for 5 April
#: [W m-2 um-1] (tests/validation/sky_references.py, CHECKS 'toa_irradiance').
SIXS_E0_550 = 1871.429
#: LOWTRAN7's extraterrestrial band irradiances [W m-2] at the mean Earth-Sun distance over
#: bands in cm-1 (tests/validation/lowtran_closure_references.py, 'toa_band_irradiance').
LOWTRAN_BANDS = {(21740.0, 22725.0): 39.62973, (17860.0, 18515.0): 36.88504,
                 (14925.0, 15385.0): 30.9909}
CLOSE = 0.025  # relative: reference spectra agree in band means to a few per cent


def _table():
    path = resources.files("radscene") / "data" / "solar" / "tsis1_hsrs_v2_1nm.csv"
    text = path.read_text(encoding="utf-8")
    rows = [line.split(",") for line in text.splitlines()
            if line and not line.startswith(("#", "wavelength"))]
    return text, np.array(rows, dtype=float)


def _band_mean(lo, hi, spectrum):
    wl = np.linspace(lo, hi, 20_001)
    return np.trapezoid(toa_solar_irradiance(wl, spectrum=spectrum), wl) / (hi - lo)


def test_tsis1_table_carries_its_source_and_the_published_integral():
    text, data = _table()
    for needle in ("doi:10.1029/2020GL091709", "doi:10.1029/2022EA002637", "c2022-11-30",
                   "sha256", "licence", "LIME-ESA/lime_tbx"):
        assert needle in text, needle
    wl, e, unc = data.T
    assert wl[0] == pytest.approx(0.2025) and wl[-1] == pytest.approx(2.7295)
    assert np.diff(wl) == pytest.approx(np.full(wl.size - 1, 1e-3), abs=1e-9)  # 1 nm bins
    assert np.all(e > 0) and np.all(unc > 0) and np.all(unc < 0.05 * e)
    # box means: the bins times 1 nm are the file's integral over 202-2730 nm
    assert e.sum() * 1e-3 == pytest.approx(HSRS_FILE_INTEGRAL, abs=0.01)
    # which is 97.4 % of the TSI: the HSRS covers 202-2730 nm only
    assert e.sum() * 1e-3 / TSI == pytest.approx(0.9742, abs=5e-4)


def test_tsis1_integral_over_radscenes_range_is_the_tsi():
    # 0.25-2.7295 um from the HSRS, the radscene spectrum beyond: 0.07 % below the TSI
    assert solar_constant("tsis1") == pytest.approx(TSI, rel=2e-3)
    assert solar_constant("tsis1") == pytest.approx(1359.81, abs=0.01)
    assert solar_constant() == pytest.approx(1366.0, abs=0.05)  # the default, unchanged
    wl, e = toa_solar_spectrum("tsis1")
    keep = wl <= 2.7295
    hsrs_part = np.trapezoid(e[keep], wl[keep])  # exact: the table is linear between samples
    assert hsrs_part == pytest.approx(1323.85, abs=0.01)
    assert hsrs_part / solar_constant("tsis1") == pytest.approx(0.9735, abs=5e-4)


@pytest.mark.parametrize("spectrum", SOLAR_SPECTRUM_NAMES)
def test_native_sampling_integrates_to_the_solar_constant(spectrum):
    wl, e = toa_solar_spectrum(spectrum)
    assert wl[0] == 0.25 and wl[-1] == 20.0 and np.all(np.diff(wl) > 0)
    assert e == pytest.approx(toa_solar_irradiance(wl, spectrum=spectrum), rel=1e-14)
    # exact for the tables; the blackbody tail is sampled every 5 nm
    assert np.trapezoid(e, wl) == pytest.approx(solar_constant(spectrum), rel=1e-4)


def test_tsis1_is_the_table_below_the_join_and_the_default_beyond():
    _, data = _table()
    wl, e = data[:, 0], data[:, 1]
    inside = (wl >= 0.25)
    assert toa_solar_irradiance(wl[inside], spectrum="tsis1") == pytest.approx(e[inside],
                                                                               rel=1e-12)
    beyond = np.array([2.73, 3.0, 3.9, 4.5, 12.0])
    assert toa_solar_irradiance(beyond, spectrum="tsis1") == pytest.approx(
        toa_solar_irradiance(beyond), rel=1e-14)
    below, above = toa_solar_irradiance([2.7295, 2.7295 + 1e-9], spectrum="tsis1")
    assert above / below == pytest.approx(0.973, abs=0.005)  # the stated 2.7 % step
    # distance scaling and the disk radiance follow the chosen spectrum
    d = np.array([[0.983], [1.017]])
    assert toa_solar_irradiance([0.5, 1.0], d, "TSIS1") == pytest.approx(
        toa_solar_irradiance([0.5, 1.0], 1.0, "tsis1") / d**2, rel=1e-14)
    assert sun_radiance(0.5, spectrum="tsis1") / sun_radiance(0.5) == pytest.approx(
        toa_solar_irradiance(0.5, spectrum="tsis1") / toa_solar_irradiance(0.5), rel=1e-12)


@pytest.mark.parametrize(("lo", "hi"), [(0.3, 0.4), (0.4, 0.5), (0.5, 0.6), (0.6, 0.7),
                                        (0.7, 0.9), (0.9, 1.2), (1.2, 1.6), (1.6, 2.0),
                                        (2.0, 2.5), (0.3, 2.7)])
def test_tsis1_band_means_agree_with_gueymard(lo, hi):
    # band means within a few per cent of ASTM G173-03 / Gueymard (2004); measured: within 2 %
    ratio = _band_mean(lo, hi, "tsis1") / _band_mean(lo, hi, "radscene")
    assert ratio == pytest.approx(1.0, abs=CLOSE)


@pytest.mark.parametrize("spectrum", SOLAR_SPECTRUM_NAMES)
def test_band_means_agree_with_6s_and_lowtran(spectrum):
    # 6S at 0.55 um, brought back to 1 AU from its 5 April (its own Earth-Sun factor)
    sixs = SIXS_E0_550 / sixs_model.earth_sun_factor_6s(4, 5)
    assert _band_mean(0.5475, 0.5525, spectrum) == pytest.approx(sixs, rel=CLOSE)
    for (nu_lo, nu_hi), band in LOWTRAN_BANDS.items():
        lo, hi = 1e4 / nu_hi, 1e4 / nu_lo
        assert _band_mean(lo, hi, spectrum) * (hi - lo) == pytest.approx(band, rel=CLOSE)


def test_unknown_spectrum_is_refused():
    for call in (lambda: toa_solar_irradiance(0.5, spectrum="kurucz"),
                 lambda: toa_solar_spectrum("6s"), lambda: solar_constant("thuillier")):
        with pytest.raises(ConfigError, match="^solar_spectrum: unknown solar spectrum"):
            call()


def test_engines_offer_tsis1_with_its_source():
    assert "Coddington" in SOLAR_SPECTRA["tsis1"] and "2020GL091709" in SOLAR_SPECTRA["tsis1"]
    assert "tsis1" in ENGINE_SPECTRA["sixs"] and "tsis1" in ENGINE_SPECTRA["database"]
    assert ENGINE_SPECTRA["database"][0] == "radscene"  # the default stays the default
    none = dict(visibility=None, aot550=None, water=None, ozone=None, date=None,
                earth_sun_distance=None)
    assert check_options("database", **none, solar_spectrum="TSIS1")["solar_spectrum"] == "tsis1"
    with pytest.raises(ConfigError, match="solar_spectrum: the lowtran engine uses lowtran"):
        check_options("lowtran", **none, solar_spectrum="tsis1")


def test_database_engine_scales_its_sun_by_the_chosen_spectrum():
    from radscene.atmosphere.api import line_of_sight
    from radscene.atmosphere.database import DatabaseAtmosphere

    wl = np.array([0.45, 0.55, 0.87, 1.6])
    kw = dict(engine="database", wavelength=wl, sun_zenith=30.0)
    ours = line_of_sight(100_000.0, 0.0, 20.0, **kw)
    theirs = line_of_sight(100_000.0, 0.0, 20.0, solar_spectrum="tsis1", **kw)
    assert theirs.attrs["solar_spectrum"] == "tsis1"
    assert "Coddington" in theirs.attrs["solar_spectrum_source"]
    ratio = toa_solar_irradiance(wl, spectrum="tsis1") / toa_solar_irradiance(wl)
    for name in ("direct_solar_irradiance", "path_radiance"):
        assert theirs[name].values / ours[name].values == pytest.approx(ratio, rel=1e-9), name
    assert theirs["transmittance"].values == pytest.approx(ours["transmittance"].values,
                                                           rel=1e-12)
    with pytest.raises(ConfigError, match="^atmosphere.solar_spectrum: unknown value '6s'"):
        DatabaseAtmosphere(solar_spectrum="6s")


def test_renderer_sun_follows_the_atmosphere():
    from types import SimpleNamespace

    from radscene.render.spectral import solar_spectrum

    assert solar_spectrum(SimpleNamespace(solar_spectrum="tsis1")) == "tsis1"
    assert solar_spectrum(SimpleNamespace(solar_spectrum="6s")) == "radscene"
    from radscene.atmosphere.lowtran import LowtranAtmosphere

    assert solar_spectrum(LowtranAtmosphere) == "lowtran"  # the sun that lights its sky
    assert solar_spectrum(SimpleNamespace()) == "radscene"  # engines without a spectrum


#: LOWTRAN7's extraterrestrial band irradiances [W m-2] of the two short-wave infrared bands
#: of tests/validation/lowtran_closure_references.py ('toa_band_irradiance'), where the
#: spectra part: radscene's is 1.4 % and 11.8 % above LOWTRAN's.
LOWTRAN_SWIR_BANDS = {(6210.0, 6290.0): 5.029813, (4525.0, 4565.0): 1.42518}


def test_lowtran_table_is_lowtrans_own_sun():
    path = resources.files("radscene") / "data" / "solar" / "lowtran7_5cm1.csv"
    text = path.read_text(encoding="utf-8")
    for needle in ("AFGL-TR-88-0177", "SUNRAD", "build_lowtran_solar_spectrum.py", "IDAY 0"):
        assert needle in text, needle
    wl, e = toa_solar_spectrum("lowtran")
    assert wl.size == 7901 and wl[0] == 0.25 and wl[-1] == 20.0
    assert 1e4 / wl == pytest.approx(np.arange(40000.0, 499.0, -5.0), abs=1e-4)  # its 5 cm-1 grid
    assert solar_constant("lowtran") == pytest.approx(1370.68, abs=0.01)
    for (nu_lo, nu_hi), band in (LOWTRAN_BANDS | LOWTRAN_SWIR_BANDS).items():
        lo, hi = 1e4 / nu_hi, 1e4 / nu_lo
        # the same samples as LOWTRAN's band sum: equal to its single precision
        assert _band_mean(lo, hi, "lowtran") * (hi - lo) == pytest.approx(band, rel=2e-4)
    ratio = _band_mean(2.1906, 2.2099, "radscene") / _band_mean(2.1906, 2.2099, "lowtran")
    assert ratio == pytest.approx(1.118, abs=0.002)


def test_lowtran_spectrum_is_the_lowtran_engines_alone():
    from radscene.atmosphere.database import DatabaseAtmosphere

    assert ENGINE_SPECTRA["lowtran"] == ("lowtran",)
    with pytest.raises(ConfigError, match="^atmosphere.solar_spectrum: unknown value 'lowtran'"):
        DatabaseAtmosphere(solar_spectrum="lowtran")
