"""Validation of the sensor chain against reference figures (``shared/reference/cases.json``)
and against the analytic noise budget.

The reference figures are typed in with their case id and source; nothing here reads the
shared folder.
"""

from __future__ import annotations

import gzip
import hashlib
from pathlib import Path

import numpy as np
import pytest
import xarray as xr

from radscene.sensor import make_sensor, noise_3d, noise_budget
from radscene.sensor.otf import detector_otf, diffraction_otf
from radscene.sensor.sampling import apply_otf, apply_otf_reference, rfft_frequencies

MTF_ABS = 1e-6  # tolerance of the mtf_* cases

# case mtf_diffraction_circular_aperture — Goodman, Introduction to Fourier Optics: incoherent
# diffraction-limited OTF of a clear circular pupil, nu_c = 1 / (lambda F#).
DIFFRACTION_X = [0.1, 0.25, 0.5, 0.75, 0.9]
DIFFRACTION_MTF = [0.872889, 0.685038, 0.391002, 0.144294, 0.037386]
# case mtf_detector_footprint — Boreman, MTF in Optical and Electro-Optical Systems:
# MTF = |sinc(w nu)|.
FOOTPRINT_WNU = [0.25, 0.5, 1.0]
FOOTPRINT_MTF = [0.900316, 0.63662, 0.0]
# case pyradi_3d_noise_sample — NelisW/pyradi@61dc954: pyradi/data/sensornoise.raw
# (20 x 100 x 100 frames) decomposed with pyradi/ry3dnoise.py; digital counts (std dev).
PYRADI_3D = {"mean": 2033.157, "total": 9.936, "h": 3.1321, "th": 1.2188, "v": 0.3491,
             "tv": 3.0251, "vh": 1.9849, "tvh": 8.6087, "t": 0.3374}
PYRADI_ABS = 0.001
PYRADI_SHA256 = "d4d7a2b3c002c92f26ce4c574db187c235bee66269232be4ff3d21cccd416000"
DATA = Path(__file__).parent / "data"


def test_mtf_diffraction_circular_aperture():
    # lambda = 10 um, F/2: nu_c = 0.05 cycles/um = 50 cycles/mm
    nu = np.array(DIFFRACTION_X) * 0.05
    assert diffraction_otf(nu, 10.0, 2.0) == pytest.approx(DIFFRACTION_MTF, abs=MTF_ABS)
    # the case's example: 25 cycles/mm at F/2, 10 um
    assert float(diffraction_otf(0.025, 10.0, 2.0)) == pytest.approx(0.391002, abs=MTF_ABS)


def test_mtf_detector_footprint():
    assert np.abs(detector_otf(np.array(FOOTPRINT_WNU), 0.0, 1.0)) == pytest.approx(
        FOOTPRINT_MTF, abs=MTF_ABS)


@pytest.mark.parametrize("w_nu", [0.25, 0.5])
def test_fourier_filter_of_the_chain_transfers_a_cosine_by_the_footprint_mtf(w_nu):
    """A cosine of w nu cycles per pitch leaves the detector sampling with amplitude |sinc|.

    The cosine peaks on the detector centres (at Nyquist, a cosine through the centres' zero
    crossings would vanish whatever the MTF).
    """
    k, m = 8, 16  # samples per pitch, detectors
    n = k * m
    x = np.arange(n) + 0.5  # sample centres [samples]; detector j is centred at j k + k / 2
    image = 1.0 + 0.5 * np.cos(2 * np.pi * (w_nu / k) * (x - k / 2))[None, :] * np.ones((n, 1))
    carrier = np.cos(2 * np.pi * w_nu * np.arange(m))

    def otf(fy, fx):
        return detector_otf(fx, fy, k)

    for out, tol in ((apply_otf_reference(image, otf, k), MTF_ABS),
                     (apply_otf(image, otf(*rfft_frequencies(image.shape)), k), 1e-5)):
        amplitude = (out[0] - 1.0) @ carrier / (carrier @ carrier)
        expected = FOOTPRINT_MTF[FOOTPRINT_WNU.index(w_nu)]
        assert amplitude / 0.5 == pytest.approx(expected, abs=tol)


def _cube_with_components(shape, sigma, mean, seed=0):
    axes = {"t": 0, "v": 1, "h": 2}
    rng = np.random.default_rng(seed)
    cube = np.full(shape, mean)
    for comp, s in sigma.items():
        a = rng.standard_normal([shape[i] if name in comp else 1 for name, i in axes.items()])
        for name in comp:
            a = a - a.mean(axis=axes[name], keepdims=True)
        cube = cube + a * (s / np.std(a, ddof=1))
    return cube


def test_pyradi_3d_noise_sample_data():
    """pyradi's own sensor video (tests/validation/data, see its README) decomposes into the
    case's components, all 20 frames."""
    raw = gzip.decompress((DATA / "pyradi_sensornoise.raw.gz").read_bytes())
    assert hashlib.sha256(raw).hexdigest() == PYRADI_SHA256
    cube = np.frombuffer(raw, dtype="<u2").reshape(20, 100, 100).astype(float)
    result = noise_3d(cube)
    assert result.mean == pytest.approx(PYRADI_3D["mean"], abs=PYRADI_ABS)
    for c in ("t", "v", "h", "tv", "th", "vh", "tvh"):
        assert getattr(result, c) == pytest.approx(PYRADI_3D[c], abs=PYRADI_ABS), c
    assert result.total == pytest.approx(PYRADI_3D["total"], abs=PYRADI_ABS)


def test_pyradi_3d_noise_sample_synthetic():
    """A synthetic 20 x 100 x 100 cube with the case's components decomposes back to them."""
    sigma = {c: PYRADI_3D[c] for c in ("t", "v", "h", "tv", "th", "vh", "tvh")}
    result = noise_3d(_cube_with_components((20, 100, 100), sigma, PYRADI_3D["mean"]))
    assert result.mean == pytest.approx(PYRADI_3D["mean"], abs=PYRADI_ABS)
    for c, value in sigma.items():
        assert getattr(result, c) == pytest.approx(value, abs=PYRADI_ABS), c
    # the case's total is the root sum of squares of its components (pyradi getTotal)
    assert result.total == pytest.approx(PYRADI_3D["total"], abs=PYRADI_ABS)


PTC_GAIN = 4.0  # e-/DN
PTC_REL = 0.01  # the issue: slope of variance against mean = 1 / gain within 1 %
SNR_REL = 0.02  # the issue: SNR of a uniform scene = analytic budget within 2 %


def _uniform(level, n, band):
    return xr.Dataset({"radiance": (("band", "y", "x"), np.full((1, n, n), float(level)))},
                      coords={"band": [band]})


def test_photon_transfer_curve_slope_is_one_over_gain():
    sensor = make_sensor({
        "optics": {"focal_length": 0.05, "f_number": 2.0, "transmittance": 0.9},
        "detector": {"type": "cmos", "pitch": 10e-6, "quantum_efficiency": 0.6,
                     "integration_time": 0.01, "temperature": 293.0, "read_noise": 10,
                     "full_well": 2e5, "dark_current": 1e-15, "prnu": 0.01, "dsnu": 0.2},
        "electronics": {"gain": PTC_GAIN, "offset": 100, "bits": 16},
        "bands": {"vis": {"response": {"type": "rectangular", "wavelength_min": 0.5,
                                       "wavelength_max": 0.6}}}})
    means, variances = [], []
    for i, level in enumerate(np.linspace(0.02, 0.6, 10)):  # up to ~90 % of the full well
        out = sensor.apply(_uniform(level, 512, "vis"), frames=2, seed=100 + i)
        d = out["dn_raw"].values[:, 0].astype(float)
        means.append(d.mean() - 100.0)
        variances.append(np.var(d[0] - d[1]) / 2.0)  # the difference removes the fixed pattern
    slope = np.polyfit(means, variances, 1)[0]
    assert slope == pytest.approx(1.0 / PTC_GAIN, rel=PTC_REL)


def _measured_snr(sensor, band, level, n=256, realisations=4):
    """Scene signal (scene minus dark frame) over the spatial noise of single frames.

    1/f noise puts much of its variance in a few low-frequency modes, so one frame's variance
    scatters by ~10 % of the 1/f part; the variance is averaged over independent frames.
    """
    gain = sensor.channel(band).electronics.gain
    signal, variance = [], []
    for seed in range(realisations):
        scene = sensor.apply(_uniform(level, n, band), seed=2 * seed)["dn_raw"].values[0, 0]
        dark = sensor.apply(_uniform(0.0, n, band), seed=2 * seed + 1)["dn_raw"].values[0, 0]
        signal.append((scene.mean() - dark.mean()) * gain)
        variance.append(np.var(scene.astype(float)) * gain**2)
    return np.mean(signal) / np.sqrt(np.mean(variance))


def test_snr_of_a_uniform_scene_photon_detector():
    sensor = make_sensor({
        "optics": {"focal_length": 0.1, "f_number": 2.5, "transmittance": 0.8,
                   "temperature": 300.0},
        "detector": {"type": "cooled_ir", "pitch": 15e-6, "quantum_efficiency": 0.7,
                     "integration_time": 0.001, "temperature": 80.0, "read_noise": 200,
                     "dark_current": 2e-12, "flicker_corner": 3e5, "cold_shield_f_number": 2.5,
                     "shape": [256, 256]},
        "electronics": {"gain": 50.0, "bits": 16, "frame_rate": 100.0},
        "bands": {"mwir": {"response": {"type": "rectangular", "wavelength_min": 3.5,
                                        "wavelength_max": 4.8}}}})
    level = 0.5  # W m-2 sr-1
    budget = noise_budget(sensor, "mwir", radiance=level)
    # every term matters: shot, read, 1/f, quantisation (in e-); without the 1/f term the
    # budget would miss the measurement by more than the tolerance
    assert float(budget.shot_rms) > 100 and budget.flicker_rms > 50
    no_flicker = budget.signal / np.sqrt(budget.temporal_rms**2 - budget.flicker_rms**2)
    assert abs(no_flicker / budget.snr - 1) > 2 * SNR_REL
    assert _measured_snr(sensor, "mwir", level) == pytest.approx(float(budget.snr), rel=SNR_REL)


def test_snr_of_a_uniform_scene_microbolometer():
    sensor = make_sensor({
        "optics": {"focal_length": 0.025, "f_number": 1.0, "transmittance": 0.9,
                   "temperature": 300.0},
        "detector": {"type": "microbolometer", "pitch": 17e-6, "fill_factor": 0.8,
                     "integration_time": 0.0167, "temperature": 300.0, "read_noise": 2e-6,
                     "flicker_corner": 3e4, "shape": [256, 256]},
        "electronics": {"gain": 2e-7, "offset": 30000, "bits": 16, "frame_rate": 30.0},
        "bands": {"lwir": {"response": {"type": "rectangular", "wavelength_min": 8.0,
                                        "wavelength_max": 14.0}}}})
    level = 1.0  # W m-2 sr-1 above the zero-radiance reference
    budget = noise_budget(sensor, "lwir", radiance=level)
    assert budget.unit == "V" and budget.flicker_rms > 0.4 * budget.white_rms
    no_flicker = budget.signal / np.sqrt(budget.temporal_rms**2 - budget.flicker_rms**2)
    assert abs(no_flicker / budget.snr - 1) > 2 * SNR_REL
    assert _measured_snr(sensor, "lwir", level) == pytest.approx(float(budget.snr), rel=SNR_REL)
