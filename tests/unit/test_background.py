"""The reflected-background pass (radscene.render.background): the vectorised estimator
against its one-path-at-a-time reference, determinism, and the scene settings."""

from __future__ import annotations

import numpy as np
import pytest

from radscene import load_scene, render
from radscene.errors import ConfigError
from radscene.geometry import RayTracer, box, plate
from radscene.materials import Material
from radscene.render import background
from radscene.render.spectral import band_quadrature

SUN = np.array([0.5, -0.3, 0.8]) / np.linalg.norm([0.5, -0.3, 0.8])


class _Band:
    """A rectangular response of peak 1 over [lo, hi] [um]."""

    def __init__(self, lo, hi):
        self.support = (lo, hi)
        self.center = 0.5 * (lo + hi)

    def __call__(self, wl):
        wl = np.asarray(wl, dtype=float)
        return ((wl >= self.support[0]) & (wl <= self.support[1])).astype(float)


def _setup(bounces, specular=0.0, packets=True, brdfs=None, n=12, samples=16):
    """A 2 m box on a 40 m plate, a visible and a thermal band; ``n`` points on the plate
    around the box, looking up, ``samples`` paths each. ``brdfs`` as for
    :func:`background.band_tables`."""
    meshes = [plate(40.0, 40.0), box((2.0, 2.0, 2.0)).transformed(translation=(0.0, 0.0, 0.0))]
    tracer = RayTracer(meshes, packets=packets)
    materials = [Material.create("ground", reflectance=0.3 + specular,
                                 specular_reflectance=specular,
                                 specular_exponent=40.0),
                 Material.create("wall", reflectance=0.6)]
    bands = [_Band(0.5, 0.6), _Band(8.0, 12.0)]
    quadrature = [band_quadrature(b) for b in bands]
    sun_spectra = [np.full(q[0].shape, 1500.0) for q in quadrature]
    zen, az = np.array([0.0, 45.0, 90.0]), np.array([0.0, 180.0])
    sky = np.array([[20.0, 25.0, 30.0, 32.0, 40.0, 41.0], [2.0, 2.5, 3.0, 3.0, 4.0, 4.0]])
    faces = [len(m.faces) for m in meshes]
    face_offset = np.array([0, faces[0]])
    face_material = np.concatenate([np.zeros(faces[0], int), np.ones(faces[1], int)])
    face_temperature = np.concatenate([np.full(faces[0], 300.0), np.full(faces[1], 320.0)])
    tables = background.band_tables(materials, brdfs or {}, quadrature, sun_spectra, sky,
                                    (zen, az), [False, True], face_offset, face_material,
                                    face_temperature)
    rng = np.random.default_rng(4)
    azimuth, radius = rng.uniform(0.0, 2.0 * np.pi, n), rng.uniform(1.5, 2.5, n)
    xy = radius[:, None] * np.column_stack([np.cos(azimuth), np.sin(azimuth)])  # beside the box
    origin = np.column_stack([xy, np.full(n, 1e-3)])
    normal = np.tile([0.0, 0.0, 1.0], (n, 1))
    wo = np.tile([0.2, 0.1, 1.0] / np.linalg.norm([0.2, 0.1, 1.0]), (n, 1))
    u = background.draws(7, 0, n, samples, bounces)
    return tracer, tables, origin, normal, wo, np.zeros(n, int), u


def _fan(tracer, origin, normal, sky_samples, seed=5):
    """The points' sky fans of ``sky_samples`` directions, traced as the render traces them
    (their rotations from ``seed``), with their blocked flags; None for ``sky_samples`` None."""
    from radscene.render import illumination

    if sky_samples is None:
        return None
    shift = np.random.default_rng(seed).random((len(origin), 2))
    blocked = np.empty((len(origin), sky_samples), dtype=bool)
    illumination.sky_fractions(tracer, origin, normal, sky_samples, np.array([0.0, 90.0]),
                               None, shift=shift, blocked=blocked)
    return background.Fan(shift, sky_samples, blocked)


@pytest.mark.parametrize("bounces", [1, 3])
@pytest.mark.parametrize("specular", [0.0, 0.3])
@pytest.mark.parametrize("sky", [None, 4, 16, 64])
def test_vectorised_pass_equals_reference(bounces, specular, sky):
    """Without a sky fan, with one smaller than the paths (16 per point), as many, larger."""
    tracer, tables, origin, normal, wo, material, u = _setup(bounces, specular)
    fan = _fan(tracer, origin, normal, sky)
    args = (tracer, tables, origin, normal, wo, material, SUN, u)
    fast = background.reflected(*args, epsilon=1e-3, fan=fan)
    slow = background.reflected_reference(*args, epsilon=1e-3, fan=fan)
    assert np.count_nonzero(fast[:, 1]) >= 8  # most points see the box
    assert fast == pytest.approx(slow, rel=1e-12, abs=1e-12)


@pytest.mark.parametrize("sky", [None, 9])
def test_vectorised_pass_equals_reference_without_packets(sky):
    """Without Embree's packets the first directions are drawn first, then intersected."""
    tracer, tables, origin, normal, wo, material, u = _setup(2, 0.3, packets=False)
    assert tracer.packets is None
    fan = _fan(tracer, origin, normal, sky)
    args = (tracer, tables, origin, normal, wo, material, SUN, u)
    fast = background.reflected(*args, epsilon=1e-3, fan=fan)
    assert np.count_nonzero(fast[:, 1]) >= 8
    assert fast == pytest.approx(background.reflected_reference(*args, epsilon=1e-3, fan=fan),
                                 rel=1e-12, abs=1e-12)


@pytest.mark.parametrize("sky", [None, 16])
def test_vectorised_pass_equals_reference_with_a_brdf_model_among_plain_materials(sky):
    """Points of a material with a BRDF model (drawn through the registry) among plain ones
    (from the fan, or drawn and traced in the compiled first pass): the paths are merged in
    order."""
    from radscene.materials.brdf import make_brdf

    model = make_brdf({"type": "lambertian", "reflectance": 0.6})
    tracer, tables, origin, normal, wo, material, u = _setup(2, brdfs={1: model})
    material = np.arange(len(material)) % 2  # every other point of the modelled material
    fan = _fan(tracer, origin, normal, sky)
    args = (tracer, tables, origin, normal, wo, material, SUN, u)
    fast = background.reflected(*args, epsilon=1e-3, fan=fan)
    assert np.count_nonzero(fast[material == 0, 1]) >= 4
    assert np.count_nonzero(fast[material == 1, 1]) >= 4
    assert fast == pytest.approx(background.reflected_reference(*args, epsilon=1e-3, fan=fan),
                                 rel=1e-12, abs=1e-12)


@pytest.mark.parametrize("sky", [None, 4])
def test_vectorised_pass_does_not_depend_on_the_chunk_size(monkeypatch, sky):
    tracer, tables, origin, normal, wo, material, u = _setup(2, 0.3)
    fan = _fan(tracer, origin, normal, sky)
    args = (tracer, tables, origin, normal, wo, material, SUN, u)
    whole = background.reflected(*args, epsilon=1e-3, fan=fan)
    monkeypatch.setattr(background, "CHUNK_SAMPLES", 40)  # 2 points per chunk
    assert background.reflected(*args, epsilon=1e-3, fan=fan) == pytest.approx(whole,
                                                                                  rel=1e-14)


def test_band_mean_reflectance_and_emission():
    _tracer, tables, *_ = _setup(1)
    assert tables.diffuse[:, 0] == pytest.approx([0.3, 0.6], rel=1e-12)
    from radscene.radiometry import band_radiance

    for t, temperature in enumerate(tables.temperature_nodes):
        assert tables.emission[1, t, 1] == pytest.approx(
            0.4 * float(band_radiance(8.0, 12.0, temperature)), rel=1e-6)


def test_brdf_weight_of_a_lambertian_is_its_reflectance():
    _tracer, tables, _o, normal, wo, material, _u = _setup(1)
    u = np.random.default_rng(0).random((len(material), 2))
    wi, weight = background.brdf_weight(tables, material, wo, normal, u)
    assert np.all(wi[:, 2] > 0.0)
    assert weight == pytest.approx(np.tile(tables.diffuse[0], (len(material), 1)), rel=1e-12)


def test_sky_radiance_is_zero_below_the_horizon():
    _tracer, tables, *_ = _setup(1)
    d = np.array([[0.0, 0.0, 1.0], [1.0, 0.0, 0.0], [0.0, 0.6, -0.8]])
    sky = background.sky_radiance(tables, d)
    assert sky[0] == pytest.approx([20.0, 2.0], rel=1e-12)
    assert sky[2] == pytest.approx([0.0, 0.0], abs=0.0)


def _open_plate(**render_settings):
    return {
        "name": "open",
        "environment": {"sun": {"zenith": 30.0, "azimuth": 180.0},
                        "atmosphere": {"type": "uniform", "sky_radiance": 3.0}},
        "materials": {"grey": {"reflectance": 0.4}},
        "objects": [{"name": "plate", "shape": {"type": "plate", "width": 100, "length": 100},
                     "material": "grey", "temperature": "300 K"},
                    {"name": "block", "shape": {"type": "box", "size": [4, 4, 6]},
                     "position": [0, 6, 0], "material": "grey", "temperature": "330 K"}],
        "bands": [{"name": "vis", "min": 0.5, "max": 0.6}, {"name": "lwir", "min": 8, "max": 12}],
        "observers": [{"name": "nadir", "type": "orthographic", "center": [0, 0], "gsd": 1.0,
                       "shape": [8, 8], "altitude": 1000}],
        "render": render_settings,
    }


@pytest.mark.parametrize("supersample", [1, 2])
def test_radiance_is_the_sum_of_the_layers_with_the_background(supersample):
    scene = _open_plate(background_samples=8)
    scene["observers"][0]["supersample"] = supersample
    ds = render(load_scene(scene))
    layers = ("sun_diffuse", "sun_specular", "thermal_emission", "sky_reflected",
              "path_radiance", "background_reflected", "multiple_reflection",
              "diffuse_transmitted", "adjacency")
    total = sum(ds[name] for name in layers)
    assert ds["radiance"].values == pytest.approx(total.values, rel=1e-12)
    assert float(ds["background_reflected"].max()) > 0.0  # the block's neighbours
    assert ds.attrs["background_bounces"] == 1


def test_renders_repeat_for_a_seed_and_change_with_it():
    a = render(load_scene(_open_plate(background_samples=4, seed=3)))["background_reflected"]
    b = render(load_scene(_open_plate(background_samples=4, seed=3)))["background_reflected"]
    c = render(load_scene(_open_plate(background_samples=4, seed=4)))["background_reflected"]
    assert np.array_equal(a.values, b.values)
    assert not np.array_equal(a.values, c.values)


def test_off_gives_a_zero_layer_and_leaves_the_other_terms():
    on = render(load_scene(_open_plate(background_samples=4)))
    off = render(load_scene(_open_plate(background_bounces=0)))
    assert np.all(off["background_reflected"].values == 0.0)
    for name in ("sun_diffuse", "sky_reflected", "thermal_emission", "path_radiance"):
        assert on[name].values == pytest.approx(off[name].values, rel=1e-12), name
    assert on["radiance"].values == pytest.approx(
        (off["radiance"] + on["background_reflected"]).values, rel=1e-12)


@pytest.mark.parametrize(("key", "value", "match"), [
    ("background_samples", 0, "render.background_samples"),
    ("background_samples", -4, "render.background_samples"),
    ("background_bounces", -1, "render.background_bounces"),
    ("background_bounces", 1.5, "render.background_bounces"),
])
def test_bad_settings_name_the_key(key, value, match):
    with pytest.raises(ConfigError, match=match):
        load_scene(_open_plate(**{key: value}))


@pytest.mark.parametrize(("rho_d", "rho_s", "exponent"), [
    (0.3, 0.0, 0.0), (0.0, 0.5, 300.0), (0.2, 0.3, 12.0), (0.0, 0.0, 5.0), (0.1, 0.4, 0.0)])
def test_compiled_phong_sampling_equals_the_registry_model(rho_d, rho_s, exponent):
    """The compiled kernels draw, weigh and evaluate as the registry's phong model does."""
    rng = np.random.default_rng(11)
    n = 500
    material = Material.create("m", reflectance=rho_d + rho_s, specular_reflectance=rho_s,
                               specular_exponent=exponent)
    quadrature = [band_quadrature(_Band(0.5, 0.6)), band_quadrature(_Band(8.0, 12.0))]
    tables = background.band_tables(
        [material], {}, quadrature, [np.ones(q[0].shape) for q in quadrature],
        np.zeros((2, 1)), (np.array([0.0]), np.array([0.0])), [False, True], np.array([0]),
        np.zeros(2, int), np.full(2, 300.0))
    normal = rng.normal(size=(n, 3))
    normal /= np.linalg.norm(normal, axis=1, keepdims=True)
    wo = rng.normal(size=(n, 3))
    wo /= np.linalg.norm(wo, axis=1, keepdims=True)
    wo = np.where((np.einsum("nc,nc->n", wo, normal) > 0.0)[:, None], wo, -wo)
    u = rng.random((n, 2))
    m = np.zeros(n, int)
    wi, weight = background.brdf_weight(tables, m, wo, normal, u)
    wi_ref, weight_ref = background.brdf_weight_reference(tables, m, wo, normal, u)
    assert wi == pytest.approx(wi_ref, abs=1e-12)
    assert weight == pytest.approx(weight_ref, rel=1e-10, abs=1e-12)
    f = background.brdf(tables, m, wi, wo, normal)
    assert f == pytest.approx(background.brdf_reference(tables, m, wi, wo, normal),
                              rel=1e-10, abs=1e-12)


def test_a_lambertian_brdf_model_reflects_the_background_like_the_plain_material():
    """Where the plain material draws its own directions (no sky fan), the registry's
    lambertian model draws the same cosine-weighted ones from the same uniforms: the same
    layer to rounding. In a render the plain material's first directions come from the sky
    fan: the layers then agree within their noise."""
    from radscene.materials.brdf import make_brdf

    model = make_brdf({"type": "lambertian", "reflectance": 0.3})
    tracer, tables, origin, normal, wo, material, u = _setup(2)
    _, modelled, *_ = _setup(2, brdfs={0: model})
    args = (origin, normal, wo, material, SUN, u)
    a = background.reflected(tracer, tables, *args, epsilon=1e-3)
    b = background.reflected(tracer, modelled, *args, epsilon=1e-3)
    assert np.count_nonzero(a[:, 1]) >= 8
    assert b == pytest.approx(a, rel=1e-9, abs=1e-12)
    plain = _open_plate(background_samples=64)
    spec = _open_plate(background_samples=64)
    spec["materials"]["grey"]["brdf"] = {"type": "lambertian", "reflectance": 0.4}
    a = render(load_scene(plain))["background_reflected"].values
    b = render(load_scene(spec))["background_reflected"].values
    assert np.count_nonzero(a) > 10
    assert not np.allclose(a, b, rtol=1e-9)  # other directions
    for band in range(2):  # the images' means agree within 4 standard errors
        diff = (a[band] - b[band]).ravel()
        assert abs(diff.mean()) < 4.0 * diff.std() / np.sqrt(diff.size)
        assert a[band].mean() == pytest.approx(b[band].mean(), rel=0.05)


def test_a_lone_plate_under_the_sky_has_no_background():
    """Every direction above an open plate is sky: it stays in sky_reflected."""
    scene = _open_plate(background_samples=16, background_bounces=3)
    scene["objects"] = scene["objects"][:1]
    ds = render(load_scene(scene))
    assert np.all(ds["background_reflected"].values == 0.0)
    assert np.all(ds["sky_reflected"].values > 0.0)


def _splitmix_reference(key, path, bounce, depth, dim):
    """SplitMix64 (Steele, Lea & Flood 2014) in Python integers, at the pass's counter."""
    mask = (1 << 64) - 1
    counter = (path * depth + bounce) * 2 + dim
    z = (key + (counter + 1) * 0x9E3779B97F4A7C15) & mask
    z = ((z ^ (z >> 30)) * 0xBF58476D1CE4E5B9) & mask
    z = ((z ^ (z >> 27)) * 0x94D049BB133111EB) & mask
    return ((z ^ (z >> 31)) >> 11) / 2.0**53


def test_counter_uniforms_are_splitmix64_and_uniform():
    u = background.draws(5, 131072, 1000, 4, 2)
    paths = np.array([0, 1, 17, 3999])
    got = u.at(paths, 2)
    expected = [[_splitmix_reference(u.key, int(p), 2, 3, d) for d in range(2)] for p in paths]
    assert got == pytest.approx(np.array(expected), abs=0.0)
    sample = u.at(np.arange(4000), 0).ravel()
    counts = np.histogram(sample, bins=20, range=(0.0, 1.0))[0]
    chi2 = float(np.sum((counts - 400.0) ** 2 / 400.0))
    assert chi2 < 43.8  # 19 degrees of freedom, p = 0.001
    assert not np.array_equal(u.at(paths, 0), background.draws(6, 131072, 1000, 4, 2).at(paths, 0))


def _media(albedo=0.0):
    """A smoke ellipsoid over the box and the points (optical depth ~1.2 through its middle),
    with the bands of :func:`_setup`."""
    from types import SimpleNamespace

    from radscene.render import media
    from radscene.render.volumes import Volume

    smoke = Volume("smoke", "ellipsoid", np.array([0.5, 0.0, 2.0]), np.array([5.0, 4.0, 2.5]),
                   lambda wl: np.full(np.shape(wl), 0.25), albedo=albedo, temperature=340.0)
    bands = [SimpleNamespace(response=_Band(0.5, 0.6)), SimpleNamespace(response=_Band(8.0, 12.0))]
    sun = None
    if albedo > 0.0:
        sun = (SUN, lambda wl, altitude: np.full(np.shape(wl), 1500.0))
    return media.Media((smoke,), bands, 0.0, sun)


@pytest.mark.parametrize("bounces", [1, 3])
@pytest.mark.parametrize("albedo", [0.0, 0.4])
def test_vectorised_pass_through_a_volume_equals_reference(bounces, albedo):
    """Segments through a volume (its transmittance, emission and scattered sun) and the
    vertices' sun through it: the vectorised pass equals the reference path by path."""
    tracer, tables, origin, normal, wo, material, u = _setup(bounces)
    args = (tracer, tables, origin, normal, wo, material, SUN, u)
    medium = _media(albedo)
    fan = _fan(tracer, origin, normal, 16)
    fast = background.reflected(*args, epsilon=1e-3, media=medium, fan=fan)
    slow = background.reflected_reference(*args, epsilon=1e-3, media=medium, fan=fan)
    clear = background.reflected(*args, epsilon=1e-3, fan=fan)
    assert fast == pytest.approx(slow, rel=1e-12, abs=1e-12)
    # the smoke changes the background of most points, in both bands (the test's sun shines
    # in the LWIR too)
    changed = np.abs(fast - clear) > 0.01 * np.abs(clear)
    assert np.all(changed.sum(axis=0) >= 6)


@pytest.mark.parametrize("bounces", [1, 3])
@pytest.mark.parametrize("air", [False, True])
def test_self_emitted_part_equals_reference(bounces, air):
    """The self-emitted part of the background (the vertices' emission, the sky's and the
    air's, seed 001 eq. 1's H) against the reference, with a sky that emits and air between
    the surfaces; the total is unchanged by the split."""
    tracer, tables, origin, normal, wo, material, u = _setup(bounces, 0.3)
    whole = background.reflected(tracer, tables, origin, normal, wo, material, SUN, u,
                                 epsilon=1e-3)
    tables.sky_thermal = tables.sky * np.array([[0.0], [0.8]])  # the thermal band's sky emits
    if air:
        tables.air_extinction = np.array([0.0, 2e-3])
    args = (tracer, tables, origin, normal, wo, material, SUN, u)
    fast = background.reflected_parts(*args, epsilon=1e-3)
    slow = background.reflected_reference_parts(*args, epsilon=1e-3)
    for got, want in zip(fast, slow, strict=True):
        assert got == pytest.approx(want, rel=1e-12, abs=1e-12)
    total, thermal = fast
    if not air:
        assert np.array_equal(total, whole)
    assert np.all(thermal[:, 1] > 0.0) and np.all(thermal[:, 1] < total[:, 1])
    # the visible band: the 300-320 K surfaces' emission only, next to nothing of the total
    assert np.all(thermal[:, 0] < 1e-20 * total[:, 0])
    no_sun = background.reflected_parts(tracer, tables, origin, normal, wo, material,
                                        -SUN, u, epsilon=1e-3)
    assert np.all(no_sun[1][:, 1] > 0.0)


@pytest.mark.parametrize("centre", [(3.0, -2.0, 3.0), (-2.5, 2.0, 1.5), (1.0, 1.5, 4.0),
                                    (-3.0, 3.0, 5.0), (3.0, 6.0, 3.0),
                                    (4.0, 1.0, 1.0)])
def test_what_the_record_and_the_fan_miss_cannot_change_a_points_background(centre):
    """A key frame's record (radscene.render.background_record): a box put where no recorded
    ray of a point and no direction of its sky fan passes leaves that point's background as
    it was; the points it changes are all caught."""
    from radscene.render.background_record import PathRecord, meeting_samples
    from radscene.render.kept_fans import bounding_sphere, fans_meet_spheres

    tracer, tables, origin, normal, wo, material, u = _setup(1, specular=0.3, n=40)
    fan = _fan(tracer, origin, normal, 4)
    record = PathRecord(len(origin))
    args = (tables, origin, normal, wo, material, SUN, u)
    before = background.reflected_parts(tracer, *args, epsilon=1e-3, fan=fan,
                                        record=record.bind(np.arange(len(origin))))[0]
    paths = record.finish()
    assert np.any(np.all(np.isclose(paths.direction, SUN), axis=1))  # vertices' shadow rays
    blocker = box((0.6, 0.6, 0.6)).transformed(translation=centre)
    moved = RayTracer([plate(40.0, 40.0), box((2.0, 2.0, 2.0)), blocker])
    tables.face_offset = np.append(tables.face_offset, len(tables.face_material))
    tables.face_material = np.append(tables.face_material, np.ones(len(blocker.faces), int))
    tables.face_temperature = np.append(tables.face_temperature,
                                        np.full(len(blocker.faces), 320.0))
    after = background.reflected(moved, *args, epsilon=1e-3, fan=_fan(moved, origin, normal, 4))
    sphere = bounding_sphere(blocker.vertices)[None, :]
    caught = np.zeros(len(origin), dtype=bool)
    caught[meeting_samples(paths, sphere)] = True
    caught |= fans_meet_spheres(origin, normal, 4, fan.shift, sphere)
    changed = np.any(np.abs(after - before) > 1e-9 * np.abs(before).max(), axis=1)
    assert np.any(changed)
    assert not np.any(changed & ~caught), np.flatnonzero(changed & ~caught)
