"""Volumes: chords, marched optical paths against the per-ray reference and closed forms,
band sums, and the render's layers."""

from __future__ import annotations

import math

import numpy as np
import pytest

from radscene import load_scene, render
from radscene.errors import ConfigError
from radscene.render import volume_scattering, volumes
from radscene.render.volumes import Volume

#: The vectorised and the per-ray paths add the same terms in another order.
ORDER_REL = 1e-12


def _volume(shape="box", profile="uniform", **kwargs):
    args = dict(name="v", shape=shape, center=np.array([1.0, -2.0, 5.0]),
                half_size=np.array([3.0, 2.0, 1.5]), extinction=lambda wl: 0.2 + 0.0 * wl,
                profile=profile, scale_height=0.8, sigma=np.array([1.5, 1.0, 0.7]),
                density=1.3)
    args.update(kwargs)
    return Volume(**args)


def _rays(n, seed=4):
    rng = np.random.default_rng(seed)
    origins = rng.uniform(-5.0, 5.0, (n, 3)) + np.array([1.0, -2.0, 5.0])
    directions = rng.normal(size=(n, 3))
    directions[: n // 8, 1:] = 0.0  # some along an axis: parallel to faces
    directions /= np.linalg.norm(directions, axis=1, keepdims=True)
    return origins, directions


@pytest.mark.parametrize("shape", ["box", "ellipsoid"])
@pytest.mark.parametrize("profile", ["uniform", "exponential", "gaussian"])
def test_vectorised_path_equals_the_reference(shape, profile):
    vol = _volume(shape, profile)
    origins, directions = _rays(800)
    t_max = np.where(np.arange(800) % 3 == 0, 4.0, np.inf)
    fast = volumes.optical_path(vol, origins, directions, t_max)
    slow = [volumes.optical_path_reference(vol, o, d, t) for o, d, t in
            zip(origins, directions, t_max, strict=True)]
    assert np.count_nonzero(fast) > 60  # enough rays cross it
    assert fast == pytest.approx(slow, rel=ORDER_REL, abs=1e-13)


def test_box_chord_is_the_slab_thickness_over_the_cosine():
    vol = _volume(center=np.zeros(3), half_size=np.array([50.0, 50.0, 1.0]), density=1.0)
    zen = np.radians([0.0, 20.0, 60.0])
    d = np.stack([np.sin(zen), np.zeros(3), -np.cos(zen)], axis=1)
    x = volumes.optical_path(vol, np.array([[0.0, 0.0, 10.0]] * 3), d)
    assert x == pytest.approx(2.0 / np.cos(zen), rel=1e-14)


def test_sphere_chord_at_an_impact_parameter():
    vol = _volume("ellipsoid", center=np.zeros(3), half_size=np.full(3, 2.0), density=1.0)
    b = np.array([0.0, 1.0, 1.9, 2.5])
    origins = np.stack([b, np.full(4, -10.0), np.zeros(4)], axis=1)
    x = volumes.optical_path(vol, origins, np.tile([0.0, 1.0, 0.0], (4, 1)))
    assert x == pytest.approx(2.0 * np.sqrt(np.maximum(4.0 - b**2, 0.0)), rel=1e-12)


def test_a_ray_starting_inside_counts_from_its_origin():
    vol = _volume(center=np.zeros(3), half_size=np.full(3, 1.0), density=1.0)
    x = volumes.optical_path(vol, np.zeros((1, 3)), np.array([[0.0, 0.0, 1.0]]))
    assert x == pytest.approx([1.0], rel=1e-14)


def test_exponential_profile_vertical_path():
    """∫_0^H ρ_0 e^{−z/h} dz = ρ_0 h (1 − e^{−H/h})."""
    vol = _volume(profile="exponential")
    x = volumes.optical_path(vol, np.array([[1.0, -2.0, 0.0]]), np.array([[0.0, 0.0, 1.0]]))
    expected = 1.3 * 0.8 * (1.0 - math.exp(-3.0 / 0.8))
    # the midpoint rule's bound, H Δ² max|ρ''| / 24 with Δ = H / 64
    bound = 3.0 * (3.0 / volumes.MARCH_STEPS) ** 2 * 1.3 / 0.8**2 / 24.0
    assert abs(x[0] - expected) <= bound
    assert abs(x[0] - expected) > bound / 10.0  # a marched, not an analytic, answer


def test_gaussian_profile_through_the_centre():
    """ρ_0 ∫ e^{−z²/2σ²} dz over ±c = ρ_0 σ √(2π) erf(c / (σ √2))."""
    vol = _volume(profile="gaussian")
    x = volumes.optical_path(vol, np.array([[1.0, -2.0, 0.0]]), np.array([[0.0, 0.0, 1.0]]))
    sigma, c = 0.7, 1.5
    expected = 1.3 * sigma * math.sqrt(2 * math.pi) * math.erf(c / (sigma * math.sqrt(2)))
    # the midpoint rule's bound, H Δ² max|ρ''| / 24 with Δ = H / 64, max|ρ''| = ρ_0 / σ²
    bound = 3.0 * (3.0 / volumes.MARCH_STEPS) ** 2 * 1.3 / sigma**2 / 24.0
    assert abs(x[0] - expected) <= bound


def test_band_sums():
    k = np.array([0.1, 0.5, 2.0])
    w = np.array([0.2, 0.5, 0.3])
    x = np.array([0.0, 1.0, 4.0])
    t = volumes.band_transmittance(k, w, x)
    assert t == pytest.approx([(w * np.exp(-k * xi)).sum() / w.sum() for xi in x], rel=1e-14)
    b = np.array([3.0, 5.0, 7.0])
    e = volumes.band_emission(k, w, x, b, albedo=0.25, transmittance=0.9)
    assert e == pytest.approx([0.75 * 0.9 * (w * b * (1 - np.exp(-k * xi))).sum() for xi in x],
                              rel=1e-14)


def test_nearer_volume_attenuates_the_emission_of_the_farther():
    band = type("B", (), {})()
    from radscene.radiometry import RectangularResponse

    band.response = RectangularResponse(8.0, 12.0)
    near = _volume(center=np.array([0.0, 0.0, 5.0]), half_size=np.array([5.0, 5.0, 1.0]),
                   density=1.0, temperature=300.0, extinction=lambda wl: 0.3 + 0.0 * wl)
    far = _volume(center=np.array([0.0, 0.0, 1.0]), half_size=np.array([5.0, 5.0, 0.5]),
                  density=1.0, temperature=400.0, extinction=lambda wl: 1.0 + 0.0 * wl)
    origin, down = np.array([[0.0, 0.0, 20.0]]), np.array([[0.0, 0.0, -1.0]])
    for order in ([near, far], [far, near]):
        crosses, through, light = volumes.line_of_sight(order, [band], origin, down,
                                                        np.array([np.inf]))
        alone = [volumes.line_of_sight([v], [band], origin, down, np.array([np.inf]))
                 for v in (near, far)]
        assert crosses[0]
        assert through[0, 0] == pytest.approx(math.exp(-0.6) * math.exp(-1.0), rel=1e-14)
        assert light[0, 0] == pytest.approx(alone[0][2][0, 0] + math.exp(-0.6)
                                            * alone[1][2][0, 0], rel=1e-14)


def _scene(supersample=1, **volume):
    return {
        "name": "smoke",
        "environment": {"sun": {"zenith": 35.0, "azimuth": 160.0},
                        "atmosphere": {"type": "uniform", "sky_radiance": 3.0,
                                       "transmittance": 0.8, "path_radiance": 1.5}},
        "materials": {"grey": {"reflectance": 0.4}},
        "objects": [{"name": "plate", "shape": {"type": "plate", "width": 100, "length": 100},
                     "material": "grey", "temperature": "300 K"},
                    {"name": "block", "shape": {"type": "box", "size": [4, 4, 6]},
                     "position": [0, 6, 0], "material": "grey", "temperature": "330 K"}],
        "volumes": [{"name": "cloud", "shape": {"type": "ellipsoid", "radii": [5, 4, 3]},
                     "position": [-3, 0, 8], "optical_depth": 0.9, "temperature": "320 K",
                     **volume}],
        "bands": [{"name": "vis", "min": 0.5, "max": 0.6}, {"name": "lwir", "min": 8, "max": 12}],
        "observers": [{"name": "cam", "type": "perspective", "position": [30, -30, 25],
                       "look_at": [0, 0, 3], "fov": 50, "shape": [24, 24],
                       "supersample": supersample}],
        "render": {"background_samples": 4},
    }


LAYERS = ("sun_diffuse", "sun_specular", "thermal_emission", "sky_reflected", "path_radiance",
          "background_reflected", "multiple_reflection", "diffuse_transmitted", "adjacency",
          "transmitted", "volume_emission", "volume_scattered")


@pytest.mark.parametrize("supersample", [1, 2])
def test_radiance_is_the_sum_of_the_layers_with_a_volume(supersample):
    ds = render(load_scene(_scene(supersample, single_scattering_albedo=0.5)))
    total = sum(ds[name] for name in LAYERS)
    assert ds["radiance"].values == pytest.approx(total.values, rel=1e-12)
    seen = ds["volume_transmittance"].values < 1.0
    assert np.count_nonzero(seen[0]) > 10  # the cloud covers part of the image
    assert np.all(ds["volume_emission"].values[:, ~seen[0]] == 0.0)
    assert np.all(ds["transmitted"].values[:, ~seen[0]] == 0.0)
    assert float(ds["transmitted"].sel(band="vis").max()) > 0.0
    assert float(ds["volume_scattered"].sel(band="vis").max()) > 0.0


def test_volume_of_zero_density_changes_nothing():
    clear = _scene()
    del clear["volumes"]
    a = render(load_scene(clear))
    b = render(load_scene(_scene(density=0.0, extinction=0.3, optical_depth=None)))
    for name in ("radiance", "sun_diffuse", "thermal_emission", "brightness_temperature"):
        assert b[name].values == pytest.approx(a[name].values, rel=1e-12, nan_ok=True), name


def test_optical_depth_with_a_profile_is_that_of_the_vertical_through_the_centre():
    scene = load_scene(_scene(profile={"type": "exponential", "scale_height": 1.5}))
    vol = scene.volumes[0]
    below = vol.center - np.array([0.0, 0.0, 10.0])
    x = volumes.optical_path(vol, below[None], np.array([[0.0, 0.0, 1.0]]))
    assert float(vol.extinction(np.array([10.0]))[0] * x[0]) == pytest.approx(0.9, rel=1e-12)


@pytest.mark.parametrize(("change", "key"), [
    ({"density": -1.0}, "volumes[0].density"),
    ({"temperature": None}, "volumes[0].temperature"),
    ({"extinction": 0.2}, "volumes[0]"),
    ({"optical_depth": -0.5}, "volumes[0].optical_depth"),
    ({"single_scattering_albedo": 1.2}, "volumes[0].single_scattering_albedo"),
    ({"profile": {"type": "exponential"}}, "volumes[0].profile"),
    ({"profile": {"type": "uniform", "sigma": 3.0}}, "volumes[0].profile"),
    ({"shape": {"type": "cone", "radius": 3.0}}, "volumes[0].shape"),
])
def test_bad_volumes_name_the_key(change, key):
    scene = _scene()
    scene["volumes"][0].update(change)
    scene["volumes"][0] = {k: v for k, v in scene["volumes"][0].items() if v is not None}
    with pytest.raises(ConfigError, match=key.replace("[", r"\[").replace("]", r"\]")):
        load_scene(scene)


@pytest.mark.parametrize("shape", ["box", "ellipsoid"])
@pytest.mark.parametrize("profile", ["uniform", "exponential", "gaussian"])
def test_single_scattering_equals_the_reference(shape, profile):
    vol = _volume(shape, profile, albedo=0.8, asymmetry=0.6, extinction=None)
    origins, directions = _rays(200, seed=9)
    sun = np.array([0.3, -0.4, 0.866])
    sun /= np.linalg.norm(sun)
    t_max = np.where(np.arange(200) % 4 == 0, 3.0, np.inf)
    k, weight, source = 0.45, 1.0, 1.7
    steps = 16  # the reference marches the sun path of every step: keep it short
    fast = volume_scattering.single_scattering(vol, np.array([k]), np.array([weight]),
                                     np.array([source]), origins, directions, t_max, sun,
                                     steps=steps, sun_steps=8)
    slow = [volume_scattering.single_scattering_reference(vol, k, source, o, d, t, sun, steps=steps,
                                                sun_steps=8)
            for o, d, t in zip(origins, directions, t_max, strict=True)]
    assert np.count_nonzero(fast) > 15
    assert fast == pytest.approx(slow, rel=1e-12, abs=1e-15)


def test_henyey_greenstein_is_normalised():
    mu = np.linspace(-1.0, 1.0, 200001)
    for g in (0.0, 0.3, -0.5, 0.8):
        p = volume_scattering.phase_function(mu, g)
        integral = 2.0 * np.pi * np.sum(0.5 * (p[1:] + p[:-1]) * np.diff(mu))
        assert integral == pytest.approx(4.0 * np.pi, rel=1e-6), g


def _grid_scene(tmp_path, grid, name="density.npy"):
    path = tmp_path / name
    if name.endswith(".npy"):
        np.save(path, grid)
    else:
        import xarray as xr

        dims = ("z", "y", "x") if np.ndim(grid) == 3 else ("y", "x")
        xr.Dataset({"density": (dims, grid)}).to_netcdf(path, engine="h5netcdf")
    scene = _scene(extinction=0.2, optical_depth=None,
                   profile={"type": "grid", "file": name})
    scene["volumes"][0]["shape"] = {"type": "box", "size": [8, 6, 4]}
    return scene


@pytest.mark.parametrize("name", ["density.npy", "density.nc"])
def test_grid_profile_is_trilinear_between_its_nodes(tmp_path, name):
    """Density rising linearly with height, 0 at the base to 2 at the top: the midpoint rule
    integrates a linear profile exactly, ∫_0^4 (z/2) dz = 4 along the vertical."""
    z = np.linspace(0.0, 2.0, 3)
    grid = np.broadcast_to(z[:, None, None], (3, 4, 5)).copy()
    scene = load_scene(_grid_scene(tmp_path, grid, name), base_dir=tmp_path)
    vol = scene.volumes[0]
    x = volumes.optical_path(vol, np.array([[-3.0, 0.5, -5.0], [-3.0, 0.5, 12.0]]),
                             np.array([[0.0, 0.0, 1.0], [0.0, 0.0, -1.0]]))
    assert x == pytest.approx([4.0, 4.0], rel=1e-12)
    ref = volumes.optical_path_reference(vol, [-3.0, 0.5, -5.0], [0.0, 0.0, 1.0])
    assert ref == pytest.approx(4.0, rel=1e-12)
    # outside the box nothing
    assert volumes.density(vol, np.array([[100.0, 0.0, 8.0]])) == pytest.approx([0.0])


@pytest.mark.parametrize(("grid", "name", "match"), [
    (np.ones((4, 4)), "density.npy", "three dimensions"),
    (np.ones((1, 4, 4)), "density.npy", "at least two"),
    (-np.ones((2, 2, 2)), "density.npy", ">= 0"),
    (np.ones((4, 4)), "density.nc", "dims"),
])
def test_bad_grids_name_the_file_key(tmp_path, grid, name, match):
    with pytest.raises(ConfigError, match=r"volumes\[0\]\.profile\.file: .*" + match):
        load_scene(_grid_scene(tmp_path, grid, name), base_dir=tmp_path)
