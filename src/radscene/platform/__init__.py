"""Platforms and observers: camera models that generate rays."""

from radscene.platform.cameras import OrthographicCamera, PerspectiveCamera, RayBundle

__all__ = ["OrthographicCamera", "PerspectiveCamera", "RayBundle"]
