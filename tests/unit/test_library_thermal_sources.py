"""The thermal-infrared part of every built-in material names its source and extension rule.

Spot checks type figures of the cited sources into the test:

* SLUM - Spectral Library of impervious Urban Materials, S. Kotthaus et al., ISPRS J. Photogramm.
  Remote Sens. 94, 194-212 (2014), data doi:10.5281/zenodo.4263842, file LUMA_SLUM_IR.csv: the
  mean of the measured points of a sample in a 0.1 um bin.
* Hagen-Rubens relation for a metal of DC resistivity r at wavelength lam, normal emissivity
  0.365 sqrt(r / lam) (r in ohm m, lam in m); aluminium r = 2.65e-8 ohm m at 20 C.
* Fresnel hemispherical emissivity of a smooth dielectric of index 1.5: 0.908.
* 8-14 um band emissivity (hemispherical, weighted by the 300 K Planck radiance) of the soils,
  sand and dry plant matter, the published band levels of sources/thermal_emissivity.csv:
  sand 0.905, the mid-point of the 0.89-0.92 for sands, and clay 0.96, of R. A. Sutherland,
  J. Atmos. Oceanic Technol. 3(1), 199-202 (1986),
  doi:10.1175/1520-0426(1986)003<0199:BASEOS>2.0.CO;2; dry plant matter 0.97, inside the
  0.94-1.00 implied by the 0.0-6.0 % reflectance of dry plant materials of C. D. Elvidge, Remote
  Sens. Environ. 26, 265-285 (1988), and below the under-0.98 emissivities of dry vegetation of
  A. Olioso et al., IEEE Geosci. Remote Sens. Lett. 4(1), 112-116 (2007),
  doi:10.1109/LGRS.2006.885857.
"""

import re
from pathlib import Path

import numpy as np
import pytest

import radscene
from radscene.materials import get_material, library_info, list_materials
from radscene.materials.thermal import longwave_emissivity

#: Label of a thermal part whose 8-14 um band level is a published figure and whose spectral shape
#: is modelled (sources/thermal_emissivity.csv, scaled by scripts/build_material_library.py).
PUBLISHED_BAND = "PUBLISHED BAND VALUE, MODELLED SHAPE"
#: Label of a thermal part that is one published broadband (hemispherical) emissivity, flat in
#: wavelength; the materials that carry it, by that emissivity [-].
PUBLISHED_GREY = "PUBLISHED BROADBAND VALUE, GREY"
GREY_LEVEL = {"glass": 0.84}  # IGDB v11.4, NFRC ID 102, both faces
#: Materials with such a thermal part, by the published band level they take [-].
BAND_LEVEL = {
    "sand": 0.905, "bright_soil": 0.905,  # Sutherland 1986, sands 0.89-0.92 (mid-point)
    "bare_soil": 0.96, "gravel": 0.96, "compacted_dirt": 0.96, "dark_soil": 0.96,
    "burned_ground": 0.96,  # Sutherland 1986, clay
    "dry_grass": 0.97, "wood_shingle": 0.97, "weathered_wood": 0.97, "tree_bark": 0.97,
    "leaf_litter": 0.97,  # Elvidge 1988 (0.94-1.00), Olioso et al. 2007 (below 0.98)
}


def _thermal_part(source: str) -> str:
    """The sentences of a library source that describe its thermal-infrared part: from the range
    that covers 3-20 um up to the description of the specular split or the diffuse VSWIR part."""
    for marker in ("Thermal 3-20 µm", "3-20 µm", "-20 µm", "-20.4 µm", "-22.5 µm"):
        i = source.find(marker)
        if i >= 0:
            return re.split("Specular|Diffuse", source[i:])[0]
    return ""


@pytest.mark.parametrize("name", sorted(list_materials()))
def test_thermal_part_names_its_source(name):
    source = library_info()["materials"][name]["source"]
    thermal = _thermal_part(source)
    assert thermal, f"{name}: the source says nothing of the thermal part"
    assert any(w in thermal for w in ("MEASURED", "MODEL", PUBLISHED_BAND, PUBLISHED_GREY,
                                      "measured")), name
    assert (PUBLISHED_GREY in thermal) == (name in GREY_LEVEL), name


@pytest.mark.parametrize("name", sorted(GREY_LEVEL))
def test_a_grey_thermal_part_is_its_published_value_at_every_wavelength(name):
    thermal = _thermal_part(library_info()["materials"][name]["source"])
    assert f"emissivity {GREY_LEVEL[name]:g}" in thermal and "flat" in thermal, name
    m = get_material(name)
    wl = np.linspace(3.0, 20.0, 341)
    np.testing.assert_allclose(m.emissivity(wl), GREY_LEVEL[name], atol=1e-12)


@pytest.mark.parametrize("name", sorted(list_materials()))
def test_no_thermal_part_is_assumed(name):
    thermal = _thermal_part(library_info()["materials"][name]["source"])
    assert "ASSUMED" not in thermal, name
    assert (PUBLISHED_BAND in thermal) == (name in BAND_LEVEL), name


@pytest.mark.parametrize("name", sorted(BAND_LEVEL))
def test_band_emissivity_is_the_published_figure(name):
    # hemispherical emissivity weighted by the 300 K Planck radiance over 8-14 um
    band = longwave_emissivity(get_material(name), temperature=300.0, band=(8.0, 14.0))
    assert band == pytest.approx(BAND_LEVEL[name], abs=1e-3)
    thermal = _thermal_part(library_info()["materials"][name]["source"])
    assert f"hemispherical emissivity {BAND_LEVEL[name]:g}" in thermal, name
    assert "Salisbury & D'Aria" in thermal and "Uncertainty" in thermal, name
    assert "not measured" in thermal, name


@pytest.mark.parametrize("name, column", [("sand", "sand"), ("bare_soil", "bare_soil"),
                                          ("dry_grass", "dry_grass")])
def test_band_level_scaling_keeps_the_published_shape(name, column):
    # eps = 1 - k (1 - eps_column): the departure from 1 is the column's, times one factor
    source = library_info()["materials"][name]["source"]
    assert f"the {column} column of sources/thermal_emissivity.csv" in source
    path = Path(radscene.__file__).parent / "data/materials/sources/thermal_emissivity.csv"
    lines = [ln for ln in path.read_text().splitlines() if ln and not ln.startswith("#")]
    header = lines[0].split(",")
    rows = np.array([[float(v) for v in ln.split(",")] for ln in lines[1:]])
    wl, shape = rows[:, 0], rows[:, header.index(column)]
    eps = get_material(name).emissivity(wl)
    k = (1.0 - eps) / (1.0 - shape)
    np.testing.assert_allclose(k, k[0], rtol=1e-4)
    assert 0.0 < k[0] and np.all((eps >= 0.0) & (eps <= 1.0))


@pytest.mark.parametrize(
    "name, sample", [("asphalt", "A003"), ("fresh_asphalt", "A009"), ("asphalt_shingle", "A003"),
                     ("concrete", "C006"), ("concrete_roof_tile", "C006"), ("roof_tile", "B013"),
                     ("brick", "B013")]
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
        ("brick", 8.25, 0.900686),  # the same specimen
    ],
)
def test_slum_emissivity_matches_the_data_set(name, wavelength, expected):
    assert float(get_material(name).emissivity(wavelength)) == pytest.approx(expected, abs=2e-6)


@pytest.mark.parametrize(
    "wavelength, expected",
    [(0.55, 0.190713), (0.65, 0.306125), (1.65, 0.499945), (2.2, 0.50669)],
)
def test_brick_short_wave_reflectance_is_the_data_sets(wavelength, expected):
    """SLUM B013's short-wave reflectance (LUMA_SLUM_SW.csv, per cent), the mean of its samples
    within 5 nm of each wavelength: a red brick (0.65 um over 0.55 um 1.6)."""
    assert float(get_material("brick").reflectance(wavelength)) == pytest.approx(expected, abs=2e-6)


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
