"""Unit tests of radscene.radiometry.srf (spectral response functions)."""

import math

import numpy as np
import pytest
from scipy.integrate import quad

from radscene.errors import ConfigError
from radscene.radiometry import (
    RESPONSES,
    GaussianResponse,
    RectangularResponse,
    SpectralResponse,
    TabulatedResponse,
    band_radiance,
    make_response,
    spectral_radiance,
)

QUADRATURE_REL = 1e-9  # promised accuracy of every response's quadrature for smooth f
EXACT_REL = 1e-12  # integrals the rule is exact for (polynomials × piecewise-linear S)


def gaussian_width(fwhm):
    return fwhm * math.sqrt(math.pi / (4 * math.log(2)))


# One example of every registered type, for the shared contract test.
EXAMPLES = {
    "rectangular": {"type": "rectangular", "wavelength_min": 8.0, "wavelength_max": 12.0},
    "gaussian": {"type": "gaussian", "center": 4.0, "fwhm": 0.3},
    "tabulated": {
        "type": "tabulated",
        "wavelength": [0.4, 0.5, 0.6, 0.7],
        "response": [0.0, 1.0, 0.5, 0.0],
    },
}


def test_every_registered_type_has_an_example():
    assert set(EXAMPLES) == set(RESPONSES)


@pytest.mark.parametrize("kind", sorted(RESPONSES))
def test_registered_response_contract(kind):
    response = make_response(EXAMPLES[kind])
    assert isinstance(response, RESPONSES[kind])
    assert isinstance(response.name, str) and response.name
    lo, hi = response.support
    nodes, weights = response.quadrature()
    assert np.all(np.diff(nodes) > 0)
    assert nodes[0] > lo and nodes[-1] < hi
    assert np.all(weights >= 0)
    assert lo < response.center < hi
    width = response.equivalent_width()
    assert response.integrate_function(np.ones_like) == pytest.approx(width, rel=EXACT_REL)
    # S vanishes outside the support, and quadrature matches adaptive integration of S f.
    assert np.all(response(np.array([lo * 0.9, hi * 1.1])) == 0.0)
    for t in (250.0, 1000.0):
        ref = quad(
            lambda wl, t=t: float(response(wl)) * float(spectral_radiance(wl, t)),
            lo,
            hi,
            points=[response.center],
            epsabs=0,
            epsrel=1e-12,
            limit=500,
        )[0]
        got = response.integrate_function(lambda wl, t=t: spectral_radiance(wl, t))
        assert got == pytest.approx(ref, rel=QUADRATURE_REL)


@pytest.mark.parametrize(("lo", "hi"), [(8.0, 12.0), (3.0, 5.0), (0.4, 0.7), (0.4, 20.0)])
@pytest.mark.parametrize("temperature", [200.0, 300.0, 1000.0, 5778.0])
def test_rectangular_quadrature_matches_exact_band_radiance(lo, hi, temperature):
    got = RectangularResponse(lo, hi).integrate_function(
        lambda wl: spectral_radiance(wl, temperature)
    )
    assert got == pytest.approx(band_radiance(lo, hi, temperature), rel=QUADRATURE_REL)


@pytest.mark.parametrize(("center", "fwhm"), [(10.0, 1.0), (10.0, 0.01), (0.55, 0.04), (4.0, 0.5)])
def test_gaussian_equivalent_width_and_shape(center, fwhm):
    g = GaussianResponse(center, fwhm)
    assert g.equivalent_width() == pytest.approx(gaussian_width(fwhm), rel=1e-9)
    assert g(center) == pytest.approx(1.0, rel=1e-15)
    assert g(np.array([center - fwhm / 2, center + fwhm / 2])) == pytest.approx(0.5, rel=1e-12)
    assert g.center == center
    sigma = fwhm / (2 * math.sqrt(2 * math.log(2)))
    assert g.support == pytest.approx((center - 7 * sigma, center + 7 * sigma), rel=1e-15)


def test_tabulated_triangle_integrates_linear_function_exactly():
    tri = TabulatedResponse([8.0, 10.0, 12.0], [0.0, 1.0, 0.0], name="tri")
    # ∫ S dλ = 2, centroid 10  ->  ∫ S (3λ + 1) dλ = 2 (3·10 + 1) = 62
    assert tri.equivalent_width() == pytest.approx(2.0, rel=EXACT_REL)
    assert tri.integrate_function(lambda wl: 3.0 * wl + 1.0) == pytest.approx(62.0, rel=EXACT_REL)
    assert tri.center == pytest.approx(10.0, rel=EXACT_REL)
    # a quadratic times the triangle: exact too (checked against adaptive quadrature)
    ref = quad(lambda wl: float(tri(wl)) * wl**2, 8.0, 12.0, points=[10.0], epsabs=0, epsrel=1e-13)[
        0
    ]
    assert tri.integrate_function(lambda wl: wl**2) == pytest.approx(ref, rel=EXACT_REL)


def test_tabulated_trims_zero_tails_and_interpolates():
    resp = TabulatedResponse([1.0, 2.0, 3.0, 4.0, 5.0, 6.0], [0.0, 0.0, 0.5, 1.0, 0.0, 0.0])
    assert resp.support == (2.0, 5.0)
    assert resp(np.array([1.5, 2.5, 3.5, 5.5])) == pytest.approx([0.0, 0.25, 0.75, 0.0], abs=1e-15)


def test_integrate_function_keeps_leading_axes():
    g = GaussianResponse(10.0, 1.0)
    t = np.array([[250.0], [300.0], [350.0]])
    out = g.integrate_function(lambda wl: spectral_radiance(wl, t))
    assert out.shape == (3,)
    assert out[1] == pytest.approx(
        g.integrate_function(lambda wl: spectral_radiance(wl, 300.0)), rel=1e-14
    )
    with pytest.raises(ConfigError, match="last axis"):
        g.integrate_function(lambda wl: np.ones((wl.size, 2)))


def test_integrate_tabulated_spectrum():
    band = RectangularResponse(8.0, 12.0)
    wl = np.linspace(7.0, 13.0, 6001)  # 1 nm: linear interpolation error ~ h² L'' / 8 ~ 1e-8
    t = np.array([[280.0, 300.0, 320.0], [200.0, 250.0, 1000.0]])
    spectra = spectral_radiance(wl, t[..., None])
    got = band.integrate(wl, spectra)
    assert got.shape == (2, 3)
    assert got == pytest.approx(band_radiance(8.0, 12.0, t), rel=1e-6)
    # a linear spectrum is interpolated exactly
    assert band.integrate([8.0, 12.0], [1.0, 5.0]) == pytest.approx(12.0, rel=EXACT_REL)


@pytest.mark.parametrize(
    ("wavelength", "values", "match"),
    [
        ([8.5, 12.0], [1.0, 1.0], "does not cover the support"),
        ([8.0, 11.0], [1.0, 1.0], "does not cover the support"),
        ([8.0, 10.0, 10.0, 12.0], [1.0, 1.0, 1.0, 1.0], "strictly increasing"),
        ([8.0, 12.0], [1.0, 1.0, 1.0], "last axis"),
    ],
)
def test_integrate_bad_tables_raise(wavelength, values, match):
    with pytest.raises(ConfigError, match=match):
        RectangularResponse(8.0, 12.0).integrate(wavelength, values)


def test_call_propagates_nan():
    for resp in (RectangularResponse(8.0, 12.0), GaussianResponse(10.0, 1.0)):
        assert np.isnan(resp(np.nan))


@pytest.mark.parametrize(
    ("factory", "key"),
    [
        (lambda: RectangularResponse(0.0, 12.0), "wavelength_min"),
        (lambda: RectangularResponse(12.0, 8.0), "wavelength_max"),
        (lambda: RectangularResponse("a", 8.0), "wavelength_min"),
        (lambda: GaussianResponse(10.0, 0.0), "fwhm"),
        (lambda: GaussianResponse(1.0, 1.0), "center"),
        (lambda: GaussianResponse(np.nan, 1.0), "center"),
        (lambda: TabulatedResponse([1.0, 2.0], [1.0]), "wavelength"),
        (lambda: TabulatedResponse([2.0, 1.0], [1.0, 1.0]), "wavelength"),
        (lambda: TabulatedResponse([1.0, 2.0], [1.0, -0.1]), "response"),
        (lambda: TabulatedResponse([1.0, 2.0], [0.0, 0.0]), "response"),
    ],
)
def test_bad_parameters_raise(factory, key):
    with pytest.raises(ConfigError, match=f"^{key}: "):
        factory()


def test_from_file_with_header_csv_and_nm(tmp_path):
    path = tmp_path / "band31.csv"
    path.write_text("Sensor band 31\nwavelength_nm,response\n9000,0\n10000,1.0\n11000,0\n")
    resp = TabulatedResponse.from_file(path, wavelength_unit="nm")
    assert resp.name == "band31"
    assert resp.support == pytest.approx((9.0, 11.0), rel=1e-15)
    assert resp.equivalent_width() == pytest.approx(1.0, rel=EXACT_REL)
    spaces = tmp_path / "srf.txt"
    spaces.write_text("# um  S\n9.0 0.0\n\n10.0\t1.0\n11.0   0.0\n")
    assert TabulatedResponse.from_file(spaces).equivalent_width() == pytest.approx(
        1.0, rel=EXACT_REL
    )


@pytest.mark.parametrize(
    ("text", "match"),
    [
        ("9 0\n10 -1\n11 0\n", "response must be >= 0"),
        ("9 0\n11 1\n10 0\n", "strictly increasing"),
        ("9 0\n10 0\n11 0\n", "integral of the response must be > 0"),
        ("9 0\n10 1\noops\n11 0\n", "line 3: expected two numbers"),
        ("header only\n", "at least 2 rows"),
    ],
)
def test_from_file_bad_files_name_the_file(tmp_path, text, match):
    path = tmp_path / "bad_srf.txt"
    path.write_text(text)
    with pytest.raises(ConfigError, match=match) as info:
        TabulatedResponse.from_file(path)
    assert "bad_srf.txt" in str(info.value)


def test_from_file_missing_file_and_bad_unit(tmp_path):
    with pytest.raises(ConfigError, match="cannot read spectral response file"):
        TabulatedResponse.from_file(tmp_path / "missing.csv")
    with pytest.raises(ConfigError, match="unknown wavelength unit 'furlong'"):
        TabulatedResponse.from_file(tmp_path / "missing.csv", wavelength_unit="furlong")


def test_make_response_types_case_insensitive_and_file(tmp_path):
    g = make_response({"type": "GAUSSIAN", "center": 10.0, "fwhm": 1.0, "name": "b10"})
    assert isinstance(g, GaussianResponse) and g.name == "b10"
    assert isinstance(g, SpectralResponse)
    path = tmp_path / "s.csv"
    path.write_text("9,0\n10,1\n11,0\n")
    t = make_response({"type": "Tabulated", "file": str(path)})
    assert t.equivalent_width() == pytest.approx(1.0, rel=EXACT_REL)


@pytest.mark.parametrize(
    ("spec", "match"),
    [
        (
            {"type": "boxcar"},
            "unknown spectral response type 'boxcar'; known: rectangular, gaussian, tabulated",
        ),
        ({"center": 10.0}, "mapping with a 'type' key"),
        ("gaussian", "mapping with a 'type' key"),
        (
            {"type": "gaussian", "centre": 10.0, "fwhm": 1.0},
            "accepted parameters of 'gaussian': center, fwhm, name",
        ),
        ({"type": "rectangular", "wavelength_min": 8.0}, "accepted parameters"),
    ],
)
def test_make_response_bad_specs(spec, match):
    with pytest.raises(ConfigError, match=match):
        make_response(spec)
