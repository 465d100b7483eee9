"""The coupling layers through a render: switches, uniform scenes and refused settings."""

from __future__ import annotations

import numpy as np
import pytest

from radscene import load_scene, render
from radscene.errors import ConfigError
from radscene.render import BACKGROUND_TERM, COUPLING_TERMS, TERMS

DATABASE = {"type": "database", "profile": "us_standard", "aerosol": "rural",
            "visibility": "23 km"}
BANDS = [{"name": "blue", "min": 0.44, "max": 0.46}, {"name": "nir", "min": 0.86, "max": 0.88}]


def _plate(make_plate_scene, atmosphere=DATABASE, altitude=700_000.0, **settings):
    scene = make_plate_scene({"reflectance": 0.3}, atmosphere, BANDS, sky_samples=64, **settings)
    scene["objects"][0]["shape"] = {"type": "plate", "width": 20_000, "length": 20_000}
    scene["observers"][0].update(altitude=altitude, gsd=100.0, shape=[10, 10])
    return scene


def test_layers_sum_to_the_radiance_and_a_uniform_plate_has_no_adjacency(make_plate_scene):
    ds = render(load_scene(_plate(make_plate_scene)))
    total = sum(ds[name].values for name in TERMS + (BACKGROUND_TERM,) + COUPLING_TERMS)
    np.testing.assert_allclose(ds["radiance"].values, total, rtol=1e-12)
    for name in ("multiple_reflection", "diffuse_transmitted"):
        assert np.all(ds[name].values > 0.0), name
    # the PSF moves nothing on a uniform plate: only the pixels' sky-fan noise is blurred
    # (pixel by pixel ±1 %; over the image its mean is the noise of the border cells, whose
    # mean stands for the surroundings beyond the image: ~0.3 % of it, times t_d / τ)
    direct = ds["sun_diffuse"] + ds["sky_reflected"]
    assert abs(float(ds["adjacency"].mean())) < 1e-3 * float(direct.mean())
    assert float(np.abs(ds["adjacency"]).max()) < 0.02 * float(direct.mean())


def test_coupling_off_gives_the_direct_terms_alone(make_plate_scene):
    on = render(load_scene(_plate(make_plate_scene)))
    off = render(load_scene(_plate(make_plate_scene, coupling=False)))
    for name in COUPLING_TERMS:
        assert np.all(off[name].values == 0.0)
    for name in TERMS:
        np.testing.assert_allclose(off[name].values, on[name].values, rtol=1e-12)


def test_adjacency_switch_and_its_automatic_default(make_plate_scene):
    # an aircraft below the boundary layer: no PSF by default (the uniform-surroundings
    # coupling stays); forcing it on gives the same image on a uniform plate
    low = render(load_scene(_plate(make_plate_scene, altitude=1000.0)))
    assert np.all(low["adjacency"].values == 0.0)
    assert np.all(low["diffuse_transmitted"].values > 0.0)
    forced = render(load_scene(_plate(make_plate_scene, altitude=1000.0, adjacency=True)))
    assert np.any(forced["adjacency"].values != 0.0)
    # (pixel by pixel the PSF smooths the sky fans' sampling noise; the mean is unchanged)
    assert float(forced["radiance"].mean()) == pytest.approx(float(low["radiance"].mean()),
                                                             rel=1e-3)


def test_engines_that_do_not_scatter_leave_the_layers_zero(make_plate_scene):
    uniform = {"type": "uniform", "transmittance": 0.8, "sun_transmittance": 0.9,
               "path_radiance": 5.0, "sky_radiance": 2.0}
    ds = render(load_scene(_plate(make_plate_scene, atmosphere=uniform)))
    for name in COUPLING_TERMS:
        assert np.all(ds[name].values == 0.0)


def test_a_fixed_surface_albedo_with_coupling_is_refused(make_plate_scene):
    scene = _plate(make_plate_scene, atmosphere={**DATABASE, "surface_albedo": 0.15})
    with pytest.raises(ConfigError) as err:
        load_scene(scene)
    assert err.value.key == "environment.atmosphere.surface_albedo"
    assert "coupling: false" in str(err.value)
    scene["render"]["coupling"] = False
    load_scene(scene)


def test_lowtrans_fixed_ground_albedo_is_refused_under_its_own_key(make_plate_scene):
    # the lowtran engine names it albedo (its SALB); the check reads the engine's key
    scene = _plate(make_plate_scene, atmosphere={"type": "lowtran", "albedo": 0.2})
    with pytest.raises(ConfigError) as err:
        load_scene(scene)
    assert err.value.key == "environment.atmosphere.albedo"
    scene["render"]["coupling"] = False
    load_scene(scene)


def test_adjacency_setting_accepts_auto_or_a_boolean(make_plate_scene):
    with pytest.raises(ConfigError) as err:
        load_scene(_plate(make_plate_scene, adjacency="sometimes"))
    assert "adjacency" in str(err.value)
