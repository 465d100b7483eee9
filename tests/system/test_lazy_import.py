"""``import radscene`` and ``radscene --version`` import no heavy library and no renderer, and
``radscene.render`` is the render function whatever was imported before it.

Each case runs in a fresh interpreter: what the test session imported would hide what
``import radscene`` does. What was not imported is checked, not how long it took.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest

import radscene

#: Imported by the renderer, the scene loader or the writers, never by ``import radscene``.
HEAVY = ("scipy", "scipy.interpolate", "matplotlib", "numba", "xarray", "pandas", "pydantic",
         "numpy", "radscene.render.integrator", "radscene.pipeline", "radscene.scene")


def _child(code: str) -> subprocess.CompletedProcess:
    env = dict(os.environ, PYTHONPATH=str(Path(radscene.__file__).parents[1]))
    return subprocess.run([sys.executable, "-c", textwrap.dedent(code)], capture_output=True,
                          text=True, env=env, timeout=300)


def _modules_after(code: str) -> set[str]:
    result = _child(textwrap.dedent(code) + "\nimport json, sys\nprint(json.dumps(sorted(sys.modules)))")
    assert result.returncode == 0, result.stderr
    return set(json.loads(result.stdout.strip().splitlines()[-1]))


def test_import_radscene_imports_no_heavy_library():
    loaded = _modules_after("import radscene")
    assert not loaded & set(HEAVY), sorted(loaded & set(HEAVY))


def test_version_option_imports_no_renderer():
    loaded = _modules_after("""
        import sys
        sys.argv = ["radscene", "--version"]
        from radscene.cli import app
        try:
            app()
        except SystemExit as stop:
            assert stop.code in (0, None), stop.code
        """)
    assert "radscene.cli" in loaded
    absent = {"radscene.render", "radscene.render.integrator", "radscene.pipeline", "radscene.scene",
              "scipy", "matplotlib", "numba", "xarray"}
    assert not loaded & absent, sorted(loaded & absent)


def test_version_option_prints_the_version():
    result = _child("""
        import sys
        sys.argv = ["radscene", "--version"]
        from radscene.cli import app
        app()
        """)
    assert result.stdout.strip() == f"radscene {radscene.__version__}"


def test_public_names_resolve_on_first_use():
    for name in radscene.__all__:
        assert getattr(radscene, name) is not None, name
    assert set(radscene.__all__) <= set(dir(radscene))
    with pytest.raises(AttributeError, match="no attribute 'rendr'"):
        radscene.rendr  # noqa: B018


_SCENE = """
    scene = {
        "name": "lazy_plate",
        "environment": {"sun": {"zenith": 30.0, "azimuth": 180.0}, "atmosphere": {"type": "none"}},
        "materials": {"grey": {"reflectance": 0.3}},
        "objects": [{"name": "plate", "shape": {"type": "plate", "width": 100, "length": 100},
                     "material": "grey", "temperature": "300 K"}],
        "bands": [{"name": "red", "min": "0.6 um", "max": "0.7 um"}],
        "observers": [{"name": "map", "type": "orthographic", "center": [0, 0], "gsd": 5,
                       "shape": [2, 2], "altitude": 1000}],
    }
    """


@pytest.mark.parametrize("first", [
    "import radscene.render.integrator",
    "from radscene.render import sun_geometry",
    "pass",
])
def test_render_is_the_function_whatever_was_imported_first(first):
    result = _child(first + "\n" + textwrap.dedent(_SCENE) + textwrap.dedent("""
        import radscene
        images = radscene.render(scene, "map")
        assert images["radiance"].shape == (1, 2, 2), images["radiance"].shape
        import radscene.render.integrator
        again = radscene.render(scene)
        assert float(abs(again["radiance"] - images["radiance"]).max()) == 0.0
        from radscene import render
        assert render is radscene.render
        from radscene.render import sun_geometry, sun_track, TERMS
        assert callable(sun_track) and callable(sun_geometry) and "path_radiance" in TERMS, TERMS
        import inspect
        assert list(inspect.signature(radscene.render).parameters)[:2] == ["scene", "observer"]
        print("ok")
        """))
    assert result.returncode == 0, result.stderr
    assert result.stdout.strip().endswith("ok")


def test_render_subpackage_keeps_its_names():
    from radscene.render import TERMS, render, sun_geometry
    from radscene.render.integrator import TERMS as integrator_terms
    from radscene.render.integrator import render as integrator_render
    from radscene.render.sun_track import sun_geometry as track_sun_geometry

    assert TERMS is integrator_terms
    assert render is integrator_render
    assert sun_geometry is track_sun_geometry


def test_io_names_resolve_and_writing_netcdf_leaves_matplotlib_alone():
    import radscene.io

    assert set(radscene.io.__all__) == set(radscene.io._LAZY)
    for name in radscene.io.__all__:
        assert callable(getattr(radscene.io, name)), name
    loaded = _modules_after("import radscene\nradscene.write_netcdf")
    assert "xarray" in loaded and "matplotlib" not in loaded
