"""Scenes: the scene-file schema and the loader that resolves it."""

from radscene.scene.load import Band, ObserverSetup, Scene, SceneObject, load_scene, read_scene_file
from radscene.scene.schema import SceneSpec

__all__ = ["Band", "ObserverSetup", "Scene", "SceneObject", "SceneSpec", "load_scene", "read_scene_file"]
