"""The chain's internals: its OTF against the analytic one, seeds, fixed pattern, eq. 7 terms."""

from __future__ import annotations

import numpy as np
import pytest
import xarray as xr

from radscene.radiometry import RectangularResponse, band_radiance
from radscene.sensor import Channel, Motion, make_sensor, system_mtf
from radscene.sensor.chain import _half_grid_otf
from radscene.sensor.sampling import rfft_frequencies

CFG = {
    "name": "unit", "oversample": 4, "fixed_pattern_seed": 11,
    "optics": {"focal_length": 0.1, "f_number": 2.0, "obscuration": 0.3, "transmittance": 0.8,
               "temperature": 295.0, "wavefront_error": 0.3, "defocus": 0.5},
    "detector": {"type": "cooled_ir", "pitch": 15e-6, "fill_factor": 0.8, "quantum_efficiency": 0.7,
                 "integration_time": 0.0005, "temperature": 80.0, "read_noise": 150,
                 "dark_current": 1e-12, "prnu": 0.02, "dsnu": 0.1, "full_well": 1e7,
                 "cold_shield_f_number": 2.0},
    "electronics": {"gain": 500.0, "offset": 200, "bits": 16},
    "motion": {"jitter": ["20 urad", "10 urad"], "smear": [0.7, -0.3]},
    "bands": {"mwir": {"response": {"type": "rectangular", "wavelength_min": 3.5,
                                    "wavelength_max": 4.8}},
              "lwir": {"response": {"type": "rectangular", "wavelength_min": 8.0,
                                    "wavelength_max": 9.5}}},
}


def _scene(level, n=64, bands=("mwir", "lwir")):
    data = np.stack([np.full((n, n), float(v)) for v in np.broadcast_to(level, len(bands))])
    return xr.Dataset({"radiance": (("band", "y", "x"), data)}, coords={"band": list(bands)})


@pytest.mark.parametrize("band", ["mwir", "lwir"])
def test_chain_otf_is_the_analytic_system_otf(band):
    s = make_sensor(CFG)
    ch = s.channel(band)
    rad = ch.radiometry(ch.response)
    shape, k = (64, 48), 4
    fast = _half_grid_otf(ch, rad, shape, k, {})
    fy, fx = rfft_frequencies(shape)
    spacing = ch.detector.pitch / k
    exact = ch.otf(rad, fy / spacing, fx / spacing)
    assert fast == pytest.approx(exact, abs=2e-6)  # a diagonal smear: all rows
    # without the smear the OTF is even in fy, and only the rows fy >= 0 are computed
    straight = Channel(ch.optics, ch.detector, ch.electronics, Motion(ch.motion.jitter, (0.7, 0)),
                       ch.processing, ch.response)
    half = _half_grid_otf(straight, rad, shape, k, {})
    exact = straight.otf(rad, fy / spacing, fx / spacing)
    assert half.shape == (shape[0] // 2 + 1, shape[1] // 2 + 1)
    assert half[:-1] == pytest.approx(exact[: shape[0] // 2], abs=2e-6)
    assert exact[-5] == pytest.approx(exact[5], abs=1e-12)
    # and system_mtf reads the same function per detector pitch
    assert system_mtf(s, 0.3, -0.1, band) == pytest.approx(
        abs(float(ch.otf(rad, -0.1 / ch.detector.pitch, 0.3 / ch.detector.pitch))), rel=1e-12)


def test_a_band_of_coarser_ifov_keeps_its_footprint_on_the_base_grid():
    # base IFOV 15 um / 0.1 m = 150 urad; the "coarse" band: 60 um / 0.2 m = 300 urad
    cfg = {**CFG, "motion": {}, "bands": {
        **CFG["bands"],
        "coarse": {"response": CFG["bands"]["lwir"]["response"],
                   "optics": {"focal_length": 0.2, "f_number": 2.0},
                   "detector": {"pitch": 60e-6, "cold_shield_f_number": None}}}}
    s = make_sensor(cfg)
    assert s.grid_pitch("mwir") == s.channel("mwir").detector.pitch == 15e-6
    # the base grid (one output pixel per 150 urad) in the coarse band's focal plane
    assert s.grid_pitch("coarse") == pytest.approx(15e-6 * 0.2 / 0.1, rel=1e-12)
    ch = s.channel("coarse")
    rad = ch.radiometry(ch.response)
    shape, k = (64, 48), 4
    fast = _half_grid_otf(ch, rad, shape, k, {}, s.grid_pitch("coarse"))
    fy, fx = rfft_frequencies(shape)
    spacing = 30e-6 / k
    exact = ch.otf(rad, fy / spacing, fx / spacing)
    assert fast[:-1] == pytest.approx(exact[: shape[0] // 2], abs=2e-6)
    # its 60 um detector covers two output pixels: the footprint's first zero at 0.5 cycles
    # per output pixel, i.e. cycles per 30 um in its focal plane
    fill = np.sqrt(ch.detector.fill_factor)
    assert system_mtf(s, 0.5 / fill, 0.0, "coarse") == pytest.approx(0.0, abs=1e-9)
    assert system_mtf(s, 0.5 / fill, 0.0, "mwir") > 0.05
    # a point source spreads over twice the output pixels when the footprint dominates
    # (visible band: diffraction spot 1 um, pitches 15 um and 60 um)
    vis = {"type": "rectangular", "wavelength_min": 0.5, "wavelength_max": 0.6}
    s = make_sensor({
        "oversample": 4, "optics": {"focal_length": 0.1, "f_number": 2.0},
        "detector": {"type": "ccd", "pitch": 15e-6, "quantum_efficiency": 0.5,
                     "integration_time": 0.001, "temperature": 290.0},
        "electronics": {"gain": 1.0, "bits": 16},
        "bands": {"fine": {"response": vis},
                  "coarse": {"response": vis, "optics": {"focal_length": 0.2},
                             "detector": {"pitch": 60e-6}}}})
    point = np.zeros((2, 64, 64))
    point[:, 32, 32] = 1.0
    ds = xr.Dataset({"radiance": (("band", "y", "x"), point)}, coords={"band": ["fine", "coarse"]})
    out = s.apply(ds, seed=0)["radiance_optics"]
    fine, coarse = (out.sel(band=b).values for b in ("fine", "coarse"))
    assert fine.sum() == pytest.approx(coarse.sum(), rel=1e-4)  # both conserve the energy
    # the 60 um detector averages over 2 x 2 output pixels of the base grid (a footprint
    # scaled by its own pitch would leave the peak unchanged)
    assert fine.max() > 2.5 * coarse.max()


def test_seeds_fixed_pattern_and_frames():
    s = make_sensor(CFG)
    a = s.apply(_scene(1.0), frames=3, seed=5)
    b = s.apply(_scene(1.0), frames=3, seed=5)
    c = s.apply(_scene(1.0), frames=3, seed=6)
    assert a["dn"].shape == (3, 2, 16, 16)
    assert np.array_equal(a["dn_raw"].values, b["dn_raw"].values)
    assert not np.array_equal(a["dn_raw"].values, c["dn_raw"].values)
    # the fixed pattern belongs to the sensor: the same whatever the noise seed or band order
    swapped = s.apply(_scene(1.0, bands=("lwir", "mwir")), seed=9)
    for band in ("mwir", "lwir"):
        assert np.array_equal(a["gain_nonuniformity"].sel(band=band).values,
                              swapped["gain_nonuniformity"].sel(band=band).values)
    assert not np.array_equal(a["gain_nonuniformity"].sel(band="mwir").values,
                              a["gain_nonuniformity"].sel(band="lwir").values)
    other = make_sensor({**CFG, "fixed_pattern_seed": 12}).apply(_scene(1.0), seed=5)
    assert not np.array_equal(other["gain_nonuniformity"].values, a["gain_nonuniformity"].values)


def test_noise_rms_truth_matches_the_temporal_scatter():
    cfg = {**CFG, "detector": {**CFG["detector"], "prnu": 0.0, "dsnu": 0.0}}
    s = make_sensor(cfg)
    out = s.apply(_scene(2.0, n=256), frames=2, seed=1)
    assert not out["saturated"].any()
    d = out["dn_raw"].sel(band="mwir").values.astype(float)
    measured = np.std(d[0] - d[1]) / np.sqrt(2) * 500.0  # e-
    assert measured == pytest.approx(float(out["noise_rms"].sel(band="mwir").mean()), rel=0.02)


def test_heated_dome_and_optics_raise_the_signal_by_eq7():
    """Eq. 7: a hotter dome adds A Ω (1 - ε²) ∫ S τ_optics ε_dome ΔB dλ of flux."""
    cool = {**CFG, "optics": {**CFG["optics"], "dome": {"transmittance": 0.9, "emissivity": 0.1,
                                                          "temperature": 300.0}}}
    hot = {**cool, "optics": {**cool["optics"], "dome": {**cool["optics"]["dome"],
                                                          "temperature": 400.0}}}
    scene = _scene(0.5)
    a = make_sensor(cool).apply(scene, seed=1)
    b = make_sensor(hot).apply(scene, seed=1)
    g = (15e-6) ** 2 * 0.8 * np.pi / 16 * (1 - 0.09)
    expected = g * 0.8 * 0.1 * (band_radiance(3.5, 4.8, 400.0) - band_radiance(3.5, 4.8, 300.0))
    got = float(b["flux_heated_dome"].sel(band="mwir") - a["flux_heated_dome"].sel(band="mwir"))
    assert got == pytest.approx(expected, rel=1e-8)
    assert float(b["flux_detector"].sel(band="mwir").mean() - a["flux_detector"].sel(band="mwir").mean()) \
        == pytest.approx(expected, rel=1e-4)
    assert not b["saturated"].any()
    assert float(b["dn_raw"].mean()) > float(a["dn_raw"].mean())


def test_cos4_falloff_and_dark_current_temperature():
    wide = {**CFG, "oversample": 1,
            "optics": {**CFG["optics"], "focal_length": 0.005, "relative_illumination": "cos4"},
            "motion": {}, "detector": {**CFG["detector"], "prnu": 0.0, "dsnu": 0.0}}
    out = make_sensor(wide).apply(_scene(1.0, n=128, bands=("mwir",)), seed=0)
    flux = out["flux_scene"].values[0]
    # corner detector: field angle atan(63.5 * sqrt(2) * 15 um / 5 mm)
    angle = np.arctan(63.5 * np.sqrt(2) * 15e-6 / 0.005)
    assert flux[0, 0] / flux[64, 64] == pytest.approx(
        np.cos(angle) ** 4 / np.cos(np.arctan(0.5 * np.sqrt(2) * 15e-6 / 0.005)) ** 4, rel=1e-5)
    warm = make_sensor({**CFG, "detector": {**CFG["detector"], "temperature": 90.0,
                                            "dark_reference_temperature": 80.0,
                                            "activation_energy": 0.23, "temperature_exponent": 3}})
    leak = warm.apply(_scene(1.0), seed=0)["leakage"].sel(band="mwir").values.mean()
    expected = 1e-12 * (90 / 80) ** 3 * np.exp(-0.23 / 8.617333262e-5 * (1 / 90 - 1 / 80))
    assert leak == pytest.approx(expected, rel=0.01)  # DSNU averages out over 512 detectors


def test_response_from_the_dataset_coordinates():
    s = make_sensor({k: v for k, v in CFG.items() if k != "bands"})
    ds = _scene(1.0, bands=("b1",)).assign_coords(wavelength_center=("band", [4.0]),
                                                  equivalent_width=("band", [1.0]))
    out = s.apply(ds, seed=0)
    rad = s.base.radiometry(RectangularResponse(3.5, 4.5))
    assert float(out["responsivity"].values[0]) == pytest.approx(rad.responsivity, rel=1e-12)
