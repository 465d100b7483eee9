"""Unit tests of the weather that drives the heat balance: radscene.thermal.weather."""

import numpy as np
import pytest

from radscene.errors import ConfigError
from radscene.radiometry.constants import SIGMA
from radscene.thermal import (
    CLEAR_SKY_EMISSIVITY_MODELS,
    CLOUD_EMISSIVITY_MODELS,
    clear_sky_emissivity,
    cloud_diffuse_fraction,
    cloud_shortwave_factor,
    cloudy_sky_emissivity,
    dew_point_to_relative_humidity,
    relative_humidity_to_dew_point,
    saturation_vapour_pressure,
    sky_longwave,
    specific_humidity,
)

T0 = 273.15
#: Saturation vapour pressure over water [Pa] from the IAPWS-95 formulation as tabulated by
#: Wagner & Pruss (2002), J. Phys. Chem. Ref. Data 31, 387, doi:10.1063/1.1461829.
IAPWS_SATURATION = {0.01: 611.657, 20.0: 2339.2, 40.0: 7384.9}
#: Alduchov & Eskridge (1996) state the AERK form within 0.4 % of Wexler's over -40..50 °C.
AERK_ACCURACY = 4e-3


# --- humidity ----------------------------------------------------------------------------


@pytest.mark.parametrize("celsius, expected", sorted(IAPWS_SATURATION.items()))
def test_saturation_vapour_pressure_against_iapws(celsius, expected):
    assert saturation_vapour_pressure(T0 + celsius) == pytest.approx(expected, rel=AERK_ACCURACY)


def test_saturation_vapour_pressure_magnus_constant_at_zero_celsius():
    # the form's prefactor is e_s(0 °C) itself
    assert saturation_vapour_pressure(T0) == pytest.approx(610.94, rel=1e-12)


def test_dew_point_round_trip_and_broadcast():
    t = np.array([[250.0], [290.0], [310.0]])
    rh = np.array([[0.05, 0.4, 1.0]])
    td = relative_humidity_to_dew_point(t, rh)
    assert td.shape == (3, 3)
    np.testing.assert_allclose(dew_point_to_relative_humidity(t, td), np.broadcast_to(rh, (3, 3)), rtol=1e-12)
    np.testing.assert_allclose(td[:, 2], t[:, 0], rtol=1e-12)  # saturated: dew point = air


def test_dew_point_above_air_refused():
    with pytest.raises(ConfigError, match="dew point above the air temperature"):
        dew_point_to_relative_humidity(280.0, 281.0)


def test_relative_humidity_as_percentage_refused():
    with pytest.raises(ConfigError, match=r"\[0, 1\]"):
        relative_humidity_to_dew_point(290.0, 50.0)


def test_specific_humidity_reference_value():
    # 20 °C, 50 %, 1013.25 hPa: e = 1166.7 Pa, q = 0.622 e / (p - 0.378 e) = 7.19 g/kg
    e = 0.5 * saturation_vapour_pressure(T0 + 20)
    assert specific_humidity(T0 + 20, 0.5, 101325.0) == pytest.approx(0.622 * e / (101325.0 - 0.378 * e), rel=1e-12)
    assert specific_humidity(T0 + 20, 0.5, 101325.0) == pytest.approx(7.19e-3, abs=0.01e-3)
    assert specific_humidity(T0 + 20, 0.0, 101325.0) == 0.0
    with pytest.raises(ConfigError, match="pressure"):
        specific_humidity(T0 + 20, 0.5, 0.0)


# --- sky ---------------------------------------------------------------------------------


def test_brutsaert_at_20_celsius_and_half_humidity():
    # e = 0.5 * 2333.44 Pa = 11.667 hPa; 1.24 (11.667 / 293.15)^(1/7) = 0.7824
    assert clear_sky_emissivity(T0 + 20, 0.5, "brutsaert") == pytest.approx(0.7824, abs=1e-4)
    # the kPa form of the same formula, 1.723 (e/T)^(1/7)
    e_kpa = 0.5 * saturation_vapour_pressure(T0 + 20) / 1000
    assert clear_sky_emissivity(T0 + 20, 0.5) == pytest.approx(1.723 * (e_kpa / (T0 + 20)) ** (1 / 7), rel=1e-3)


def test_prata_at_20_celsius_and_half_humidity():
    # w = 46.5 * 11.667 / 293.15 = 1.851 g cm-2; 1 - 2.851 exp(-sqrt(6.553)) = 0.7879
    assert clear_sky_emissivity(T0 + 20, 0.5, "Prata") == pytest.approx(0.7879, abs=1e-4)


def test_clear_sky_models_agree_where_both_were_fitted():
    # two independent derivations: within 0.01 in warm humid air, Brutsaert up to 0.09 lower
    # in cold dry air (0 °C, 30 %), where Prata's w-based form stays higher
    t, rh = np.meshgrid(T0 + np.array([0.0, 10, 20, 30]), [0.3, 0.6, 0.9])
    b = clear_sky_emissivity(t, rh, "brutsaert")
    p = clear_sky_emissivity(t, rh, "prata")
    assert np.all(np.abs(b - p) < 0.1)
    assert np.all(np.abs(b - p)[1:, 2:] < 0.015)
    assert np.all((b > 0.6) & (b < 1.0))


@pytest.mark.parametrize("model", sorted(CLEAR_SKY_EMISSIVITY_MODELS))
def test_clear_sky_emissivity_grows_with_humidity(model):
    eps = clear_sky_emissivity(T0 + 15, np.linspace(0.1, 1, 10), model)
    assert np.all(np.diff(eps) > 0)


@pytest.mark.parametrize("model", sorted(CLOUD_EMISSIVITY_MODELS))
def test_cloud_raises_emissivity_monotonically(model):
    n = np.linspace(0, 1, 11)
    eps = cloudy_sky_emissivity(0.75, n, model)
    assert eps[0] == pytest.approx(0.75, rel=1e-12)
    assert np.all(np.diff(eps) > 0)
    assert eps[-1] <= 1.0


def test_cloud_models_reference_values():
    assert cloudy_sky_emissivity(0.75, 1.0, "crawford_duchon") == pytest.approx(1.0, rel=1e-12)
    assert cloudy_sky_emissivity(0.75, 1.0, "unsworth_monteith") == pytest.approx(0.16 * 0.75 + 0.84, rel=1e-12)


def test_sky_longwave_is_emissivity_times_sigma_t4():
    t = T0 + 20
    assert sky_longwave(t, 0.5, 0.0) == pytest.approx(0.7824 * SIGMA * t**4, rel=2e-4)
    assert sky_longwave(t, 0.5, 1.0) == pytest.approx(SIGMA * t**4, rel=1e-12)  # black overcast
    out = sky_longwave(np.full((2, 3), t), 0.5, np.array([0.0, 0.5, 1.0]))
    assert out.shape == (2, 3)


def test_unknown_models_list_the_known_ones():
    with pytest.raises(ConfigError, match="known: brutsaert, prata"):
        clear_sky_emissivity(290.0, 0.5, "swinbank")
    with pytest.raises(ConfigError, match="known: crawford_duchon, unsworth_monteith"):
        cloudy_sky_emissivity(0.8, 0.5, "tva")


def test_kasten_czeplak_published_figures():
    # G(N)/G(0) = 1 - 0.75 N^3.4: 1 for clear sky, 0.25 overcast; D/G = 0.3 + 0.7 N^2
    assert cloud_shortwave_factor(0.0) == 1.0
    assert cloud_shortwave_factor(1.0) == pytest.approx(0.25, rel=1e-12)
    assert cloud_shortwave_factor(0.5) == pytest.approx(1 - 0.75 * 0.5**3.4, rel=1e-12)
    assert cloud_diffuse_fraction(0.0) == pytest.approx(0.3, rel=1e-12)
    assert cloud_diffuse_fraction(1.0) == pytest.approx(1.0, rel=1e-12)


@pytest.mark.parametrize("bad", [-0.1, 1.5, 80.0, np.nan])
def test_cloud_cover_out_of_range_refused(bad):
    with pytest.raises(ConfigError, match="cloud_cover"):
        cloud_shortwave_factor(bad)
