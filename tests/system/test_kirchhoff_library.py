"""System test: every built-in material obeys Kirchhoff's law on 0.4-20 um, states its sources and
has thermal properties."""

import sys

import numpy as np
import pytest

from radscene.errors import ConfigError
from radscene.materials import Material, get_material, library_info, list_materials

REQUIRED = {
    "green_vegetation",
    "dry_grass",
    "bare_soil",
    "sand",
    "asphalt",
    "concrete",
    "water",
    "painted_metal",
    "bare_aluminium",
    "roof_tile",
}
GRID = np.linspace(0.4, 20.0, 3921)  # 5 nm steps


def test_library_has_the_required_materials():
    assert REQUIRED <= set(list_materials())
    assert len(list_materials()) >= 30  # issue 4, item 4


@pytest.mark.parametrize("name", sorted(list_materials()))
def test_every_source_says_what_is_measured_modelled_or_assumed(name):
    source = library_info()["materials"][name]["source"]
    assert any(word in source for word in ("MEASURED", "MODEL", "ASSUMED")), name
    # every thermal part is labelled: a measurement, a model, a published band value with a
    # modelled shape or an assumption, never silent
    # (tests/unit/test_library_thermal_sources.py checks the thermal part itself)
    labels = ("MODEL", "ASSUMED", "MEASURED 8.0-14.0 µm", "PUBLISHED BAND VALUE, MODELLED SHAPE")
    assert any(w in source for w in labels), name
    assert "doi:" in source or "https://" in source, name


@pytest.mark.parametrize("name", sorted(list_materials()))
def test_every_material_has_thermal_properties(name):
    from radscene.materials import get_thermal_properties

    tp = get_thermal_properties(name)
    assert tp.layers and all(layer.source for layer in tp.layers)
    assert 0.0 < tp.solar_absorptance < 1.0
    assert 0.0 < tp.longwave_emissivity < 1.0


@pytest.mark.parametrize("name", sorted(list_materials()))
def test_kirchhoff_and_bounds(name):
    comps = get_material(name).components(GRID)
    total = sum(comps.values())
    np.testing.assert_allclose(total, 1.0, rtol=1e-12, atol=0)
    for label, values in comps.items():
        assert values.shape == GRID.shape
        assert np.all((values >= 0.0) & (values <= 1.0)), f"{name}.{label}"


@pytest.mark.parametrize("name", sorted(list_materials()))
def test_metadata_and_range(name):
    m = get_material(name)
    entry = library_info()["materials"][name]
    assert m.source == entry["source"] and len(m.source) > 100
    assert m.description and m.category
    lo, hi = m.wavelength_range
    assert lo <= 0.4 and hi >= 20.0
    with pytest.raises(ConfigError, match="outside the tabulated range"):
        m.emissivity(25.0)


def test_water_is_fresnel_specular_with_narrow_lobe():
    water = get_material("water")
    # independent: normal-incidence Fresnel reflectance for n = 1.333 (Hale & Querry, 0.55 um)
    assert water.specular_reflectance(0.55) == pytest.approx((0.333 / 2.333) ** 2, rel=1e-3)
    assert water.specular_exponent >= 200.0
    assert water.diffuse_reflectance(0.55) < 0.02
    # n = 1.218, k = 0.0508 at 10 um
    r10 = (0.218**2 + 0.0508**2) / (2.218**2 + 0.0508**2)
    assert water.emissivity(10.0) == pytest.approx(1.0 - r10, abs=1e-6)  # CSV has 6 decimals


def test_metals_have_specular_lobes_and_aluminium_low_emissivity():
    for name in ("painted_metal", "bare_aluminium"):
        m = get_material(name)
        assert m.specular_exponent > 0.0
        assert np.all(m.specular_reflectance(GRID) > 0.0)
    assert np.all(get_material("bare_aluminium").emissivity(np.linspace(8, 14, 61)) < 0.1)


def test_lookup_is_case_insensitive_and_cached():
    assert get_material("Asphalt") is get_material("asphalt")
    with pytest.raises(
        ConfigError, match="unknown material 'asfalt'; known: asphalt, asphalt_shingle, bare_al"
    ):
        get_material("asfalt")


def test_library_info_is_a_copy_with_licence():
    info = library_info()
    assert "MIT" in info["licence"] and "CC0" in info["licence"]
    info["materials"].clear()
    assert REQUIRED <= set(library_info()["materials"])


def test_runtime_does_not_need_earthlib():
    for name in list_materials():
        get_material(name)
    assert "earthlib" not in sys.modules


def test_inconsistent_reflectance_and_emissivity_raise():
    with pytest.raises(ConfigError, match="Kirchhoff"):
        Material.create("bad", reflectance=0.6, emissivity=0.6)
