"""The Python API takes a scene dict or file as the command line does, with the same errors."""

import numpy as np
import pytest

import radscene
from radscene.errors import ConfigError


def _scene(**atmosphere):
    return {
        "name": "api_plate",
        "environment": {"sun": {"zenith": 30.0, "azimuth": 180.0},
                        "atmosphere": {"type": "none", **atmosphere}},
        "materials": {"grey": {"reflectance": 0.3}},
        "objects": [{"name": "plate", "shape": {"type": "plate", "width": "100 m",
                                                "length": "100 m"},
                     "material": "grey", "temperature": "300 K"}],
        "bands": [{"name": "red", "min": "0.6 um", "max": "0.7 um"}],
        "observers": [{"name": "map", "type": "orthographic", "center": [0, 0], "gsd": "5 m",
                       "shape": [4, 4], "altitude": "1 km"}],
    }


def test_render_of_a_dict_equals_render_of_the_loaded_scene():
    from_dict = radscene.render(_scene())
    loaded = radscene.render(radscene.load_scene(_scene()))
    np.testing.assert_array_equal(from_dict["radiance"].values, loaded["radiance"].values)


def test_render_of_a_file_path(tmp_path):
    import yaml

    path = tmp_path / "plate.yaml"
    path.write_text(yaml.safe_dump(_scene()))
    images = radscene.render(str(path))
    assert images["radiance"].shape == (1, 4, 4)


def test_a_bad_dict_gives_the_command_lines_error():
    bad = _scene()
    bad["objects"][0]["material"] = "asfalt"
    with pytest.raises(ConfigError, match=r"objects\[0\]\.material.*asfalt"):
        radscene.render(bad)


def test_something_else_is_refused_by_name():
    with pytest.raises(TypeError, match="not int"):
        radscene.render(3)


def test_a_misspelt_key_gets_a_suggestion():
    bad = _scene()
    bad["observers"][0]["supersampel"] = 2
    with pytest.raises(ConfigError, match=r"observers\[0\]\.supersampel: unknown key; did you "
                                          r"mean 'supersample'\?"):
        radscene.render(bad)
    bad["observers"][0].pop("supersampel")
    bad["observers"][0]["zzz"] = 1
    with pytest.raises(ConfigError, match=r"observers\[0\]\.zzz: unknown key$"):
        radscene.render(bad)


def test_importing_radscene_leaves_matplotlib_alone():
    """A notebook keeps its backend: radscene's pictures are drawn outside pyplot."""
    import subprocess
    import sys

    code = ("import matplotlib; matplotlib.use('svg'); import radscene, radscene.io.quicklook, "
            "radscene.io.thermal_plots; assert matplotlib.get_backend() == 'svg', "
            "matplotlib.get_backend(); import sys; assert 'matplotlib.pyplot' not in sys.modules")
    result = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert result.returncode == 0, result.stderr


ENTRY_POINTS = {
    "render": lambda s: radscene.render(s, progress=False),
    "render_all": lambda s: radscene.render_all(s, progress=False),
    "simulate": lambda s: radscene.simulate(s, "map", progress=False),
    "solve_thermal": lambda s: radscene.solve_thermal(s, progress=False),
    "Simulation": lambda s: radscene.Simulation(s),
    "render_sequence": lambda s: radscene.render_sequence(s, progress=False),
    "render_hyperspectral": lambda s: radscene.render_hyperspectral(s, progress=False),
}


@pytest.mark.parametrize("entry", ENTRY_POINTS)
def test_every_entry_point_takes_a_dict_or_a_path_with_the_same_errors(tmp_path, entry):
    import yaml

    call = ENTRY_POINTS[entry]
    bad = _scene()
    bad["materials"]["grey"]["reflectance"] = 1.4
    with pytest.raises(ConfigError, match=r"materials\.grey.*outside \[0, 1\]"):
        call(bad)
    path = tmp_path / "bad.yaml"
    path.write_text(yaml.safe_dump(bad))
    with pytest.raises(ConfigError, match=r"materials\.grey.*outside \[0, 1\]"):
        call(path)
    with pytest.raises(ConfigError, match=r"scene: no such scene file"):
        call(str(tmp_path / "missing.yaml"))
    for other in (3, [1], None, b"scene.yaml"):
        with pytest.raises(TypeError, match=f"not {type(other).__name__}"):
            call(other)
    sized = _scene()  # a memory-sized mistake is a ConfigError naming its key, never MemoryError
    sized["observers"][0]["shape"] = [200000, 200000]
    with pytest.raises(ConfigError, match=r"observers\[0\]\.shape: rendering it needs about"):
        call(sized)
