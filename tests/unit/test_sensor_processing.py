"""Processing stages: two-point NUC, AGC, DCS, and their truth in the signal Dataset."""

from __future__ import annotations

import numpy as np
import pytest
import xarray as xr

from radscene.errors import ConfigError
from radscene.radiometry import band_radiance
from radscene.sensor import make_sensor, noise_3d
from radscene.sensor.processing import (
    agc_stretch,
    apply_nuc,
    make_processing,
    two_point_nuc_coefficients,
)


def test_two_point_nuc_flattens_a_linear_array_exactly():
    rng = np.random.default_rng(0)
    gain = 1 + 0.1 * rng.standard_normal((16, 16))
    offset = 50 * rng.standard_normal((16, 16))

    def frame(level):
        return gain * level + offset

    g, o, bad = two_point_nuc_coefficients(frame(100.0), frame(900.0))
    assert not bad.any()
    for level in (0.0, 350.0, 2000.0):
        corrected = apply_nuc(frame(level), g, o)
        assert corrected.std() == pytest.approx(0.0, abs=1e-3)
    # the references map to their own means
    assert apply_nuc(frame(100.0), g, o) == pytest.approx(np.full((16, 16), frame(100.0).mean()),
                                                          abs=1e-3)


def test_two_point_nuc_flags_dead_pixels():
    low = np.full((4, 4), 10.0)
    high = np.full((4, 4), 20.0)
    high[1, 2] = 10.0
    g, o, bad = two_point_nuc_coefficients(low, high)
    assert bad.sum() == 1 and bad[1, 2]
    assert g[1, 2] == 0.0 and np.isfinite(o).all()


def test_agc_maps_percentiles_to_the_output_range():
    img = np.linspace(0.0, 1000.0, 10_000).reshape(1, 100, 100)
    out, gain, offset = agc_stretch(img, 1.0, 99.0, 8)
    assert out.min() == 0.0 and out.max() == 255.0
    assert offset[0] == pytest.approx(10.0, rel=1e-6)
    assert gain[0] == pytest.approx(255.0 / 980.0, rel=1e-6)
    assert np.all(out == np.round(out))
    flat, g, _ = agc_stretch(np.full((1, 4, 4), 7.0))
    assert np.all(flat == 0.0) and np.isfinite(g).all()


@pytest.mark.parametrize(("cfg", "key"), [
    ({"median": {}}, "processing.median"),
    ({"nuc": {"high": 300}}, "processing.nuc.low"),
    ({"nuc": {"low": 300, "high": 290}}, "processing.nuc.high"),
    ({"nuc": {"low": {"radiance": 1.0, "temperature": 3}, "high": 300}}, "processing.nuc.low"),
    ({"agc": {"low_percentile": 90, "high_percentile": 10}}, "processing.agc.high_percentile"),
    ({"dcs": {"frames": 0}}, "processing.dcs.frames"),
])
def test_bad_processing_names_the_key(cfg, key):
    with pytest.raises(ConfigError, match=key.replace(".", r"\.")):
        make_processing(cfg)


def test_processing_order_and_disabling():
    stages = make_processing({"AGC": {}, "nuc": {"low": "20 degC", "high": {"radiance": 5.0}},
                              "dcs": None})
    assert list(stages) == ["dcs", "nuc", "agc"]
    assert stages["nuc"].low == ("temperature", pytest.approx(293.15))
    assert stages["nuc"].high == ("radiance", 5.0)
    assert list(make_processing({"dcs": False, "agc": {}})) == ["agc"]
    assert make_processing(None) == {}


def _ir_sensor(processing):
    return make_sensor({
        "oversample": 1, "fixed_pattern_seed": 3,
        "optics": {"focal_length": 0.1, "f_number": 2.0, "transmittance": 0.8,
                   "temperature": 300.0},
        "detector": {"type": "cooled_ir", "pitch": 15e-6, "quantum_efficiency": 0.7,
                     "integration_time": 0.002, "temperature": 80.0, "read_noise": 100,
                     "dark_current": 5e-12, "dsnu": 0.5, "prnu": 0.05, "full_well": 2e7,
                     "cold_shield_f_number": 2.0},
        "electronics": {"gain": 1000.0, "offset": 100, "bits": 16},
        "processing": processing,
        "bands": {"mwir": {"response": {"type": "rectangular", "wavelength_min": 3.5,
                                        "wavelength_max": 4.8}}},
    })


def _uniform(level, n=48):
    return xr.Dataset({"radiance": (("band", "y", "x"), np.full((1, n, n), level))},
                      coords={"band": ["mwir"]})


def test_nuc_in_the_chain_removes_the_fixed_pattern():
    level = band_radiance(3.5, 4.8, 310.0)
    raw = _ir_sensor(None).apply(_uniform(level), frames=8, seed=1)
    corrected = _ir_sensor({"nuc": {"low": "290 K", "high": "330 K", "frames": 64}}).apply(
        _uniform(level), frames=8, seed=1)
    fixed_raw = noise_3d(raw["dn"].values[:, 0]).vh
    fixed_nuc = noise_3d(corrected["dn"].values[:, 0]).vh
    temporal = noise_3d(corrected["dn"].values[:, 0]).tvh
    assert fixed_raw > 10 * temporal  # PRNU and DSNU dominate before the correction
    # after it: the calibration's own noise, temporal / sqrt(64 frames) per reference, remains
    assert fixed_nuc < 0.5 * temporal
    assert {"nuc_gain", "nuc_offset", "nuc_bad_pixel"} <= set(corrected.data_vars)
    assert corrected["nuc_gain"].dims == ("band", "y", "x")
    assert float(corrected["nuc_gain"].mean()) == pytest.approx(1.0, abs=0.02)


def test_dcs_subtracts_the_shutter_background():
    level = band_radiance(3.5, 4.8, 300.0)
    plain = _ir_sensor(None).apply(_uniform(level), seed=2)
    dcs = _ir_sensor({"dcs": {"shutter_temperature": "300 K", "frames": 64, "pedestal": 500}}).apply(
        _uniform(level), seed=2)
    # the scene equals the shutter: everything but the pedestal comes off, offsets included
    assert float(dcs["dn_raw"].mean()) == pytest.approx(100 + 500, abs=2.0)
    assert float(dcs["dn_raw"].std()) < 0.3 * float(plain["dn_raw"].std())
    truth = dcs["dcs_background"].values[0]
    expected = plain["signal_mean"].values[0] - 500 * 1000.0
    assert truth == pytest.approx(expected, rel=0.01)
    assert dcs["signal_mean"].values.mean() == pytest.approx(500 * 1000.0, rel=0.01)


def test_agc_in_the_chain_leaves_its_truth():
    out = _ir_sensor({"agc": {"bits": 8}}).apply(_uniform(band_radiance(3.5, 4.8, 300.0)),
                                                  frames=3, seed=0)
    assert out["agc_gain"].dims == ("frame", "band")
    assert out["dn"].min() == 0 and out["dn"].max() == 255
    assert out["dn_raw"].dtype == np.uint16
