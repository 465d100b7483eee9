"""Tests of radscene.materials.spectrum."""

import numpy as np
import pytest

from radscene.errors import ConfigError
from radscene.materials import Spectrum, make_spectrum
from radscene.materials.spectrum import linear_combination, union_wavelengths


def test_constant_shape_range_and_nan():
    s = Spectrum.constant(0.3, name="c")
    wl = np.array([[0.5, 1.0, np.nan], [2.0, 10.0, 20.0]])
    out = s(wl)
    assert out.shape == wl.shape
    assert out[0, 0] == pytest.approx(0.3, abs=0.0)
    assert np.isnan(out[0, 2])
    assert s.range == (0.0, float("inf"))
    assert s.wavelength is None and s.is_constant
    assert s(1.0).shape == ()


def test_table_interpolation_reference_values():
    s = Spectrum.from_table([0.4, 1.0, 2.0], [0.1, 0.4, 0.2], name="t")
    # hand-computed: 0.7 -> 0.1 + 0.3 * 0.5 ; 1.5 -> 0.4 - 0.2 * 0.5
    assert s([0.4, 0.7, 1.0, 1.5, 2.0]) == pytest.approx([0.1, 0.25, 0.4, 0.3, 0.2], abs=1e-15)
    assert s.range == (0.4, 2.0)


def test_table_keeps_input_shape():
    s = Spectrum.from_table([1.0, 3.0], [0.0, 1.0])
    wl = np.full((2, 3, 4), 2.0)
    assert s(wl).shape == (2, 3, 4)
    assert np.all(s(wl) == 0.5)


def test_extend_error_names_spectrum_and_range():
    s = Spectrum.from_table([0.4, 2.5], [0.1, 0.2], name="grass.reflectance")
    with pytest.raises(ConfigError, match=r"grass\.reflectance.*\[0\.4, 2\.5\]"):
        s([1.0, 3.0])
    with pytest.raises(ConfigError, match="outside"):
        s(0.39)


def test_extend_edge_holds_end_values():
    s = Spectrum.from_table([0.4, 2.5], [0.1, 0.2], extend="edge")
    assert s([0.1, 0.4, 100.0]) == pytest.approx([0.1, 0.1, 0.2], abs=0.0)
    assert s.extend == "edge"
    assert s.range == (0.4, 2.5)


@pytest.mark.parametrize(
    ("wavelength", "values", "extend", "match"),
    [
        ([1.0, 1.0], [0.1, 0.2], "error", "strictly increasing"),
        ([2.0, 1.0], [0.1, 0.2], "error", "strictly increasing"),
        ([1.0], [0.1], "error", "at least 2"),
        ([1.0, 2.0], [0.1], "error", "shape"),
        ([-1.0, 2.0], [0.1, 0.2], "error", "positive"),
        ([1.0, 2.0], [0.1, np.nan], "error", "finite"),
        ([1.0, 2.0], [0.1, 0.2], "linear", "extend must be one of"),
    ],
)
def test_invalid_tables(wavelength, values, extend, match):
    with pytest.raises(ConfigError, match=match):
        Spectrum.from_table(wavelength, values, extend=extend)


def test_non_positive_wavelength_query_raises():
    with pytest.raises(ConfigError, match="positive"):
        Spectrum.constant(0.5)(0.0)


def test_immutable():
    s = Spectrum.from_table([1.0, 2.0], [0.1, 0.2])
    with pytest.raises(ValueError, match="read-only"):
        s.values[0] = 5.0
    with pytest.raises(AttributeError):
        s.name = "other"
    src = np.array([0.1, 0.2])
    s2 = Spectrum.from_table([1.0, 2.0], src)
    src[0] = 9.0
    assert s2.values[0] == 0.1


def test_from_file_micrometres_with_header_and_comments(tmp_path):
    path = tmp_path / "r.csv"
    path.write_text(
        "# a comment\nwavelength_um, reflectance, other  # trailing\n0.5,0.1,1\n\n1.5,0.3,2\n"
    )
    s = Spectrum.from_file(path)
    assert s.range == (0.5, 1.5)
    assert s(1.0) == pytest.approx(0.2, abs=1e-15)
    assert Spectrum.from_file(path, column="other")(1.0) == pytest.approx(1.5, abs=1e-15)
    assert Spectrum.from_file(path, column=2)(0.5) == pytest.approx(1.0, abs=0.0)
    assert str(path) in s.source


@pytest.mark.parametrize("label", ["wavelength_nm", "Wavelength(nm)", "lambda[nm]", "nanometers"])
def test_from_file_nanometres_by_header(tmp_path, label):
    path = tmp_path / "r.txt"
    path.write_text(f"{label}\tvalue\n400\t0.1\n2500\t0.5\n")
    assert Spectrum.from_file(path).range == pytest.approx((0.4, 2.5), rel=1e-15)


def test_from_file_no_header_whitespace_is_micrometres(tmp_path):
    path = tmp_path / "r.dat"
    path.write_text("8 0.9\n14 0.95\n")
    assert Spectrum.from_file(path).range == (8.0, 14.0)


def test_from_file_errors(tmp_path):
    with pytest.raises(ConfigError, match="cannot read"):
        Spectrum.from_file(tmp_path / "missing.csv")
    bad = tmp_path / "bad.csv"
    bad.write_text("wl,r\n1,0.1\nfoo,bar\n")
    with pytest.raises(ConfigError, match="line 3.*not numeric"):
        Spectrum.from_file(bad)
    good = tmp_path / "good.csv"
    good.write_text("wl,r\n1,0.1\n2,0.2\n")
    with pytest.raises(ConfigError, match="column 2 is not a value column"):
        Spectrum.from_file(good, column=2)
    with pytest.raises(ConfigError, match=r"'x' is not in the header of .*\(its header names 1 value column\(s\)\)"):
        Spectrum.from_file(good, column="x")
    single = tmp_path / "single.csv"
    single.write_text("1\n2\n")
    with pytest.raises(ConfigError, match="at least one value column"):
        Spectrum.from_file(single)


def test_make_spectrum_forms(tmp_path):
    assert make_spectrum(0.25)(3.0) == pytest.approx(0.25, abs=0.0)
    table = make_spectrum({"wavelength": [1, 2], "values": [0, 1], "extend": "edge"}, key="k")
    assert table.extend == "edge" and table.name == "k"
    (tmp_path / "e.csv").write_text("wavelength_um,emissivity\n8,0.9\n12,0.98\n")
    from_file = make_spectrum({"file": "e.csv"}, key="m.emissivity", base_dir=tmp_path)
    assert from_file(10.0) == pytest.approx(0.94, rel=1e-12)
    assert from_file.name == "m.emissivity"
    assert make_spectrum(table) is table


@pytest.mark.parametrize(
    ("spec", "match"),
    [
        ("0.3", "a spectrum is a number"),
        (True, "a spectrum is a number"),
        ({"values": [1, 2]}, "needs 'wavelength' and 'values'"),
        ({"wavelength": [1, 2], "values": [0, 1], "colour": 1}, "unknown keys"),
        ({"file": "x.csv", "units": "nm"}, "unknown keys"),
    ],
)
def test_make_spectrum_errors_name_key(spec, match):
    with pytest.raises(ConfigError, match=match) as info:
        make_spectrum(spec, key="objects[2].material.reflectance")
    assert info.value.key == "objects[2].material.reflectance"


def test_arithmetic_is_exact_on_union_of_knots():
    a = Spectrum.from_table([1.0, 2.0, 3.0], [0.1, 0.5, 0.2])
    b = Spectrum.from_table([1.5, 2.5], [0.2, 0.1], extend="edge")
    c = 1.0 - a - 2.0 * b
    wl = np.linspace(1.0, 3.0, 101)
    assert c(wl) == pytest.approx(1.0 - a(wl) - 2.0 * b(wl), abs=1e-14)
    assert c.range == (1.0, 3.0) and c.extend == "error"
    assert set(union_wavelengths([a, b])) <= set(c.wavelength)
    assert (Spectrum.constant(0.2) + 0.3)(5.0) == pytest.approx(0.5, abs=1e-15)


def test_combination_range_rules():
    a = Spectrum.from_table([1.0, 3.0], [0.1, 0.2])
    b = Spectrum.from_table([2.0, 5.0], [0.3, 0.4])
    assert (a + b).range == (2.0, 3.0)
    edge = Spectrum.from_table([1.0, 3.0], [0.1, 0.2], extend="edge")
    edge2 = Spectrum.from_table([2.0, 5.0], [0.3, 0.4], extend="edge")
    both = edge + edge2
    assert both.extend == "edge" and both.range == (1.0, 5.0)
    assert both(10.0) == pytest.approx(0.6, abs=1e-15)
    far = Spectrum.from_table([8.0, 9.0], [0.3, 0.4], name="far")
    with pytest.raises(ConfigError, match="no common wavelength range"):
        linear_combination([(1.0, a), (1.0, far)])
    with pytest.raises(TypeError):
        a * b


def test_scalar_input_returns_0d_array_and_pickles():
    import pickle

    for s in (Spectrum.constant(0.2), Spectrum.from_table([1.0, 2.0], [0.1, 0.2], name="p")):
        out = s(1.5)
        assert isinstance(out, np.ndarray) and out.shape == ()
        clone = pickle.loads(pickle.dumps(s))
        assert clone(1.5) == pytest.approx(float(out), abs=0.0)
        assert clone.name == s.name and clone.extend == s.extend
