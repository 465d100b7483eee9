"""Detectors: dark current, responsivity, eq. 6, bolometer noise, integration, configuration."""

from __future__ import annotations

import math

import numpy as np
import pytest

from radscene.errors import ConfigError
from radscene.sensor.detector import (
    Microbolometer,
    PhotonDetector,
    bolometer_responsivity,
    dark_current,
    detector_current,
    johnson_noise,
    photon_responsivity,
    thermal_fluctuation_noise,
)

K_EV = 8.617333262e-5  # Boltzmann constant [eV K-1] (CODATA 2018)
K_B = 1.380649e-23  # [J K-1]


def photon(**kw):
    cfg = {"pitch": 10e-6, "quantum_efficiency": 0.6, "integration_time": 0.01,
           "temperature": 293.0, **kw}
    return PhotonDetector.from_config(cfg)


def test_dark_current_arrhenius_law():
    # independent evaluation of I_ref (T/T_ref)^p exp(-Ea/k (1/T - 1/T_ref))
    t = np.array([250.0, 293.0, 300.0, 320.0])
    expected = 1e-12 * (t / 293.0) ** 1.5 * np.exp(-0.605 / K_EV * (1 / t - 1 / 293.0))
    assert dark_current(t, 1e-12, 293.0, 0.605) == pytest.approx(expected, rel=1e-9)
    assert float(dark_current(80.0, 2e-14, 80.0, 0.23, 3.0)) == pytest.approx(2e-14, rel=1e-15)
    # silicon rule of thumb: the dark current doubles every 5-8 K near room temperature
    doubling = 7.0
    ratio = float(dark_current(293.0 + doubling, 1.0, 293.0, 0.605))
    assert 1.7 < ratio < 2.6
    with pytest.raises(ConfigError, match="temperature"):
        dark_current(0.0, 1.0, 293.0, 0.6)


def test_photon_responsivity_and_eq6():
    # R = eta q lambda / (h c) = eta lambda [um] / 1.23984198 [A/W]
    assert float(photon_responsivity(1.0, 1.0)) == pytest.approx(1 / 1.2398419843, rel=1e-9)
    assert photon_responsivity([0.5, 4.0], [0.8, 0.5]) == pytest.approx(
        [0.8 * 0.5 / 1.2398419843, 0.5 * 4.0 / 1.2398419843], rel=1e-9)
    # I = Phi R dR + I_leak
    assert float(detector_current(2e-9, 0.5, 1.1, 3e-12)) == pytest.approx(
        2e-9 * 0.5 * 1.1 + 3e-12, rel=1e-15)
    assert detector_current(np.ones((2, 3)), 1.0, np.array([1.0, 2.0, 3.0])).shape == (2, 3)


def test_bolometer_responsivity_and_noise():
    assert float(bolometer_responsivity(-0.025, 1e-5, 1e5, 1e-7)) == pytest.approx(2.5e5, rel=1e-15)
    assert float(johnson_noise(300.0, 1e5, 50.0)) == pytest.approx(
        math.sqrt(4 * K_B * 300.0 * 1e5 * 50.0), rel=1e-12)
    assert float(thermal_fluctuation_noise(300.0, 1e-7, 30.0)) == pytest.approx(
        math.sqrt(4 * K_B * 300.0**2 * 1e-7 * 30.0), rel=1e-12)
    det = Microbolometer.from_config({"pitch": "17 um", "integration_time": "16.7 ms",
                                      "temperature": "300 K", "tcr": "-2.5 %/K",
                                      "resistance": "100 kohm", "bias_current": "10 uA",
                                      "thermal_conductance": 1e-7, "read_noise": "2 uV"})
    bw = 0.5 / 0.0167
    rv = 0.025 * 1e-5 * 1e5 / 1e-7
    expected = (4 * K_B * 300 * 1e5 * bw + 4 * K_B * 300**2 * 1e-7 * bw * rv**2 + (2e-6) ** 2)
    assert det.voltage_responsivity == pytest.approx(rv, rel=1e-12)
    assert det.white_variance() == pytest.approx(expected, rel=1e-9)
    assert det.spectral_responsivity(10.0) == pytest.approx(0.8 * rv, rel=1e-12)


def test_photon_integration_statistics_and_full_well():
    det = photon(full_well=5000.0)
    rng = np.random.default_rng(4)
    mean = np.full((64, 64), 1000.0)
    counts, sat = det.integrate(mean, 0.0, 0.0, 16, rng)
    assert counts.shape == (16, 64, 64) and counts.dtype == np.float32
    assert counts.mean() == pytest.approx(1000.0, rel=2e-3)
    assert counts.var() == pytest.approx(1000.0, rel=0.02)
    assert not sat.any()
    # averaging 16 frames in distribution divides the variance by 16
    avg, _ = det.integrate(mean, 0.0, 0.0, 16, rng, average=16)
    assert avg.var() == pytest.approx(1000.0 / 16, rel=0.03)
    full, sat = det.integrate(np.full((4, 4), 1e5), 0.0, 0.0, 2, rng)
    assert np.all(full == 5000.0) and sat.all()
    # DCS: the skim comes off the well, the pedestal goes on, shot noise stays that of the total
    skimmed, _ = det.integrate(mean, 900.0, 100.0, 16, rng)
    assert skimmed.mean() == pytest.approx(200.0, abs=1.0)
    assert skimmed.var() == pytest.approx(1000.0, rel=0.03)


def test_dark_current_and_dsnu_maps():
    det = photon(dark_current="1 pA", dark_reference_temperature="20 degC", dsnu=0.1, prnu=0.02)
    assert det.leakage() == pytest.approx(1e-12, rel=1e-12)
    rng = np.random.default_rng(0)
    offset = det.offset_map((200, 200), rng)
    gain = det.gain_map((200, 200), rng)
    assert offset.std() == pytest.approx(1e-13, rel=0.02)
    assert gain.mean() == pytest.approx(1.0, abs=1e-3) and gain.std() == pytest.approx(0.02, rel=0.02)
    assert det.to_signal(1.602176634e-19 / 0.01) == pytest.approx(1.0, rel=1e-12)


@pytest.mark.parametrize(("cfg", "key"), [
    ({"pitch": None}, "detector.pitch"),
    ({"pitch": "-5 um"}, "detector.pitch"),
    ({"quantum_efficiency": 1.5}, "detector.quantum_efficiency"),
    ({"responsivity": 1.0}, "detector.quantum_efficiency"),  # both given
    ({"fill_factor": 0.0}, "detector.fill_factor"),
    ({"dsnu": 2.0}, "detector.dsnu"),
    ({"shot_noise": "binomial"}, "detector.shot_noise"),
    ({"shape": [10]}, "detector.shape"),
    ({"dark_current": "3 parsec"}, "detector.dark_current"),
    ({"colour": 1}, "detector.colour"),
])
def test_bad_photon_detector_names_the_key(cfg, key):
    base = {"pitch": 10e-6, "quantum_efficiency": 0.6, "integration_time": 0.01,
            "temperature": 293.0}
    base.update(cfg)
    base = {k: v for k, v in base.items() if v is not None}
    with pytest.raises(ConfigError, match=key.replace(".", r"\.")):
        PhotonDetector.from_config(base)


def test_bad_bolometer_names_the_key():
    with pytest.raises(ConfigError, match=r"detector\.tcr"):
        Microbolometer.from_config({"pitch": 17e-6, "integration_time": 0.01, "tcr": 0})
    with pytest.raises(ConfigError, match=r"detector\.thermal_conductance"):
        Microbolometer.from_config({"pitch": 17e-6, "integration_time": 0.01,
                                    "thermal_conductance": 0})
