"""radscene.atmosphere.bands (band values of the API's spectra) and radscene.atmosphere.options
(aerosol, gas, date and solar-spectrum options checked against an engine)."""

from __future__ import annotations

import datetime as dt

import numpy as np
import pytest
import xarray as xr

from radscene.atmosphere.bands import (
    THERMAL_BAND_MIN,
    attach_bands,
    band_integral,
    band_responses,
)
from radscene.atmosphere.options import ENGINE_SPECTRA, SOLAR_SPECTRA, check_options, sun_date
from radscene.errors import ConfigError
from radscene.radiometry.planck import spectral_radiance
from radscene.radiometry.srf import GaussianResponse, RectangularResponse, TabulatedResponse

EXACT = 1e-12  # relative: exact integrals up to rounding
FINE = 2e-3  # relative: a 1e-5 um trapezoid against an exact integral of wiggly spectra
rng = np.random.default_rng(7)


def _fine(wl, values, response):
    grid = np.linspace(response.support[0], response.support[1], 200_001)
    return np.trapezoid(response(grid) * np.interp(grid, wl, values), grid)


def test_tabulated_band_integral_is_exact_for_piecewise_linear_spectra():
    wl = np.sort(rng.uniform(0.5, 0.8, 40))
    values = rng.uniform(0.0, 2.0, (3, wl.size))
    tri = TabulatedResponse([0.55, 0.61, 0.64, 0.7], [0.0, 1.0, 0.7, 0.0], name="tri")
    got = band_integral(wl, values, tri)
    assert got.shape == (3,)
    for row, value in zip(values, got, strict=True):
        assert value == pytest.approx(_fine(wl, row, tri), rel=1e-8)
    # a linear spectrum on two samples: ∫ S λ dλ = centroid × width, exactly
    assert band_integral(np.array([0.5, 0.8]), np.array([0.5, 0.8]), tri) == pytest.approx(
        tri.center * tri.equivalent_width(), rel=EXACT)


def test_rectangle_is_the_trapezoid_and_gaussian_uses_its_quadrature():
    wl = np.linspace(8.0, 12.0, 81)
    values = spectral_radiance(wl, 290.0)
    box = RectangularResponse(8.5, 11.5)
    inside = (wl >= 8.5) & (wl <= 11.5)
    assert band_integral(wl, values, box) == pytest.approx(
        np.trapezoid(values[inside], wl[inside]), rel=EXACT)
    gauss = GaussianResponse(10.0, 0.5)  # support ±7 sigma = ±1.49 um
    assert band_integral(wl, values, gauss) == pytest.approx(_fine(wl, values, gauss), rel=1e-6)


def test_band_responses_checks_pairs_and_coverage():
    wl = np.array([0.5, 0.9])
    assert band_responses(None, wl)[0].support == (0.5, 0.9)
    assert band_responses(None, np.array([0.55])) == []
    with pytest.raises(ConfigError, match=r"bands\[0\]: \(0.7, 0.6\) must be increasing"):
        band_responses([(0.7, 0.6)], wl)
    tri = TabulatedResponse([0.45, 0.6, 0.7], [0.0, 1.0, 0.0], name="wide")
    with pytest.raises(ConfigError, match=r"bands\[1\]: band 'wide' spans 0.45-0.7 µm, "
                                          r"beyond the wavelengths 0.5-0.9 µm"):
        band_responses([(0.6, 0.7), tri], wl)


def test_attach_bands_means_and_brightness_temperatures():
    """A 285 K blackbody spectrum reads 285 K in a thermal band (to the grid's linear
    interpolation error) and no temperature in a short-wave band."""
    wl = np.concatenate([np.linspace(0.5, 0.7, 21), np.linspace(10.0, 12.0, 401)])
    ds = xr.Dataset({"apparent_radiance": ("wavelength", spectral_radiance(wl, 285.0),
                                           {"units": "W m-2 sr-1 um-1"}),
                     "transmittance": ("wavelength", np.full(wl.size, 0.8), {"units": "1"})},
                    coords={"wavelength": wl})
    ds = attach_bands(ds, [(0.5, 0.7), (10.5, 11.5)])
    assert list(ds["band_name"].values) == ["0.5-0.7 um", "10.5-11.5 um"]
    assert ds["band_width"].values == pytest.approx([0.2, 1.0], rel=EXACT)
    assert ds["band_transmittance"].values == pytest.approx([0.8, 0.8], rel=EXACT)
    assert ds["band_apparent_radiance"].attrs["units"] == "W m-2 sr-1"
    assert ds["band_mean_apparent_radiance"].values == pytest.approx(
        ds["band_apparent_radiance"].values / [0.2, 1.0], rel=EXACT)
    bt = ds["band_apparent_brightness_temperature"].values
    assert np.isnan(bt[0]) and ds["band_center"].values[1] >= THERMAL_BAND_MIN
    assert bt[1] == pytest.approx(285.0, abs=2e-3)


# -- options ----------------------------------------------------------------------------------
def test_sun_date():
    d, doy, iso = sun_date("2024-07-04")
    assert (doy, iso) == (186, "2024-07-04") and d == pytest.approx(1.0167, abs=1e-4)
    assert sun_date(dt.date(2024, 1, 3))[0] == pytest.approx(0.9833, abs=1e-4)
    for bad in ("2024-02-30", "2024-7-4", "04/07/2024", "", "2024-07-04T12:00"):
        with pytest.raises(ConfigError, match="date: a date YYYY-MM-DD"):
            sun_date(bad)


def test_every_engine_spectrum_is_documented():
    for spectra in ENGINE_SPECTRA.values():
        assert set(spectra) <= set(SOLAR_SPECTRA)
    assert "Gueymard" in SOLAR_SPECTRA["radscene"]


@pytest.mark.parametrize(("engine", "options", "match"), [
    ("sixs", {"aot550": 0.1, "visibility": "10 km"}, "aot550: give visibility or aot550"),
    ("sixs", {"date": "2024-01-01", "earth_sun_distance": 1.0},
     "earth_sun_distance: give date or earth_sun_distance"),
    ("sixs", {"earth_sun_distance": -1.0}, "earth_sun_distance: must be > 0 AU"),
    ("sixs", {"water": float("nan")}, r"water: must lie in \[0, 10\]"),
    ("sixs", {"ozone": 350}, r"ozone: must lie in \[0, 1\] cm-atm"),
    ("lowtran", {"aot550": 0.2}, "aot550: the lowtran engine does not take aot550"),
    ("lowtran", {"earth_sun_distance": 0.99}, "earth_sun_distance: LOWTRAN takes"),
    ("database", {"solar_spectrum": "6S"}, "solar_spectrum: the database engine uses radscene"),
    ("sixs", {"solar_spectrum": "kurucz"}, "solar_spectrum: unknown solar spectrum 'kurucz'"),
])
def test_check_options_refuses(engine, options, match):
    kw = {"visibility": None, "aot550": None, "water": None, "ozone": None, "date": None,
          "earth_sun_distance": None, "solar_spectrum": None, **options}
    with pytest.raises(ConfigError, match=match):
        check_options(engine, **kw)


def test_check_options_settings():
    s = check_options("sixs", None, 0.3, 2.0, 0.3, "2024-07-04", None, "6S")
    assert s["visibility"] is None and s["aot550"] == 0.3 and s["solar_spectrum"] == "6s"
    assert s["day_of_year"] == 186 and s["distance"] == pytest.approx(1.0167, abs=1e-4)
    s = check_options("lowtran", None, None, None, None, None, None, None)
    assert s["visibility"] == 23_000.0 and s["solar_spectrum"] == "lowtran"
    assert s["distance"] == 1.0 and s["date"] is None
