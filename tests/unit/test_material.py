"""Tests of radscene.materials.material."""

import dataclasses

import numpy as np
import pytest

from radscene.errors import ConfigError
from radscene.materials import Material, Spectrum


def test_reflectance_only():
    m = Material.create("m", reflectance=0.3, specular_reflectance=0.05, specular_exponent=10)
    assert m.diffuse_reflectance(1.0) == pytest.approx(0.25, abs=1e-15)
    assert m.emissivity(10.0) == pytest.approx(0.7, abs=1e-15)
    assert m.specular_exponent == 10.0


def test_emissivity_only():
    m = Material.create("m", emissivity=0.9, transmittance=0.02, specular_reflectance=0.03)
    # rho_d = 1 - eps - tau - rho_s
    assert m.diffuse_reflectance(5.0) == pytest.approx(0.05, abs=1e-15)
    assert m.emissivity(5.0) == pytest.approx(0.9, abs=1e-15)


def test_both_consistent_tabulated():
    wl = [0.4, 1.0, 10.0]
    rho = [0.1, 0.4, 0.05]
    m = Material.create(
        "m",
        reflectance={"wavelength": wl, "values": rho},
        emissivity={"wavelength": wl, "values": [0.9, 0.6, 0.95]},
    )
    assert m.emissivity([0.4, 10.0]) == pytest.approx([0.9, 0.95], abs=1e-15)


def test_both_inconsistent_raises():
    with pytest.raises(ConfigError, match=r"= 1\.2 at .*Kirchhoff"):
        Material.create("bad", reflectance=0.6, emissivity=0.6)
    # off by more than 1e-6 at one tabulated wavelength only
    with pytest.raises(ConfigError, match="at 2 µm"):
        Material.create(
            "bad",
            reflectance={"wavelength": [1, 2, 3], "values": [0.1, 0.2, 0.3]},
            emissivity={"wavelength": [1, 2, 3], "values": [0.9, 0.79, 0.7]},
        )
    # within 1e-6: accepted
    Material.create("ok", reflectance=0.6, emissivity=0.4 + 5e-7)


def test_neither_raises():
    with pytest.raises(ConfigError, match="give reflectance .* or emissivity"):
        Material.create("m")


def test_check_names_material_and_first_wavelength():
    # specular larger than total reflectance between 2 and 3 um
    with pytest.raises(
        ConfigError, match=r"'shiny'.*diffuse_reflectance = -0\.1 at wavelength 2 µm"
    ):
        Material.create(
            "shiny",
            reflectance={"wavelength": [1, 2, 3], "values": [0.5, 0.1, 0.1]},
            specular_reflectance=0.2,
        )
    with pytest.raises(ConfigError, match="'leaky': reflectance \\+ transmittance = 1.1 exceeds 1"):
        Material.create("leaky", reflectance=0.7, transmittance=0.4)
    with pytest.raises(ConfigError, match=r"'bright': reflectance = 1\.2 is outside \[0, 1\]"):
        Material.create("bright", reflectance=1.2)
    # the constructor (spectra given directly) still checks every component
    with pytest.raises(ConfigError, match="emissivity = -0.1 .*must not exceed 1"):
        Material(name="leaky", diffuse_reflectance=Spectrum.constant(0.7),
                 transmittance=Spectrum.constant(0.4))


def test_check_is_exact_at_knots_of_either_spectrum():
    # tau peaks at 1.5 um, a knot of tau only; rho is tabulated at 1 and 2 um
    rho = Spectrum.from_table([1.0, 2.0], [0.5, 0.5])
    tau = Spectrum.from_table([1.0, 1.5, 2.0], [0.1, 0.6, 0.1])
    with pytest.raises(ConfigError, match="at wavelength 1.5 µm"):
        Material(name="m", diffuse_reflectance=rho, transmittance=tau)


def test_check_explicit_wavelengths():
    m = Material.create("m", reflectance={"wavelength": [1, 2], "values": [0.2, 0.3]})
    m.check([1.0, 1.5, 2.0])
    with pytest.raises(ConfigError, match="outside the tabulated range"):
        m.check([0.5])


def test_components_shapes_and_values():
    m = Material.create(
        "m",
        reflectance={"wavelength": [1, 3], "values": [0.2, 0.4]},
        transmittance=0.1,
        specular_reflectance=0.05,
    )
    wl = np.array([[1.0, 2.0], [3.0, 2.5]])
    comps = m.components(wl)
    assert set(comps) == {
        "diffuse_reflectance",
        "specular_reflectance",
        "transmittance",
        "emissivity",
    }
    for arr in comps.values():
        assert arr.shape == (2, 2) and arr.dtype == np.float64
    assert comps["emissivity"] == pytest.approx(
        1 - np.array([[0.2, 0.3], [0.4, 0.35]]) - 0.1, abs=1e-15
    )
    total = sum(comps.values())
    assert total == pytest.approx(np.ones((2, 2)), rel=1e-15)
    assert m.reflectance(2.0) == pytest.approx(0.3, abs=1e-15)
    assert m.emissivity_spectrum(2.0) == pytest.approx(0.6, abs=1e-15)


def test_frozen_and_types():
    m = Material.create("m", reflectance=0.3)
    with pytest.raises(dataclasses.FrozenInstanceError):
        m.name = "x"
    with pytest.raises(ConfigError, match="must be a Spectrum"):
        Material(name="m", diffuse_reflectance=0.3)
    for bad in (-1.0, float("nan"), float("inf"), "10"):
        with pytest.raises(ConfigError, match="specular_exponent must be a finite number >= 0"):
            Material.create("m", reflectance=0.3, specular_exponent=bad)


def test_errors_name_key():
    with pytest.raises(ConfigError) as info:
        Material.create("m", reflectance="high", key="objects[1].material")
    assert info.value.key == "objects[1].material.reflectance"


def test_scalar_input_returns_0d_arrays_and_pickles():
    import pickle

    m = Material.create("m", reflectance={"wavelength": [1, 3], "values": [0.2, 0.4]})
    assert isinstance(m.emissivity(2.0), np.ndarray) and m.emissivity(2.0).shape == ()
    assert all(isinstance(v, np.ndarray) for v in m.components(2.0).values())
    clone = pickle.loads(pickle.dumps(m))
    assert clone.emissivity(2.0) == pytest.approx(0.7, abs=1e-15)
