"""Every bundled example scene loads and validates."""

from __future__ import annotations

from importlib import resources

import pytest

import radscene

EXAMPLES = sorted(p.name.removesuffix(".yaml")
                  for p in (resources.files("radscene") / "examples").iterdir()
                  if p.name.endswith(".yaml"))


def test_there_are_examples():
    assert {"demo", "thermal_cameras"} <= set(EXAMPLES)


@pytest.mark.parametrize("name", EXAMPLES)
def test_example_loads(name):
    scene = radscene.load_scene(radscene.example_path(name))
    assert scene.observers
    assert scene.bands or all(o.spectral is not None for o in scene.observers)
