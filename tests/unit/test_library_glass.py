"""The built-in ``glass``: a clear float-glass pane of the LBNL International Glazing Database.

Figures typed into the tests come from the IGDB v11.4 record of product NFRC ID 102, "Generic
Clear Glass" (IGDB product id 363, data file CLEAR_3.DAT, 3.048 mm, specular): normal-incidence
transmittance T and front reflectance Rf at 0.55 um 0.903 and 0.083, at 1.00 um 0.762 and 0.066,
at 2.50 um 0.822 and 0.068; thermal-infrared transmittance 0; hemispherical emissivity 0.84 on
both faces; NFRC-integrated T_sol 0.8338 and R_f,sol 0.0748. The refractive index of soda-lime
glass, n = 1.5130 - 0.003169 lam^2 + 0.003962 / lam^2 (lam in um), is that of M. Rubin, Sol.
Energy Mater. 12, 275-288 (1985), doi:10.1016/0165-1633(85)90052-8.
"""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pytest

import radscene.materials
import radscene.materials.library
from radscene.materials import get_material, get_thermal_properties, library_info, list_materials
from radscene.materials.brdf import fresnel_reflectance
from radscene.materials.library import LIBRARY_DIR

SOURCE = LIBRARY_DIR / "sources" / "transmittance_igdb_clear_glass_nfrc102.csv"
ROOT = Path(__file__).resolve().parents[2]


def _source():
    lines = [ln for ln in SOURCE.read_text(encoding="utf-8").splitlines()
             if ln.strip() and not ln.startswith("#")]
    header = lines[0].split(",")
    rows = np.array([[float(v) for v in ln.split(",")] for ln in lines[1:]])
    return {name: rows[:, i] for i, name in enumerate(header)}


def test_the_library_lists_glass_and_states_its_count_and_version():
    names = list_materials()
    assert "glass" in names and "glass" in list_materials(category="man-made")
    assert len(names) == 33
    info = library_info()
    assert info["library_version"] == "2.2.0"
    header = (LIBRARY_DIR / "library.yaml").read_text(encoding="utf-8")
    stated = re.search(r"Materials of library (\d+)\.(\d+) \((\d+)\)", header)
    assert stated and int(stated.group(3)) == len(names)
    assert info["library_version"].startswith(f"{stated.group(1)}.{stated.group(2)}.")
    assert f"({len(names)} materials" in radscene.materials.library.__doc__
    assert f"{len(names)} materials spanning" in radscene.materials.__doc__


@pytest.mark.parametrize("path, text", [("README.md", "{n} built-in materials"),
                                        ("docs/architecture.md", "{n} built-in materials")])
def test_the_documents_state_the_count(path, text):
    file = ROOT / path
    if not file.is_file():
        pytest.skip(f"{path} is not beside the tests")
    assert text.format(n=len(list_materials())) in file.read_text(encoding="utf-8")


def test_the_source_file_names_the_igdb_record():
    header = SOURCE.read_text(encoding="utf-8")
    for words in ("IGDB", "version 11.4", "NFRC ID 102", "Generic Clear Glass", "3.048 mm",
                  "LBNL-ETA/pyWinCalc, test/products/CLEAR_3.json", "MEASURED"):
        assert words in header, words
    data = _source()
    wl = data["wavelength_um"]
    assert wl.size == 111 and wl[0] == 0.3 and wl[-1] == 2.5
    steps = np.round(np.diff(wl), 3)
    assert set(steps[wl[:-1] < 0.4]) == {0.005} and set(steps[(wl[:-1] >= 0.4) & (wl[:-1] < 1.0)]) == {0.01}
    assert set(steps[wl[:-1] >= 1.0]) == {0.05}


@pytest.mark.parametrize(
    "wavelength, t, rf",
    [(0.55, 0.903, 0.083), (1.00, 0.762, 0.066), (2.50, 0.822, 0.068), (0.40, 0.893, 0.086)],
)
def test_stored_values_are_the_igdb_figures(wavelength, t, rf):
    m = get_material("glass")
    assert float(m.transmittance(wavelength)) == pytest.approx(t, abs=1e-12)
    assert float(m.reflectance(wavelength)) == pytest.approx(rf, abs=1e-12)


def test_every_measured_point_is_stored_unchanged_and_all_reflectance_is_specular():
    data = _source()
    m = get_material("glass")
    wl = data["wavelength_um"]
    np.testing.assert_allclose(m.transmittance(wl), data["T"], rtol=0, atol=1e-12)
    np.testing.assert_allclose(m.specular_reflectance(wl), data["Rf"], rtol=0, atol=1e-12)
    grid = np.linspace(0.3, 20.0, 1971)
    np.testing.assert_allclose(m.diffuse_reflectance(grid), 0.0, atol=1e-12)
    # short-wave emissivity by Kirchhoff: what the pane absorbs, 1 - R - T
    np.testing.assert_allclose(m.emissivity(wl), 1.0 - data["Rf"] - data["T"], atol=1e-12)
    # the back reflectance, not stored, is within 0.001 of the front one
    assert np.max(np.abs(data["Rb"] - data["Rf"])) <= 0.001 + 1e-12
    assert m.specular_exponent == 2000.0


def test_thermal_infrared_is_opaque_with_the_igdb_emissivity_and_the_join_is_linear():
    m = get_material("glass")
    thermal = np.linspace(3.0, 20.0, 171)
    np.testing.assert_allclose(m.transmittance(thermal), 0.0, atol=0)
    np.testing.assert_allclose(m.emissivity(thermal), 0.84, atol=1e-12)
    # 2.50-3.0 um: linear from the last measured point to the thermal values
    assert float(m.transmittance(2.75)) == pytest.approx(0.822 / 2, abs=1e-12)
    assert float(m.reflectance(2.75)) == pytest.approx((0.068 + 0.16) / 2, abs=1e-12)
    tp = get_thermal_properties("glass")
    assert tp.longwave_emissivity == pytest.approx(0.84, abs=1e-6)


def test_the_measured_reflectance_is_that_of_two_faces_of_soda_lime_glass():
    """A non-absorbing slab reflects 2 R / (1 + R), R the Fresnel reflectance of one face at
    normal incidence; with Rubin's index at 0.55 um (1.525) that is 0.0829, the IGDB's 0.083."""
    lam = 0.55
    n = 1.5130 - 0.003169 * lam**2 + 0.003962 / lam**2
    r = float(fresnel_reflectance(1.0, n))
    slab = 2.0 * r / (1.0 + r)
    assert n == pytest.approx(1.525, abs=5e-4)
    assert float(get_material("glass").specular_reflectance(lam)) == pytest.approx(slab, abs=1e-3)


def test_solar_integrals_agree_with_the_nfrc_figures():
    """Weighted by the ASTM G173-03 global tilted spectrum over 0.3-2.5 um, the stored spectrum
    gives T_sol 0.836 and R_sol 0.0756 against the NFRC's 0.8338 and 0.0748 (NFRC weights with
    its own solar spectrum); the library's solar absorptance (0.4-4 um) 0.090 against the NFRC's
    1 - 0.8338 - 0.0748 = 0.0914."""
    from pvlib.spectrum import get_reference_spectra

    table = get_reference_spectra(standard="ASTM G173-03")
    lam = table.index.to_numpy() / 1000.0
    keep = (lam >= 0.3) & (lam <= 2.5)
    lam, e = lam[keep], table["global"].to_numpy()[keep]
    m = get_material("glass")

    def weighted(values):
        return float(np.trapezoid(values * e, lam) / np.trapezoid(e, lam))

    assert weighted(m.transmittance(lam)) == pytest.approx(0.8338, abs=0.005)
    assert weighted(m.reflectance(lam)) == pytest.approx(0.0748, abs=0.002)
    assert get_thermal_properties("glass").solar_absorptance == pytest.approx(
        1.0 - 0.8338 - 0.0748, abs=0.005)


def test_the_source_labels_each_part():
    source = library_info()["materials"]["glass"]["source"]
    for words in ("0.30-2.50 µm: MEASURED", "2.50-3.0 µm: ASSUMED",
                  "Thermal 3-20 µm: PUBLISHED BROADBAND VALUE, GREY", "emissivity 0.84",
                  "NFRC ID 102", "3.048 mm", "doi:10.1016/0165-1633(85)90052-8",
                  "exponent 2000 ASSUMED"):
        assert words in source, words


def test_the_stack_is_one_pane_of_soda_lime_glass_before_a_room():
    """EN ISO 10456:2007 Table 3, glass, soda lime (including float glass): 1.00 W m-1 K-1,
    2500 kg m-3, 750 J kg-1 K-1; the measured pane's 3.048 mm; a room at 20 degC behind it with
    h_in = 1/R_si = 1/0.13 W m-2 K-1 (EN ISO 6946, horizontal heat flow), as for the brick wall."""
    tp = get_thermal_properties("glass")
    (pane,) = tp.layers
    assert (pane.conductivity, pane.density, pane.specific_heat) == (1.00, 2500.0, 750.0)
    assert pane.thickness == pytest.approx(3.048e-3, rel=1e-12) and "ISO 10456" in pane.source
    assert tp.bottom == {"interior_air": 293.15, "h": 7.7} == get_thermal_properties("brick").bottom
