"""Spectral-library readers: ECOSTRESS/ASTER text, USGS splib07 ASCII, ENVI .sli + .hdr, earthlib.

The test files are written here in the real formats (headers as the libraries print them; the
numbers are made up for the test).
"""

import importlib.util
import sys

import numpy as np
import pytest

from radscene.errors import ConfigError
from radscene.materials.libraries import (
    FORMATS,
    LibrarySpectrum,
    SpectralLibrary,
    detect_format,
    read_ecostress,
    read_envi,
    read_library,
    read_spectrum,
    read_usgs,
    write_envi_library,
)

ECOSTRESS_HEADER = """Name: Construction Concrete
Type: Manmade
Class: Concrete
Subclass: Construction Concrete
Particle Size: Solid
Sample No.: 0598UUUCNC
Owner: JHU
Wavelength Range: All
Origin: Runway side strip
Collection Date: N/A
Description: Light grey weathered concrete with granite aggregate.
Sample was slightly soiled.
Measurement: Directional (10 Degree) Hemispherical Reflectance
First Column: X
Second Column: Y
X Units: Wavelength (micrometers)
Y Units: Reflectance (percent)
First X Value: 14.0000
Last X Value: 0.4000
Number of X Values: {n}
Additional Information: manmade.concrete.constructionconcrete.solid.all.0598uuucnc.jhu.becknic.ancillary.txt

"""
# descending wavelength, as the library writes them [um, percent]
ECOSTRESS_ROWS = [(14.0, 6.0), (10.0, 4.0), (8.0, 9.0), (2.5, 30.0), (1.0, 35.0), (0.4, 20.0)]


def write_ecostress(path, rows=ECOSTRESS_ROWS, header=ECOSTRESS_HEADER, n=None):
    text = header.format(n=len(rows) if n is None else n)
    text += "".join(f"{w:.4f}\t{v:.4f}\n" for w, v in rows)
    path.write_text(text, encoding="utf-8")
    return path


def write_usgs(folder, values, wavelengths, title="splib07a Record=4785: Concrete_WTC01-37A ASDFRa AREF"):
    spec = folder / "splib07a_Concrete_WTC01-37A_ASDFRa_AREF.txt"
    spec.write_text(title + "\n" + "".join(f"{v:14.6e}\n" for v in values))
    wl = folder / f"splib07a_Wavelengths_ASD_0.35-2.5_microns_{len(wavelengths)}_ch.txt"
    wl.write_text(
        f"splib07a Record=2: Wavelengths ASD 0.35-2.5 microns {len(wavelengths)} ch\n"
        + "".join(f"{w:12.6f}\n" for w in wavelengths)
    )
    return spec, wl


# --------------------------------------------------------------------- ECOSTRESS / ASTER
def test_ecostress_reads_sorts_and_converts_percent(tmp_path):
    s = read_ecostress(write_ecostress(tmp_path / "concrete.spectrum.txt"))
    assert s.name == "Construction Concrete"
    assert s.quantity == "reflectance"
    np.testing.assert_allclose(s.wavelength, [0.4, 1.0, 2.5, 8.0, 10.0, 14.0], rtol=0, atol=0)
    np.testing.assert_allclose(s.values, [0.20, 0.35, 0.30, 0.09, 0.04, 0.06], rtol=1e-12)
    assert s.metadata["class"] == "Concrete" and s.metadata["sample no."] == "0598UUUCNC"
    # a description continued on the next line stays one field
    assert s.metadata["description"].endswith("Sample was slightly soiled.")
    # every sample knows its line: the 0.4 um row is the last line of the file
    assert s.where(0).endswith(":28")
    m = s.to_material()
    assert float(m.emissivity(10.0)) == pytest.approx(0.96, abs=1e-12)
    with pytest.raises(ConfigError, match="outside the tabulated range"):
        m.emissivity(20.0)  # no silent extrapolation


def test_ecostress_emissivity_and_wavenumber_units(tmp_path):
    header = ECOSTRESS_HEADER.replace("Reflectance (percent)", "Emissivity (fraction)").replace(
        "Wavelength (micrometers)", "Wavenumber (cm-1)"
    )
    rows = [(1250.0, 0.95), (1000.0, 0.97), (714.2857142857143, 0.96)]
    s = read_ecostress(write_ecostress(tmp_path / "e.txt", rows=rows, header=header))
    assert s.quantity == "emissivity"
    np.testing.assert_allclose(s.wavelength, [8.0, 10.0, 14.0], rtol=1e-6)  # 4 decimals in the file
    m = s.to_material()
    assert float(m.reflectance(10.0)) == pytest.approx(0.03, abs=1e-12)


def test_ecostress_repeated_wavelengths_are_merged_and_recorded(tmp_path):
    rows = [(2.5, 30.0), (2.5, 32.0), (0.5, 10.0)]
    s = read_ecostress(write_ecostress(tmp_path / "dup.txt", rows=rows))
    np.testing.assert_allclose(s.values, [0.10, 0.31], rtol=1e-12)
    assert "merged" in s.metadata["merged_rows"]


def test_ecostress_negative_value_names_file_and_line(tmp_path):
    rows = [(14.0, 6.0), (10.0, -0.5), (0.4, 20.0)]
    path = write_ecostress(tmp_path / "neg.txt", rows=rows)
    with pytest.raises(ConfigError, match=r"neg\.txt:24.*negative"):
        read_ecostress(path)


def test_ecostress_truncated_file_and_bad_units(tmp_path):
    with pytest.raises(ConfigError, match=r"announces 9 rows .* has 6"):
        read_ecostress(write_ecostress(tmp_path / "t.txt", n=9))
    bad = ECOSTRESS_HEADER.replace("Reflectance (percent)", "Radiance (W m-2)")
    with pytest.raises(ConfigError, match=r"u\.txt:17: .*Y Units not understood"):
        read_ecostress(write_ecostress(tmp_path / "u.txt", header=bad))
    text = ECOSTRESS_HEADER.format(n=2) + "0.5 10\nabc def\n"
    (tmp_path / "x.txt").write_text(text)
    with pytest.raises(ConfigError, match=r"x\.txt:24: non-numeric"):
        read_ecostress(tmp_path / "x.txt")


def test_reflectance_plus_transmittance_above_one_names_file_and_line(tmp_path):
    s = read_ecostress(write_ecostress(tmp_path / "c.txt"))
    with pytest.raises(ConfigError, match=r"c\.txt:27: material 'leafy'.*exceeds 1"):
        s.to_material("leafy", transmittance=0.7)  # 0.35 + 0.7 at 1.0 um (line 27)
    with pytest.raises(ConfigError, match=r"c\.txt:.*outside \[0, 1\]|exceeds 1"):
        LibrarySpectrum("hot", [0.5, 1.0], [0.5, 1.2], source=str(tmp_path / "c.txt"),
                        lines=[3, 4]).to_material()


# --------------------------------------------------------------------- USGS splib07
def test_usgs_reads_with_wavelength_file_found_beside_it(tmp_path):
    wl = np.linspace(0.35, 2.5, 11)
    values = np.linspace(0.1, 0.3, 11)
    values[3] = -1.23e34  # deleted channel
    spec, wfile = write_usgs(tmp_path, values, wl)
    s = read_usgs(spec)
    assert s.name == "Concrete_WTC01-37A"
    assert s.metadata["instrument"] == "ASD" and s.metadata["deleted_channels"] == "1"
    assert s.metadata["wavelength_file"] == str(wfile)
    keep = np.arange(11) != 3
    np.testing.assert_allclose(s.wavelength, wl[keep], rtol=1e-6)
    np.testing.assert_allclose(s.values, values[keep], rtol=1e-6)
    assert s.where(0).endswith(":2")  # first value on line 2


def test_usgs_needs_a_matching_wavelength_file(tmp_path):
    spec, wfile = write_usgs(tmp_path, [0.1, 0.2, 0.3], [0.4, 0.5, 0.6])
    wfile.unlink()
    with pytest.raises(ConfigError, match="no wavelength file with 3 channels.*wavelength_file="):
        read_usgs(spec)
    other = tmp_path / "w.txt"
    other.write_text("splib07a Record=2: Wavelengths\n0.4\n0.5\n")
    with pytest.raises(ConfigError, match="3 values but the wavelength file w.txt has 2"):
        read_usgs(spec, wavelength_file=other)


def test_usgs_negative_value_names_line(tmp_path):
    spec, _ = write_usgs(tmp_path, [0.1, -0.02, 0.3], [0.4, 0.5, 0.6])
    with pytest.raises(ConfigError, match=r"AREF\.txt:3: .*negative"):
        read_usgs(spec)


# --------------------------------------------------------------------- ENVI
def test_envi_round_trip_big_endian_scale_factor(tmp_path):
    wl = np.array([400.0, 500.0, 700.0, 900.0])  # nanometres
    spectra = np.array([[1000, 2000, 3000, 4000], [500, 500, 600, 9000]], dtype=np.int16)
    write_envi_library(tmp_path / "lib", wl, spectra, ["grass a", "soil_b"], data_type=2,
                       byte_order=1, wavelength_units="Nanometers", reflectance_scale_factor=10000)
    lib = read_envi(tmp_path / "lib.hdr")
    assert lib.names == ["grass a", "soil_b"]
    np.testing.assert_allclose(lib[0].wavelength, [0.4, 0.5, 0.7, 0.9], rtol=1e-12)
    np.testing.assert_allclose(lib[1].values, [0.05, 0.05, 0.06, 0.9], rtol=1e-12)
    assert read_envi(tmp_path / "lib.sli").names == lib.names  # either path works
    # the other header convention, spectra.sli.hdr (earthlib's), and a folder read finds it once
    (tmp_path / "lib.hdr").rename(tmp_path / "lib.sli.hdr")
    assert read_library(tmp_path).names == ["grass a", "soil_b"]


@pytest.mark.skipif(importlib.util.find_spec("spectral") is None, reason="spectral (SPy) not installed")
def test_envi_agrees_with_spy(tmp_path):
    """Independent reader: Spectral Python's envi.open."""
    import spectral.io.envi as envi

    rng = np.random.default_rng(3)
    wl = np.linspace(0.4, 2.5, 7)
    spectra = rng.uniform(0.0, 1.0, (5, 7))
    data, header = write_envi_library(tmp_path / "r.sli", wl, spectra, [f"s{i}" for i in range(5)],
                                      data_type=5)
    ours = read_envi(data)
    spy = envi.open(str(header), str(data))
    np.testing.assert_allclose(np.array([s.values for s in ours]), spy.spectra, rtol=0, atol=0)
    np.testing.assert_allclose(ours[0].wavelength, spy.bands.centers, rtol=1e-6)


def test_envi_unit_rule_without_units_is_stated(tmp_path):
    data, header = write_envi_library(tmp_path / "n.sli", [450.0, 550.0], [[0.1, 0.2]])
    text = header.read_text().replace("wavelength units = Micrometers\n", "")
    header.write_text(text)
    s = read_envi(data)[0]
    np.testing.assert_allclose(s.wavelength, [0.45, 0.55], rtol=1e-12)
    assert s.metadata["wavelength units"].startswith("assumed nanometers")


def test_envi_errors_name_file_and_line(tmp_path):
    data, header = write_envi_library(tmp_path / "e.sli", [0.5, 0.6], [[0.1, -0.2]])
    with pytest.raises(ConfigError, match=r"e\.sli: spectrum 'spectrum_1'.*-0.2 at 0.6 µm"):
        read_envi(data)
    data, header = write_envi_library(tmp_path / "f.sli", [0.5, 0.6], [[0.1, 0.2]])
    header.write_text(header.read_text().replace("data type = 4", "data type = 7"))
    with pytest.raises(ConfigError, match=r"f\.hdr:8: data type 7 not supported"):
        read_envi(data)
    header.write_text(header.read_text().replace("data type = 7", "data type = 5"))
    with pytest.raises(ConfigError, match="has 8 bytes; the header .* needs 16"):
        read_envi(data)
    header.write_text("ENVI\nsamples 2\n")
    with pytest.raises(ConfigError, match=r"f\.hdr:2: header line is not 'key = value'"):
        read_envi(data)


# --------------------------------------------------------------------- detection, folders
def test_detect_format_and_unknown_format(tmp_path):
    eco = write_ecostress(tmp_path / "a.txt")
    spec, wfile = write_usgs(tmp_path, [0.1, 0.2], [0.4, 0.5])
    data, header = write_envi_library(tmp_path / "c.sli", [0.5, 0.6], [[0.1, 0.2]])
    assert (detect_format(eco), detect_format(spec), detect_format(data)) == ("ecostress", "usgs", "envi")
    odd = tmp_path / "odd.csv"
    odd.write_text("wavelength,reflectance\n0.5,0.1\n")
    with pytest.raises(ConfigError, match=r"odd\.csv:1: unknown spectral library format.*accepted"):
        read_library(odd)
    with pytest.raises(ConfigError, match="unknown library format 'specpr'; known: aster, ecostress"):
        read_library(odd, format="specpr")
    assert set(FORMATS) == {"ecostress", "aster", "usgs", "envi"}


def test_read_library_folder_mixes_formats_and_skips_ancillaries(tmp_path):
    write_ecostress(tmp_path / "a.spectrum.txt")
    (tmp_path / "a.ancillary.txt").write_text("Sample No.: 0598UUUCNC\n")
    write_usgs(tmp_path, [0.1, 0.2], [0.4, 0.5])
    write_envi_library(tmp_path / "c.sli", [0.5, 0.6], [[0.1, 0.2], [0.3, 0.4]], ["p", "q"])
    lib = read_library(tmp_path)
    assert sorted(lib.names) == ["Concrete_WTC01-37A", "Construction Concrete", "p", "q"]
    assert "a.ancillary.txt" in lib.skipped
    # files are read in name order: a.spectrum.txt, c.sli, splib07a_...
    assert lib.search(name="*concrete*").names == ["Construction Concrete", "Concrete_WTC01-37A"]
    assert lib.search(name="wtc").names == ["Concrete_WTC01-37A"]  # plain text: substring
    assert lib.search(cls="concrete").names == ["Construction Concrete"]
    with pytest.raises(ConfigError, match="holds 4 spectra"):
        read_spectrum(tmp_path)
    assert read_spectrum(tmp_path / "a.spectrum.txt").name == "Construction Concrete"


def test_spectral_library_get_is_unique():
    s = LibrarySpectrum("ash", [0.4, 2.5], [0.1, 0.2])
    lib = SpectralLibrary([s, s], name="lib")
    with pytest.raises(ConfigError, match=r"2 spectra are named 'ASH' \(indices \[0, 1\]\)"):
        lib.get("ASH")
    with pytest.raises(ConfigError, match="no spectrum named 'sand'"):
        lib.get("sand")


# --------------------------------------------------------------------- earthlib
earthlib_missing = importlib.util.find_spec("earthlib") is None


@pytest.mark.skipif(earthlib_missing, reason="earthlib not installed: pip install earthlib")
def test_earthlib_library_searchable_by_class_and_name():
    from radscene.materials.libraries import earthlib_classes, earthlib_library

    lib = earthlib_library()
    assert len(lib) == 7261  # earthlib 1.1.0
    assert "earthlib" not in sys.modules  # read from its files, not imported
    roads = lib.search(cls="road")
    assert len(roads) == 170 and all(s.metadata["level_3"] == "road" for s in roads)
    assert len(lib.search(level_3="soil")) == 4185
    grass = lib.get("deadgras")
    assert grass.metadata["notes"] == "joint fire science program"
    assert grass.range == (0.4, 2.45)
    # the asphalt built-in is this very spectrum (row 4999, rpaeyg.003-)
    from radscene.materials import get_material

    asphalt = lib[4999]
    assert asphalt.name == "rpaeyg.003-"
    np.testing.assert_allclose(get_material("asphalt").reflectance(asphalt.wavelength),
                               asphalt.values, atol=5e-7, rtol=0)
    classes = earthlib_classes()
    assert classes["impervious/built/road/measured"] == 170
    assert sum(classes.values()) == 7261


def test_earthlib_missing_gives_install_hint(monkeypatch):
    import radscene.materials.libraries.earthlib_reader as mod

    monkeypatch.setattr(mod.importlib.util, "find_spec", lambda name: None)
    with pytest.raises(ConfigError, match=r"earthlib: .*optional dependency.*pip install earthlib.*pip install '\.\[earthlib\]'"):
        mod.earthlib_data_dir()


# --------------------------------------------------------------------- materials from libraries
def test_make_material_from_a_library_file_with_stated_thermal_extension(tmp_path):
    from radscene.materials import make_material

    data, _ = write_envi_library(tmp_path / "v.sli", [0.4, 1.0, 2.4], [[0.1, 0.3, 0.2], [0.2, 0.2, 0.2]],
                                 ["tarmac", "paint"], data_type=5)
    m = make_material({"type": "file", "path": "v.sli", "spectrum": "tarmac", "thermal_emissivity": 0.9},
                      key="materials.road", base_dir=tmp_path)
    assert m.name == "road" and m.wavelength_range == (0.4, 20.0)
    # the stated rule: 1 - eps from 3 um, linear from the last measured point (2.4 um) to 3 um
    assert float(m.reflectance(2.7)) == pytest.approx(0.2 + (0.1 - 0.2) * 0.3 / 0.6, rel=1e-12)
    assert float(m.emissivity(10.0)) == pytest.approx(0.9, rel=1e-12)
    bare = make_material({"type": "file", "path": str(data), "spectrum": 1}, key="materials.p")
    with pytest.raises(ConfigError, match="outside the tabulated range"):
        bare.emissivity(10.0)  # no thermal data: no silent extrapolation
    with pytest.raises(ConfigError, match=r"materials.x.spectrum: the library holds 2 spectra"):
        make_material({"type": "file", "path": str(data)}, key="materials.x")
    with pytest.raises(ConfigError, match=r"unknown keys \['colour'\] for a file material"):
        make_material({"type": "file", "path": str(data), "colour": "red"}, key="materials.x")
    with pytest.raises(ConfigError, match="unknown material type 'brdf'; known: canopy, custom, earthlib"):
        make_material({"type": "brdf"}, key="materials.x")


def test_make_material_file_errors_name_file_and_line(tmp_path):
    from radscene.materials import make_material

    path = write_ecostress(tmp_path / "c.txt")
    with pytest.raises(ConfigError, match=r"c\.txt:27: material 'wall'.*exceeds 1"):
        make_material({"type": "file", "path": str(path), "transmittance": 0.7}, key="materials.wall")


@pytest.mark.skipif(earthlib_missing, reason="earthlib not installed: pip install earthlib")
def test_make_material_from_earthlib():
    from radscene.materials import make_material

    m = make_material({"type": "earthlib", "spectrum": 4285, "thermal_emissivity":
                       {"wavelength": [3.0, 20.0], "values": [0.93, 0.96]}}, key="materials.straw")
    assert m.wavelength_range == (0.4, 20.0)
    assert float(m.emissivity(20.0)) == pytest.approx(0.96, rel=1e-12)
