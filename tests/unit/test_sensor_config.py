"""Sensor configuration: registry, YAML examples, band overrides, geometry, bad input, CLI."""

from __future__ import annotations

import math

import numpy as np
import pytest
import xarray as xr
import yaml
from typer.testing import CliRunner

from radscene.cli.sensor import app
from radscene.errors import ConfigError
from radscene.sensor import (
    DETECTORS,
    SENSOR_TYPES,
    Microbolometer,
    PhotonDetector,
    example_sensor_path,
    example_sensors,
    load_sensor,
    make_sensor,
)
from radscene.sensor.config import read_sensor_file

BASE = {
    "name": "test",
    "oversample": 2,
    "optics": {"focal_length": "50 mm", "f_number": 2.0},
    "detector": {"type": "CCD", "pitch": "10 um", "quantum_efficiency": 0.6,
                 "integration_time": "10 ms", "temperature": "20 degC", "read_noise": 5},
    "electronics": {"gain": 2.0, "bits": 12},
    "bands": {"red": {"response": {"type": "rectangular", "wavelength_min": 0.6,
                                   "wavelength_max": 0.7},
                      "detector": {"quantum_efficiency": 0.4}}},
}


def _radiance(shape=(1, 16, 16), bands=("red",), value=1.0):
    return xr.Dataset({"radiance": (("band", "y", "x"), np.full(shape, value))},
                      coords={"band": list(bands),
                              "wavelength_center": ("band", [0.65] * len(bands)),
                              "equivalent_width": ("band", [0.1] * len(bands))})


def test_make_sensor_and_registries():
    s = make_sensor(BASE)
    assert type(s) is SENSOR_TYPES["staring"]
    assert isinstance(s.base.detector, PhotonDetector)
    assert set(DETECTORS) >= {"photon", "ccd", "cmos", "cooled_ir", "microbolometer"}
    assert s.base.detector.temperature == pytest.approx(293.15)
    assert s.ifov == pytest.approx(math.degrees(2 * math.atan(5e-6 / 0.05)), rel=1e-12)
    assert float(s.ground_sample_distance(1000.0)) == pytest.approx(0.2, rel=1e-12)
    assert make_sensor(s) is s
    assert "F/2" in repr(s)


def test_band_overrides_merge_into_the_base():
    s = make_sensor(BASE)
    red, other = s.channel("red"), s.channel("blue")
    assert red.detector.quantum_efficiency(0.65) == pytest.approx(0.4)
    assert other.detector.quantum_efficiency(0.65) == pytest.approx(0.6)
    assert red.detector.read_noise == 5.0  # the rest of the base stays
    assert red.response is not None and other.response is None


def test_a_band_may_change_the_detector_type():
    cfg = {**BASE, "bands": {"lwir": {
        "response": {"type": "rectangular", "wavelength_min": 8, "wavelength_max": 12},
        "detector": {"type": "microbolometer", "pitch": "10 um", "integration_time": "10 ms"},
        "electronics": {"gain": "1 uV/DN"}}}}
    s = make_sensor(cfg)
    assert isinstance(s.channel("lwir").detector, Microbolometer)
    assert isinstance(s.channel("red").detector, PhotonDetector)
    out = s.apply(_radiance(bands=("red", "lwir"), shape=(2, 16, 16)), seed=0)
    assert out["signal_unit"].values.tolist() == ["e-", "V"]


def test_observer_geometry_puts_oversample_samples_on_a_pitch():
    s = make_sensor({**BASE, "detector": {**BASE["detector"], "shape": [48, 64]}})
    geo = s.observer_geometry()
    assert geo["shape"] == (96, 128)
    assert geo["fov"] == pytest.approx(math.degrees(2 * math.atan(32 * 10e-6 / 0.05)), rel=1e-12)
    assert geo["gsd_per_distance"] == pytest.approx(10e-6 / 0.05 / 2, rel=1e-12)


@pytest.mark.parametrize("name", ["mwir_cooled", "lwir_microbolometer", "landsat_like"])
def test_bundled_examples_load(name):
    assert name in example_sensors()
    s = load_sensor(name)
    assert s.name == name
    assert load_sensor(example_sensor_path(name)).name == name
    kind = {"mwir_cooled": PhotonDetector, "lwir_microbolometer": Microbolometer,
            "landsat_like": PhotonDetector}[name]
    assert isinstance(s.base.detector, kind)
    band = next(iter(s.config["bands"]))
    assert s.channel(band).response is not None


@pytest.mark.parametrize(("patch", "key"), [
    ({"type": "pushbroom_typo"}, "type"),
    ({"colour": "red"}, "colour"),
    ({"oversample": 0}, "oversample"),
    ({"optics": {"focal_length": 0.05, "f_number": 0}}, "optics.f_number"),
    ({"optics": {"focal_length": 0.05, "f_number": -1.4}}, "optics.f_number"),
    ({"detector": {"type": "photomultiplier"}}, "detector.type"),
    ({"electronics": None}, "electronics"),
    ({"motion": {"jitter": "-3 urad"}}, "motion.jitter"),
    ({"scene_weighting": "sunny"}, "scene_weighting"),
    ({"bands": {"red": {"optics": {"f_number": 0}}}}, "bands.red.optics.f_number"),
    ({"bands": {"red": {"response": {"type": "tabulated", "wavelength": [0.6, 0.7],
                                     "response": [0.0, 0.0]}}}}, "bands.red.response"),
    ({"bands": {"red": {"gain": 3}}}, "bands.red.gain"),
])
def test_bad_configuration_names_the_key(patch, key):
    cfg = {**BASE, **patch}
    with pytest.raises(ConfigError, match=key.replace(".", r"\.")) as info:
        make_sensor(cfg)
    assert info.value.key.startswith(key.split(".")[0])


def test_unknown_type_lists_the_registered_ones():
    with pytest.raises(ConfigError, match="known: staring"):
        make_sensor({**BASE, "type": "magic"})
    with pytest.raises(ConfigError, match="microbolometer"):
        make_sensor({**BASE, "detector": {"type": "magic"}})


def test_apply_bad_input_names_the_key():
    s = make_sensor(BASE)
    with pytest.raises(ConfigError, match=r"detector\.pitch"):
        s.apply(_radiance((1, 16, 16)), oversample=32)  # a pitch larger than the image
    with pytest.raises(ConfigError, match="oversample"):
        s.apply(_radiance((1, 15, 16)))
    with pytest.raises(ConfigError, match="frames"):
        s.apply(_radiance(), frames=0)
    with pytest.raises(ConfigError, match="radiance"):
        s.apply(xr.Dataset({"dn": (("y", "x"), np.zeros((4, 4)))}))
    with pytest.raises(ConfigError, match="radiance"):
        s.apply(xr.Dataset({"radiance": (("y", "x"), np.zeros((4, 4)))}))
    shaped = make_sensor({**BASE, "detector": {**BASE["detector"], "shape": [4, 4]}})
    with pytest.raises(ConfigError, match=r"detector\.shape"):
        shaped.apply(_radiance((1, 16, 16)))
    holes = _radiance()
    holes["radiance"][0, 3, 3] = np.nan
    with pytest.raises(ConfigError, match="NaN"):
        s.apply(holes)
    no_coords = xr.Dataset({"radiance": (("band", "y", "x"), np.ones((1, 8, 8)))},
                           coords={"band": ["green"]})
    with pytest.raises(ConfigError, match=r"bands\.green\.response"):
        s.apply(no_coords)


def test_apply_with_explicit_responses_and_a_dataarray():
    s = make_sensor(BASE)
    da = _radiance(bands=("green",))["radiance"]
    out = s.apply(da, responses={"green": {"type": "gaussian", "center": 0.55, "fwhm": 0.04}},
                  seed=1)
    assert out["dn"].dims == ("frame", "band", "y", "x")
    assert out["dn"].shape == (1, 1, 8, 8)


def test_library_responses_come_from_the_bundled_srfs():
    bands = {"red": {"response": {"type": "Library", "sensor": "landsat8_oli", "band": "b4"}},
             "tir": {"response": {"sensor": "landsat8_tirs", "band": "B10"}}}
    s = make_sensor({**BASE, "bands": bands})
    assert s.channel("red").response.name == "landsat8_oli B4"
    assert s.channel("red").response.center == pytest.approx(0.655, abs=0.005)
    assert s.channel("tir").response.name == "landsat8_tirs B10"


@pytest.mark.parametrize(("response", "match"), [
    ({"type": "library", "sensor": "landsat88_oli", "band": "B4"},
     r"bands\.red\.response\.sensor: unknown sensor 'landsat88_oli'; known: landsat8_oli"),
    ({"type": "library", "sensor": "landsat8_oli", "band": "B12"},
     r"bands\.red\.response.*unknown band 'B12'; known: B1, B2"),
    ({"type": "library", "sensor": "landsat8_oli"},
     r"bands\.red\.response: a library response is \{type: library, sensor"),
    ({"type": "library", "sensor": "landsat8_oli", "band": "B4", "colour": "red"},
     r"bands\.red\.response: a library response is"),
    ({"type": "libary", "sensor": "landsat8_oli", "band": "B4"},
     r"bands\.red\.response\.type: unknown spectral response type 'libary'.*or library"),
])
def test_bad_library_response_names_the_key(response, match):
    with pytest.raises(ConfigError, match=match):
        make_sensor({**BASE, "bands": {"red": {"response": response}}})


def test_sensor_file_parts(tmp_path):
    both = tmp_path / "both.yaml"
    both.write_text(yaml.safe_dump({"sensor": BASE, "observer": {"type": "pushbroom"}}))
    parts = read_sensor_file(both)
    assert parts["sensor"]["name"] == "test" and parts["observer"] == {"type": "pushbroom"}
    assert load_sensor(both).name == "test"
    assert read_sensor_file("landsat_like")["observer"]["type"] == "pushbroom"
    assert read_sensor_file("mwir_cooled")["observer"] is None
    extra = tmp_path / "extra.yaml"
    extra.write_text(yaml.safe_dump({"sensor": BASE, "platform": {}}))
    with pytest.raises(ConfigError, match=r"extra\.yaml: unknown part\(s\) platform beside "
                                          r"'sensor'; accepted: sensor, observer"):
        load_sensor(extra)
    bad = tmp_path / "bad_band.yaml"
    bad.write_text(yaml.safe_dump({"sensor": {**BASE, "bands": {"red": {"response": {
        "type": "library", "sensor": "landsat8_oli", "band": "B0"}}}}}))
    with pytest.raises(ConfigError, match=r"unknown band 'B0'.*\(sensor file .*bad_band\.yaml\)"):
        load_sensor(bad)
    with pytest.raises(ConfigError, match="a sensor file holds a mapping"):
        bad.write_text("- 1\n- 2\n")
        load_sensor(bad)


def test_load_sensor_errors(tmp_path):
    with pytest.raises(ConfigError, match="cannot read"):
        load_sensor(tmp_path / "missing.yaml")
    bad = tmp_path / "bad.yaml"
    bad.write_text("optics: [1, 2\n")
    with pytest.raises(ConfigError, match="YAML"):
        load_sensor(bad)
    good = tmp_path / "good.yaml"
    good.write_text(yaml.safe_dump({"sensor": BASE}))
    assert load_sensor(good).name == "test"


def test_cli_list_info_and_apply(tmp_path):
    from radscene.io import write_netcdf

    runner = CliRunner()
    result = runner.invoke(app, ["list"])
    assert result.exit_code == 0 and "mwir_cooled" in result.output
    result = runner.invoke(app, ["info", "mwir_cooled", "--temperature", "30 degC"])
    assert result.exit_code == 0, result.output
    assert "NETD" in result.output and "303.15 K" in result.output
    cfg = tmp_path / "cam.yaml"
    cfg.write_text(yaml.safe_dump(BASE))
    rad = tmp_path / "radiance.nc"
    write_netcdf(_radiance(), rad)
    out = tmp_path / "signal.nc"
    result = runner.invoke(app, ["apply", str(rad), "--sensor", str(cfg), "-o", str(out),
                                 "--frames", "2", "--seed", "3"])
    assert result.exit_code == 0, result.output
    signal = xr.load_dataset(out, engine="h5netcdf")
    assert signal["dn"].shape == (2, 1, 8, 8)
    result = runner.invoke(app, ["apply", str(rad), "--sensor", str(cfg), "-o", str(out),
                                 "--oversample", "32"])
    assert isinstance(result.exception, ConfigError)
    assert result.exception.key == "detector.pitch"


def test_cli_apply_quiet_and_verbose(tmp_path):
    """--quiet prints nothing and writes the file; --verbose adds each stage and its time on
    standard error; both together are refused (exit code 2 through the radscene command)."""
    from radscene.cli import app as main_app
    from radscene.io import write_netcdf

    runner = CliRunner()
    cfg = tmp_path / "cam.yaml"
    cfg.write_text(yaml.safe_dump(BASE))
    rad = tmp_path / "radiance.nc"
    write_netcdf(_radiance(), rad)
    args = ["apply", str(rad), "--sensor", str(cfg), "--seed", "3", "-o"]
    quiet = runner.invoke(app, [*args, str(tmp_path / "q.nc"), "--quiet"])
    assert quiet.exit_code == 0 and quiet.output == "", quiet.output
    assert (tmp_path / "q.nc").is_file()
    loud = runner.invoke(app, [*args, str(tmp_path / "v.nc"), "-v"])
    assert loud.exit_code == 0, loud.output
    for words in ("loaded sensor test", "read ", "1 band(s), 16×16 px", "sensor applied: 1 "
                  "frame(s)", f"wrote {tmp_path / 'v.nc'} (", " s)", "8 x 8 detectors"):
        assert words in loud.output, words
    both = runner.invoke(main_app, ["sensor", *args, str(tmp_path / "b.nc"), "-q", "-v"])
    assert both.exit_code == 2 and "error: --quiet: give --quiet or --verbose" in both.output
    assert len(both.output.strip().splitlines()) == 1 and not (tmp_path / "b.nc").exists()
