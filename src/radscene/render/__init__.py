"""Rendering: signature terms, illumination queries and the image integrator.

The package is also the public function ``radscene.render``: calling it,
``radscene.render(scene, observer, ...)``, calls :func:`radscene.pipeline.render` (the
scene's heat balance, then :func:`radscene.render.integrator.render` of one observer).
``radscene.render`` names this package once it is imported, whoever imports it first, so the
package itself is made callable (its module class, ``radscene._RenderPackage``) rather than a
function bound to the name that the import system would later replace.

The integrator (numba, scipy, xarray) is imported on first use of ``render``, ``render_all``,
``TERMS``, ``BACKGROUND_TERM`` or ``COUPLING_TERMS`` (PEP 562); ``sun_geometry`` and
``sun_track`` need numpy only.
"""

import importlib
import sys
from typing import TYPE_CHECKING

# eager: the function sun_track must shadow the module radscene.render.sun_track here
from radscene.render.sun_track import SunGeometry, SunTrack, sun_geometry, sun_track

if TYPE_CHECKING:  # for type checkers and the API docs; at run time __getattr__ imports them
    from radscene.render.integrator import (
        BACKGROUND_TERM,
        COUPLING_TERMS,
        TERMS,
        render,
        render_all,
    )

__all__ = ["TERMS", "BACKGROUND_TERM", "COUPLING_TERMS", "SunGeometry", "SunTrack", "render", "render_all",
           "sun_geometry", "sun_track"]

_FROM_INTEGRATOR = ("TERMS", "BACKGROUND_TERM", "COUPLING_TERMS", "render", "render_all")


def __getattr__(name: str):
    if name in _FROM_INTEGRATOR:
        value = getattr(importlib.import_module("radscene.render.integrator"), name)
        globals()[name] = value
        return value
    raise AttributeError(f"module 'radscene.render' has no attribute {name!r}")


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(__all__))


# radscene.render, called, is the top-level function radscene.pipeline.render: the class that
# makes it so belongs to the top-level package (radscene/__init__.py), which stands above the
# layers and is always imported before this one
from radscene import _RenderPackage  # noqa: E402

sys.modules[__name__].__class__ = _RenderPackage
