"""Thermal properties of the built-in materials: layers with sources, solar absorptance, emissivity."""

import math

import numpy as np
import pytest
from scipy import integrate

from radscene.errors import ConfigError
from radscene.materials import Material, get_material, list_materials
from radscene.materials.thermal import (
    LONGWAVE_BAND,
    get_thermal_properties,
    longwave_emissivity,
    make_layers,
    solar_absorptance,
    thermal_properties_info,
)
from radscene.radiometry.planck import spectral_radiance


@pytest.mark.parametrize("name", list_materials())
def test_every_material_has_a_valid_stack_and_the_stored_optics_match_the_spectra(name):
    tp = get_thermal_properties(name)
    assert tp.material == name
    if isinstance(tp.bottom, dict):  # a room behind the stack
        assert set(tp.bottom) == {"interior_air", "h"} and 273.15 < tp.bottom["interior_air"] < 313.15
        assert 0.0 < tp.bottom["h"] < 30.0 and tp.layers[-1].thickness > 0
    else:
        assert tp.bottom in ("semi-infinite", "insulated")
    for layer in tp.layers:
        assert layer.conductivity > 0 and layer.density > 0 and layer.specific_heat > 0
        assert layer.source
    assert all(layer.thickness > 0 for layer in tp.layers[:-1])
    if tp.bottom == "semi-infinite":
        assert tp.layers[-1].thickness is None
    m = get_material(name)
    # thermal_optics.csv is generated from the spectra: recompute (6 decimals stored)
    assert tp.solar_absorptance == pytest.approx(solar_absorptance(m), abs=1e-6)
    assert tp.longwave_emissivity == pytest.approx(longwave_emissivity(m), abs=1e-6)


def test_iso_10456_design_values_typed_in():
    # EN ISO 10456:2007 Table 3: asphalt 2100 kg m-3, 0.70 W m-1 K-1, 1000 J kg-1 K-1;
    # aluminium alloys 2800, 160, 880; steel 7800, 50, 450; snow slightly compacted 300, 0.23, 2000
    a = get_thermal_properties("asphalt").surface
    assert (a.density, a.conductivity, a.specific_heat) == (2100.0, 0.70, 1000.0)
    al = get_thermal_properties("bare_aluminium").surface
    assert (al.density, al.conductivity, al.specific_heat) == (2800.0, 160.0, 880.0)
    steel = get_thermal_properties("painted_metal").layers[1]
    assert (steel.density, steel.conductivity, steel.specific_heat) == (7800.0, 50.0, 450.0)
    snow = get_thermal_properties("snow").surface
    assert (snow.density, snow.conductivity, snow.specific_heat) == (300.0, 0.23, 2000.0)
    # glass, soda lime (including float glass) 2500, 1.00, 750
    glass = get_thermal_properties("glass").surface
    assert (glass.density, glass.conductivity, glass.specific_heat) == (2500.0, 1.00, 750.0)
    # EN ISO 13370 Table 7: clay or silt lambda 1.5, rho c 3.0e6; sand or gravel 2.0, about 2.0e6
    soil = get_thermal_properties("bare_soil").surface
    assert soil.conductivity == 1.5 and soil.volumetric_heat_capacity == pytest.approx(3.0e6, rel=1e-12)
    sand = get_thermal_properties("sand").surface
    assert sand.conductivity == 2.0 and sand.volumetric_heat_capacity == pytest.approx(2.0e6, rel=0.02)
    assert "ISO 10456" in a.source and "ISO 13370" in soil.source


def test_layer_derived_quantities():
    a = get_thermal_properties("asphalt").surface
    assert a.diffusivity == pytest.approx(0.70 / (2100.0 * 1000.0), rel=1e-12)
    assert a.thermal_inertia == pytest.approx(math.sqrt(0.70 * 2100.0 * 1000.0), rel=1e-12)


def test_canopy_heat_capacity_follows_its_stated_formula():
    # C = LAI (C_w c_water + C_m c_dry), g cm-2 -> 10 kg m-2, c_water 4186, c_dry 1600
    cases = {"grass_canopy": (2.5, 0.010, 0.005), "deciduous_canopy": (5.0, 0.012, 0.007),
             "conifer_canopy": (4.0, 0.020, 0.025), "sparse_canopy": (1.0, 0.008, 0.008),
             "senescent_canopy": (3.0, 0.004, 0.008), "green_vegetation": (6.0, 0.012, 0.013)}
    for name, (lai, cw, cm) in cases.items():
        c = get_thermal_properties(name).canopy
        assert c["lai"] == lai
        assert c["areal_heat_capacity"] == pytest.approx(lai * 10 * (cw * 4186 + cm * 1600), abs=0.06)


def test_broadband_definitions_on_grey_materials():
    grey = Material.create("grey", reflectance=0.3, transmittance=0.1)
    assert solar_absorptance(grey) == pytest.approx(0.6, rel=1e-12)
    assert longwave_emissivity(grey) == pytest.approx(0.6, rel=1e-12)
    # a step in emissivity at 8 um: independent Planck-weighted quadrature (scipy)
    step = Material.create("step", emissivity={"wavelength": [3.0, 7.999999, 8.0, 20.0],
                                               "values": [0.5, 0.5, 0.9, 0.9]})

    def b(w):
        return float(spectral_radiance(w, 300.0))

    lo, hi = LONGWAVE_BAND
    num = 0.5 * integrate.quad(b, lo, 8.0)[0] + 0.9 * integrate.quad(b, 8.0, hi)[0]
    ref = num / integrate.quad(b, lo, hi)[0]
    assert longwave_emissivity(step) == pytest.approx(ref, rel=1e-5)
    # hotter: more weight at short wavelengths where this material is less emissive
    assert longwave_emissivity(step, temperature=600.0) < longwave_emissivity(step)


def test_broadband_optics_order_materials_as_expected():
    def alpha(n):
        return get_thermal_properties(n).solar_absorptance

    assert alpha("snow") < alpha("white_paint") < alpha("concrete") < alpha("asphalt") < alpha("fresh_asphalt")
    assert get_thermal_properties("polished_aluminium").longwave_emissivity < 0.05
    assert get_thermal_properties("water").longwave_emissivity > 0.95


def test_errors():
    with pytest.raises(ConfigError, match="no thermal properties for 'lava'; known: asphalt"):
        get_thermal_properties("lava")
    with pytest.raises(ConfigError, match=r"layers\[0\].conductivity: must be a finite number > 0; got -1"):
        make_layers([{"conductivity": -1, "density": 1, "specific_heat": 1}])
    with pytest.raises(ConfigError, match=r"layers\[0\].thickness"):
        make_layers([{"conductivity": 1, "density": 1, "specific_heat": 1},
                     {"conductivity": 1, "density": 1, "specific_heat": 1}])
    with pytest.raises(ConfigError, match=r"unknown keys \['colour'\]"):
        make_layers([{"conductivity": 1, "density": 1, "specific_heat": 1, "colour": "red"}])
    narrow = Material.create("narrow", reflectance={"wavelength": [0.5, 2.0], "values": [0.1, 0.1]})
    with pytest.raises(ConfigError, match=r"defined on \[0.5, 2\] µm; the integral needs \[0.4, 4\]"):
        solar_absorptance(narrow)
    with pytest.raises(ConfigError, match="temperature"):
        longwave_emissivity(get_material("asphalt"), temperature=-3.0)
    assert "ISO 10456" in str(thermal_properties_info()["layers"]["asphalt"]["source"])
    assert np.isfinite(get_thermal_properties("Asphalt").solar_absorptance)  # case-insensitive
