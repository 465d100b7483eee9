"""radscene: radiometrically correct EO/IR scene and sensor simulation, 0.4–20 µm.

>>> import radscene
>>> scene = radscene.load_scene(radscene.example_path("demo"))   # doctest: +SKIP
>>> images = radscene.render(scene, "map")                        # doctest: +SKIP
"""

from __future__ import annotations

from importlib import resources
from pathlib import Path

__version__ = "0.1.0"

# render and render_all apply the scene's heat balance first (the function shadows the package name)
from radscene.io import write_netcdf, write_zarr  # noqa: E402
from radscene.pipeline import (  # noqa: E402
    render,
    render_all,
    render_hyperspectral,
    simulate,
    solve_thermal,
)
from radscene.pipeline.simulation import Simulation, render_sequence  # noqa: E402
from radscene.scene import load_scene  # noqa: E402

__all__ = ["__version__", "load_scene", "render", "render_all", "render_hyperspectral", "simulate", "solve_thermal",
           "Simulation", "render_sequence", "example_path", "write_netcdf", "write_zarr"]


def example_path(name: str) -> Path:
    """Path of a bundled example scene (``radscene examples`` lists them)."""
    from radscene.errors import ConfigError

    path = Path(str(resources.files("radscene") / "examples" / f"{name}.yaml"))
    if not path.is_file():
        known = sorted(p.name.removesuffix(".yaml")
                       for p in (resources.files("radscene") / "examples").iterdir()
                       if p.name.endswith(".yaml"))
        raise ConfigError(f"unknown example {name!r}; known: {', '.join(known)}", key="name")
    return path
