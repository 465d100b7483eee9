"""Sky rays through volumes and sheets (radscene.render.media): the vectorised change of the
sky fans against the ray-by-ray reference, on a scene with an opaque box, a sheet and a
volume."""

from __future__ import annotations

import numpy as np
import pytest

from radscene import load_scene
from radscene.render import illumination, integrator, media, media_sky

SCENE = {
    "name": "media",
    "environment": {"sun": {"zenith": 40.0, "azimuth": 120.0}, "atmosphere": {"type": "none"}},
    "materials": {"ground": {"reflectance": 0.3}, "net": {"reflectance": 0.1,
                                                          "transmittance": 0.6}},
    "objects": [
        {"name": "ground", "shape": {"type": "plate", "width": 60, "length": 60},
         "material": "ground", "temperature": 300.0},
        {"name": "box", "shape": {"type": "box", "size": [4, 4, 4]}, "position": [3, 0, 0],
         "material": "ground", "temperature": 300.0},
        {"name": "net", "shape": {"type": "plate", "width": 6, "length": 6},
         "position": [-3, 0, 3], "material": "net", "temperature": 300.0,
         "transmissive": True},
    ],
    "volumes": [{"name": "smoke", "shape": {"type": "ellipsoid", "radii": [6, 5, 3]},
                 "position": [0, 2, 6], "optical_depth": 0.9, "temperature": 330.0,
                 "single_scattering_albedo": 0.3,
                 "profile": {"type": "gaussian", "sigma": 3.0}}],
    "bands": [{"name": "vis", "min": 0.5, "max": 0.6}, {"name": "lwir", "min": 8.0, "max": 12.0}],
    "observers": [{"name": "cam", "type": "orthographic", "center": [0, 0], "gsd": 1.0,
                   "shape": [4, 4], "altitude": 100}],
}


@pytest.fixture(scope="module")
def setup():
    scene = load_scene(SCENE)
    tables = integrator.scene_tables(scene)
    bands = [scene.band(b["name"]) for b in SCENE["bands"]]
    sun = np.array([0.3, 0.5, 0.8]) / np.linalg.norm([0.3, 0.5, 0.8])
    medium = media_sky.for_render(scene, tables, bands, sun, False, None)
    rng = np.random.default_rng(3)
    n = 10
    xy = rng.uniform(-5.0, 0.5, (n, 2))
    origins = np.column_stack([xy, np.full(n, tables.epsilon)])
    normals = np.tile([0.0, 0.0, 1.0], (n, 1))
    return tables, medium, origins, normals, rng.random((n, 2))


def test_sky_fan_change_equals_reference(setup):
    tables, medium, origins, normals, shift = setup
    samples = 16
    change = media.sky_fan(tables, medium, origins, normals, samples, shift)
    visible = illumination.sky_fractions(tables.tracer, origins, normals, samples,
                                         (np.array([0.0, 90.0]), np.array([0.0])), None,
                                         shift=shift).sum(axis=1)
    reference = media.sky_fan_reference(tables, medium, origins, normals, samples, shift)
    fast = visible[:, None] + change.view(len(origins))
    assert fast == pytest.approx(reference, rel=1e-12, abs=1e-12)
    # the scene is not trivial: rays through the net, the smoke and both, and the box
    assert len(change.point) > 0.3 * samples * len(origins)
    assert np.all(change.light[:, 1] >= 0.0) and np.any(change.light[:, 1] > 0.0)
    assert np.any(reference[:, 0] != reference[:, 1])  # no scattering in the LWIR


def test_sky_fan_change_does_not_depend_on_the_chunk_size(setup, monkeypatch):
    tables, medium, origins, normals, shift = setup
    whole = media.sky_fan(tables, medium, origins, normals, 16, shift)
    monkeypatch.setattr(media, "CHUNK_RAYS", 48)  # three points per chunk
    parts = media.sky_fan(tables, medium, origins, normals, 16, shift)
    np.testing.assert_array_equal(parts.point, whole.point)
    assert parts.delta == pytest.approx(whole.delta, rel=1e-14, abs=1e-15)
    assert parts.light == pytest.approx(whole.light, rel=1e-14, abs=1e-15)


@pytest.mark.parametrize("exponent", [3.0, 40.0])
def test_lobe_fan_change_equals_reference(setup, exponent):
    """The lobe fans' change: the same directions as the lobe's sky fractions (their view),
    ray by ray. The normals lean 40° one way and the lobes' axes up to 80° the other, so
    part of each lobe is below the surface though above the horizon: never sky."""
    tables, medium, origins, _, shift = setup
    samples = 16
    lean = np.radians(40.0)
    normals = np.tile([np.sin(lean), 0.0, np.cos(lean)], (len(origins), 1))
    tilt = np.radians(np.linspace(10.0, 80.0, len(origins)))
    axes = np.column_stack([-np.sin(tilt), np.zeros_like(tilt), np.cos(tilt)])
    exponents = np.full(len(origins), exponent)
    change = media.lobe_fan(tables, medium, origins, normals, axes, exponents, samples, shift)
    visible = illumination.lobe_sky_fractions(tables.tracer, origins, normals, axes, exponents,
                                              samples, (np.array([0.0, 90.0]), np.array([0.0])),
                                              None, shift=shift).sum(axis=1)
    reference = media.sky_fan_reference(tables, medium, origins, normals, samples, shift,
                                        (axes, exponents))
    fast = visible[:, None] + change.view(len(origins))
    assert fast == pytest.approx(reference, rel=1e-12, abs=1e-12)
    assert len(change.point) > 0.1 * samples * len(origins)  # the lobes meet the media
    assert np.any(visible < 1.0 - 1e-9)  # and some rays go below the surface or are blocked
