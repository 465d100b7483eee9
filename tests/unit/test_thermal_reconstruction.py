"""The terrain's temperature reconstruction across thermal cells (thermal/reconstruction.py):
linear fields reproduced and continuous at the cell edges, every element's mean kept, no new
extrema, material edges and object facets left alone."""

import numpy as np
import pytest

from radscene.geometry import Heightfield
from radscene.thermal.elements import build_elements
from radscene.thermal.reconstruction import corner_temperature, limited_slopes, terrain_neighbours

MEAN_TOL = 1e-9  # K: the area mean of the reconstruction over an element is its value to rounding


def _terrain(n=9, spacing=1.0, resolution=2.0, material=None, relief=0.0):
    rng = np.random.default_rng(3)
    hf = Heightfield(relief * rng.random((n, n)), spacing=(spacing, spacing), origin=(0.0, 0.0))
    mesh = hf.to_mesh()
    mat = np.zeros(len(mesh.faces), int) if material is None else material(mesh)
    return mesh, build_elements([mesh], [mat], [True], terrain=0, heightfield=hf, resolution=resolution)


def _element_means(elements, corners):
    face_mean = corners.mean(axis=1)  # a linear function's mean over a triangle: its corners' mean
    return np.bincount(elements.face_element, weights=elements.face_weight * face_mean, minlength=elements.size)


def _edge_jumps(elements, corners):
    """Largest difference between the temperatures two faces give one shared vertex."""
    xyz = np.round(elements.face_vertices.reshape(-1, 3), 9)
    _, vertex = np.unique(xyz, axis=0, return_inverse=True)
    t = corners.ravel()
    hi = np.full(vertex.max() + 1, -np.inf)
    lo = np.full(vertex.max() + 1, np.inf)
    np.maximum.at(hi, vertex.ravel(), t)
    np.minimum.at(lo, vertex.ravel(), t)
    return float(np.max(hi - lo))


@pytest.mark.parametrize("resolution", [1.0, 2.0, 4.0])
def test_a_linear_field_is_reproduced_and_continuous(resolution):
    mesh, el = _terrain(resolution=resolution)  # flat: on relief the centroids leave the lattice
    t = 290.0 + 1.5 * el.position[:, 0] - 0.7 * el.position[:, 1]
    corners = corner_temperature(el, t, np.zeros(len(mesh.faces)))
    want = 290.0 + 1.5 * el.face_vertices[:, :, 0] - 0.7 * el.face_vertices[:, :, 1]
    np.testing.assert_allclose(corners, want, rtol=0, atol=1e-9)
    assert _edge_jumps(el, corners) < 1e-9
    # one temperature per cell, for comparison: jumps of a cell's step at every edge
    blocks = np.repeat(t[el.face_element][:, None], 3, axis=1)
    assert _edge_jumps(el, blocks) == pytest.approx(1.5 * resolution + 0.7 * resolution, rel=1e-9)


def test_element_means_are_kept_and_no_new_extrema():
    mesh, el = _terrain(n=17, resolution=2.0, relief=0.3)
    rng = np.random.default_rng(11)
    t = 280.0 + 20.0 * rng.random(el.size)
    corners = corner_temperature(el, t, np.zeros(len(mesh.faces)))
    np.testing.assert_allclose(_element_means(el, corners), t, rtol=0, atol=MEAN_TOL)
    nb = terrain_neighbours(el)
    interior = np.all(nb >= 0, axis=1)[el.face_element]  # at the grid's edge the range extends (below)
    around = np.where(nb >= 0, t[np.maximum(nb, 0)], t[:, None])
    lo = np.minimum(t, around.min(axis=1))[el.face_element]
    hi = np.maximum(t, around.max(axis=1))[el.face_element]
    assert np.all(corners[interior] >= lo[interior, None] - 1e-9)
    assert np.all(corners[interior] <= hi[interior, None] + 1e-9)
    assert corners.min() >= 280.0 - 20.0 and corners.max() <= 300.0 + 20.0  # at most one step beyond


def test_a_cell_colder_than_its_neighbours_stays_flat():
    mesh, el = _terrain(n=17, resolution=2.0)
    t = np.full(el.size, 320.0)
    cold = int(np.argmin(np.hypot(el.position[:, 0] - 7.0, el.position[:, 1] - 9.0)))
    t[cold] = 300.0
    corners = corner_temperature(el, t, np.zeros(len(mesh.faces)))
    np.testing.assert_allclose(corners[el.face_element == cold], 300.0, rtol=0, atol=1e-12)
    assert corners.max() <= 320.0 + 1e-12 and corners.min() >= 300.0 - 1e-12
    np.testing.assert_allclose(_element_means(el, corners), t, rtol=0, atol=MEAN_TOL)


def test_slopes_do_not_cross_a_material_edge():
    def west_east(mesh):
        centre = mesh.vertices[mesh.faces].mean(axis=1)
        return (centre[:, 0] > 4.0).astype(int)

    mesh, el = _terrain(n=9, resolution=2.0, material=west_east)
    nb = terrain_neighbours(el)
    for e in range(el.size):
        for j in range(4):
            if nb[e, j] >= 0:
                assert el.material[nb[e, j]] == el.material[e]
    assert np.any(nb == -1) and np.any(nb == -2)  # the material edge and the grid's edge
    t = np.where(el.material == 0, 300.0, 330.0) + 0.5 * el.position[:, 1]
    slopes = limited_slopes(t, el.position, nb)
    np.testing.assert_allclose(slopes[:, 0], 0.0, atol=1e-12)  # no east-west gradient within a material
    np.testing.assert_allclose(slopes[:, 1], 0.5, rtol=1e-12)


def test_objects_and_fixed_faces_keep_their_temperatures():
    from radscene.geometry import box

    hf = Heightfield(np.zeros((5, 5)), spacing=(1.0, 1.0), origin=(0.0, 0.0))
    ground = hf.to_mesh()
    cube = box((1.0, 1.0, 1.0))
    solved = [np.arange(len(ground.faces)) % 7 != 0, True]  # some terrain faces fixed
    el = build_elements([ground, cube], [np.zeros(len(ground.faces), int), np.ones(len(cube.faces), int)], solved,
                        terrain=0, heightfield=hf)
    t = 300.0 + el.position[:, 0]
    fixed = np.full(len(ground.faces) + len(cube.faces), 250.0)
    corners = corner_temperature(el, t, fixed)
    free = el.face_element >= 0
    np.testing.assert_array_equal(corners[~free], 250.0)
    on_box = free & (np.arange(fixed.size) >= len(ground.faces))
    np.testing.assert_array_equal(corners[on_box], np.repeat(t[el.face_element[on_box]][:, None], 3, axis=1))
