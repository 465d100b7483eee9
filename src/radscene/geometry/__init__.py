"""Geometry: frames and angle conventions, meshes, primitives, terrain and the ray engine."""

from radscene.geometry.frames import (
    angles_from_direction,
    direction_from_angles,
    normalize,
    orthonormal_basis,
    to_world,
)
from radscene.geometry.mesh import (
    GLTF_TO_ENU,
    MESH_FORMATS,
    Mesh,
    concatenate,
    load_mesh,
    rotation_matrix,
)
from radscene.geometry.primitives import box, cylinder, plate
from radscene.geometry.raytracer import Hits, RayTracer
from radscene.geometry.terrain import Heightfield, procedural_terrain

__all__ = [
    "angles_from_direction",
    "direction_from_angles",
    "normalize",
    "orthonormal_basis",
    "to_world",
    "GLTF_TO_ENU",
    "MESH_FORMATS",
    "Mesh",
    "concatenate",
    "load_mesh",
    "rotation_matrix",
    "box",
    "cylinder",
    "plate",
    "Hits",
    "RayTracer",
    "Heightfield",
    "procedural_terrain",
]
