"""A flat ground of one material (``terrain: {type: flat}``) and roads painted onto the terrain
(``terrain.roads``): geometry, radiance, heat balance and bad input."""

from __future__ import annotations

import numpy as np
import pytest

import radscene
from radscene.errors import ConfigError
from radscene.geometry.terrain import polyline_distance

SPACING = 2.0  # m, the terrain's grid
SUN = {"zenith": 30.0, "azimuth": 180.0}


def _scene(terrain=None, objects=(), atmosphere=None, bands=None, **extra):
    spec = {
        "name": "ground",
        "environment": {"sun": SUN, "atmosphere": atmosphere or {"type": "none"}},
        "bands": bands or [{"name": "red", "min": "0.6 um", "max": "0.7 um"}],
        "observers": [{"name": "map", "type": "orthographic", "center": [20, 20], "gsd": 1,
                       "shape": [40, 40], "altitude": 100}],
        "objects": list(objects),
        **extra,
    }
    if terrain is not None:
        spec["terrain"] = {"type": "flat", "size": [40, 40], "spacing": SPACING, **terrain}
    return spec


def _road(**kwargs):
    return {"points": [[0, 20], [40, 20]], "width": 6, **kwargs}


# -- flat ground -------------------------------------------------------------------------------

def test_flat_ground_is_one_material_without_textures_or_relief():
    scene = radscene.load_scene(_scene({"material": "dry_grass", "height": 3.5}))
    terrain = scene.objects[0]
    assert terrain.is_terrain
    assert scene.material_names == ["dry_grass"]
    assert np.all(terrain.face_material == 0)
    assert terrain.textures == {}  # no noise multiplier, no texture of any kind
    np.testing.assert_array_equal(terrain.mesh.vertices[:, 2], 3.5)
    assert scene.heightfield.extent == (0.0, 40.0, 0.0, 40.0)
    assert len(terrain.mesh.faces) == 2 * (40 / SPACING) ** 2


def test_flat_ground_renders_as_a_plate_of_its_material():
    """Lambertian ground under the sun, no atmosphere: the same radiance as a horizontal plate of
    the same material, and uniform (no noise)."""
    ground = radscene.render(_scene({"material": "dry_grass", "temperature": "300 K"}))
    plate = radscene.render(_scene(objects=[{
        "name": "plate", "shape": {"type": "plate", "width": 60, "length": 60}, "position": [20, 20, 0],
        "material": "dry_grass", "temperature": "300 K"}]))
    values = ground["radiance"].values
    assert np.ptp(values) == pytest.approx(0.0, abs=1e-9 * values.max())
    np.testing.assert_allclose(values, plate["radiance"].values, rtol=1e-6)


def test_flat_ground_keeps_a_material_map():
    spec = _scene({"material_map": {"type": "noise", "materials": ["dry_grass", "bare_soil"], "scale": 10}})
    scene = radscene.load_scene(spec)
    assert set(np.unique(scene.objects[0].face_material)) == {0, 1}


# -- roads -------------------------------------------------------------------------------------

def test_a_road_along_the_grid_covers_its_width_times_its_length():
    scene = radscene.load_scene(_scene({"material": "dry_grass", "roads": [_road()]}))
    terrain = scene.objects[0]
    asphalt = scene.material_names.index("asphalt")
    area = terrain.mesh.area[terrain.face_material == asphalt].sum()
    assert area == pytest.approx(6.0 * 40.0, rel=1e-9)


def test_an_oblique_road_covers_its_area_to_within_the_grid():
    road = _road(points=[[0, 5], [40, 30]], width=8)
    scene = radscene.load_scene(_scene({"material": "dry_grass", "roads": [road]}))
    terrain = scene.objects[0]
    on = terrain.face_material == scene.material_names.index("asphalt")
    area = terrain.mesh.area[on].sum()
    # the true stripe's area inside the square, from a 5 cm grid of points
    fine = np.arange(0.025, 40.0, 0.05)
    xx, yy = np.meshgrid(fine, fine)
    inside = polyline_distance(np.column_stack([xx.ravel(), yy.ravel()]), road["points"]) <= 4.0
    exact = inside.mean() * 40.0 ** 2
    # faces are taken whole: the two edges (each about the road's length) are resolved to half
    # a grid spacing
    edges = 2 * np.hypot(40.0, 25.0)
    assert abs(area - exact) <= edges * SPACING / 2
    assert abs(area - exact) <= 0.1 * exact
    centroid = terrain.mesh.vertices[terrain.mesh.faces].mean(axis=1)[:, :2]
    assert polyline_distance(centroid[on], road["points"]).max() <= 4.0
    assert polyline_distance(centroid[~on], road["points"]).min() > 4.0


def test_later_roads_are_painted_over_earlier_ones():
    roads = [_road(), _road(points=[[20, 0], [20, 40]], material="concrete")]
    scene = radscene.load_scene(_scene({"material": "dry_grass", "roads": roads}))
    terrain = scene.objects[0]
    centroid = terrain.mesh.vertices[terrain.mesh.faces].mean(axis=1)
    crossing = (np.abs(centroid[:, 0] - 20) < 3) & (np.abs(centroid[:, 1] - 20) < 3)
    assert set(terrain.face_material[crossing]) == {scene.material_names.index("concrete")}


def test_a_road_renders_as_its_material():
    """No atmosphere, the sun only: road pixels have the radiance of an all-asphalt ground,
    the others that of the grass."""
    road = radscene.render(_scene({"material": "dry_grass", "temperature": "300 K", "roads": [_road()]}))
    grass = radscene.render(_scene({"material": "dry_grass", "temperature": "300 K"}))
    asphalt = radscene.render(_scene({"material": "asphalt", "temperature": "300 K"}))
    image = road["radiance"].sel(band="red").values
    y = road["y"].values
    on = np.abs(y - 20) < 3 - 0.5  # pixel centres whose whole pixel lies on the road
    off = np.abs(y - 20) > 3 + 0.5
    np.testing.assert_allclose(image[on], asphalt["radiance"].sel(band="red").values[on], rtol=1e-6)
    np.testing.assert_allclose(image[off], grass["radiance"].sel(band="red").values[off], rtol=1e-6)
    material = road["material_id"].values
    assert material[on].min() == material[on].max() != material[off].min()


def test_the_heat_balance_solves_road_cells_as_their_material():
    """Flat ground, no lateral conduction: each road element follows the same course as the
    ground of an all-asphalt scene, the others as the all-grass one."""
    thermal = {"start": "2024-06-21T09:00:00+02:00", "end": "2024-06-21T12:00:00+02:00", "step": "30 min",
               "hemisphere_samples": 4, "spin_up": False}
    environment = {"location": {"latitude": 45.0, "longitude": 7.0, "altitude": 200.0},
                   "time": "2024-06-21T12:00:00+02:00", "atmosphere": {"type": "uniform", "transmittance": 1.0}}

    def solve(terrain):
        spec = _scene({"size": [20, 20], **terrain}, bands=[{"name": "lwir", "min": "8 um", "max": "12 um"}],
                      thermal=thermal)
        spec["environment"] = environment
        return radscene.solve_thermal(spec)

    mixed = solve({"material": "dry_grass", "roads": [_road(points=[[0, 10], [20, 10]], width=4)]})
    grass = solve({"material": "dry_grass"})["surface_temperature"].values
    asphalt = solve({"material": "asphalt"})["surface_temperature"].values
    road = mixed["material"].values == "asphalt"
    assert road.sum() == 20 and set(mixed["material"].values[~road]) == {"dry_grass"}  # 2 rows of 10 cells
    temperature = mixed["surface_temperature"].values
    np.testing.assert_allclose(temperature[:, road], asphalt[:, road], rtol=1e-6)
    np.testing.assert_allclose(temperature[:, ~road], grass[:, ~road], rtol=1e-6)
    assert np.abs(temperature[-1, road].mean() - temperature[-1, ~road].mean()) > 1.0  # K


@pytest.mark.parametrize(("road", "key", "message"), [
    ({"width": 1}, r"terrain\.roads\[0\]\.width", "narrower than the terrain's spacing 2 m"),
    ({"points": [[100, 100], [200, 100]]}, r"terrain\.roads\[0\]\.points",
     "no terrain face lies within 3 m of its centre line; the terrain spans x 0..40 m"),
    ({"material": "asfalt"}, r"terrain\.roads\[0\]\.material", "unknown material 'asfalt'; known: asphalt"),
    ({"points": [[0, 0], [0, 0]]}, r"terrain\.roads\[0\]\.points", "points 0 and 1 are the same point"),
    ({"points": [[0, 0]]}, r"terrain\.roads\[0\]\.points", "at least 2 items"),
    ({"width": -3}, r"terrain\.roads\[0\]\.width", "must be > 0"),
])
def test_a_bad_road_is_refused_by_key(road, key, message):
    with pytest.raises(ConfigError, match=f"{key}: .*{message}"):
        radscene.load_scene(_scene({"roads": [_road(**road)]}))


def test_roads_take_units():
    spec = _scene({"roads": [_road(width="600 cm")]})
    assert radscene.load_scene(spec).spec.terrain.roads[0].width == pytest.approx(6.0, rel=1e-12)


# -- polyline_distance -------------------------------------------------------------------------

def test_polyline_distance_reference_values():
    vertices = [[0.0, 0.0], [10.0, 0.0], [10.0, 10.0]]
    points = [[5.0, -2.0], [-3.0, -4.0], [12.0, 5.0], [10.0, 10.0], [13.0, 14.0]]
    np.testing.assert_allclose(polyline_distance(points, vertices), [2.0, 5.0, 2.0, 0.0, 5.0],
                               rtol=0, atol=1e-12)
    assert polyline_distance([[3.0, 4.0]], [[0.0, 0.0]]).tolist() == [5.0]


def test_polyline_distance_needs_a_vertex():
    with pytest.raises(ValueError, match="at least one vertex"):
        polyline_distance([[0.0, 0.0]], np.empty((0, 2)))
