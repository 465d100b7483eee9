"""Tests of radscene.sensor.srf_library: bundled real SRFs, their sources, user files."""

from importlib import resources

import numpy as np
import pytest

from radscene.errors import ConfigError
from radscene.radiometry.planck import spectral_radiance
from radscene.radiometry.srf import TabulatedResponse
from radscene.sensor.srf_library import (
    get_band,
    get_sensor_bands,
    library_response,
    list_sensors,
    read_srf_table,
    resolve_responses,
    sensor_info,
)

CENTRE_NM = 1.5e-3  # [um]: centroid vs published centre wavelength
REQUIRED = ["landsat8_oli", "landsat8_tirs", "landsat9_oli", "landsat9_tirs", "sentinel2a_msi",
            "sentinel2b_msi", "terra_modis", "aqua_modis"]


def test_required_sensors_are_bundled_with_their_sources():
    sensors = list_sensors()
    assert set(REQUIRED) <= set(sensors)
    for name in sensors:
        info = sensor_info(name)
        assert info["source"] and info["via"] and info["title"]
        assert info["kind"] in ("measured", "band model"), name
        if info["kind"] == "measured":
            assert any(route in info["via"] for route in ("Py6S", "pyrsr", "eradiate-data"))
        else:
            assert "not a measured response" in info["shape"]


@pytest.mark.parametrize("sensor", list_sensors())
def test_every_bundled_band_is_a_valid_response(sensor):
    bands = get_sensor_bands(sensor)
    assert [name for name, _ in bands] == list(sensor_info(sensor)["bands"])
    for name, response in bands:
        assert isinstance(response, TabulatedResponse)
        assert response.name == f"{sensor} {name}"
        assert np.all(response.response >= 0.0)
        assert 0.5 <= response.response.max() <= 1.01  # relative responses peak near 1
        assert response.equivalent_width() > 0.0
        lo, hi = response.support
        assert 0.3 < lo < response.center < hi < 16.0  # SEVIRI IR13.4 reaches 15.0 um


# Published centre wavelengths [um]. OLI: Barsi et al. (2014), Remote Sens. 6, 10232, Table 3
# (FWHM centres); Sentinel-2A: ESA S2 MSI spectral response document, central wavelengths;
# TIRS: USGS Landsat 8 Data Users Handbook (10.9 and 12.0 um).
@pytest.mark.parametrize(("sensor", "centres", "tol"), [
    ("landsat8_oli", {"B1": 0.4430, "B2": 0.4826, "B3": 0.5613, "B4": 0.6546, "B5": 0.8646,
                      "B6": 1.6090, "B7": 2.2010, "B9": 1.3730}, 3e-3),
    ("sentinel2a_msi", {"B1": 0.4427, "B2": 0.4924, "B3": 0.5598, "B4": 0.6646, "B5": 0.7041,
                        "B6": 0.7405, "B7": 0.7828, "B8": 0.8328, "B8A": 0.8647,
                        "B9": 0.9451, "B10": 1.3735, "B11": 1.6137, "B12": 2.2024}, CENTRE_NM),
    ("landsat8_tirs", {"B10": 10.9, "B11": 12.0}, 0.01),
])
def test_centres_match_the_published_ones(sensor, centres, tol):
    bands = dict(get_sensor_bands(sensor, list(centres)))
    for name, centre in centres.items():
        assert bands[name].center == pytest.approx(centre, abs=tol), name


# MODIS band ranges [um] of the instrument specification (NASA MODIS web site, "Specifications").
MODIS_RANGES = {"B1": (0.620, 0.670), "B2": (0.841, 0.876), "B3": (0.459, 0.479),
                "B4": (0.545, 0.565), "B5": (1.230, 1.250), "B6": (1.628, 1.652),
                "B7": (2.105, 2.155), "B8": (0.405, 0.420), "B9": (0.438, 0.448)}


@pytest.mark.parametrize("sensor", ["terra_modis", "aqua_modis"])
def test_modis_centroids_lie_in_the_specified_ranges(sensor):
    for name, (lo, hi) in MODIS_RANGES.items():
        c = get_band(sensor, name).center
        assert lo - 0.002 <= c <= hi + 0.002, (name, c)


@pytest.mark.parametrize(("band", "k1", "k2"), [("B10", 774.8853, 1321.0789),
                                                ("B11", 480.8883, 1201.1442)])
def test_tirs_band_radiance_matches_the_usgs_calibration_constants(band, k1, k2):
    """USGS publishes L = K1 / (exp(K2 / T) - 1) [W m-2 sr-1 um-1] for the band-averaged
    radiance of TIRS (Landsat 8 Data Users Handbook, K1_CONSTANT_BAND_10 etc.); a two-parameter
    fit, good to ~0.3 % over 240-330 K."""
    response = get_band("landsat8_tirs", band)
    temperature = np.array([240.0, 270.0, 300.0, 330.0])
    mean = response.integrate_function(
        lambda wl: spectral_radiance(wl, temperature[:, None])) / response.equivalent_width()
    assert mean == pytest.approx(k1 / np.expm1(k2 / temperature), rel=4e-3)


def test_bundled_tables_are_the_py6s_numbers():
    py6s = pytest.importorskip("Py6S", reason="Py6S is needed only to rebuild the library")
    _, start, _, values = py6s.PredefinedWavelengths.LANDSAT_OLI_B5
    response = get_band("landsat8_oli", "B5")
    wl = start + 0.0025 * np.arange(values.size)
    assert response(wl) == pytest.approx(np.clip(values, 0, None), abs=1e-6)
    _, start, _, values = py6s.PredefinedWavelengths.S2B_MSI_8A
    wl = start + 0.0025 * np.arange(values.size)
    assert get_band("sentinel2b_msi", "b8a")(wl) == pytest.approx(np.clip(values, 0, None),
                                                                  abs=1e-6)


# Published centre wavelengths [um] of the imagers bundled as band models. ABI: Schmit et al.
# (2017), BAMS 98, 681-698; AVHRR/3: the middle of the channel limits of the NOAA KLM User's
# Guide, section 3.1 (it gives no centres); AHI: the middle of JMA's band limits (module
# docstring of scripts/build_srf_library.py; the nominal wavelengths are checked below).
BAND_MODEL_CENTRES = {
    "goes16_abi": {"B7": 3.90, "B8": 6.185, "B9": 6.95, "B10": 7.34, "B11": 8.50, "B12": 9.61,
                   "B13": 10.35, "B14": 11.20, "B15": 12.30, "B16": 13.30},
    "himawari_ahi": {"B01": 0.455, "B02": 0.51, "B03": 0.645, "B04": 0.86, "B05": 1.61,
                     "B06": 2.26, "B07": 3.85, "B08": 6.245, "B09": 6.95, "B10": 7.345,
                     "B11": 8.60, "B12": 9.63, "B13": 10.45, "B14": 11.20, "B15": 12.35,
                     "B16": 13.30},
    "avhrr3": {"3B": 3.74, "4": 10.80, "5": 12.00},
}
# Nominal central wavelengths of AHI [um]: JMA, Himawari Standard Data User's Guide v1.3,
# Table 1.
AHI_NOMINAL = {"B01": 0.47, "B02": 0.51, "B03": 0.64, "B04": 0.86, "B05": 1.6, "B06": 2.3,
               "B07": 3.9, "B08": 6.2, "B09": 6.9, "B10": 7.3, "B11": 8.6, "B12": 9.6,
               "B13": 10.4, "B14": 11.2, "B15": 12.4, "B16": 13.3}
# Published centre wavelengths [um] of the thermal imagers bundled as measured responses, and
# how far the measured centroids lie from them. SEVIRI: Schmetz et al. (2002), BAMS 83, 977-992,
# Table 1 (lambda_cen; measured within 0.06 um); VIIRS: the design centres of Cao et al. (2014),
# IEEE TGRS 52, 1142-1156, Table I (NOAA-20's measured centroids within 0.05 um, M16 0.14 um
# short of its design centre); AVHRR/3: the middle of the KLM channel limits (within 0.06 um).
MEASURED_THERMAL = {
    "meteosat11_seviri": ({"IR3.9": 3.92, "WV6.2": 6.25, "WV7.3": 7.35, "IR8.7": 8.70,
                           "IR9.7": 9.66, "IR10.8": 10.80, "IR12.0": 12.00, "IR13.4": 13.40},
                          0.06),
    "noaa20_viirs": ({"M12": 3.70, "M13": 4.05, "M14": 8.55, "M15": 10.763, "M16": 12.013,
                      "I4": 3.74, "I5": 11.45}, 0.15),
    "metopb_avhrr3": ({"3B": 3.74, "4": 10.80, "5": 12.00}, 0.06),
}


@pytest.mark.parametrize("sensor", sorted(MEASURED_THERMAL))
def test_measured_thermal_imagers_carry_their_source_and_published_centres(sensor):
    """The measured thermal responses name the agency table and the route; each band's
    centroid lies near the published centre, and its equivalent width near the band model's
    it replaced (the published width): within 35 %."""
    centres, tol = MEASURED_THERMAL[sensor]
    info = sensor_info(sensor)
    assert info["kind"] == "measured" and "band model" not in info["title"]
    assert "eradiate-data" in info["via"] and "raw data url" in info["via"]
    assert info["edits"] and "within 0.001 of the peak" in info["edits"][0]
    bands = dict(get_sensor_bands(sensor))
    assert list(bands) == list(centres)
    for name, centre in centres.items():
        response = bands[name]
        assert response.center == pytest.approx(centre, abs=tol), name
        assert response.response.max() == pytest.approx(1.0, abs=1e-6)
        # the ends were trimmed near the out-of-band floor (1e-3 of the peak, or the table's
        # own end)
        assert max(response.response[0], response.response[-1]) < 5e-3, name
    text = (resources.files("radscene") / "data" / "srf" / f"{sensor}.csv").read_text(
        encoding="utf-8")
    assert "# source: " in text and "# via: " in text and "BAND MODEL" not in text


@pytest.mark.parametrize(("sensor", "band", "lo", "hi"), [
    ("noaa20_viirs", "M15", 10.263, 11.263), ("noaa20_viirs", "I5", 10.50, 12.40),
    ("metopb_avhrr3", "4", 10.30, 11.30), ("metopb_avhrr3", "5", 11.50, 12.50)])
def test_measured_widths_agree_with_the_published_band_limits(sensor, band, lo, hi):
    response = get_band(sensor, band)
    assert response.equivalent_width() == pytest.approx(hi - lo, rel=0.35)
    # a 300 K scene: the band-mean radiance of the measured response and of a box over the
    # published limits agree to a few per cent in these windows
    wl = np.linspace(*response.support, 4001)
    measured = np.trapezoid(response(wl) * spectral_radiance(wl, 300.0), wl) / np.trapezoid(
        response(wl), wl)
    box = np.linspace(lo, hi, 4001)
    nominal = np.trapezoid(spectral_radiance(box, 300.0), box) / (hi - lo)
    assert measured == pytest.approx(nominal, rel=0.05)


# SEVIRI's lambda_min, lambda_max (Schmetz et al. 2002, Table 1) bound each channel's extent;
# the measured responses are about half as wide (IR10.8: equivalent width 1.05 um in 9.8-11.8)
# and lie within those bounds: at least 95 % of each response's integral falls inside.
@pytest.mark.parametrize(("band", "lo", "hi"), [
    ("IR3.9", 3.48, 4.36), ("WV6.2", 5.35, 7.15), ("WV7.3", 6.85, 7.85), ("IR8.7", 8.30, 9.10),
    ("IR9.7", 9.38, 9.94), ("IR10.8", 9.80, 11.80), ("IR12.0", 11.00, 13.00),
    ("IR13.4", 12.40, 14.40)])
def test_seviri_responses_lie_within_the_published_channel_bounds(band, lo, hi):
    response = get_band("meteosat11_seviri", band)
    wl = np.linspace(*response.support, 20_001)
    inside = (wl >= lo) & (wl <= hi)
    share = np.trapezoid(response(wl) * inside, wl) / np.trapezoid(response(wl), wl)
    assert share > 0.95, band
    assert 0.3 * (hi - lo) < response.equivalent_width() < 0.9 * (hi - lo)


def test_ahi_band_model_cites_jma_and_bessho_and_its_nominal_wavelengths():
    info = sensor_info("himawari_ahi")
    assert "doi:10.2151/jmsj.2016-009" in info["source"] and "JMA" in info["source"]
    for name, nominal in AHI_NOMINAL.items():
        assert f"({nominal:g} um nominal)" in info["bands"][name]["common_name"], name
        centre = get_band("himawari_ahi", name).center  # the middle of the limits
        assert centre == pytest.approx(nominal, abs=0.05 + 1e-9), name
BAND_MODEL_CENTRE = 5e-3  # [um]: the stated tolerance of a band model's centroid


@pytest.mark.parametrize("sensor", sorted(BAND_MODEL_CENTRES))
def test_thermal_band_models_are_marked_normalised_and_centred(sensor):
    """Each band model says it is one, peaks at 1 as the library's responses do, reaches 50 %
    at the band limits it records (so its FWHM and equivalent width are the published width)
    and has its centroid at the published centre."""
    info = sensor_info(sensor)
    assert info["kind"] == "band model"
    assert "band model" in info["title"]
    bands = dict(get_sensor_bands(sensor))
    assert list(bands) == list(BAND_MODEL_CENTRES[sensor])
    for name, centre in BAND_MODEL_CENTRES[sensor].items():
        response = bands[name]
        lo, hi = info["bands"][name]["band_limits_um"]
        assert response.response.max() == 1.0
        assert response([lo, hi]) == pytest.approx([0.5, 0.5], abs=1e-9)
        assert response.equivalent_width() == pytest.approx(hi - lo, rel=1e-9)
        assert response.center == pytest.approx(centre, abs=BAND_MODEL_CENTRE), name
        assert info["bands"][name]["center_um"] == pytest.approx(centre, abs=BAND_MODEL_CENTRE)


def test_band_model_files_say_they_are_models():
    from importlib import resources

    for sensor in BAND_MODEL_CENTRES:
        text = (resources.files("radscene") / "data" / "srf" / f"{sensor}.csv").read_text(
            encoding="utf-8")
        assert "# BAND MODEL, NOT A MEASURED RESPONSE" in text
        assert "# source: " in text


def test_selection_order_and_errors():
    names = [n for n, _ in get_sensor_bands("LANDSAT8_OLI", ["b5", "B4"])]
    assert names == ["B5", "B4"]
    with pytest.raises(ConfigError, match="sensor: unknown sensor 'landsat99'; known: .*"
                                          "landsat8_oli"):
        get_sensor_bands("landsat99")
    with pytest.raises(ConfigError, match="unknown band 'B12'; known: B1, B2"):
        get_band("landsat8_oli", "B12")


# -- user files -------------------------------------------------------------------------------


def test_wide_user_table_in_nm(tmp_path):
    path = tmp_path / "camera.csv"
    path.write_text("# my camera\nwavelength,R,G\n500,0,0\n550,0,1\n600,1,0\n650,0,\n")
    bands = get_sensor_bands(path, wavelength_unit="nm")
    assert [n for n, _ in bands] == ["R", "G"]
    red, green = (r for _, r in bands)
    assert red.equivalent_width() == pytest.approx(0.05, rel=1e-12)  # triangle 0.55-0.65 um
    assert green.support == pytest.approx((0.5, 0.6))
    assert red.name == "camera R"


def test_long_user_table(tmp_path):
    path = tmp_path / "pair.txt"
    path.write_text("band wavelength response\nA 9.0 0\nA 10.0 1\nA 11.0 0\nB 3.0 0\nB 4.0 2\n"
                    "B 5.0 0\n")
    bands = dict(read_srf_table(path, bands=["b", "a"]))
    assert list(bands) == ["B", "A"]
    assert bands["B"].equivalent_width() == pytest.approx(2.0, rel=1e-12)
    assert bands["A"].center == pytest.approx(10.0, rel=1e-12)


@pytest.mark.parametrize(("text", "match"), [
    ("wavelength,Z\n1.0,0\n2.0,0\n", r"\.Z\.response: .*integral of the response must be > 0"),
    ("wavelength,N\n1.0,0.5\n2.0,-0.1\n", r"\.N\.response: .*response must be >= 0"),
    ("wavelength,N\n1.0,0.5\n2.0\n", r"line 3: 1 fields, the header has 2"),
    ("wavelength,N\n1.0,x\n2.0,1\n", r"line 2: every field must be a number"),
    ("# nothing\n", r"no data rows"),
])
def test_bad_user_tables_name_the_file_and_band(tmp_path, text, match):
    path = tmp_path / "bad.csv"
    path.write_text(text)
    with pytest.raises(ConfigError, match=match) as info:
        read_srf_table(path)
    assert str(path) in str(info.value)


# -- library responses in sensor configurations ------------------------------------------------


def test_resolve_library_responses_in_a_sensor_config():
    cfg = {"name": "x", "response": {"sensor": "landsat8_tirs", "band": "B10"},
           "bands": {"red": {"response": {"type": "library", "sensor": "landsat8_oli",
                                          "band": "B4"}},
                     "box": {"response": {"type": "rectangular", "wavelength_min": 1,
                                          "wavelength_max": 2}}}}
    out = resolve_responses(cfg)
    assert isinstance(out["response"], TabulatedResponse)
    assert out["bands"]["red"]["response"].name == "landsat8_oli B4"
    assert out["bands"]["box"]["response"] == cfg["bands"]["box"]["response"]
    assert isinstance(cfg["bands"]["red"]["response"], dict)  # the input is left alone
    with pytest.raises(ConfigError, match=r"sensors\.s\.bands\.red\.response\.sensor "
                                          r"landsat8_oli\.band: unknown band 'B99'"):
        resolve_responses({"bands": {"red": {"response": {"sensor": "landsat8_oli",
                                                          "band": "B99"}}}}, "sensors.s")
    with pytest.raises(ConfigError, match="response: a library response is"):
        library_response({"sensor": "landsat8_oli"})


def test_landsat_like_example_resolves_its_bands():
    from importlib import resources

    import yaml

    path = resources.files("radscene") / "data" / "sensors" / "landsat_like.yaml"
    spec = yaml.safe_load(path.read_text(encoding="utf-8"))
    cfg = resolve_responses(spec["sensor"], "sensor")
    centres = {b: round(v["response"].center, 2) for b, v in cfg["bands"].items()}
    assert centres == {"coastal": 0.44, "blue": 0.48, "green": 0.56, "red": 0.65, "nir": 0.86,
                       "cirrus": 1.37, "swir1": 1.61, "swir2": 2.2, "tir1": 10.9, "tir2": 12.0}
