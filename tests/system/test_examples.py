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



def _reaches_thermal(scene):
    """Whether a band or a spectral grid of the scene reaches beyond 2.5 µm."""
    from radscene.pipeline import THERMAL_FROM

    return (any(b.response.support[1] > THERMAL_FROM for b in scene.bands)
            or any(o.spectral is not None and o.spectral.wavelength[-1] > THERMAL_FROM
                   for o in scene.observers))


@pytest.mark.parametrize("name", EXAMPLES)
def test_thermal_channels_come_from_the_heat_balance(name):
    """An example whose bands or channels reach the thermal infrared fixes no surface's
    temperature: the heat balance sets them all (README, "Temperatures")."""
    import numpy as np

    from radscene.pipeline import thermal_active

    scene = radscene.load_scene(radscene.example_path(name))
    if not _reaches_thermal(scene):
        pytest.skip(f"{name} has no band beyond 2.5 µm")
    assert thermal_active(scene)
    fixed = {obj.name: int(np.sum(obj.face_fixed)) for obj in scene.objects
             if obj.face_fixed is not None and np.any(obj.face_fixed)}
    assert not fixed, fixed


def _object_id_map(scene, setup):
    """The object_id truth map of an observer's render (the object each pixel's centre ray
    meets first, -1 for none), traced without rendering: the render's heat balance and
    radiometry take minutes, the rays a second."""
    import numpy as np

    from radscene.geometry import RayTracer

    tracer = RayTracer([obj.mesh for obj in scene.objects])
    rays = setup.camera.rays(supersample=1)
    hits = tracer.intersect(rays.origins, rays.directions)
    ids = np.full(rays.shape[0] * rays.shape[1], -1)
    ids[rays.pixel[hits.hit]] = hits.object[hits.hit]
    return ids.reshape(rays.shape)


def test_thermal_cameras_frame_every_vehicle():
    """Each thermal camera of the thermal example sees the truck and both cars whole: each
    covers at least 400 pixels of the render (25 detector pixels at the sensors' 4x
    oversampling) and none is cut by the edge of the image."""
    import numpy as np

    scene = radscene.load_scene(radscene.example_path("thermal_cameras"))
    names = [obj.name for obj in scene.objects]
    vehicles = ("truck", "car_1", "car_2")
    assert set(vehicles) <= set(names)
    thermal = [o for o in scene.observers
               if all(scene.band(b).response.center >= 2.5 for b in o.bands)]
    assert {o.name for o in thermal} == {"mwir", "lwir"}
    for setup in thermal:
        ids = _object_id_map(scene, setup)
        ny, nx = ids.shape
        for vehicle in vehicles:
            rows, cols = np.nonzero(ids == names.index(vehicle))
            assert len(rows) >= 400, (setup.name, vehicle, len(rows))
            assert rows.min() > 0 and cols.min() > 0, (setup.name, vehicle)
            assert rows.max() < ny - 1 and cols.max() < nx - 1, (setup.name, vehicle)
