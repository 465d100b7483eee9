"""The geolocation truth is the pixel's centre whatever the supersampling (an even k×k grid has
no sub-sample at the centre: the middle 2×2 are averaged)."""

import numpy as np
import pytest

import radscene
from radscene.scene import load_scene


def _scene(supersample):
    return {
        "environment": {"location": {"latitude": 45.0, "longitude": 7.0}, "time": "2026-06-21T10:00:00Z"},
        "objects": [{"name": "ground", "shape": {"type": "plate", "width": 400, "length": 400},
                     "position": [0, 0, 0], "material": "asphalt", "temperature": "300 K"}],
        "bands": [{"name": "red", "min": "0.63 um", "max": "0.69 um"}],
        "observers": [{"name": "map", "type": "orthographic", "center": [0, 0], "gsd": 10.0, "shape": [6, 6],
                       "altitude": 1000, "supersample": supersample}],
        "render": {"sky_samples": 1, "specular_samples": 1},
    }


@pytest.mark.parametrize("supersample", [2, 3, 4])
def test_geolocation_does_not_move_with_the_supersampling(supersample):
    ref = radscene.render(load_scene(_scene(1), base_dir="."), "map")
    got = radscene.render(load_scene(_scene(supersample), base_dir="."), "map")
    # 1e-9 deg is 0.1 mm; a third of a 10 m pixel is 3e-5 deg
    np.testing.assert_allclose(got.latitude.values, ref.latitude.values, rtol=0, atol=1e-9)
    np.testing.assert_allclose(got.longitude.values, ref.longitude.values, rtol=0, atol=1e-9)
    np.testing.assert_allclose(got.height.values, ref.height.values, rtol=0, atol=1e-6)
