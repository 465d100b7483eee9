"""Rendering: signature terms, illumination queries and the image integrator."""

from radscene.render.integrator import TERMS, SunGeometry, render, render_all, sun_geometry

__all__ = ["TERMS", "SunGeometry", "render", "render_all", "sun_geometry"]
