"""Surface elements and what they see (thermal.elements, thermal.exposure), the ground's
irradiance from an engine (thermal.irradiance) and the time axis (thermal.solve)."""

import numpy as np
import pytest

from radscene.errors import ConfigError
from radscene.geometry import Heightfield, RayTracer, box, plate
from radscene.thermal.elements import build_elements
from radscene.thermal.exposure import hemisphere_exposure, sunlit_fraction
from radscene.thermal.solve import sun_vectors, time_axis


def _parallel_squares_view_factor(x, y):
    """Two coaxial parallel rectangles a × b at distance c, X = a/c, Y = b/c (Howell's catalogue
    C-11; Modest 2013, Appendix D)."""
    return 2.0 / (np.pi * x * y) * (
        np.log(np.sqrt((1 + x**2) * (1 + y**2) / (1 + x**2 + y**2)))
        + x * np.sqrt(1 + y**2) * np.arctan(x / np.sqrt(1 + y**2))
        + y * np.sqrt(1 + x**2) * np.arctan(y / np.sqrt(1 + x**2))
        - x * np.arctan(x) - y * np.arctan(y))


def _scene(*meshes):
    mats = [np.full(len(m.faces), k, dtype=np.int64) for k, m in enumerate(meshes)]
    return RayTracer(list(meshes)), build_elements(list(meshes), mats, [True] * len(meshes))


def test_view_factor_between_parallel_squares_matches_closed_form():
    lower = plate(1.0, 1.0)
    upper = plate(1.0, 1.0).transformed(translation=(0.0, 0.0, 1.0), rotation=(0.0, 180.0, 0.0))
    tracer, el = _scene(lower, upper)
    h = hemisphere_exposure(tracer, el, n_samples=4096, seed=3)
    expected = _parallel_squares_view_factor(1.0, 1.0)  # 0.19982
    assert expected == pytest.approx(0.19982, abs=1e-5)
    f = h.exchange.toarray()
    # 8192 rays per plate: standard error 0.0044
    assert f[0, 1] == pytest.approx(expected, abs=0.015)
    assert f[1, 0] == pytest.approx(expected, abs=0.015)
    assert h.sky_view == pytest.approx(1.0 - f.sum(axis=1), abs=1e-12)


def test_box_on_ground_faces_see_sky_ground_and_nothing():
    ground = plate(100.0, 100.0)
    body = box((3.0, 8.0, 3.2)).transformed(translation=(0.0, 0.0, 0.5))
    tracer, el = _scene(ground, body)
    h = hemisphere_exposure(tracer, el, n_samples=256, seed=0)
    up = (el.object == 1) & (el.normal[:, 2] > 0.9)
    down = (el.object == 1) & (el.normal[:, 2] < -0.9)
    side = (el.object == 1) & (np.abs(el.normal[:, 2]) < 0.1)
    assert el.size == 7  # the ground, and the box's six sides (two faces each)
    assert h.sky_view[up] == pytest.approx([1.0])
    assert h.sky_view[down] == pytest.approx([0.0])
    # a vertical wall on an infinite plane sees half sky, half ground (a 100 m plate: a little less)
    assert np.all(np.abs(h.sky_view[side] - 0.5) < 0.05)
    ground_row = h.exchange.toarray()[np.flatnonzero(side)][:, 0]
    assert ground_row + h.sky_view[side] == pytest.approx(np.ones(4))


def test_same_seed_same_answer_and_fixed_faces_go_to_fixed():
    ground = plate(20.0, 20.0)
    body = box((2.0, 2.0, 2.0))
    tracer = RayTracer([ground, body])
    mats = [np.zeros(2, np.int64), np.ones(12, np.int64)]
    el = build_elements([ground, body], mats, [True, False])
    assert el.size == 1 and np.all(el.face_element[2:] == -1)
    a = hemisphere_exposure(tracer, el, 1024, seed=5)
    b = hemisphere_exposure(tracer, el, 1024, seed=5)
    assert np.array_equal(a.sky_view, b.sky_view)
    assert a.fixed.shape == (1, 14)
    assert a.fixed.sum() == pytest.approx(1.0 - a.sky_view[0], abs=1e-12)
    assert a.fixed.sum() > 0


def test_shadow_of_a_plate_on_the_ground():
    ground = plate(10.0, 10.0)
    roof = plate(1.0, 1.0).transformed(translation=(0.0, 0.0, 1.0))
    tracer, el = _scene(ground, roof)
    # the sun straight up: the ground loses the roof's 1 m2 of its 100 m2; tilted 36.87 deg
    # east, the shadow moves 0.75 m but keeps its area
    sun = np.array([[0.0, 0.0, 1.0], [0.6, 0.0, 0.8], [0.0, 0.0, -1.0]])
    lit = sunlit_fraction(tracer, el, sun, spacing=0.05)
    ground_faces = el.face_element[:2]
    assert np.all(ground_faces == 0)
    # the ground is one face pair of 100 m2 traced at one point each (terrain-like coarse):
    # test the roof instead, fully lit, and the horizon sun, nothing lit
    assert lit[:2, 1] == pytest.approx([1.0, 1.0])
    assert lit[2] == pytest.approx([0.0, 0.0])


def test_shadow_on_terrain_cells():
    elevation = np.zeros((21, 21))
    hf = Heightfield(elevation, origin=(0.0, 0.0), spacing=(1.0, 1.0))
    ground = hf.to_mesh()
    wall = box((1.0, 20.0, 5.0)).transformed(translation=(10.0, 10.0, 0.0))
    tracer = RayTracer([ground, wall])
    mats = [np.zeros(len(ground.faces), np.int64), np.ones(len(wall.faces), np.int64)]
    el = build_elements([ground, wall], mats, [True, True], terrain=0, heightfield=hf)
    assert el.grid_shape == (20, 20)
    # sun 45 deg up in the west: the wall (x 9.5-10.5, 5 m high) shades x 10.5-15.5
    sun = sun_vectors(45.0, 270.0)
    lit = sunlit_fraction(tracer, el, sun)[0]
    cells = el.object == 0
    x = el.position[cells, 0]
    shaded = lit[cells] < 0.5
    assert np.all(shaded[(x > 11.0) & (x < 15.0)])
    assert not np.any(shaded[(x < 9.0) | (x > 16.0)])


def test_resolution_groups_terrain_cells():
    hf = Heightfield(np.zeros((11, 11)), origin=(0.0, 0.0), spacing=(1.0, 1.0))
    mesh = hf.to_mesh()
    el = build_elements([mesh], [np.zeros(len(mesh.faces), np.int64)], [True], terrain=0, heightfield=hf,
                        resolution=2.0)
    assert el.size == 25 and el.grid_shape == (5, 5)
    assert el.area == pytest.approx(np.full(25, 4.0))
    with pytest.raises(ConfigError, match="finer than the terrain"):
        build_elements([mesh], [np.zeros(len(mesh.faces), np.int64)], [True], terrain=0, heightfield=hf,
                       resolution=0.5)


def test_time_axis_and_its_errors():
    t = time_axis(np.datetime64("2026-06-21T00:00"), np.datetime64("2026-06-21T01:00"), 600.0)
    assert t.size == 7 and t[-1] == np.datetime64("2026-06-21T01:00", "ns")
    t = time_axis(np.datetime64("2026-06-21T00:00"), np.datetime64("2026-06-21T00:25"), 600.0)
    assert t.size == 4  # 0, 10, 20 and the end at 25 min
    with pytest.raises(ConfigError, match="not before the end"):
        time_axis(np.datetime64("2026-06-21T01:00"), np.datetime64("2026-06-21T00:00"), 60.0)
    with pytest.raises(ConfigError, match="longer than the span"):
        time_axis(np.datetime64("2026-06-21T00:00"), np.datetime64("2026-06-21T00:10"), 3600.0)


def test_ground_irradiance_from_the_uniform_engine():
    from radscene.atmosphere.uniform import UniformAtmosphere
    from radscene.sun import toa_solar_irradiance
    from radscene.thermal.irradiance import SHORTWAVE, shortwave_table, sky_longwave_irradiance

    atm = UniformAtmosphere(transmittance=0.8, sky_radiance=10.0)
    table = shortwave_table(atm, 0.0, 172, 1.0)
    # direct: 0.8 of the top-of-atmosphere integral over 0.3-4 um; diffuse: pi x 10 x 3.7 um
    expected = 0.8 * np.trapezoid(toa_solar_irradiance(SHORTWAVE), SHORTWAVE)
    assert table.direct_normal == pytest.approx(np.full(table.zenith.size, expected), rel=1e-9)
    assert table.diffuse == pytest.approx(np.full(table.zenith.size, np.pi * 10.0 * 3.7), rel=1e-3)
    direct, diffuse = table.at([0.0, 90.0, 120.0])
    assert direct[1:] == pytest.approx([0.0, 0.0]) and diffuse[1:] == pytest.approx([0.0, 0.0])
    # a user's sky of constant radiance L over the long-wave: pi L (100 - 4) um
    assert sky_longwave_irradiance(atm, 0.0, 288.0) == pytest.approx(np.pi * 10.0 * 96.0, rel=1e-3)
    # tabulated to 20 um only: pi L 16 um, plus the blackbody at the air temperature beyond
    from radscene.radiometry.planck import band_radiance

    short = UniformAtmosphere(transmittance=0.8, sky_radiance={"wavelength": [0.3, 20.0], "values": [10.0, 10.0]})
    assert sky_longwave_irradiance(short, 0.0, 288.0) == pytest.approx(
        np.pi * 10.0 * 16.0 + np.pi * band_radiance(20.0, 1e5, 288.0), rel=1e-3)


def test_ground_irradiance_from_the_database_falls_with_the_sun():
    from radscene.atmosphere import make_atmosphere
    from radscene.thermal.irradiance import shortwave_table

    atm = make_atmosphere({"type": "database", "profile": "midlatitude_summer", "aerosol": "rural",
                           "visibility": "23 km"})
    table = shortwave_table(atm, 0.0, 172, 1.0)
    assert np.all(np.diff(table.direct_normal) < 0) and np.all(np.diff(table.diffuse) < 0)
    # a clear sky (AOT550 0.24), sun overhead: 850-1000 W m-2 direct normal; diffuse 10-25 % of
    # it (measured 175 of 867 W m-2)
    assert 850.0 < table.direct_normal[0] < 1000.0
    assert 0.1 < table.diffuse[0] / table.direct_normal[0] < 0.25


@pytest.mark.parametrize(("tau", "sun_zenith"), [(0.4, 0.0), (1.2, 50.0)])
def test_a_volume_over_the_ground_shades_it_partially(tau, sun_zenith):
    """Terrain cells under a wide slab of optical depth τ: sunlit share e^{−τ/μ_0}; the
    transmittance is the heat balance's, from the scene's volumes (pipeline)."""
    from radscene import load_scene
    from radscene.pipeline import _volume_sun_transmittance

    scene = load_scene({
        "environment": {"sun": {"zenith": 30.0}, "atmosphere": {"type": "none"}},
        "objects": [{"name": "p", "shape": {"type": "plate", "width": 10, "length": 10},
                     "material": "asphalt"}],
        "volumes": [{"name": "slab", "shape": {"type": "box", "size": [400, 400, 2]},
                     "position": [10, 10, 30], "optical_depth": tau, "temperature": 300.0}],
        "bands": [{"name": "vis", "min": 0.5, "max": 0.6}],
        "observers": [{"name": "o", "type": "orthographic", "center": [0, 0], "gsd": 1.0,
                       "shape": [2, 2]}]})
    wavelength = np.linspace(0.3, 3.0, 50)
    transmittance = _volume_sun_transmittance(scene, wavelength, np.ones_like(wavelength))
    hf = Heightfield(np.zeros((11, 11)), origin=(0.0, 0.0), spacing=(2.0, 2.0))
    ground = hf.to_mesh()
    tracer = RayTracer([ground])
    el = build_elements([ground], [np.zeros(len(ground.faces), np.int64)], [True], terrain=0,
                        heightfield=hf)
    sun = sun_vectors(sun_zenith, 180.0)
    clear = sunlit_fraction(tracer, el, sun)[0]
    shaded = sunlit_fraction(tracer, el, sun, transmittance=transmittance)[0]
    assert clear == pytest.approx(np.ones_like(clear), abs=1e-12)
    assert shaded == pytest.approx(np.full_like(clear, np.exp(-tau / np.cos(np.radians(
        sun_zenith)))), rel=1e-12)
