"""Bad material input is refused with an error that names the material, the file and line, or the
scene key, and says what is accepted."""

from __future__ import annotations

import pytest

from radscene import load_scene
from radscene.errors import ConfigError
from radscene.materials import make_material


def _scene(material: dict) -> dict:
    return {
        "name": "bad",
        "environment": {"sun": {"zenith": 30.0}},
        "materials": {"wall": material},
        "objects": [{"name": "p", "shape": {"type": "plate", "width": 10, "length": 10},
                     "material": "wall", "on_ground": False}],
        "bands": [{"name": "red", "min": 0.6, "max": 0.7}],
        "observers": [{"name": "o", "type": "orthographic", "center": [0, 0], "gsd": 1,
                       "shape": [2, 2], "altitude": 100}],
    }


def test_negative_reflectance_in_a_file_names_file_line_and_material(tmp_path):
    (tmp_path / "wall.csv").write_text(
        "# a wall\nwavelength_um,reflectance\n0.4,0.2\n1.0,-0.05\n2.0,0.3\n")
    with pytest.raises(ConfigError) as err:
        make_material({"type": "custom", "reflectance": {"file": "wall.csv", "column": "reflectance"}},
                      key="materials.wall", base_dir=tmp_path)
    assert err.value.key == "materials.wall.reflectance"
    assert f"{tmp_path / 'wall.csv'}:4: material 'wall': reflectance = -0.05 at 1 µm" in err.value.message
    assert "outside [0, 1]" in err.value.message


def test_reflectance_plus_transmittance_above_one_names_file_line_and_material(tmp_path):
    (tmp_path / "leaf.csv").write_text(
        "wavelength_um,reflectance,transmittance\n0.4,0.1,0.1\n0.8,0.6,0.5\n2.0,0.3,0.2\n")
    spec = {"type": "custom",
            "reflectance": {"file": "leaf.csv", "column": "reflectance"},
            "transmittance": {"file": "leaf.csv", "column": "transmittance"}}
    with pytest.raises(ConfigError, match=r"leaf\.csv:3: material 'leaf': reflectance \+ "
                                          r"transmittance = 1\.1 at 0\.8 µm exceeds 1") as err:
        make_material(spec, key="materials.leaf", base_dir=tmp_path)
    assert err.value.key == "materials.leaf"


def test_negative_reflectance_in_a_scene_names_the_key():
    with pytest.raises(ConfigError, match=r"'wall': reflectance = -0\.1 is outside \[0, 1\]") as err:
        load_scene(_scene({"reflectance": -0.1}))
    assert err.value.key == "materials.wall.reflectance"


def test_reflectance_plus_transmittance_above_one_in_a_scene_names_the_key():
    with pytest.raises(ConfigError, match="reflectance \\+ transmittance = 1.2 exceeds 1") as err:
        load_scene(_scene({"reflectance": 0.7, "transmittance": 0.5}))
    assert err.value.key == "materials.wall"


def test_library_file_in_an_unknown_format_names_file_and_line(tmp_path):
    (tmp_path / "wall.xyz").write_text("wavelength_um reflectance\n0.4 0.1\n")
    with pytest.raises(ConfigError, match="unknown spectral library format .*accepted: "
                                          "ECOSTRESS/ASTER") as err:
        load_scene(_scene({"type": "file", "path": "wall.xyz", "spectrum": "a"}),
                   base_dir=tmp_path)
    assert err.value.key == "materials.wall" and "wall.xyz:1: " in err.value.message


def test_unknown_brdf_parameter_names_the_key_and_the_accepted_ones():
    spec = {"reflectance": 0.3,
            "brdf": {"type": "rpv", "rho0": 0.1, "k": 0.9, "theta": -0.1, "hotspot_size": 3}}
    with pytest.raises(ConfigError, match="unknown parameter 'hotspot_size' for BRDF 'rpv'; "
                                          "accepted: rho0, k, theta, rho_c") as err:
        load_scene(_scene(spec))
    assert err.value.key == "materials.wall.brdf.hotspot_size"
