"""``radscene atmosphere los|sky`` with the options 6S and LOWTRAN users give: sensor bands
and response files, the date, the solar spectrum, aerosol and gas amounts, the ground albedo;
and bad input — one line naming the option, exit code 2, nothing written.

Band values are checked against independent computations: the spectral output and the
library's response table integrated on a fine grid (trapezoid), the brightness temperature by
inverting a Planck function written here from the CODATA constants.
"""

from __future__ import annotations

from importlib import resources
from pathlib import Path

import numpy as np
import pytest
import xarray as xr
from scipy import constants
from scipy.optimize import brentq
from typer.testing import CliRunner

from radscene.cli import app
from radscene.sun import toa_solar_irradiance

runner = CliRunner()

FINE = 1e-5  # [um] step of the independent integrations
BAND_REL = 1e-5  # relative agreement of band values with the fine-grid trapezoid
BT_ABS = 0.01  # [K] agreement of brightness temperatures with the independent inversion


def _sixs_or_skip():
    from radscene.atmosphere.sixs_runner import sixs_available

    ok, reason = sixs_available()
    if not ok:
        pytest.skip(f"6S cannot run here: {reason}")


def _invoke(*args):
    return runner.invoke(app, ["atmosphere", *map(str, args)])


def _los(tmp_path, *args, name="los.nc"):
    out = tmp_path / name
    res = _invoke("los", *args, "-o", out)
    assert res.exit_code == 0, res.output
    return xr.open_dataset(out, engine="h5netcdf").load()


def _library_band(sensor, band):
    """(wavelength [um], response) of one band, read from the library's CSV directly."""
    path = resources.files("radscene") / "data" / "srf" / f"{sensor}.csv"
    rows = [line.split(",") for line in path.read_text(encoding="utf-8").splitlines()
            if line and not line.startswith("#") and not line.startswith("band,")]
    data = np.array([(float(w), float(r)) for b, w, r in rows if b == band])
    return data[:, 0], data[:, 1]


def _weighted(srf_wl, srf, wl, values):
    """(∫ S v dλ, ∫ S dλ) on a fine grid, S and v linear between their samples."""
    grid = np.arange(srf_wl[0], srf_wl[-1] + FINE / 2, FINE)
    s = np.interp(grid, srf_wl, srf)
    return np.trapezoid(s * np.interp(grid, wl, values), grid), np.trapezoid(s, grid)


def _planck(wl_um, temperature):
    """Planck spectral radiance [W m-2 sr-1 um-1], from CODATA h, c, k."""
    lam = wl_um * 1e-6
    h, c, k = constants.h, constants.c, constants.k
    return 2 * h * c**2 / lam**5 / np.expm1(h * c / (lam * k * temperature)) * 1e-6


def _inverse_planck(band_radiance, srf_wl, srf):
    grid = np.arange(srf_wl[0], srf_wl[-1] + FINE / 2, FINE)
    s = np.interp(grid, srf_wl, srf)
    return brentq(lambda t: np.trapezoid(s * _planck(grid, t), grid) - band_radiance,
                  100.0, 500.0, xtol=1e-6)


# -- sensor bands, end to end ---------------------------------------------------------------
def test_sixs_landsat8_oli_b4_band_is_the_srf_weighted_mean(tmp_path):
    """``los --engine sixs --sensor landsat8_oli --band B4``: the band radiance is the
    response-weighted integral and mean of the spectral output, and the apparent radiance is
    the coupled one of the ground albedo."""
    _sixs_or_skip()
    ds = _los(tmp_path, "--engine", "sixs", "--sensor", "landsat8_oli", "--band", "B4",
              "--sun-zenith", "35", "--ground-albedo", "0.25")
    wl = ds["wavelength"].values
    srf_wl, srf = _library_band("landsat8_oli", "B4")
    assert wl[0] <= srf_wl[srf > 0][0] and wl[-1] >= srf_wl[srf > 0][-1]
    assert str(ds["band_name"].values[0]) == "landsat8_oli B4"
    for name in ("apparent_radiance", "path_radiance"):
        integral, width = _weighted(srf_wl, srf, wl, ds[name].values)
        assert ds[f"band_{name}"].item() == pytest.approx(integral, rel=BAND_REL)
        assert ds[f"band_mean_{name}"].item() == pytest.approx(integral / width, rel=BAND_REL)
    integral, width = _weighted(srf_wl, srf, wl, ds["transmittance"].values)
    assert ds["band_transmittance"].item() == pytest.approx(integral / width, rel=BAND_REL)
    assert ds["band_width"].item() == pytest.approx(width, rel=BAND_REL)
    # the coupled apparent radiance of a uniform Lambertian ground
    rho = 0.25
    s = ds["spherical_albedo"].values
    e = ds["direct_irradiance"].values + ds["diffuse_irradiance"].values
    t = ds["transmittance"].values + ds["diffuse_transmittance"].values
    expected = ds["path_radiance"].values + rho / (1 - s * rho) * e / np.pi * t
    assert ds["apparent_radiance"].values == pytest.approx(expected, rel=1e-9)
    assert ds.attrs["ground_albedo"] == rho
    assert np.isnan(ds["band_apparent_brightness_temperature"].item())  # a solar band


def test_sixs_apparent_radiance_matches_6s_for_a_lambertian_ground(tmp_path):
    """The coupled apparent radiance at 550 nm (one of 6S's own wavelengths) against 6S's
    apparent radiance of the same uniform Lambertian ground, with 6S's solar spectrum, AOT and
    gas columns given as 6S users give them. 6S applies its gaseous transmittance to the whole
    signal, radscene per path: 0.2 % covers that at 550 nm (the two agree to 0.02 %)."""
    _sixs_or_skip()
    from radscene.atmosphere.sixs_runner import SixSCase, SixSRunner

    ds = _los(tmp_path, "--engine", "sixs", "--wavelength-min", "0.55", "--wavelength-max",
              "0.56", "--step", "0.01", "--sun-zenith", "40", "--ground-albedo", "0.3",
              "--aot550", "0.2", "--water", "2.0", "--ozone", "0.3", "--solar-spectrum", "6s")
    assert ds.attrs["aot550"] == 0.2 and ds.attrs["solar_spectrum"] == "6s"
    assert ds.attrs["water_g_cm-2"] == 2.0 and ds.attrs["ozone_cm-atm"] == 0.3
    assert "visibility_m" not in ds.attrs
    case = SixSCase(wavelength=0.55, profile="user", water=2.0, ozone=0.3, aerosol="rural",
                    aot550=0.2, visibility=None, target_altitude=0.0, sensor="satellite",
                    sun_zenith=40.0, sun_azimuth=0.0, view_zenith=0.0, view_azimuth=0.0,
                    month=4, day=5, ground=("lambertian", 0.3))
    sixs = SixSRunner(workers=1, cache_dir=False).run_one(case)["apparent_radiance"]
    assert ds["apparent_radiance"].sel(wavelength=0.55).item() == pytest.approx(sixs, rel=2e-3)
    # more aerosol: less transmittance, more path radiance
    thick = _los(tmp_path, "--engine", "sixs", "--wavelength-min", "0.55", "--wavelength-max",
                 "0.56", "--step", "0.01", "--sun-zenith", "40", "--aot550", "0.6", "--water",
                 "2.0", "--ozone", "0.3", name="thick.nc")
    assert np.all(thick["transmittance"].values < ds["transmittance"].values)
    assert np.all(thick["path_radiance"].values > 0.9 * ds["path_radiance"].values)


def test_thermal_band_brightness_temperature_inverts_planck(tmp_path):
    """A GOES-16 ABI band 13 model through the database's thermal tables: the band brightness
    temperature is the inverse of the response-weighted Planck integral; over a path of zero
    length a 300 K black ground reads 300 K."""
    srf_wl, srf = _library_band("goes16_abi", "B13")
    ds = _los(tmp_path, "--sensor", "goes16_abi", "--band", "B13", "--zenith", "20",
              "--surface-temperature", "300", "--step", "0.01")
    integral, _ = _weighted(srf_wl, srf, ds["wavelength"].values,
                            ds["apparent_radiance"].values)
    assert ds["band_apparent_radiance"].item() == pytest.approx(integral, rel=BAND_REL)
    bt = ds["band_apparent_brightness_temperature"].item()
    assert bt == pytest.approx(_inverse_planck(integral, srf_wl, srf), abs=BT_ABS)
    assert 280.0 < bt < 300.0  # the atmosphere cools the window a few kelvin
    bt_path = ds["band_path_brightness_temperature"].item()
    path_integral, _ = _weighted(srf_wl, srf, ds["wavelength"].values,
                                 ds["path_radiance"].values)
    assert bt_path == pytest.approx(_inverse_planck(path_integral, srf_wl, srf), abs=BT_ABS)
    none = _los(tmp_path, "--sensor", "goes16_abi", "--band", "B13", "--observer-altitude",
                "0", "--surface-temperature", "300", "--step", "0.01", name="none.nc")
    assert none["band_apparent_brightness_temperature"].item() == pytest.approx(300.0,
                                                                              abs=1e-3)


def test_sky_thermal_band_brightness_temperatures(tmp_path):
    out = tmp_path / "sky.nc"
    res = _invoke("sky", "--zenith", "0,60", "--azimuth", "0,180", "--sensor", "noaa20_viirs",
                  "--band", "M15", "--step", "0.02", "-o", out)
    assert res.exit_code == 0, res.output
    assert "brightness temperature [K]" in " ".join(res.output.split())
    ds = xr.open_dataset(out, engine="h5netcdf").load()
    srf_wl, srf = _library_band("noaa20_viirs", "M15")
    bt = ds["band_sky_brightness_temperature"].values[..., 0]
    for i, j in np.ndindex(bt.shape):
        integral, _ = _weighted(srf_wl, srf, ds["wavelength"].values,
                                ds["sky_radiance"].values[i, j])
        assert bt[i, j] == pytest.approx(_inverse_planck(integral, srf_wl, srf), abs=BT_ABS)
    assert bt[1].mean() > bt[0].mean()  # the sky is warmer towards the horizon


def test_srf_file_bands(tmp_path):
    """``--srf FILE`` (a header, then wavelength, response) in nm, beside a rectangle."""
    srf = tmp_path / "camera.csv"
    srf.write_text("# my camera's red channel\nwavelength,response\n600,0\n640,0.8\n660,1\n"
                   "700,0\n")
    ds = _los(tmp_path, "--srf", srf, "--srf-unit", "nm", "--band", "0.6,0.7",
              "--wavelength-min", "0.55", "--wavelength-max", "0.75")
    assert list(ds["band_name"].values) == ["0.6-0.7 um", "camera"]
    srf_wl, response = np.array([0.6, 0.64, 0.66, 0.7]), np.array([0.0, 0.8, 1.0, 0.0])
    integral, width = _weighted(srf_wl, response, ds["wavelength"].values,
                                ds["apparent_radiance"].values)
    assert ds["band_mean_apparent_radiance"].values[1] == pytest.approx(integral / width,
                                                                        rel=BAND_REL)
    assert ds["band_center"].values[1] == pytest.approx(
        np.trapezoid(response * srf_wl, srf_wl) / np.trapezoid(response, srf_wl), rel=0.02)
    assert ds["band_width"].values[0] == pytest.approx(0.1, rel=1e-12)


def test_a_sensor_without_bands_gives_all_its_bands(tmp_path):
    out = tmp_path / "avhrr.nc"
    res = _invoke("los", "--sensor", "avhrr3", "--surface-temperature", "290", "--step",
                  "0.02", "-o", out)
    assert res.exit_code == 0, res.output
    assert "BT" in res.output and "brightness temperatures [K]" in " ".join(res.output.split())
    ds = xr.open_dataset(out, engine="h5netcdf").load()
    assert list(ds["band_name"].values) == ["avhrr3 3B", "avhrr3 4", "avhrr3 5"]
    assert np.all(np.isfinite(ds["band_apparent_brightness_temperature"].values))


# -- date, solar spectrum, albedos ----------------------------------------------------------
def test_date_sets_the_earth_sun_distance(tmp_path):
    import pandas as pd
    from pvlib.solarposition import nrel_earthsun_distance

    args = ("--wavelength-min", "0.5", "--wavelength-max", "0.6", "--sun-zenith", "30",
            "--ground-albedo", "0.2")
    mean = _los(tmp_path, *args, name="mean.nc")
    july = _los(tmp_path, *args, "--date", "2024-07-04", name="july.nc")
    d = float(np.asarray(nrel_earthsun_distance(
        pd.DatetimeIndex(["2024-07-04 12:00"], tz="UTC")))[0])
    assert july.attrs["earth_sun_distance_au"] == pytest.approx(d, rel=1e-9)
    assert july.attrs["date"] == "2024-07-04" and july.attrs["day_of_year"] == 186
    assert mean.attrs["earth_sun_distance_au"] == 1.0 and "date" not in mean.attrs
    for name in ("direct_solar_irradiance", "path_radiance", "apparent_radiance"):
        assert july[name].values == pytest.approx(mean[name].values / d**2, rel=1e-9), name
    res = _invoke("los", *args, "--date", "2024-07-04")
    assert res.exit_code == 0 and "2024-07-04" in res.output and "1.01672 AU" in res.output


def test_solar_spectrum_6s_with_the_sixs_engine(tmp_path):
    _sixs_or_skip()
    args = ("--engine", "sixs", "--wavelength-min", "0.55", "--wavelength-max", "0.65",
            "--step", "0.05")
    ours = _los(tmp_path, *args, name="ours.nc")
    theirs = _los(tmp_path, *args, "--solar-spectrum", "6s", name="theirs.nc")
    assert ours.attrs["solar_spectrum"] == "radscene"
    assert "Gueymard" in ours.attrs["solar_spectrum_source"]
    assert theirs.attrs["solar_spectrum"] == "6s"
    ratio = theirs["direct_solar_irradiance"].values / ours["direct_solar_irradiance"].values
    assert np.all(np.abs(ratio - 1) < 0.05) and np.any(np.abs(ratio - 1) > 1e-4)
    assert theirs["transmittance"].values == pytest.approx(ours["transmittance"].values,
                                                           rel=1e-12)


def test_solar_spectrum_tsis1_with_the_database_engine(tmp_path):
    args = ("--wavelength-min", "0.45", "--wavelength-max", "0.65", "--step", "0.05")
    ours = _los(tmp_path, *args, name="ours.nc")
    hsrs = _los(tmp_path, *args, "--solar-spectrum", "tsis1", name="hsrs.nc")
    assert hsrs.attrs["solar_spectrum"] == "tsis1"
    assert "Coddington" in hsrs.attrs["solar_spectrum_source"]
    wl = hsrs["wavelength"].values
    ratio = toa_solar_irradiance(wl, spectrum="tsis1") / toa_solar_irradiance(wl)
    for name in ("direct_solar_irradiance", "path_radiance", "apparent_radiance"):
        assert hsrs[name].values / ours[name].values == pytest.approx(ratio, rel=1e-9), name
    res = _invoke("los", *args, "--solar-spectrum", "tsis1")
    assert res.exit_code == 0 and "solar spectrum tsis1" in res.output


def test_ground_albedo_defaults_to_the_surface_albedo(tmp_path):
    args = ("--wavelength-min", "0.6", "--wavelength-max", "0.7", "--surface-albedo", "0.1")
    default = _los(tmp_path, *args, name="default.nc")
    bright = _los(tmp_path, *args, "--ground-albedo", "0.5", name="bright.nc")
    assert default.attrs["ground_albedo"] == 0.1 and bright.attrs["ground_albedo"] == 0.5
    assert np.all(bright["apparent_radiance"].values > default["apparent_radiance"].values)
    assert bright["path_radiance"].values == pytest.approx(default["path_radiance"].values,
                                                           rel=1e-12)


# -- bad input ------------------------------------------------------------------------------
BAD_SRF = {
    "three columns": ("wavelength,response,extra\n0.6,0,1\n0.65,1,1\n0.7,0,1\n",
                      "line 2: not two numeric columns"),
    "text in the data": ("0.6,0\n0.65,high\n0.7,0\n", "line 2: not two numeric columns"),
    "decreasing": ("0.7,0\n0.65,1\n0.6,0\n", "wavelengths must increase; 0.65 follows 0.7"),
    "negative": ("0.6,0\n0.65,1\n0.7,-0.2\n", "responses must be >= 0; got -0.2 at 0.7"),
    "in nm": ("600,0\n650,1\n700,0\n", "are they in nm"),
    "one row": ("0.6,1\n", "at least two rows"),
}

BAD = [
    (["los", "--sensor", "landsat99"], "--sensor: unknown sensor 'landsat99'; known: "
                                       "landsat8_oli"),
    (["los", "--sensor", "landsat8_oli", "--band", "B99"], "--band: unknown band 'B99'; "
                                                           "known: B1, B2"),
    (["sky", "--sensor", "goes16_abi", "--band", "C13"], "--band: unknown band 'C13'; known: B7"),
    (["los", "--band", "B4"], r"--band: 'min,max' in µm \(a band name needs --sensor\)"),
    (["los", "--date", "2024-13-01"], "--date: a date YYYY-MM-DD"),
    (["sky", "--date", "04/07/2024"], "--date: a date YYYY-MM-DD"),
    (["los", "--date", "tomorrow"], "--date: a date YYYY-MM-DD"),
    (["los", "--aot550", "-0.1", "--engine", "sixs"], "--aot550: must be >= 0; got '-0.1'"),
    (["los", "--aot550", "lots"], "--aot550: must be a number"),
    (["los", "--aot550", "0.2", "--visibility", "10km"], "--aot550: give visibility or aot550"),
    (["los", "--water", "25", "--ozone", "0.3", "--engine", "sixs"],
     r"--water: must lie in \[0, 10\] g cm-2"),
    (["sky", "--ozone", "300", "--water", "1", "--engine", "sixs"],
     r"--ozone: must lie in \[0, 1\] cm-atm \(300 DU = 0.3 cm-atm\)"),
    (["los", "--water", "2", "--engine", "sixs"], "--water: give both water"),
    (["los", "--engine", "lowtran", "--aot550", "0.2"], "--aot550: the lowtran engine does not "
                                                        "take aot550"),
    (["los", "--engine", "lowtran", "--water", "0"], r"--water: must lie in \(0, 15\] g cm-2"),
    (["los", "--engine", "lowtran", "--solar-spectrum", "radscene"],
     "--solar-spectrum: the lowtran engine uses lowtran, not radscene"),
    (["los", "--solar-spectrum", "6s"], "--solar-spectrum: the database engine uses radscene or "
                                        "tsis1, not 6s"),
    (["sky", "--solar-spectrum", "kurucz"], "--solar-spectrum: unknown solar spectrum 'kurucz'; "
                                            "known: radscene, tsis1, 6s, lowtran"),
    (["los", "--ground-albedo", "1.5"], r"--ground-albedo: must lie in \[0, 1\]"),
    (["los", "--engine", "sixs", "--sensor", "landsat8_tirs", "--band", "B10"],
     "--sensor landsat8_tirs --band B10: the 'sixs' atmosphere covers 0.25–4 µm; asked for "
     "9–14 µm"),
    (["los", "--sensor", "landsat8_oli", "--band", "B4", "--wavelength-min", "0.4",
      "--wavelength-max", "0.6"], "--sensor landsat8_oli --band B4: band 'landsat8_oli B4' "
                                  "spans .* beyond the wavelengths 0.4-0.6 µm"),
]


def test_lowtran_scales_the_water_vapour_column(tmp_path):
    """``--water`` with the lowtran engine: its model's H2O profile scaled to the column
    (radscene.atmosphere.lowtran.profiles); the 0.94 um band darkens, the record says so."""
    from radscene.atmosphere.lowtran import NOT_BUILT, lowtran_available

    if not lowtran_available():
        pytest.skip(NOT_BUILT)
    args = ("--engine", "lowtran", "--band", "0.9,0.98", "--wavelength-min", "0.9",
            "--wavelength-max", "0.98", "--step", "0.01")
    own, wet = _los(tmp_path, *args, name="own.nc"), _los(tmp_path, *args, "--water", "2.83",
                                                          name="wet.nc")
    assert wet.attrs["water_g_cm-2"] == 2.83 and "water_g_cm-2" not in own.attrs
    assert float(wet["transmittance"].mean()) < float(own["transmittance"].mean()) - 0.03


def _assert_refused(res, match, out):
    import re

    assert res.exit_code == 2, res.output
    message = res.output.strip()
    assert "Traceback" not in message
    assert len(message.splitlines()) == 1, message
    assert re.search(match, message), message
    assert not out.exists()


@pytest.mark.parametrize(("args", "match"), BAD, ids=[" ".join(a) for a, _ in BAD])
def test_bad_options_are_one_line_exit_2_and_write_nothing(tmp_path, args, match):
    out = tmp_path / "out.nc"
    res = _invoke(*args, "-o", out)
    _assert_refused(res, match, out)


@pytest.mark.parametrize("case", sorted(BAD_SRF))
def test_bad_srf_files_are_refused(tmp_path, case):
    text, match = BAD_SRF[case]
    srf = tmp_path / "bad.csv"
    srf.write_text(text)
    out = tmp_path / "out.nc"
    res = _invoke("los", "--srf", srf, "-o", out, "--plot", tmp_path / "out.png")
    _assert_refused(res, f"--srf {srf}: .*{match}", out)
    assert not (tmp_path / "out.png").exists()


def test_a_missing_srf_file_is_refused(tmp_path):
    out = tmp_path / "out.nc"
    res = _invoke("sky", "--srf", tmp_path / "none.csv", "-o", out)
    _assert_refused(res, "--srf .*none.csv: cannot read it", out)


def test_band_models_are_documented_as_such():
    from radscene.sensor.srf_library import sensor_info

    text = Path(resources.files("radscene") / "data" / "srf" / "library.yaml").read_text(
        encoding="utf-8")
    assert "kind: band model" in text
    assert sensor_info("goes16_abi")["kind"] == "band model"
