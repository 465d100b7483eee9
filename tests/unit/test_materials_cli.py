"""``radscene materials``: list, show, plot, earthlib, read."""

import importlib.util

import numpy as np
import pytest
from typer.testing import CliRunner

from radscene.cli.materials import app
from radscene.errors import ConfigError
from radscene.materials import list_materials

runner = CliRunner()


def invoke(*args):
    result = runner.invoke(app, list(args))
    if result.exception is not None and not isinstance(result.exception, SystemExit):
        raise result.exception
    return result


def test_list_shows_every_material_and_filters():
    out = invoke("list").output
    assert f"{len(list_materials())} material(s)" in out
    for name in ("asphalt", "snow", "green_leaf", "polished_aluminium"):
        assert name in out
    soil = invoke("list", "--category", "soil").output
    assert "bright_soil" in soil and "asphalt " not in soil
    assert "1 material(s)" in invoke("list", "--search", "polished").output
    with pytest.raises(ConfigError, match="unknown material category 'rock'; known: man-made"):
        invoke("list", "--category", "rock")


def test_show_prints_sources_spectra_and_thermal_properties():
    out = invoke("show", "Asphalt", "-w", "0.55", "-w", "10").output
    assert "rpaeyg.003-" in out and "Herold" in out  # the measured spectrum and its citation
    assert "0.55" in out and "10" in out
    assert "solar absorptance" in out and "ISO 10456" in out
    out = invoke("show", "grass_canopy").output
    assert "canopy: LAI 2.5" in out
    with pytest.raises(ConfigError, match="unknown material 'asfalt'; known: asphalt"):
        invoke("show", "asfalt")
    with pytest.raises(ConfigError, match=r"wavelength: wavelengths must be finite and > 0"):
        invoke("show", "asphalt", "-w", "-1")


def test_plot_writes_spectrum_and_polar_brdf_pngs(tmp_path):
    import matplotlib.image as mpimg

    out = invoke("plot", "painted_metal", "-o", str(tmp_path / "figs"), "-i", "0", "-i", "45").output
    spectrum = tmp_path / "figs" / "painted_metal_spectrum.png"
    brdf = tmp_path / "figs" / "painted_metal_brdf.png"
    assert str(spectrum) in out.replace("\n", "") and brdf.is_file()
    for png in (spectrum, brdf):
        image = mpimg.imread(png)
        assert image.ndim == 3 and image.shape[0] > 200 and np.ptp(image) > 0.5
    with pytest.raises(ConfigError, match=r"incidence angles must lie in \[0, 90\)"):
        invoke("plot", "asphalt", "-o", str(tmp_path), "-i", "95")
    (tmp_path / "file").write_text("x")
    with pytest.raises(ConfigError, match="exists and is not a folder"):
        invoke("plot", "asphalt", "-o", str(tmp_path / "file"))


def test_material_brdf_is_the_materials_lambert_plus_phong():
    from radscene.materials import get_material
    from radscene.materials.plot import material_brdf

    m = get_material("painted_metal")
    b = material_brdf(m)
    # directional-hemispherical reflectance at normal incidence: rho_d + rho_s (n+1)/(n+2), the
    # lobe (n+1)/(2 pi) cos^n about the normal weighted by cos(theta_o) (f divides by cos_i = 1)
    n = m.specular_exponent
    expected = float(m.diffuse_reflectance(0.55)) + float(m.specular_reflectance(0.55)) * (n + 1) / (n + 2)
    assert float(b.albedo(np.array([0.0, 0.0, 1.0]), 0.55)) == pytest.approx(expected, rel=1e-3)


def test_read_lists_a_library_file_and_refuses_unknown_formats(tmp_path):
    from radscene.materials.libraries import write_envi_library

    write_envi_library(tmp_path / "lib.sli", [0.5, 0.6, 0.7], [[0.1, 0.2, 0.3]], ["tarmac"])
    out = invoke("read", str(tmp_path / "lib.sli")).output
    assert "tarmac" in out and "0.5-0.7" in out
    (tmp_path / "x.dat").write_text("hello\n")
    with pytest.raises(ConfigError, match=r"x\.dat:1: unknown spectral library format"):
        invoke("read", str(tmp_path / "x.dat"))


@pytest.mark.skipif(importlib.util.find_spec("earthlib") is None, reason="earthlib not installed")
def test_earthlib_search():
    out = invoke("earthlib", "--cls", "bark", "--limit", "2").output
    assert "33 spectra match" in out and "kellbark" in out


def test_show_prints_the_moisture_availability():
    assert "moisture availability (evaporation, beta): 0.57" in invoke("show", "grass_canopy").output
    assert "moisture availability" not in invoke("show", "asphalt").output
