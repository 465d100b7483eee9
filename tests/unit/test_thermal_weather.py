"""Unit tests of the weather that drives the heat balance: radscene.thermal.weather."""

import numpy as np
import pytest

from radscene.errors import ConfigError
from radscene.radiometry.constants import SIGMA
from radscene.thermal import (
    CLEAR_SKY_EMISSIVITY_MODELS,
    CLOUD_EMISSIVITY_MODELS,
    PARTON_LOGAN_AIR_150CM,
    WeatherSeries,
    clear_sky_emissivity,
    cloud_diffuse_fraction,
    cloud_shortwave_factor,
    cloudy_sky_emissivity,
    dew_point_to_relative_humidity,
    diurnal_weather,
    read_weather,
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


# --- WeatherSeries: interpolation in time ---------------------------------------------------


def _series(**extra):
    time = np.array(["2024-06-21T00:00", "2024-06-21T01:00", "2024-06-21T03:00"], "datetime64[ns]")
    values = dict(
        air_temperature=[280.0, 290.0, 284.0],
        relative_humidity=[0.9, 0.5, 0.7],
        wind_speed=[1.0, 3.0, 2.0],
        cloud_cover=[0.0, 0.5, 1.0],
        pressure=[101000.0, 101200.0, 100800.0],
    )
    values.update(extra)
    return WeatherSeries(time, **values, latitude=43.0, longitude=-77.0, source="test series")


def test_interpolation_exact_at_samples():
    w = _series()
    got = w.at(w.time)
    for name in ("air_temperature", "relative_humidity", "wind_speed", "cloud_cover", "pressure"):
        np.testing.assert_array_equal(got[name], getattr(w, name))
    assert set(got) == set(w.variables) == {"air_temperature", "relative_humidity", "wind_speed", "cloud_cover", "pressure"}


def test_interpolation_at_midpoints_and_unequal_steps():
    w = _series()
    mid = np.array(["2024-06-21T00:30", "2024-06-21T02:00", "2024-06-21T01:30"], "datetime64[ns]")
    got = w.at(mid)["air_temperature"]
    np.testing.assert_allclose(got, [285.0, 287.0, 288.5], rtol=0, atol=1e-12)


def test_interpolation_accepts_zoned_times_and_keeps_shape():
    w = _series()
    assert float(w.at("2024-06-21T02:30+02:00")["air_temperature"]) == pytest.approx(285.0, abs=1e-12)
    times = np.array([["2024-06-21T00:00", "2024-06-21T03:00"]] * 3, "datetime64[ns]")
    assert w.at(times)["pressure"].shape == (3, 2)


def test_interpolation_refuses_times_outside_the_span():
    w = _series()
    with pytest.raises(ConfigError, match=r"2024-06-21T04:00Z lies outside the weather's span, 2024-06-21T00:00Z to 2024-06-21T03:00Z \(test series\)"):
        w.at(np.datetime64("2024-06-21T04:00"))
    with pytest.raises(ConfigError, match="time zone"):
        w.at("2024-06-21T01:00")  # naive text: local or UTC?


def test_series_refuses_bad_arrays():
    with pytest.raises(ConfigError, match="time repeated at sample 1"):
        WeatherSeries(np.array(["2024-06-21T00:00"] * 2, "datetime64[ns]"), 280.0, 0.5, 1.0, 0.0, 1e5)
    with pytest.raises(ConfigError, match=r"relative_humidity = 50.0 at sample 1 \(2024-06-21T01:00Z\)"):
        _series(relative_humidity=[0.5, 50.0, 0.5])
    with pytest.raises(ConfigError, match="shape"):
        _series(wind_speed=[1.0, 2.0])


def test_measured_longwave_replaces_the_model():
    modelled = _series()
    measured = _series(longwave_down=[300.0, 320.0, 310.0])
    t = np.datetime64("2024-06-21T00:30")
    assert float(measured.sky_longwave(t)) == pytest.approx(310.0, abs=1e-12)
    expected = sky_longwave(285.0, 0.7, 0.25)
    assert float(modelled.sky_longwave(t)) == pytest.approx(float(expected), rel=1e-12)


# --- CSV ---------------------------------------------------------------------------------

CSV_HEADER = "time [UTC],air_temperature [degC],relative_humidity [%],wind_speed [m/s],cloud_cover [%],pressure [hPa]"
CSV_ROWS = [
    "2024-06-21T00:00,15.0,80,2.0,10,1013.0",
    "2024-06-21T01:00,14.0,85,1.5,20,1012.5",
    "2024-06-21T02:00,13.5,90,1.0,30,1012.0",
    "2024-06-21T03:00,13.0,92,1.2,40,1011.0",
]


def _csv(tmp_path, rows=CSV_ROWS, header=CSV_HEADER, place="# latitude: 43.16\n# longitude: -77.61\n", name="site.csv"):
    path = tmp_path / name
    path.write_text(place + header + "\n" + "\n".join(rows) + "\n", encoding="utf-8")
    return path


def test_csv_round_trip_celsius_percent_hectopascal(tmp_path):
    w = read_weather(_csv(tmp_path))
    np.testing.assert_array_equal(w.time, np.array(["2024-06-21T00:00", "2024-06-21T01:00", "2024-06-21T02:00", "2024-06-21T03:00"], "datetime64[ns]"))
    np.testing.assert_allclose(w.air_temperature, T0 + np.array([15.0, 14.0, 13.5, 13.0]), rtol=0, atol=1e-12)
    np.testing.assert_allclose(w.relative_humidity, [0.80, 0.85, 0.90, 0.92], rtol=1e-12)
    np.testing.assert_allclose(w.cloud_cover, [0.1, 0.2, 0.3, 0.4], rtol=1e-12)
    np.testing.assert_allclose(w.pressure, [101300.0, 101250.0, 101200.0, 101100.0], rtol=1e-12)
    assert (w.latitude, w.longitude) == (43.16, -77.61)
    assert w.global_shortwave is None and w.source.endswith("site.csv")


def test_csv_other_units_dew_point_zones_and_measured_irradiance(tmp_path):
    header = ("time [UTC+02:00],air_temperature [degF],dew_point [K],wind_speed [knots],cloud_cover [oktas],"
              "pressure [kPa],global_shortwave [W m-2],diffuse_shortwave [W/m2],longwave_down [W m-2]")
    rows = ["2024-06-21T02:00,59,283.15,10,4,101.3,0,0,310",   # local time of the column's zone
            "2024-06-21T01:00Z,50,283.15,0,8,101.3,100,80,330"]  # an offset of its own wins
    w = read_weather(_csv(tmp_path, rows, header))
    np.testing.assert_array_equal(w.time, np.array(["2024-06-21T00:00", "2024-06-21T01:00"], "datetime64[ns]"))
    assert w.air_temperature[0] == pytest.approx(T0 + 15.0, abs=1e-9)
    assert w.relative_humidity[0] == pytest.approx(float(dew_point_to_relative_humidity(T0 + 15, T0 + 10)), rel=1e-12)
    assert w.relative_humidity[1] == pytest.approx(1.0, rel=1e-12)  # dew point = air temperature
    assert w.wind_speed[0] == pytest.approx(10 * 1852 / 3600, rel=1e-12)
    np.testing.assert_allclose(w.cloud_cover, [0.5, 1.0], rtol=1e-12)
    np.testing.assert_allclose(w.longwave_down, [310.0, 330.0], rtol=1e-12)
    assert set(w.at(w.time[0])) >= {"global_shortwave", "diffuse_shortwave", "longwave_down"}


def _bad_csv(tmp_path, lines):
    path = tmp_path / "bad.csv"
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")
    return path


PLACE = ["# latitude: 43.16", "# longitude: -77.61"]


@pytest.mark.parametrize(
    "lines, message",
    [
        (PLACE + [CSV_HEADER, CSV_ROWS[0], "2024-06-21T01:00,14.0,85,,20,1012.5", CSV_ROWS[2]], r"bad.csv: line 5: no wind_speed \(a gap\)"),
        (PLACE + [CSV_HEADER, CSV_ROWS[0], CSV_ROWS[1], "2024-06-21T06:00,13.5,90,1.0,30,1012.0"], r"bad.csv: gap of 5 h between line 5 .* and line 6"),
        (PLACE + [CSV_HEADER, CSV_ROWS[0], CSV_ROWS[2], CSV_ROWS[1], CSV_ROWS[3]], r"bad.csv: line 6: time 2024-06-21T01:00Z is before line 5"),
        (PLACE + [CSV_HEADER, CSV_ROWS[0], CSV_ROWS[1], CSV_ROWS[1], CSV_ROWS[2]], r"bad.csv: line 6: time 2024-06-21T01:00Z repeats the time of line 5"),
        (PLACE + [CSV_HEADER.replace(",cloud_cover [%]", ""), "2024-06-21T00:00,15,80,2,1013", "2024-06-21T01:00,15,80,2,1013"], r"bad.csv: missing column\(s\): cloud_cover"),
        (PLACE + [CSV_HEADER.replace("relative_humidity [%]", "wind_direction [deg]")] + CSV_ROWS, r"bad.csv: line 3: column 3 is none of time, air_temperature"),
        (PLACE + [CSV_HEADER.replace("[degC]", "[m/s]")] + CSV_ROWS, r"bad.csv: column 'air_temperature' has a unit that is not a unit of temperature; accepted: K"),
        (PLACE + [CSV_HEADER.replace(" [hPa]", "")] + CSV_ROWS, r"bad.csv: column 'pressure' has no unit"),
        (PLACE + [CSV_HEADER.replace("[%]", "[1]", 1)] + CSV_ROWS, r"bad.csv: line 4: relative_humidity = 80 0-1 is outside \[0, 1\]; is the unit right"),
        (PLACE + [CSV_HEADER.replace("[degC]", "[K]")] + CSV_ROWS, r"bad.csv: line 4: air_temperature = 15 K is outside the plausible"),
        (PLACE + [CSV_HEADER.replace("[hPa]", "[Pa]")] + CSV_ROWS, r"bad.csv: line 4: pressure = 1013 Pa is outside the plausible"),
        (PLACE + [CSV_HEADER + ",dew_point [degC]"] + [r + ",5" for r in CSV_ROWS], r"bad.csv: give relative_humidity or dew_point, not both"),
        (PLACE + [CSV_HEADER.replace("[UTC]", "")] + CSV_ROWS, r"bad.csv: line 4: the time has no zone"),
        (PLACE + [CSV_HEADER, CSV_ROWS[0], "2024-06-21T01:00,warm,85,1.5,20,1012.5"], r"bad.csv: line 5: the air_temperature is not a number"),
        (PLACE + [CSV_HEADER, CSV_ROWS[0], "2024-06-21T01:00,14,85,1.5,20"], r"bad.csv: line 5: 5 values; the header has 6 columns"),
        (PLACE[1:] + [CSV_HEADER] + CSV_ROWS, r"bad.csv: no '# latitude: \.\.\.' line"),
        (PLACE + [CSV_HEADER], r"bad.csv: no rows of weather"),
    ],
    ids=["empty-value", "time-gap", "unsorted", "duplicated", "missing-column", "unknown-column", "wrong-unit",
         "no-unit", "percent-as-fraction", "celsius-as-kelvin", "hpa-as-pa", "humidity-twice", "naive-time",
         "not-a-number", "short-row", "no-place", "no-rows"],
)
def test_csv_bad_input_one_clear_line(tmp_path, lines, message):
    with pytest.raises(ConfigError, match=message) as info:
        read_weather(_bad_csv(tmp_path, lines))
    assert "\n" not in str(info.value)


def test_csv_max_gap_can_be_widened(tmp_path):
    rows = [CSV_ROWS[0], CSV_ROWS[1], "2024-06-21T06:00,13.5,90,1.0,30,1012.0"]
    with pytest.raises(ConfigError, match="gap of 5 h"):
        read_weather(_csv(tmp_path, rows))
    assert read_weather(_csv(tmp_path, rows), max_gap="6 h").end == np.datetime64("2024-06-21T06:00")


def test_start_after_end_refused(tmp_path):
    with pytest.raises(ConfigError, match=r"site.csv: start .* is after end") as info:
        read_weather(_csv(tmp_path), start="2024-06-21T03:00Z", end="2024-06-21T01:00Z")
    assert info.value.key == "start"


def test_missing_file_and_unknown_suffix(tmp_path):
    with pytest.raises(ConfigError, match="nowhere.csv: no such weather file"):
        read_weather(tmp_path / "nowhere.csv")
    (tmp_path / "site.xlsx").write_bytes(b"")
    with pytest.raises(ConfigError, match=r"site.xlsx: unknown weather file suffix '.xlsx'; known: .csv"):
        read_weather(tmp_path / "site.xlsx")


# --- place and date against the scene's ------------------------------------------------------


def test_summer_file_refused_for_a_winter_scene(tmp_path):
    path = _csv(tmp_path)
    with pytest.raises(ConfigError, match=r"site.csv: covers 2024-06-21T00:00Z to 2024-06-21T03:00Z; the scene needs 2024-12-21T00:00Z to 2024-12-21T02:00Z"):
        read_weather(path, latitude=43.16, longitude=-77.61, start="2024-12-21T00:00Z", end="2024-12-21T02:00Z")
    with pytest.raises(ConfigError, match="the scene needs") as info:
        read_weather(path, start="2024-06-21T01:00Z", end="2024-06-21T05:00Z")  # runs past the end
    assert info.value.key == "end"
    assert read_weather(path, start="2024-06-21T00:00Z", end="2024-06-21T03:00Z").covers("2024-06-21T01:00Z")


def test_file_from_another_place_refused(tmp_path):
    path = _csv(tmp_path)
    with pytest.raises(ConfigError, match=r"site.csv: weather at latitude 43.16 deg, the scene at -33.9 deg: 77.06 deg apart"):
        read_weather(path, latitude=-33.9, longitude=18.4)
    with pytest.raises(ConfigError, match="longitude"):
        read_weather(path, latitude=43.16, longitude=-75.0)
    assert read_weather(path, latitude=43.5, longitude=-78.2, tolerance_deg=1.0).latitude == 43.16


def test_place_check_wraps_the_antimeridian(tmp_path):
    path = _csv(tmp_path, place="# latitude: -17.7\n# longitude: 179.9\n")
    assert read_weather(path, latitude=-17.7, longitude=-179.8).longitude == 179.9


# --- NetCDF ------------------------------------------------------------------------------


def _netcdf_dataset():
    import xarray as xr

    time = np.array(["2024-06-21T00:00", "2024-06-21T00:30", "2024-06-21T01:00", "2024-06-21T01:30"], "datetime64[ns]")
    return xr.Dataset(
        {
            "air_temperature": ("time", [15.0, 14.5, 14.0, 13.8], {"units": "degC"}),
            "relative_humidity": ("time", [80.0, 82.0, 85.0, 86.0], {"units": "%"}),
            "wind_speed": ("time", [2.0, 1.8, 1.5, 1.5], {"units": "m s-1"}),
            "cloud_cover": ("time", [0.1, 0.1, 0.2, 0.2], {"units": "1"}),
            "pressure": ("time", [1013.0, 1012.8, 1012.5, 1012.4], {"units": "hPa"}),
        },
        coords={"time": time},
        attrs={"latitude": 43.16, "longitude": -77.61},
    )


def test_netcdf_round_trip(tmp_path):
    path = tmp_path / "site.nc"
    _netcdf_dataset().to_netcdf(path, engine="h5netcdf")
    w = read_weather(path, latitude=43.16, longitude=-77.61, start="2024-06-21T00:10Z", end="2024-06-21T01:20Z")
    np.testing.assert_array_equal(w.time, _netcdf_dataset()["time"].values)
    np.testing.assert_allclose(w.air_temperature, T0 + np.array([15.0, 14.5, 14.0, 13.8]), rtol=0, atol=1e-12)
    np.testing.assert_allclose(w.relative_humidity, [0.80, 0.82, 0.85, 0.86], rtol=1e-12)
    np.testing.assert_allclose(w.pressure, [101300.0, 101280.0, 101250.0, 101240.0], rtol=1e-12)
    assert (w.latitude, w.longitude) == (43.16, -77.61)


def test_netcdf_by_cf_standard_name_with_dew_point_and_scalar_place(tmp_path):
    ds = _netcdf_dataset().rename({"air_temperature": "t2m", "relative_humidity": "td2m"})
    ds["t2m"].attrs.update(standard_name="air_temperature", units="K")
    ds["t2m"] = ds["t2m"] + T0
    ds["t2m"].attrs.update(standard_name="air_temperature", units="K")
    ds["td2m"] = ("time", [10.0, 10.0, 10.0, 10.0], {"standard_name": "dew_point_temperature", "units": "degree_Celsius"})
    ds = ds.assign_coords(lat=43.16, lon=-77.61)
    ds.attrs = {}
    path = tmp_path / "cf.nc"
    ds.to_netcdf(path, engine="h5netcdf")
    w = read_weather(path)
    assert w.air_temperature[0] == pytest.approx(T0 + 15, abs=1e-9)
    assert w.relative_humidity[0] == pytest.approx(float(dew_point_to_relative_humidity(T0 + 15, T0 + 10)), rel=1e-12)
    assert w.longitude == pytest.approx(-77.61, abs=1e-12)


@pytest.mark.parametrize(
    "edit, message",
    [
        (lambda ds: ds["air_temperature"].values.__setitem__(2, np.nan), r"cf.nc: time index 2: no air_temperature \(a missing value, a gap\)"),
        (lambda ds: ds["pressure"].attrs.pop("units"), r"cf.nc: variable 'pressure' has no unit"),
        (lambda ds: ds.attrs.pop("latitude"), r"cf.nc: no latitude"),
    ],
    ids=["nan-gap", "no-units", "no-place"],
)
def test_netcdf_bad_input(tmp_path, edit, message):
    ds = _netcdf_dataset()
    edit(ds)
    path = tmp_path / "cf.nc"
    ds.to_netcdf(path, engine="h5netcdf")
    with pytest.raises(ConfigError, match=message):
        read_weather(path)


def test_netcdf_unsorted_and_missing_variable(tmp_path):
    ds = _netcdf_dataset()
    path = tmp_path / "cf.nc"
    ds.isel(time=[0, 2, 1, 3]).to_netcdf(path, engine="h5netcdf")
    with pytest.raises(ConfigError, match=r"cf.nc: time index 2: time 2024-06-21T00:30Z is before time index 1"):
        read_weather(path)
    ds.drop_vars("wind_speed").to_netcdf(path, engine="h5netcdf")
    with pytest.raises(ConfigError, match=r"cf.nc: missing column\(s\): wind_speed"):
        read_weather(path)


# --- THERM .wth --------------------------------------------------------------------------

LY_H = 41840.0 / 3600.0  # W m-2 per Langley h-1 (1 cal_th cm-2 h-1)


def _wth_rows(count=193, step=0.25, rh=None, sky=0.70, width=13, direct=None, diffuse=None):
    """A THERM file's entries in its fixed-width layout, numbers running together as in
    published files ("0.00-15.00"): hour, T [°C], p [mbar], RH, T_d [°C], wind, direct and
    diffuse insolation [Ly/h], sky exposure, cloud type, precipitation type, rate and
    temperature (the DIRSIG manual's order); ``width`` 6 stops after the wind speed. ``rh``
    replaces the relative humidity of every entry."""
    hours = np.arange(count) * step
    air = np.round(-10.0 + 5.0 * np.sin(2 * np.pi * (hours - 9.0) / 24.0), 2)
    dew = np.full(count, -16.0)
    if rh is None:
        rh = np.round(dew_point_to_relative_humidity(air + T0, dew + T0), 2)
    rh = np.broadcast_to(rh, hours.shape)
    wind = np.round(3.0 + 0.01 * hours, 2)
    direct = np.zeros(count) if direct is None else direct
    diffuse = np.zeros(count) if diffuse is None else diffuse
    sky = np.broadcast_to(sky, hours.shape)
    lines = []
    for h, t, r, d, u, b, f, s in zip(hours, air, rh, dew, wind, direct, diffuse, sky, strict=True):
        line = f"{h:.2f}{t:6.2f}{1005.0:8.2f}{r:6.2f}{d:6.2f}{u:7.2f}"
        if width == 13:
            line += f"{b:9.2f}{f:9.2f}{s:5.2f}  0  0   0.00  0.00"
        lines.append(line)
    return lines, hours, air, rh, wind


def _wth(tmp_path, lines, header="193 0.250000"):
    path = tmp_path / "winter.wth"
    path.write_text(header + "\n" + "\n".join(lines) + "\n", encoding="ascii")
    return path


WINTER = {"start": "2024-01-15T00:00-05:00", "latitude": 43.16, "longitude": -77.61}


def test_wth_round_trip(tmp_path):
    lines, hours, air, rh, wind = _wth_rows(sky=np.where(np.arange(193) < 96, 0.70, 0.25))
    assert lines[0].startswith("0.00-") and "-16.00" in lines[0]  # numbers run together
    w = read_weather(_wth(tmp_path, lines), **WINTER)
    assert w.start == np.datetime64("2024-01-15T05:00")  # local midnight EST in UTC
    assert w.end - w.start == np.timedelta64(48, "h")
    np.testing.assert_allclose(w.air_temperature, air + T0, rtol=0, atol=1e-9)
    np.testing.assert_allclose(w.relative_humidity, rh, rtol=0, atol=1e-12)
    np.testing.assert_allclose(w.wind_speed, wind, rtol=0, atol=1e-12)
    np.testing.assert_allclose(w.pressure, 100500.0, rtol=1e-12)
    # cloud cover = 1 - sky exposure (field 9)
    np.testing.assert_allclose(w.cloud_cover, np.where(np.arange(193) < 96, 0.30, 0.75), rtol=0, atol=1e-12)
    assert w.global_shortwave is None and w.direct_normal_shortwave is None  # insolation not read undeclared
    assert (w.latitude, w.longitude) == (43.16, -77.61)
    # interpolation between the 15-minute rows
    mid = w.at(np.datetime64("2024-01-15T05:07:30"))["air_temperature"]
    assert float(mid) == pytest.approx(0.5 * (w.air_temperature[0] + w.air_temperature[1]), abs=1e-12)


def test_wth_without_sky_exposure_takes_the_callers_cloud_cover(tmp_path):
    path = _wth(tmp_path, _wth_rows(width=6)[0])
    w = read_weather(path, **WINTER, cloud_cover=0.4)
    np.testing.assert_allclose(w.cloud_cover, 0.4, rtol=1e-12)
    with pytest.raises(ConfigError, match=r"winter.wth: entries of 6 fields carry no sky exposure \(field 9\): give cloud_cover"):
        read_weather(path, **WINTER)
    with pytest.raises(ConfigError, match=r"winter.wth: the file carries its sky exposure \(field 9, cloud cover = 1 - sky exposure\); cloud_cover 0.4"):
        read_weather(_wth(tmp_path, _wth_rows()[0]), **WINTER, cloud_cover=0.4)


def test_wth_needs_date_and_place(tmp_path):
    path = _wth(tmp_path, _wth_rows()[0])
    with pytest.raises(ConfigError, match=r"winter.wth: a THERM .wth file states no date or place; give start, latitude") as info:
        read_weather(path, longitude=-77.61)
    assert info.value.key == "start"
    with pytest.raises(ConfigError, match="hours are local: give start with its zone"):
        read_weather(path, start=np.datetime64("2024-01-15T00:00"), latitude=43.16, longitude=-77.61)
    with pytest.raises(ConfigError, match="time zone"):
        read_weather(path, start="2024-01-15T00:00", latitude=43.16, longitude=-77.61)


def test_wth_scene_beyond_its_48_hours_refused(tmp_path):
    path = _wth(tmp_path, _wth_rows()[0])
    with pytest.raises(ConfigError, match=r"winter.wth: covers 2024-01-15T05:00Z to 2024-01-17T05:00Z; the scene needs"):
        read_weather(path, **WINTER, end="2024-01-18T12:00Z")


@pytest.mark.parametrize(
    "edit, message",
    [
        (lambda lines: ("190 0.25", lines), r"winter.wth: line 1 announces 190 entries; the file has 193"),
        (lambda lines: ("1 0.25", lines[:1]), r"winter.wth: line 1: 1 entries: the step of 0.25 h is longer than the span"),
        (lambda lines: ("193 0", lines), r"winter.wth: line 1: hours between entries must be > 0"),
        (lambda lines: ("193 0.25", lines[:10] + [lines[10].replace("2.50", "2.75", 1)] + lines[11:]), r"winter.wth: line 12: hour 2.75 is out of step; expected 2.5"),
        (lambda lines: ("193 0.25", lines[:10] + [lines[9]] + lines[11:]), r"winter.wth: line 12: hour 2.25 repeats"),
        (lambda lines: ("193 0.25", lines[:5] + ["1.25 -9.00 1005.00  0.50"] + lines[6:]), r"winter.wth: line 7: 4 fields; missing dew point"),
        (lambda lines: ("193 0.25", lines[:5] + [lines[5].replace(" 0.70 ", " x.70 ")] + lines[6:]), r"winter.wth: line 7: not all numbers"),
        (lambda lines: ("193 0.25", lines[:40] + [lines[40].rsplit(" ", 2)[0]] + lines[41:]), r"winter.wth: line 42: 12 fields; the first entry \(line 2\) has 13"),
        (lambda lines: ("193 0.25", _wth_rows(rh=0.99)[0]), r"winter.wth: line \d+: relative humidity 0.99 \(field 4\) and dew point -16 °C"),
        (lambda lines: ("193 0.25", _wth_rows(rh=68.0)[0]), r"winter.wth: line 2: relative humidity 68 outside \[0, 1\]"),
        (lambda lines: ("193 0.25", _wth_rows(sky=np.where(np.arange(193) == 50, 7.0, 0.7))[0]),
         r"winter.wth: line 52: sky exposure 7 \(field 9\) outside \[0, 1\] \(1 clear, 0 overcast\)"),
    ],
    ids=["count", "step-longer-than-span", "zero-step", "out-of-step", "duplicated-hour", "short-row", "not-a-number",
         "another-width", "fields-disagree", "percent", "sky-exposure-in-tenths"],
)
def test_wth_bad_input(tmp_path, edit, message):
    header, lines = edit(_wth_rows()[0])
    path = _wth(tmp_path, lines, header)
    with pytest.raises(ConfigError, match=message):
        read_weather(path, **WINTER)


def _clear_day(count=193, step=0.25):
    """Direct normal and diffuse insolation [Ly/h] of a half-sine day, 06:00 to 18:00 local."""
    local = (np.arange(count) * step) % 24.0
    day = (local > 6.0) & (local < 18.0)
    sine = np.sin(np.pi * np.clip(local - 6.0, 0.0, 12.0) / 12.0)
    direct = np.round(np.where(day, 75.0 * sine**0.3, 0.0), 2)
    diffuse = np.round(np.where(day, 8.0 * sine, 0.0), 2)
    return direct, diffuse


INSOLATION = {7: "direct_normal_shortwave [Ly/h]", 8: "diffuse_shortwave [Ly/h]"}


def test_wth_declared_insolation_is_read_in_langleys(tmp_path):
    direct, diffuse = _clear_day()
    path = _wth(tmp_path, _wth_rows(direct=direct, diffuse=diffuse)[0])
    w = read_weather(path, **WINTER, fields=INSOLATION)
    np.testing.assert_allclose(w.direct_normal_shortwave, direct * LY_H, rtol=1e-12)
    np.testing.assert_allclose(w.diffuse_shortwave, diffuse * LY_H, rtol=1e-12)
    assert float(w.direct_normal_shortwave.max()) == pytest.approx(75.0 * 11.6222, rel=1e-4)  # 872 W m-2
    np.testing.assert_allclose(w.cloud_cover, 0.3, rtol=1e-12)  # still from the sky exposure
    assert w.global_shortwave is None and w.longwave_down is None
    # a declared cloud field replaces the sky exposure
    w = read_weather(path, **WINTER, fields={**INSOLATION, 12: "cloud_cover [tenths]"})
    np.testing.assert_allclose(w.cloud_cover, 0.0, atol=1e-12)


def test_wth_measured_shortwave_drives_the_heat_balance(tmp_path):
    """Declared insolation replaces the modelled short-wave: the solver's beam and diffuse
    irradiance are the file's figures, the beam zero with the sun below the horizon."""
    import radscene
    from radscene.scene import load_scene

    direct, diffuse = _clear_day()
    path = _wth(tmp_path, _wth_rows(direct=direct, diffuse=diffuse, sky=1.0)[0])
    scene = {
        "name": "wth_measured",
        "environment": {"location": {"latitude": 43.16, "longitude": -77.61, "altitude": 150.0},
                        "time": "2024-06-21T13:00:00-04:00",
                        "atmosphere": {"type": "uniform", "transmittance": 0.8}},
        "terrain": {"type": "dem", "elevation": np.zeros((3, 3)).tolist(), "spacing": [2.0, 2.0],
                    "origin": [-2.0, -2.0], "material": "asphalt"},
        "bands": [{"name": "lwir", "min": "8 um", "max": "12 um"}],
        "observers": [{"name": "map", "type": "orthographic", "center": [0.0, 0.0], "altitude": 100.0,
                       "gsd": 1.0, "shape": [2, 2]}],
        "thermal": {"start": "2024-06-21T04:00:00-04:00", "end": "2024-06-21T13:00:00-04:00", "step": "30 min",
                    "hemisphere_samples": 4, "spin_up": False,
                    "weather": {"file": str(path), "start": "2024-06-21T00:00:00-04:00", "fields": INSOLATION}},
    }
    ds = radscene.solve_thermal(load_scene(scene, base_dir=tmp_path))
    local = (ds.time.values - np.datetime64("2024-06-21T04:00")) / np.timedelta64(1, "h")
    file_hours = np.arange(direct.size) * 0.25
    up = ds.sun_zenith.values < 90.0
    assert up.any() and (~up).any()
    np.testing.assert_allclose(ds.diffuse_irradiance.values, np.interp(local, file_hours, diffuse) * LY_H, rtol=1e-9, atol=1e-9)
    np.testing.assert_allclose(ds.direct_irradiance.values[up], np.interp(local, file_hours, direct)[up] * LY_H, rtol=1e-9)
    np.testing.assert_array_equal(ds.direct_irradiance.values[~up], 0.0)


@pytest.mark.parametrize(
    "fields, cloud, message",
    [
        ({5: "global_shortwave [W m-2]"}, None, r"winter.wth: field 5 is read as dew point"),
        ({7: "global_shortwave"}, None, r"winter.wth: field 7: 'global_shortwave' is not 'name \[unit\]'"),
        ({7: "sunshine [h]"}, None, r"winter.wth: field 7: unknown name 'sunshine'; known: global_shortwave"),
        ({7: "direct_normal_shortwave [degC]", 8: "diffuse_shortwave [Ly/h]"}, None, r"winter.wth: field 7 'direct_normal_shortwave' has a unit that is not a unit of irradiance"),
        ({7: "direct_normal_shortwave [Ly/h]"}, None, r"winter.wth: direct_normal_shortwave without diffuse_shortwave"),
        ({8: "diffuse_shortwave [Ly/h]"}, None, r"winter.wth: diffuse_shortwave without global_shortwave or direct_normal_shortwave"),
        ({7: "direct_normal_shortwave [Ly/h]", 10: "global_shortwave [W m-2]", 8: "diffuse_shortwave [Ly/h]"}, None,
         r"winter.wth: both global_shortwave and direct_normal_shortwave"),
        ({10: "cloud_cover [tenths]", 12: "cloud_cover [1]"}, None, r"winter.wth: fields 10 and 12 are both declared cloud_cover"),
        ({"x": "cloud_cover [1]"}, None, r"winter.wth: field number 'x' is not an integer"),
        ({12: "cloud_cover [tenths]"}, 0.2, r"winter.wth: cloud cover is both a declared field and given as 0.2"),
        ({14: "cloud_cover [tenths]"}, None, r"winter.wth: line 2: 13 fields; no field 14 as declared"),
        ({8: "global_shortwave [Ly/h]", 7: "diffuse_shortwave [Ly/h]"}, None,
         r"winter.wth: line 27: diffuse_shortwave \d+\.?\d* W m-2 above global_shortwave \d+\.?\d* W m-2"),
    ],
    ids=["field-1-to-6", "no-unit", "unknown-name", "wrong-unit", "direct-alone", "diffuse-alone", "two-beams", "twice",
         "not-integer", "cloud-twice", "beyond-the-row", "diffuse-above-global"],
)
def test_wth_bad_field_declaration(tmp_path, fields, cloud, message):
    direct, diffuse = _clear_day()
    path = _wth(tmp_path, _wth_rows(direct=direct, diffuse=diffuse)[0])
    with pytest.raises(ConfigError, match=message):
        read_weather(path, **WINTER, cloud_cover=cloud, fields=fields)


def test_fields_are_for_wth_files_and_shortwave_comes_in_pairs(tmp_path):
    with pytest.raises(ConfigError, match=r"site.csv: fields are declared for .wth files"):
        read_weather(_csv(tmp_path), fields={7: "cloud_cover [1]"})
    rows = ["2024-06-21T00:00Z,15,70,2,20,1013,0", "2024-06-21T01:00Z,14,75,2,20,1013,0"]
    header = "time,air_temperature [degC],relative_humidity [%],wind_speed [m/s],cloud_cover [%],pressure [hPa],global_shortwave [W m-2]"
    with pytest.raises(ConfigError, match=r"site.csv: global_shortwave without diffuse_shortwave"):
        read_weather(_csv(tmp_path, rows, header))


# --- diurnal default ---------------------------------------------------------------------


def _events(latitude, longitude, date):
    import datetime as dt

    from radscene.thermal.weather.diurnal import sun_events

    rise, set_ = sun_events(latitude, longitude, [dt.date.fromisoformat(date)])
    return rise[0], set_[0]


@pytest.mark.parametrize("latitude, longitude, date", [(43.16, -77.61, "2024-06-21"), (43.16, -77.61, "2024-12-21"), (-33.9, 18.4, "2024-06-21")])
def test_diurnal_maximum_and_minimum_at_the_stated_times(latitude, longitude, date):
    step = 60.0
    t_min, t_max = T0 + 5.0, T0 + 18.0
    w = diurnal_weather(latitude, longitude, date, t_min=t_min, t_max=t_max, relative_humidity=0.6, wind_speed=2.0, step=step)
    rise, set_ = _events(latitude, longitude, date)
    a, _, c = PARTON_LOGAN_AIR_150CM
    hour = np.timedelta64(3600 * 10**9, "ns")
    expected_max = rise + c * hour + (set_ - rise) / 2 + a * hour  # noon + a + c
    expected_min = rise + c * hour
    i, j = int(np.argmax(w.air_temperature)), int(np.argmin(w.air_temperature))
    assert abs(w.time[i] - expected_max) <= np.timedelta64(int(step), "s")
    assert abs(w.time[j] - expected_min) <= np.timedelta64(int(step), "s")
    # within a step of the extreme, the sine departs from it by (π Δt / (Y + 2a))² / 2 ≲ 2e-5
    assert w.air_temperature[i] == pytest.approx(t_max, abs=1e-3)
    assert w.air_temperature[j] == pytest.approx(t_min, abs=1e-2)
    # continuous: the steepest slopes, π (T_x - T_n)/(Y + 2a) after the minimum and
    # b (T_sn - T_n)/(Z (1 - e^-b)) after sunset, stay below 5 K/h on these days, so no step of a
    # minute changes by 0.1 K; the unscaled night curve would jump 1.4 K at the minimum
    assert np.all(np.abs(np.diff(w.air_temperature)) < 0.1)


def test_diurnal_humidity_at_constant_dew_point():
    w = diurnal_weather(43.16, -77.61, "2024-06-21", t_min="12 degC", t_max="26 degC", relative_humidity=0.55, wind_speed=2.0, days=2)
    dew = relative_humidity_to_dew_point(w.air_temperature, w.relative_humidity)
    np.testing.assert_allclose(dew, dew[0], rtol=0, atol=1e-9)
    assert float(dew_point_to_relative_humidity(T0 + 19.0, dew[0])) == pytest.approx(0.55, rel=1e-12)
    assert w.relative_humidity[np.argmin(w.air_temperature)] == pytest.approx(w.relative_humidity.max(), rel=1e-12)
    assert w.end - w.start == np.timedelta64(2 * 86400, "s")
    np.testing.assert_allclose(w.wind_speed, 2.0, rtol=0)
    assert "Parton & Logan" in w.source


@pytest.mark.parametrize(
    "kwargs, key, message",
    [
        (dict(t_min=T0 + 20, t_max=T0 + 10), "t_max", "must be above t_min"),
        (dict(relative_humidity=0.95), "relative_humidity", "the night would be supersaturated"),
        (dict(relative_humidity=60.0), "relative_humidity", r"\(0, 1\]"),
        (dict(step="2 d"), "step", "longer than the span of 1 day"),
        (dict(days=0), "days", "whole number >= 1"),
        (dict(date="21/06/2024"), "date", "YYYY-MM-DD"),
    ],
)
def test_diurnal_bad_input(kwargs, key, message):
    args = dict(t_min=T0 + 10, t_max=T0 + 24, relative_humidity=0.6, wind_speed=1.0, date="2024-06-21") | kwargs
    date = args.pop("date")
    with pytest.raises(ConfigError, match=message) as info:
        diurnal_weather(43.16, -77.61, date, **args)
    assert info.value.key == key


def test_diurnal_refuses_polar_day():
    with pytest.raises(ConfigError, match="no sunrise or sunset at latitude 80 deg"):
        diurnal_weather(80.0, 15.0, "2024-06-21", t_min=T0, t_max=T0 + 8, relative_humidity=0.5, wind_speed=1.0)


def test_series_is_immutable():
    w = _series()
    with pytest.raises(ValueError, match="read-only"):
        w.air_temperature[0] = 300.0
    with pytest.raises(AttributeError):
        w.source = "elsewhere"


def test_series_measured_shortwave_is_diffuse_with_one_beam():
    t = np.array(["2024-06-21T00:00", "2024-06-21T01:00"], "datetime64[ns]")
    base = dict(air_temperature=290.0, relative_humidity=0.5, wind_speed=2.0, cloud_cover=0.0, pressure=1e5, source="s")
    WeatherSeries(t, **base, direct_normal_shortwave=0.0, diffuse_shortwave=0.0)
    for extra in ({"global_shortwave": 0.0}, {"diffuse_shortwave": 0.0},
                  {"global_shortwave": 0.0, "direct_normal_shortwave": 0.0, "diffuse_shortwave": 0.0}):
        with pytest.raises(ConfigError, match=r"s: measured short-wave is diffuse_shortwave with one of"):
            WeatherSeries(t, **base, **extra)
