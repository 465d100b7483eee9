"""The tabulated BRDF: file format, interpolation, reciprocity, extension rule, bad files."""

import numpy as np
import pytest

from radscene.errors import ConfigError
from radscene.materials.brdf import make_brdf
from radscene.materials.brdf.tabulated import read_table, write_table

ZEN = np.arange(0.0, 90.1, 10.0)
PHI = np.arange(0.0, 180.1, 30.0)


#: At the nodes the table is returned up to the round-off of recovering Δφ from cosines (the
#: arccos near 0 and 180 deg amplifies rounding) [-].
NODE_REL = 1e-8


def _smooth(ti, to, phi):
    """A smooth reciprocal test BRDF [sr-1]: grey plus a backscatter bump."""
    ti, to, phi = np.radians(ti), np.radians(to), np.radians(phi)
    cos_g = np.cos(ti) * np.cos(to) + np.sin(ti) * np.sin(to) * np.cos(phi)
    return (0.2 + 0.05 * cos_g) / np.pi


def _write(tmp_path, name="t.csv", **kw):
    ti, to, ph = np.meshgrid(ZEN, ZEN, PHI, indexing="ij")
    return write_table(tmp_path / name, ZEN, ZEN, PHI, _smooth(ti, to, ph), **kw)


def test_nodes_are_reproduced_and_between_them_interpolated(tmp_path):
    m = make_brdf({"type": "tabulated", "file": str(_write(tmp_path))})
    ti, to, ph = np.meshgrid(ZEN[:-1], ZEN[:-1], PHI, indexing="ij")
    assert m.f_angles(ti, to, ph) == pytest.approx(_smooth(ti, to, ph), rel=NODE_REL)
    rng = np.random.default_rng(2)
    a, b, c = rng.uniform(0, 89, 300), rng.uniform(0, 89, 300), rng.uniform(0, 360, 300)
    # linear interpolation of a smooth function on a 10 deg x 30 deg grid
    assert m.f_angles(a, b, c) == pytest.approx(_smooth(a, b, c), rel=0.03)
    assert m.asymmetry == pytest.approx(0.0, abs=1e-12)


def test_brf_column_and_base_dir(tmp_path):
    path = tmp_path / "brf.csv"
    lines = ["# grey BRF 0.3", "incidence_zenith view_zenith relative_azimuth brf"]
    lines += [f"{a} {b} {c} 0.3" for a in (0, 90) for b in (0, 90) for c in (0, 180)]
    path.write_text("\n".join(lines))
    m = make_brdf({"type": "tabulated", "file": "brf.csv", "source": "test"},
                  base_dir=tmp_path)
    assert float(m.f_angles(40.0, 10.0, 77.0)) == pytest.approx(0.3 / np.pi, rel=1e-12)
    assert float(m.albedo([0, 0, 1.0])) == pytest.approx(0.3, abs=1e-6)
    assert m.config()["source"] == "test"


def test_wavelength_column_and_its_range(tmp_path):
    ti, to, ph = np.meshgrid(ZEN, ZEN, PHI, indexing="ij")
    f = _smooth(ti, to, ph)
    path = write_table(tmp_path / "w.csv", ZEN, ZEN, PHI, np.stack([f, 2 * f]),
                       wavelength=[1.0, 3.0])
    m = make_brdf({"type": "tabulated", "file": str(path)})
    got = m.f_angles(20.0, 30.0, 60.0, np.array([1.0, 2.0, 3.0]))
    assert got == pytest.approx(_smooth(20.0, 30.0, 60.0) * np.array([1.0, 1.5, 2.0]),
                                rel=NODE_REL)
    with pytest.raises(ConfigError, match=r"wavelength 5 µm is outside the range \[1, 3\]"):
        m.f_angles(20.0, 30.0, 60.0, 5.0)
    with pytest.raises(ConfigError, match="pass wavelength"):
        m.f_angles(20.0, 30.0, 60.0)
    edge = make_brdf({"type": "tabulated", "file": str(path), "extend": "edge"})
    assert float(edge.f_angles(20.0, 30.0, 60.0, 5.0)) == pytest.approx(
        2 * _smooth(20.0, 30.0, 60.0), rel=NODE_REL)


def test_asymmetric_table_is_evaluated_by_its_reciprocal_part(tmp_path):
    ti, to, ph = np.meshgrid(ZEN, ZEN, PHI, indexing="ij")
    f = _smooth(ti, to, ph) * (1.0 + 0.1 * np.sin(np.radians(ti)))  # not reciprocal
    path = write_table(tmp_path / "a.csv", ZEN, ZEN, PHI, f)
    m = make_brdf({"type": "tabulated", "file": str(path)})
    # largest |T(i, o) - T(o, i)| relative to the largest value, on the table's own grid
    assert m.asymmetry == pytest.approx(np.abs(f - f.transpose(1, 0, 2)).max() / f.max(),
                                        rel=1e-12)
    got = m.f_angles(30.0, 60.0, 90.0)
    assert float(got) == pytest.approx(float(m.f_angles(60.0, 30.0, 90.0)), rel=1e-14)
    t30 = _smooth(30.0, 60.0, 90.0)
    expected = 0.5 * t30 * ((1 + 0.1 * np.sin(np.radians(30.0)))
                            + (1 + 0.1 * np.sin(np.radians(60.0))))
    assert float(got) == pytest.approx(expected, rel=NODE_REL)


def test_partial_angle_coverage_needs_extend_edge(tmp_path):
    zen = np.arange(0.0, 70.1, 10.0)
    ti, to, ph = np.meshgrid(zen, zen, PHI, indexing="ij")
    path = write_table(tmp_path / "p.csv", zen, zen, PHI, _smooth(ti, to, ph))
    with pytest.raises(ConfigError, match=r"incidence_zenith spans \[0, 70\] deg, not "
                                          r"\[0, 90\]; set extend: edge"):
        make_brdf({"type": "tabulated", "file": str(path)})
    m = make_brdf({"type": "tabulated", "file": str(path), "extend": "edge"})
    assert float(m.f_angles(85.0, 10.0, 0.0)) == pytest.approx(_smooth(70.0, 10.0, 0.0),
                                                               rel=NODE_REL)


@pytest.mark.parametrize(("text", "message"), [
    ("incidence_zenith,view_zenith,azimuth,brdf\n", r"t\.csv:1: column 3 is none of"),
    ("incidence_zenith,view_zenith,brdf\n", r"t\.csv:1: missing column 'relative_azimuth'"),
    ("incidence_zenith,view_zenith,relative_azimuth,brdf,brf\n", r"exactly one of"),
    ("# c\nincidence_zenith,view_zenith,relative_azimuth,brdf\n0,0,0\n",
     r"t\.csv:3: expected 4 columns"),
    ("incidence_zenith,view_zenith,relative_azimuth,brdf\n0,0,zero,0.1\n",
     r"t\.csv:2: column 3 is not a number"),
    ("incidence_zenith,view_zenith,relative_azimuth,brdf\n0,0,0,-0.1\n",
     r"t\.csv:2: brdf must be finite and >= 0; got -0.1"),
    ("incidence_zenith,view_zenith,relative_azimuth,brdf\n0,0,0,0.1\n95,0,0,0.1\n",
     r"t\.csv:3: incidence_zenith must lie in \[0, 90\]"),
    ("incidence_zenith,view_zenith,relative_azimuth,brdf\n0,0,0,0.1\n0,0,0,0.2\n",
     r"t\.csv:3: grid point given twice"),
    ("incidence_zenith,view_zenith,relative_azimuth,brdf\n0,0,0,0.1\n90,90,180,0.2\n",
     r"do not fill a regular grid: no row for incidence_zenith=0, view_zenith=0, "
     r"relative_azimuth=180"),
    ("# only a comment\n", r"no header and data rows"),
])
def test_bad_files_name_the_file_and_line(tmp_path, text, message):
    path = tmp_path / "t.csv"
    path.write_text(text)
    with pytest.raises(ConfigError, match=message):
        read_table(path)


def test_missing_file(tmp_path):
    with pytest.raises(ConfigError, match="cannot read BRDF table"):
        make_brdf({"type": "tabulated", "file": str(tmp_path / "nope.csv")})
