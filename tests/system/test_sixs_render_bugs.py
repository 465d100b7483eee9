"""System tests: scenes rendered with the ``sixs`` engine that used to fail.

A flat terrain at sea level seen by a satellite at 700 km looking 30 deg off nadir, in a
maritime aerosol. The primary rays' hits on the terrain carry float32 noise of ~1e-10 m
around 0 m, which the engine refused as "a path below the ground"; and 6S prints NaN for the
maritime phase function at 3 deg in the visible, which made the sky, and so the radiance, NaN.
"""

from __future__ import annotations

import functools

import numpy as np
import pytest

from radscene import load_scene, render
from radscene.atmosphere import sixs_runner as sr
from radscene.atmosphere.sixs import SixSAtmosphere
from radscene.errors import ConfigError

AVAILABLE, REASON = sr.sixs_available()
pytestmark = pytest.mark.skipif(not AVAILABLE, reason=f"6S cannot run here: {REASON}")


def _scene(terrain: dict | None = None) -> dict:
    return {
        "name": "sixs_satellite",
        "environment": {
            "location": {"latitude": 0.0, "longitude": 0.0, "altitude": "0 m"},
            "sun": {"zenith": "30 deg", "azimuth": "180 deg"},
            "atmosphere": {"type": "sixs", "profile": "us_standard", "aerosol": "maritime",
                           "aot550": 0.2},
        },
        "materials": {"gray": {"reflectance": 0.3}},
        "terrain": terrain or {"type": "procedural", "size": ["2 km", "2 km"],
                               "spacing": "100 m", "relief": "0 m", "material": "gray"},
        "bands": [{"name": "green", "min": "0.55 um", "max": "0.57 um"}],
        "observers": [{"name": "sat", "type": "orthographic", "center": ["1 km", "1 km"],
                       "gsd": "100 m", "shape": [16, 16], "altitude": "700 km",
                       "zenith": "30 deg"}],
        "render": {"sky_samples": 4},
    }


@functools.cache
def _rendered():
    return render(load_scene(_scene()))


def test_flat_terrain_at_the_engines_lowest_altitude_renders():
    ds = _rendered()
    assert ds["view_zenith"].values == pytest.approx(30.0, abs=1e-6)
    for term in ("sun_diffuse", "path_radiance", "path_transmittance"):
        values = ds[term].values
        assert np.all(np.isfinite(values)) and np.all(values > 0), term


def test_terrain_a_metre_below_the_ground_is_still_refused():
    dem = {"type": "dem", "elevation": np.full((5, 5), -1.0).tolist(), "spacing": [500, 500],
           "material": "gray"}
    with pytest.raises(ConfigError, match="a path below the ground: -1 m"):
        render(load_scene(_scene(dem)))


def test_maritime_sky_seen_from_space_is_finite_and_near_6s_diffuse_irradiance():
    ds = _rendered()
    terms = ("sun_diffuse", "sun_specular", "thermal_emission", "sky_reflected", "path_radiance",
             "background_reflected", "multiple_reflection", "diffuse_transmitted", "adjacency")
    radiance = ds["radiance"].values
    assert np.all(np.isfinite(radiance))
    np.testing.assert_allclose(radiance, sum(ds[t].values for t in terms), rtol=1e-12)
    # a flat gray Lambertian ground that sees the whole sky: reflected sky / reflected sun is
    # 6S's diffuse / direct irradiance on a horizontal surface (the same transmittance up).
    # The renderer interpolates the sky between its nodes (zenith 20 and 40 deg around the
    # sun at 30), which alone would round off the maritime aureole (11 % less here); the node
    # table is scaled to the engine's own hemispheric integral, so the mean over the pixels'
    # sky fans is 6S's, to their sampling noise.
    atm = SixSAtmosphere(profile="us_standard", aerosol="maritime", aot550=0.2)
    irradiance = atm.components(1e5, 0.0, 0.0, [0.56], sun_zenith=30.0, relative_azimuth=0.0)
    expected = float(irradiance["diffuse_irradiance"][0, 0] / irradiance["direct_irradiance"][0, 0])
    ratio = ds["sky_reflected"].values / ds["sun_diffuse"].values
    assert np.all(ratio > 0)
    assert ratio.mean() == pytest.approx(expected, rel=0.01)
