"""The bundled Landsat-like overpass, rendered through the command line and checked.

One render of ``examples/landsat_overpass.yaml`` (module fixture): files written, digital
numbers inside the 12-bit ADC range and unsaturated over the land, thermal brightness
temperatures recovered from the DN by a two-point blackbody calibration of the same sensor,
plausible against the scene's surface temperatures and equal to the at-aperture ones, and
per-pixel geolocation around the scene's place.
"""

from __future__ import annotations

import numpy as np
import pytest
import xarray as xr
import yaml
from typer.testing import CliRunner

import radscene
from radscene.cli import app
from radscene.radiometry.planck import band_brightness_temperature, spectral_radiance
from radscene.sensor import load_sensor

EXAMPLE = "landsat_overpass"
BITS = 12
CALIBRATION_K = (270.0, 330.0)  # blackbody references bracketing the scene [K]
RADIANCE_AGREEMENT = 0.005  # DN-derived vs at-aperture band radiance, scene mean (relative)
BT_AGREEMENT_K = 0.2  # the same as brightness temperatures [K]
# Top-of-atmosphere brightness temperatures of a clear summer atmosphere lie a few kelvin below
# the surface temperature in the 11-12 um window (absorption by water vapour, emissivity < 1)
# and never above the hottest surface.
ATMOSPHERE_MARGIN_K = 12.0
LOCATION_DEG = 0.02  # the 2 km window lies within this of the scene origin [deg]


@pytest.fixture(scope="module")
def rendered(tmp_path_factory):
    out = tmp_path_factory.mktemp("landsat")
    result = CliRunner().invoke(app, ["render", str(radscene.example_path(EXAMPLE)),
                                      "-o", str(out)])
    assert result.exit_code == 0, result.output
    with xr.open_dataset(out / "landsat.nc") as ds, \
            xr.open_dataset(out / "landsat_signal.nc") as sig:
        return out, ds.load(), sig.load()


@pytest.fixture(scope="module")
def spec():
    return yaml.safe_load(radscene.example_path(EXAMPLE).read_text(encoding="utf-8"))


def test_the_example_is_listed_and_says_place_and_time(spec):
    result = CliRunner().invoke(app, ["examples"])
    assert result.exit_code == 0 and EXAMPLE in result.output
    assert {"latitude", "longitude"} <= set(spec["environment"]["location"])
    assert spec["environment"]["time"].endswith("Z")
    assert spec["sensors"]["landsat"] == {"example": "landsat_like"}


def test_radiance_signal_and_quicklooks_are_written(rendered, spec):
    out, ds, sig = rendered
    bands = [b["name"] for b in spec["bands"]]
    assert list(ds["band"].values) == bands
    assert list(sig["band"].values) == bands
    for band in bands:
        assert (out / "landsat" / f"{band}.png").is_file()
        assert (out / "landsat_signal" / f"{band}.png").is_file()
    # 192 x 192 samples of 10 m, 3 x 3 per 30 m detector
    assert ds.sizes["y"] == ds.sizes["x"] == 192
    assert sig["dn"].shape == (1, len(bands), 64, 64)
    assert sig.attrs["sensor"] == "landsat_like"
    assert sig.attrs["render_observer_type"] == "pushbroom"


def test_digital_numbers_are_inside_the_adc_range(rendered):
    _, _, sig = rendered
    raw = sig["dn_raw"].values
    assert raw.dtype.kind == "u"
    assert raw.min() >= 0 and raw.max() <= 2**BITS - 1
    # the land fills each band above the dark level and below saturation: the sensor's
    # integration time and full well put the OLI radiance maxima under the ADC's top
    assert not sig["saturated"].values.any()
    for band in sig["band"].values:
        dn = sig["dn"].sel(band=band).values
        assert np.median(dn) > 4, band
        assert dn.max() < 0.9 * (2**BITS - 1), band


def _calibration(sensor, band):
    """Mean DN of uniform blackbody images at the CALIBRATION_K temperatures, and their
    band radiance [W m-2 sr-1]."""
    response = sensor.channel(band).response
    levels = [response.integrate_function(lambda wl, t=t: spectral_radiance(wl, t))
              for t in CALIBRATION_K]
    dns = []
    for i, level in enumerate(levels):
        image = xr.Dataset({"radiance": (("band", "y", "x"), np.full((1, 96, 96), level))},
                           coords={"band": [band]})
        dns.append(float(sensor.apply(image, seed=50 + i)["dn"].values.mean()))
    return np.array(dns), np.array(levels), response


@pytest.mark.parametrize("band", ["tir1", "tir2"])
def test_thermal_brightness_temperature_from_the_dn(rendered, band):
    _, ds, sig = rendered
    dns, levels, response = _calibration(load_sensor("landsat_like"), band)
    dn = sig["dn"].sel(band=band).values[0].astype(float)
    radiance = levels[0] + (dn - dns[0]) * (levels[1] - levels[0]) / (dns[1] - dns[0])
    at_aperture = float(sig["radiance"].sel(band=band).mean())
    # one inversion (it builds a table) for the image, its mean and the at-aperture mean
    temperatures = band_brightness_temperature(
        np.append(radiance.ravel(), [radiance.mean(), at_aperture]), response)
    bt = temperatures[:-2].reshape(radiance.shape)
    surface = ds["surface_temperature"].values
    median = float(np.median(bt))
    assert np.nanmin(surface) - ATMOSPHERE_MARGIN_K < median < np.nanmax(surface)
    # against the mean surface temperature under each detector: the atmosphere and an
    # emissivity below 1 make the window channels read cooler
    cooling = float(np.mean(bt - sig["surface_temperature"].values))
    assert -ATMOSPHERE_MARGIN_K < cooling < 0.0
    # the chain neither loses nor invents heat: the optics blur (100 m detectors) moves the
    # median, not the mean, and the DN give back the mean at-aperture radiance
    assert float(radiance.mean()) == pytest.approx(at_aperture, rel=RADIANCE_AGREEMENT)
    assert temperatures[-2] == pytest.approx(temperatures[-1], abs=BT_AGREEMENT_K)
    # the warm gravel pit reads warmer than the cool reservoir; the hot bare-aluminium roof,
    # of low emissivity, reads far below its 325 K
    ids = sig["object_id"].values
    names = sig["object_id"].attrs["flag_meanings"].split()
    materials = sig["material_id"].attrs["flag_meanings"].split()
    water = sig["material_id"].values == materials.index("water")
    pit, roof = ids == names.index("gravel_pit"), ids == names.index("warehouse")
    assert water.any() and pit.any() and roof.any()
    assert bt[pit].mean() > bt[water].mean() + 5.0
    assert bt[roof].mean() < 325.0 - 10.0


def test_geolocation_is_carried_to_the_detector_grid(rendered, spec):
    _, ds, sig = rendered
    loc = spec["environment"]["location"]
    for data in (ds, sig):
        lat, lon = data["latitude"].values, data["longitude"].values
        assert np.isfinite(lat).all() and np.isfinite(lon).all()
        assert data["latitude"].attrs["units"] == "degrees_north"
        assert np.median(lat) == pytest.approx(loc["latitude"], abs=LOCATION_DEG)
        assert np.median(lon) == pytest.approx(loc["longitude"], abs=LOCATION_DEG)
    # descending (southbound) pass: row 0, the first line, is the northernmost
    lat = sig["latitude"].values
    assert lat[0].mean() > lat[-1].mean()
    # a 30 m detector spans 30 m / 111 km per degree of latitude along the track
    step = np.abs(np.diff(lat[:, 32])).mean() * 111.0e3
    assert step == pytest.approx(30.0, rel=0.05)
