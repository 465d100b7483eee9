"""The `none` and `uniform` atmosphere engines and their registry."""

from __future__ import annotations

import numpy as np
import pytest

from radscene.atmosphere import ENGINES, make_atmosphere, zenith_hat_weights
from radscene.errors import ConfigError


def test_vacuum_is_transparent_and_dark():
    atm = make_atmosphere({"type": "none"})
    wl = np.array([0.5, 10.0])
    path = atm.path(1000.0, 0.0, 30.0, wl)
    assert path.transmittance == pytest.approx([1.0, 1.0])
    assert path.radiance == pytest.approx([0.0, 0.0])
    assert atm.sky(np.array([10.0]), np.array([0.0]), wl).shape == (1, 2)
    sun = atm.sun(0.0, 30.0, wl, np.array([1800.0, 4.0]))
    assert sun.irradiance == pytest.approx([1800.0, 4.0])


def test_uniform_spectra_and_tabulated_sky():
    atm = make_atmosphere({"type": "UNIFORM", "transmittance": {"wavelength": [0.4, 1.0],
                                                              "values": [0.6, 0.8]},
                           "sun_transmittance": 0.5, "path_radiance": 3.0, "sky_radiance": 2.0,
                           "sky_zenith": [0, 60, 90], "sky_profile": [1.0, 2.0, 4.0]})
    wl = np.array([0.4, 0.7, 1.0])
    path = atm.path(np.array([100.0, 200.0]), 0.0, 0.0, wl)
    assert path.transmittance.shape == (2, 3)
    assert path.transmittance[0] == pytest.approx([0.6, 0.7, 0.8])
    assert path.thermal_radiance == pytest.approx(np.full((2, 3), 3.0))
    sky = atm.sky(np.array([0.0, 30.0, 75.0, 90.0]), 0.0, wl)
    assert sky[:, 0] == pytest.approx([2.0, 3.0, 6.0, 8.0])
    assert atm.sun(0.0, 10.0, wl, np.ones(3)).transmittance == pytest.approx([0.5] * 3)
    assert atm.sky_zenith_nodes() == pytest.approx([0, 60, 90])


def test_hat_weights_sum_to_one():
    w = zenith_hat_weights(np.array([[0.0, 15.0], [70.0, 95.0]]), [0.0, 30.0, 90.0])
    assert w.shape == (2, 2, 3)
    assert w.sum(axis=-1) == pytest.approx(np.ones((2, 2)))
    assert w[0, 1] == pytest.approx([0.5, 0.5, 0.0])


@pytest.mark.parametrize(("spec", "match"), [
    ({"type": "modtran9"}, "unknown atmosphere engine 'modtran9'; known: none, uniform"),
    ({"transmittance": 0.5}, "'type' key"),
    ({"type": "uniform", "transmittance": 1.5}, "transmittance must lie in"),
    ({"type": "uniform", "path_radiance": -1.0}, "radiance must be >= 0"),
    ({"type": "uniform", "sky_zenith": [0, 60]}, "give both sky_zenith and sky_profile"),
    ({"type": "uniform", "sky_zenith": [60, 0], "sky_profile": [1, 1]}, "increasing"),
    ({"type": "uniform", "visibility": 5}, "the .uniform. engine takes no key .visibility.; it takes: transmittance"),
])
def test_bad_parameters_name_the_key(spec, match):
    with pytest.raises(ConfigError, match=match):
        make_atmosphere(spec)


def test_wavelength_outside_the_engine_range_is_refused():
    atm = ENGINES["uniform"]()
    with pytest.raises(ConfigError, match="covers"):
        atm.path(0.0, 0.0, 0.0, np.array([0.1]))
