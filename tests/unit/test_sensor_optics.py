"""Optics configuration and the flux on the detector (Willers et al. 2011 eq. 7)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from radscene.errors import ConfigError
from radscene.radiometry import (
    RectangularResponse,
    TabulatedResponse,
    band_radiance,
    spectral_radiance,
)
from radscene.sensor.detector import Microbolometer, PhotonDetector
from radscene.sensor.flux import band_radiometry
from radscene.sensor.optics import (
    Optics,
    detector_etendue,
    projected_solid_angle,
    relative_illumination,
)

REL = 1e-9  # quadrature of Planck band integrals against the closed form


def photon(**kw):
    cfg = {"pitch": "20 um", "integration_time": "1 ms", "temperature": "77 K", **kw}
    if "responsivity" not in cfg:
        cfg.setdefault("quantum_efficiency", 0.5)
    return PhotonDetector.from_config(cfg)


def test_two_of_three_define_the_optics():
    a = Optics.from_config({"focal_length": "100 mm", "f_number": 2.5})
    b = Optics.from_config({"focal_length": 0.1, "aperture_diameter": "40 mm"})
    c = Optics.from_config({"f_number": 2.5, "aperture_diameter": 0.04})
    for o in (a, b, c):
        assert o.focal_length == pytest.approx(0.1, rel=1e-12)
        assert o.f_number == pytest.approx(2.5, rel=1e-12)
        assert o.aperture_diameter == pytest.approx(0.04, rel=1e-12)
    with pytest.raises(ConfigError, match="contradicts"):
        Optics.from_config({"focal_length": 0.1, "f_number": 2.0, "aperture_diameter": 0.04})
    with pytest.raises(ConfigError, match="two of"):
        Optics.from_config({"focal_length": 0.1})


@pytest.mark.parametrize("value", [0, -1.0, "0", 0.4])
def test_f_number_not_positive_names_the_key(value):
    with pytest.raises(ConfigError, match=r"optics\.f_number"):
        Optics.from_config({"focal_length": 0.1, "f_number": value})


@pytest.mark.parametrize(("cfg", "key"), [
    ({"obscuration": 1.0}, "optics.obscuration"),
    ({"transmittance": 1.2}, "optics.transmittance"),
    ({"relative_illumination": "cos3"}, "optics.relative_illumination"),
    ({"dome": {"transmittance": 0.9, "colour": "red"}}, "optics.dome.colour"),
    ({"temperature": "-5 K"}, "optics.temperature"),
])
def test_bad_optics_input_names_the_key(cfg, key):
    with pytest.raises(ConfigError, match=key.replace(".", r"\.")):
        Optics.from_config({"focal_length": 0.1, "f_number": 2, **cfg})


def test_solid_angle_etendue_and_cos4():
    assert float(projected_solid_angle(1.0)) == pytest.approx(math.pi / 4, rel=1e-15)
    assert float(projected_solid_angle(0.5 + 1e-12)) == pytest.approx(math.pi, rel=1e-9)
    assert float(detector_etendue(1e-10, 2.0, 0.5)) == pytest.approx(
        1e-10 * math.pi / 16 * 0.75, rel=1e-15)
    assert relative_illumination([0.0, 60.0]) == pytest.approx([1.0, 0.0625], rel=1e-12)
    assert relative_illumination(30.0, "none") == 1.0
    with pytest.raises(ConfigError, match="f_number"):
        projected_solid_angle(0.5)


def test_scene_and_self_emission_terms_of_eq7():
    """Grey spectra: every term is a closed-form Planck band integral times a geometry."""
    optics = Optics.from_config({
        "focal_length": 0.1, "f_number": 2.0, "obscuration": 0.3, "transmittance": 0.8,
        "temperature": 300.0, "mounting": {"temperature": 310.0, "emissivity": 0.9},
        "dome": {"transmittance": 0.9, "emissivity": 0.07, "temperature": 350.0},
        "heated_air": {"emissivity": 0.02, "temperature": 500.0}})
    det = photon(responsivity=2.0)  # flat A/W, so rate = 2 x flux exactly
    band = RectangularResponse(3.0, 5.0)
    rad = band_radiometry(optics, det, band)
    area = (20e-6) ** 2
    omega = math.pi / 16
    g = area * omega
    eps2 = 0.09
    b = {t: band_radiance(3.0, 5.0, t) for t in (300.0, 310.0, 350.0, 500.0)}
    assert rad.scene_flux_factor == pytest.approx(g * (1 - eps2) * 0.8 * 0.9, rel=1e-12)
    expected = {
        "optics": g * ((1 - eps2) * 0.2 + eps2) * b[300.0],
        "mounting": area * (math.pi - omega) * 0.9 * b[310.0],
        "heated_dome": g * (1 - eps2) * 0.8 * 0.07 * b[350.0],
        "heated_air": g * (1 - eps2) * 0.8 * 0.9 * 0.02 * b[500.0],
    }
    for term, value in expected.items():
        assert rad.background_flux[term] == pytest.approx(value, rel=REL), term
        assert rad.background_rate[term] == pytest.approx(2.0 * value, rel=REL), term
    assert rad.responsivity == pytest.approx(2.0, rel=1e-12)


def test_cold_shield_limits_the_mounting_view():
    optics = Optics.from_config({"focal_length": 0.1, "f_number": 4.0, "temperature": 300.0})
    band = RectangularResponse(3.0, 5.0)
    matched = band_radiometry(optics, photon(cold_shield_f_number=4.0), band)
    wider = band_radiometry(optics, photon(cold_shield_f_number=2.0), band)
    assert matched.background_flux["mounting"] == 0.0
    area = (20e-6) ** 2
    assert wider.background_flux["mounting"] == pytest.approx(
        area * (math.pi / 16 - math.pi / 64) * band_radiance(3.0, 5.0, 300.0), rel=REL)
    with pytest.raises(ConfigError, match="cold_shield_f_number"):
        band_radiometry(optics, photon(cold_shield_f_number=5.0), band)


def test_bolometer_in_an_isothermal_enclosure_sees_nothing():
    """Scene, optics and mounting at the substrate temperature: the net exchange is zero."""
    t = 300.0
    optics = Optics.from_config({"focal_length": 0.025, "f_number": 1.0, "transmittance": 0.85,
                                 "obscuration": 0.2, "temperature": t,
                                 "mounting": {"temperature": t}})
    det = Microbolometer.from_config({"pitch": 17e-6, "integration_time": 0.016,
                                      "temperature": t, "absorptance": 0.8})
    band = RectangularResponse(8.0, 14.0)
    rad = band_radiometry(optics, det, band)
    scene = rad.scene_rate_factor * band_radiance(8.0, 14.0, t)
    net = scene + rad.background_rate_total + det.leakage(rad.band_integral)
    assert abs(net) <= 1e-9 * abs(det.leakage(rad.band_integral))


def test_system_response_that_does_not_integrate_names_the_key():
    optics = Optics.from_config({"focal_length": 0.1, "f_number": 2.0})
    blind = photon(quantum_efficiency={"wavelength": [0.3, 1.0, 1.1, 20.0],
                                       "values": [0.8, 0.8, 0.0, 0.0]})
    with pytest.raises(ConfigError, match=r"bands\.lwir\.response"):
        band_radiometry(optics, blind, RectangularResponse(8.0, 12.0), key="bands.lwir.response")
    with pytest.raises(ConfigError, match="response"):
        TabulatedResponse([8.0, 10.0, 12.0], [0.0, 0.0, 0.0])


def test_spectral_transmittance_enters_the_band_mean():
    optics = Optics.from_config({"focal_length": 0.1, "f_number": 2.0,
                                 "transmittance": {"wavelength": [3.0, 5.0], "values": [0.6, 1.0]}})
    band = RectangularResponse(3.0, 5.0)
    rad = band_radiometry(optics, photon(responsivity=1.0), band, scene_weighting="flat")
    g = (20e-6) ** 2 * math.pi / 16
    assert rad.scene_flux_factor == pytest.approx(g * 0.8, rel=1e-12)
    # weighted by a 400 K blackbody, the scene term is exact for a 400 K blackbody scene
    hot = band_radiometry(optics, photon(responsivity=1.0), band, scene_weighting=400.0)
    wl = np.linspace(3.0, 5.0, 200_001)
    integrand = spectral_radiance(wl, 400.0) * np.interp(wl, [3.0, 5.0], [0.6, 1.0])
    exact = g * float(np.sum(0.5 * (integrand[1:] + integrand[:-1]) * np.diff(wl)))
    assert hot.scene_flux_factor * band_radiance(3.0, 5.0, 400.0) == pytest.approx(exact, rel=1e-8)
    assert hot.scene_flux_factor > rad.scene_flux_factor  # the hot end transmits more
    assert rad.band_integral(lambda wl: np.ones_like(wl)) == pytest.approx(2.0, rel=1e-12)
    assert rad.band_integral(lambda wl: wl) == pytest.approx(8.0, rel=1e-12)
