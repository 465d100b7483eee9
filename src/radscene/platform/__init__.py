"""Platforms and observers: camera and scanner models that generate rays, trajectories,
orbits and geolocation."""

from radscene.platform.cameras import OrthographicCamera, PerspectiveCamera, RayBundle
from radscene.platform.geolocation import LocalFrame, geolocation_truth, project
from radscene.platform.orbit import Orbit
from radscene.platform.scanners import PushbroomScanner, WhiskbroomScanner, to_body_frame
from radscene.platform.trajectory import Pose, Trajectory

__all__ = [
    "LocalFrame",
    "Orbit",
    "OrthographicCamera",
    "PerspectiveCamera",
    "Pose",
    "PushbroomScanner",
    "RayBundle",
    "Trajectory",
    "WhiskbroomScanner",
    "geolocation_truth",
    "project",
    "to_body_frame",
]
