"""radscene: radiometrically correct EO/IR scene and sensor simulation, 0.4–20 µm.

>>> import radscene
>>> scene = radscene.load_scene(radscene.example_path("demo"))   # doctest: +SKIP
>>> images = radscene.render(scene, "map")                        # doctest: +SKIP

``import radscene`` imports nothing but this module: each public name below is imported the
first time it is used (PEP 562 module ``__getattr__``), so the command line and scripts that
need one part do not pay for the renderer, xarray, scipy, numba or matplotlib.

``radscene.render`` is both the function (:func:`radscene.pipeline.render`: the heat balance,
then the render of one observer) and the subpackage :mod:`radscene.render`. It is always one
object, the subpackage, and calling it calls :func:`radscene.pipeline.render`; see
:mod:`radscene.render`.
"""

from __future__ import annotations

import importlib
import types
from pathlib import Path
from typing import TYPE_CHECKING

if TYPE_CHECKING:  # for type checkers and the API docs; at run time __getattr__ imports them
    from radscene.io.netcdf import write_netcdf
    from radscene.io.zarr_store import write_zarr
    from radscene.pipeline import render_all, render_hyperspectral, simulate, solve_thermal
    from radscene.pipeline.simulation import Simulation, render_sequence
    from radscene.scene import load_scene

__version__ = "0.1.0"

#: Public name → the module that defines it, imported on first use.
_LAZY = {
    "load_scene": "radscene.scene",
    "render_all": "radscene.pipeline",
    "render_hyperspectral": "radscene.pipeline",
    "simulate": "radscene.pipeline",
    "solve_thermal": "radscene.pipeline",
    "Simulation": "radscene.pipeline.simulation",
    "render_sequence": "radscene.pipeline.simulation",
    "write_netcdf": "radscene.io.netcdf",
    "write_zarr": "radscene.io.zarr_store",
}

__all__ = ["__version__", "load_scene", "render", "render_all", "render_hyperspectral", "simulate", "solve_thermal",
           "Simulation", "render_sequence", "example_path", "write_netcdf", "write_zarr"]


def __getattr__(name: str):
    if name == "render":
        # importing the subpackage binds it here as ``render``: a module whose call is
        # radscene.pipeline.render (radscene/render/__init__.py)
        return importlib.import_module("radscene.render")
    module = _LAZY.get(name)
    if module is None:
        raise AttributeError(f"module 'radscene' has no attribute {name!r}")
    value = getattr(importlib.import_module(module), name)
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(__all__))


class _RenderPackage(types.ModuleType):
    """The class of the module :mod:`radscene.render` (set there): a module that, called,
    renders a scene through :func:`radscene.pipeline.render`, so that ``radscene.render(scene)``
    works whether the name was bound by this module's ``__getattr__`` or by an import of
    ``radscene.render.something``."""

    def __call__(self, scene, observer=None, **kwargs):
        from radscene.pipeline import render

        return render(scene, observer, **kwargs)

    @property
    def __signature__(self):
        # inspect.signature(radscene.render) gives the function's
        import inspect

        from radscene.pipeline import render

        return inspect.signature(render)


def example_path(name: str) -> Path:
    """Path of a bundled example scene (``radscene examples`` lists them)."""
    from importlib import resources

    from radscene.errors import ConfigError, did_you_mean

    path = Path(str(resources.files("radscene") / "examples" / f"{name}.yaml"))
    if not path.is_file():
        known = sorted(p.name.removesuffix(".yaml")
                       for p in (resources.files("radscene") / "examples").iterdir()
                       if p.name.endswith(".yaml"))
        raise ConfigError(f"unknown example {name!r}; known: {', '.join(known)}"
                          f"{did_you_mean(name, known)}", key="name")
    return path
