"""Rendering: signature terms, illumination queries and the image integrator."""

from radscene.render.integrator import BACKGROUND_TERM, COUPLING_TERMS, TERMS, render, render_all
from radscene.render.sun_track import SunGeometry, SunTrack, sun_geometry, sun_track

__all__ = ["TERMS", "BACKGROUND_TERM", "COUPLING_TERMS", "SunGeometry", "SunTrack", "render", "render_all",
           "sun_geometry", "sun_track"]
