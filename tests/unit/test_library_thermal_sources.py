"""The thermal-infrared part of every built-in material names its source and extension rule.

Spot checks type figures of the cited sources into the test:

* SLUM - Spectral Library of impervious Urban Materials, S. Kotthaus et al., ISPRS J. Photogramm.
  Remote Sens. 94, 194-212 (2014), data doi:10.5281/zenodo.4263842, file LUMA_SLUM_IR.csv: the
  mean of the measured points of a sample in a 0.1 um bin.
* Hagen-Rubens relation for a metal of DC resistivity r at wavelength lam, normal emissivity
  0.365 sqrt(r / lam) (r in ohm m, lam in m); aluminium r = 2.65e-8 ohm m at 20 C.
* Fresnel hemispherical emissivity of a smooth dielectric of index 1.5: 0.908.
"""

import re

import numpy as np
import pytest

from radscene.materials import get_material, library_info, list_materials

#: Materials whose 3-20 um emissivity is still an assumed table (sources/thermal_emissivity.csv):
#: no measured spectrum of their class and no physical model is at hand.
STILL_ASSUMED = {
    "bare_soil", "bright_soil", "burned_ground", "compacted_dirt", "dark_soil", "gravel", "sand",
    "dry_grass", "leaf_litter", "tree_bark", "weathered_wood", "wood_shingle",
}


def _thermal_part(source: str) -> str:
    """The sentences of a library source that describe its thermal-infrared part: from the range
    that covers 3-20 um up to the description of the specular split or the diffuse VSWIR part."""
    for marker in ("Thermal 3-20 um", "3-20 um", "-20 um", "-20.4 um", "-22.5 um"):
        i = source.find(marker)
        if i >= 0:
            return re.split("Specular|Diffuse", source[i:])[0]
    return ""


@pytest.mark.parametrize("name", sorted(list_materials()))
def test_thermal_part_names_its_source(name):
    source = library_info()["materials"][name]["source"]
    thermal = _thermal_part(source)
    assert thermal, f"{name}: the source says nothing of the thermal part"
    assert any(w in thermal for w in ("MEASURED", "MODEL", "ASSUMED", "measured")), name


@pytest.mark.parametrize("name", sorted(list_materials()))
def test_no_thermal_part_is_assumed_but_the_listed_ones(name):
    thermal = _thermal_part(library_info()["materials"][name]["source"])
    assert ("ASSUMED" in thermal) == (name in STILL_ASSUMED), name


@pytest.mark.parametrize(
    "name, sample", [("asphalt", "A003"), ("fresh_asphalt", "A009"), ("asphalt_shingle", "A003"),
                     ("concrete", "C006"), ("concrete_roof_tile", "C006"), ("roof_tile", "B013")]
)
def test_slum_materials_state_the_sample_and_the_extension_rule(name, sample):
    source = library_info()["materials"][name]["source"]
    assert f"SLUM sample {sample}" in source and "doi:10.1016/j.isprsjprs.2014.05.005" in source
    assert "Extension rule: constant" in source


@pytest.mark.parametrize(
    "name, wavelength, expected",
    [
        ("asphalt", 10.05, 0.951676),  # SLUM A003, 10.0-10.1 um
        ("fresh_asphalt", 10.05, 0.955662),  # SLUM A009, 10.0-10.1 um
        ("concrete", 8.65, 0.938506),  # SLUM C006, 8.6-8.7 um (silicate band)
        ("concrete", 11.05, 0.952469),  # SLUM C006, 11.0-11.1 um
        ("roof_tile", 8.25, 0.900686),  # SLUM B013, 8.2-8.3 um (quartz reststrahlen)
    ],
)
def test_slum_emissivity_matches_the_data_set(name, wavelength, expected):
    assert float(get_material(name).emissivity(wavelength)) == pytest.approx(expected, abs=2e-6)


def test_slum_spectrum_is_extended_by_its_stated_rule():
    m = get_material("asphalt")
    # constant at the first bin (SLUM A003 8.0-8.1 um: 0.908667) below 8 um ...
    np.testing.assert_allclose(m.emissivity([3.0, 5.0, 8.0, 8.05]), 0.908667, atol=2e-6)
    # ... and at the last (13.9-14.0 um: 0.947795) above 14 um
    np.testing.assert_allclose(m.emissivity([13.95, 16.0, 20.0]), 0.947795, atol=2e-6)


def test_aluminium_emissivity_agrees_with_hagen_rubens():
    eps = float(get_material("bare_aluminium").emissivity(10.0))
    hagen_rubens = 0.365 * np.sqrt(2.65e-8 / 10e-6)  # 0.0188
    assert 0.5 * hagen_rubens < eps < 1.5 * hagen_rubens
    assert "Rakic" in library_info()["materials"]["bare_aluminium"]["source"]


@pytest.mark.parametrize("name", ["painted_metal", "white_paint"])
def test_paint_emissivity_is_the_fresnel_value_of_its_binder(name):
    m = get_material(name)
    np.testing.assert_allclose(m.emissivity([3.0, 10.0, 20.0]), 0.908, atol=1e-3)
    assert "n = 1.5" in library_info()["materials"][name]["source"]


@pytest.mark.parametrize("name", sorted(list_materials()))
def test_thermal_kirchhoff_closure(name):
    wl = np.linspace(3.0, 20.0, 341)
    total = sum(get_material(name).components(wl).values())
    np.testing.assert_allclose(total, 1.0, rtol=1e-12)
