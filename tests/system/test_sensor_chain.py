"""The sensor on rendered images: MTF from a rendered slanted edge, energy, truth, examples."""

from __future__ import annotations

import copy

import numpy as np
import pytest
import yaml

from radscene import load_scene, render
from radscene.sensor import (
    example_sensor_path,
    make_sensor,
    slanted_edge_mtf,
    system_mtf,
)
from radscene.sensor.sampling import block_centre, block_mean

K = 4  # rendered samples per detector pitch
N = 64  # detectors across
EDGE_ANGLE = 5.0  # deg


def edge_scene(gsd, shape, bands, card_temperature="320 K"):
    """A dark card, turned by EDGE_ANGLE, over half of a bright plate, seen from nadir."""
    return {
        "name": "slanted_edge",
        "environment": {"sun": {"zenith": 20, "azimuth": 180}, "atmosphere": {"type": "none"}},
        "materials": {"white": {"reflectance": 0.6}, "black": {"reflectance": 0.05}},
        "objects": [
            {"name": "ground", "shape": {"type": "plate", "width": 100, "length": 100},
             "position": [0, 0, 0], "material": "white", "temperature": "300 K"},
            {"name": "card", "shape": {"type": "plate", "width": 100, "length": 100},
             "position": [50, 0, 0.01], "material": "black", "rotation": [EDGE_ANGLE, 0, 0],
             "temperature": card_temperature},
        ],
        "bands": bands,
        "observers": [{"name": "nadir", "type": "orthographic", "center": [0, 0], "gsd": gsd,
                       "shape": list(shape), "altitude": 1000.0, "supersample": 2}],
        "render": {"sky_samples": 1, "shadows": False},
    }


VIS_SENSOR = {
    "name": "vis", "oversample": K,
    "optics": {"focal_length": 0.1, "f_number": 4.0, "wavefront_error": 0.03},
    "detector": {"type": "ccd", "pitch": 10e-6, "quantum_efficiency": 0.6,
                 "integration_time": 0.002, "temperature": 293.0, "read_noise": 5,
                 "full_well": 1e6, "shape": [N, N]},
    "electronics": {"gain": 10.0, "offset": 50, "bits": 16},
    "motion": {"jitter": "15 urad"},
    "bands": {"red": {"response": {"type": "rectangular", "wavelength_min": 0.6,
                                   "wavelength_max": 0.7}}},
}


@pytest.fixture(scope="module")
def edge_images():
    sensor = make_sensor(VIS_SENSOR)
    geo = sensor.observer_geometry()
    scene = load_scene(edge_scene(geo["gsd_per_distance"] * 1000.0, geo["shape"],
                                  [{"name": "red", "min": 0.6, "max": 0.7}]))
    images = render(scene)
    return sensor, images, sensor.apply(images, frames=1, seed=7)


def _expected_mtf(sensor, angle, f):
    th = np.radians(angle)
    fx, fy = f * np.cos(th), f * np.sin(th)
    # the rendered samples are themselves area means over 1/K of a pitch
    render_box = np.abs(np.sinc(fx / K) * np.sinc(fy / K))
    return system_mtf(sensor, fx, fy, "red") * render_box


def test_mtf_measured_from_a_rendered_slanted_edge(edge_images):
    sensor, _, signal = edge_images
    f = np.linspace(0.05, 0.5, 10)  # up to the detector Nyquist frequency
    ideal = slanted_edge_mtf(signal["radiance_optics"].sel(band="red").values[2:-2, 2:-2])
    assert abs(ideal.angle) == pytest.approx(EDGE_ANGLE, abs=0.05)
    expected = _expected_mtf(sensor, ideal.angle, f)
    assert ideal(f) == pytest.approx(expected, abs=0.01)
    # from the digital numbers, with shot, read and quantisation noise
    measured = slanted_edge_mtf(signal["dn"].isel(frame=0).sel(band="red").values[2:-2, 2:-2])
    assert measured(f) == pytest.approx(expected, abs=0.03)


def test_energy_is_preserved_and_truth_is_carried(edge_images):
    _, images, signal = edge_images
    fine = images["radiance"].values
    # 100 % fill factor: the OTF passes the mean exactly (periodic boundary)
    assert float(signal["radiance_optics"].mean()) == pytest.approx(float(fine.mean()), rel=1e-5)
    assert signal["radiance"].values == pytest.approx(block_mean(fine, K), rel=1e-6)
    assert np.array_equal(signal["object_id"].values, block_centre(images["object_id"].values, K))
    assert signal["object_id"].attrs["flag_meanings"] == images["object_id"].attrs["flag_meanings"]
    assert signal["surface_normal"].dims == ("vector", "y", "x")
    assert signal["x"].values == pytest.approx(images["x"].values.reshape(N, K).mean(axis=1))
    assert signal.attrs["render_observer"] == "nadir"
    # eq. 7: the detector flux is the scene flux plus the (here negligible) self-emission
    total = signal["flux_scene"] + sum(signal[f"flux_{t}"] for t in
                                       ("optics", "mounting", "heated_dome", "heated_air"))
    assert signal["flux_detector"].values == pytest.approx(total.values, rel=1e-6)
    # and the expected signal follows from it: mean electrons = flux x R x t / q
    electrons = (signal["detector_signal"] * 0.002 / 1.602176634e-19).values
    assert signal["signal_mean"].values == pytest.approx(electrons, rel=1e-6)


def _example(name, **patch):
    cfg = yaml.safe_load(example_sensor_path(name).read_text())
    cfg = copy.deepcopy(cfg)
    cfg["detector"].pop("shape")
    cfg["detector"].update(patch)
    return make_sensor(cfg)


@pytest.mark.parametrize(("name", "band"), [("lwir_microbolometer", "lwir"),
                                            ("mwir_cooled", "mwir")])
def test_example_sensors_see_a_warm_card(name, band):
    sensor = _example(name)
    resp = sensor.channel(band).response
    lo, hi = resp.support
    pitch_angle = sensor.base.detector.pitch / sensor.base.optics.focal_length
    scene = load_scene(edge_scene(pitch_angle / K * 1000.0, (N * K, N * K),
                                  [{"name": band, "min": lo, "max": hi}]))
    images = render(scene)
    signal = sensor.apply(images, frames=2, seed=3)
    assert not bool(signal["saturated"].any())
    card = images["object_id"].values == 1
    ids = signal["object_id"].values
    rad = signal["radiance"].sel(band=band).values
    inner = np.zeros_like(ids, dtype=bool)
    inner[8:-8, 8:-8] = True
    warm, cool = (ids == 1) & inner, (ids == 0) & inner
    assert card.any() and warm.sum() > 100 and cool.sum() > 100
    dn = signal["dn_raw" if name == "mwir_cooled" else "dn"].isel(frame=0).sel(band=band).values
    assert dn[warm].mean() > dn[cool].mean()
    # the DN step equals the radiance step times the channel's gain (NUC restores it)
    if name == "mwir_cooled":
        ch = sensor.channel(band)
        step = (rad[warm].mean() - rad[cool].mean()) * float(signal["responsivity"].sel(band=band)) \
            * float(np.mean(signal["flux_scene"].values / signal["radiance_optics"].values)) \
            * ch.detector.integration_time / 1.602176634e-19 / ch.electronics.gain
        assert dn[warm].mean() - dn[cool].mean() == pytest.approx(step, rel=0.05)
