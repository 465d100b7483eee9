"""The BRDF registry and configuration: make_brdf, parameter validation, errors, the polar plot."""

import numpy as np
import pytest

from radscene.errors import ConfigError
from radscene.materials.brdf import (
    BRDF,
    BRDFS,
    RPV,
    Lambertian,
    Parameter,
    make_brdf,
    plot_brdf,
    register_brdf,
)
from radscene.materials.brdf.base import parameter_table


def test_registry_lists_the_models_of_the_issue():
    assert sorted(BRDFS) == sorted([
        "lambertian", "phong", "ggx", "beckmann", "rpv", "rossli", "hapke", "coxmunk",
        "lambertian_transmission", "tabulated",
    ])
    for name, cls in BRDFS.items():
        assert cls.name == name and issubclass(cls, BRDF)


def test_type_is_case_insensitive():
    assert isinstance(make_brdf({"type": "LamBertian", "reflectance": 0.2}), Lambertian)
    assert isinstance(make_brdf({"type": "RPV", "rho0": 0.1, "k": 0.9, "theta": 0.0}), RPV)


def test_unknown_type_lists_the_registered_ones():
    with pytest.raises(ConfigError, match=r"unknown BRDF type 'lambert'; known: beckmann, "
                                          r"coxmunk, ggx, hapke, lambertian, "):
        make_brdf({"type": "lambert", "reflectance": 0.2})
    with pytest.raises(ConfigError, match="needs a type; known: beckmann"):
        make_brdf({"reflectance": 0.2})
    with pytest.raises(ConfigError, match="a BRDF is a mapping"):
        make_brdf("lambertian")


def test_unknown_parameter_is_named_with_its_key():
    with pytest.raises(ConfigError, match=r"materials\.soil\.brdf\.rho_0: unknown parameter "
                                          r"'rho_0' for BRDF 'rpv'; accepted: rho0, k, theta"):
        make_brdf({"type": "rpv", "rho_0": 0.1, "k": 0.9, "theta": 0.0},
                  key="materials.soil.brdf")


def test_missing_parameter_is_named():
    with pytest.raises(ConfigError, match=r"brdf\.k: BRDF 'rpv' needs 'k'"):
        make_brdf({"type": "rpv", "rho0": 0.1, "theta": 0.0})


@pytest.mark.parametrize(("spec", "message"), [
    ({"type": "lambertian", "reflectance": -0.1},
     r"brdf\.reflectance: reflectance must satisfy 0 <= value <= 1 \[-\]; got -0.1"),
    ({"type": "lambertian", "reflectance": {"wavelength": [0.4, 1.0, 2.0],
                                            "values": [0.2, 1.2, 0.3]}},
     r"got 1.2 at 1 µm"),
    ({"type": "rpv", "rho0": 0.1, "k": 0.9, "theta": 1.0}, r"-1 < value < 1"),
    ({"type": "ggx", "roughness": 0.0, "refractive_index": 1.5}, r"roughness must satisfy 0 <"),
    ({"type": "ggx", "roughness": "rough", "refractive_index": 1.5}, r"must be a number"),
    ({"type": "rossli", "f_iso": 0.1, "f_vol": 0.1, "f_geo": 0.1, "hotspot": "yes"},
     r"hotspot must be true or false"),
    ({"type": "rossli", "f_iso": 0.1, "f_vol": 0.1, "f_geo": 0.1, "geometric": "dense"},
     r"geometric must be one of sparse_reciprocal, sparse; got 'dense'"),
    ({"type": "lambertian_transmission", "reflectance": 0.6, "transmittance": 0.5},
     r"brdf\.transmittance: reflectance \+ transmittance must not exceed 1"),
    ({"type": "phong", "diffuse_reflectance": {"wavelength": [0.4, 1.0], "values": [0.5, 0.9]},
      "specular_reflectance": 0.2, "specular_exponent": 10.0},
     r"diffuse_reflectance \+ specular_reflectance must not exceed 1.*got 1.1 at 1 µm"),
    ({"type": "hapke", "single_scattering_albedo": 0.5, "opposition_width": 0.0},
     r"opposition_width must satisfy 0 < value"),
    ({"type": "coxmunk", "wind_speed": -3.0}, r"wind_speed must satisfy 0 <= value"),
], ids=["negative", "spectral>1", "theta", "roughness0", "roughness_str", "bool", "choice",
        "rho+tau", "rho_d+rho_s", "hapke_h", "wind"])
def test_bad_values_are_refused_with_key_and_rule(spec, message):
    with pytest.raises(ConfigError, match=message):
        make_brdf(spec)


def test_spectral_parameter_needs_a_wavelength_inside_its_table():
    m = make_brdf({"type": "lambertian", "reflectance": {"wavelength": [0.4, 2.5],
                                                         "values": [0.1, 0.5]}})
    assert float(m.albedo([0, 0, 1.0], 1.45)) == pytest.approx(0.3, abs=1e-12)
    with pytest.raises(ConfigError, match="reflectance of BRDF 'lambertian' varies with "
                                          "wavelength"):
        m.f([0, 0, 1.0], [0, 0, 1.0])
    with pytest.raises(ConfigError, match="outside the tabulated range"):
        m.emissivity([0, 0, 1.0], 10.0)
    assert m.is_spectral


def test_bad_random_numbers_are_refused():
    m = make_brdf({"type": "lambertian", "reflectance": 0.2})
    with pytest.raises(ConfigError, match=r"u1: random numbers must lie in \[0, 1\]"):
        m.sample([0, 0, 1.0], 1.2, 0.5)


def test_make_brdf_passes_a_model_through_and_config_has_the_type():
    m = make_brdf({"type": "rpv", "rho0": 0.1, "k": 0.9, "theta": 0.0})
    assert make_brdf(m) is m
    assert m.config() == {"type": "rpv", "rho0": 0.1, "k": 0.9, "theta": 0.0, "rho_c": None}
    assert "RPV(rho0=0.1" in repr(m)


def test_register_brdf():
    class Grey(BRDF):
        name = "grey_test_model"
        PARAMETERS = {"level": Parameter("-", "BRF", kind="spectrum", low=0.0, high=1.0)}

        def _kernel(self, mu_i, mu_o, cos_g, wavelength):
            return self.parameter("level", wavelength) / np.pi + 0.0 * cos_g

    try:
        register_brdf(Grey)
        m = make_brdf({"type": "Grey_Test_Model", "level": 0.4})
        assert float(m.albedo([0, 0, 1.0])) == pytest.approx(0.4, abs=1e-4)
        with pytest.raises(ConfigError, match="already registered"):
            register_brdf(type("Other", (Grey,), {}))
    finally:
        BRDFS.pop("grey_test_model", None)
    with pytest.raises(ConfigError, match="not a named BRDF subclass"):
        register_brdf(dict)


def test_parameter_table_documents_every_parameter():
    text = parameter_table(BRDFS["rossli"])
    for name in BRDFS["rossli"].PARAMETERS:
        assert name in text
    assert "required" in text and "[deg]" in text


def test_plot_brdf_writes_a_png(tmp_path):
    path = plot_brdf({"type": "rpv", "rho0": 0.076, "k": 0.648, "theta": -0.29},
                     [0.0, 30.0, 60.0], tmp_path / "rpv.png", resolution=31)
    data = path.read_bytes()
    assert data[:8] == b"\x89PNG\r\n\x1a\n" and len(data) > 10_000
    with pytest.raises(ConfigError, match=r"incidence angles must lie in \[0, 90\)"):
        plot_brdf({"type": "lambertian", "reflectance": 0.3}, [95.0], tmp_path / "x.png")
    with pytest.raises(ConfigError, match="give 1 to 6 incidence angles"):
        plot_brdf({"type": "lambertian", "reflectance": 0.3}, [], tmp_path / "x.png")
