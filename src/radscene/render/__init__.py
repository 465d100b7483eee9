"""Rendering: signature terms, illumination queries and the image integrator."""

from radscene.render.integrator import (
    COUPLING_TERMS,
    TERMS,
    SunGeometry,
    render,
    render_all,
    sun_geometry,
)

__all__ = ["TERMS", "COUPLING_TERMS", "SunGeometry", "render", "render_all", "sun_geometry"]
