"""A rendered terrain shows its solved temperatures as a continuous field, not as one block per
thermal cell: across a cell edge the surface_temperature truth map follows the reconstructed
gradient without a jump, and each cell's mean over its pixels is the solved temperature."""

import numpy as np
import pytest

import radscene
from radscene.pipeline import apply_thermal
from radscene.scene import load_scene

PIXEL = 0.25  # m
CELL = 2.0  # m, thermal.resolution (the DEM's spacing is 1 m)


def _scene(interpolate):
    return load_scene({
        "name": "mosaic",
        "environment": {"location": {"latitude": 45.0, "longitude": 7.0, "altitude": 200.0},
                        "time": "2024-06-21T12:00:00+02:00",
                        "atmosphere": {"type": "uniform", "transmittance": 1.0}},
        "terrain": {"type": "dem", "elevation": np.zeros((9, 9)).tolist(), "spacing": [1.0, 1.0],
                    "origin": [0.0, 0.0], "material": "asphalt"},
        "bands": [{"name": "lwir", "min": "8 um", "max": "12 um"}],
        "observers": [{"name": "map", "type": "orthographic", "center": [4.0, 4.0], "altitude": 100.0,
                       "gsd": PIXEL, "shape": [32, 32]}],
        "thermal": {"start": "2024-06-21T11:00:00+02:00", "end": "2024-06-21T12:00:00+02:00", "step": "1 h",
                    "hemisphere_samples": 4, "spin_up": False, "resolution": f"{CELL} m",
                    "interpolate": interpolate},
    }, base_dir=".")


def _render(interpolate, field):
    """The truth map of a scene whose solved cells take ``field(x, y)`` at their centres."""
    scene = _scene(interpolate)
    solution = radscene.solve_thermal(scene).copy()
    cells = field(solution.x.values, solution.y.values)
    solution["surface_temperature"] = (solution.surface_temperature.dims,
                                       np.broadcast_to(cells, solution.surface_temperature.shape).copy())
    apply_thermal(scene, solution)
    ds = radscene.render(scene)
    return ds, solution


@pytest.fixture(scope="module")
def gradient():
    return {flag: _render(flag, lambda x, y: 300.0 + 1.5 * x - 0.5 * y) for flag in (True, False)}


def test_a_gradient_crosses_the_cell_edges_without_a_jump(gradient):
    smooth = gradient[True][0].surface_temperature.values
    steps = np.diff(smooth, axis=1)  # along x, pixel to pixel
    np.testing.assert_allclose(steps, 1.5 * PIXEL, rtol=0, atol=1e-3)
    np.testing.assert_allclose(np.diff(smooth, axis=0), 0.5 * PIXEL, rtol=0, atol=1e-3)  # rows run south
    # one temperature per cell: flat inside a cell, a jump of a cell's step at its edges
    blocks = np.diff(gradient[False][0].surface_temperature.values, axis=1)
    assert np.isclose(blocks, 0.0, atol=1e-6).sum() == 32 * 28
    np.testing.assert_allclose(blocks[~np.isclose(blocks, 0.0, atol=1e-6)], 1.5 * CELL, rtol=0, atol=1e-6)


def test_the_cell_means_are_the_solved_temperatures():
    ds, solution = _render(True, lambda x, y: 290.0 + 0.4 * (x - 3.0) ** 2 + 3.0 * np.sin(y))
    t = ds.surface_temperature
    per = int(round(CELL / PIXEL))
    blocks = t.values.reshape(32 // per, per, 32 // per, per).mean(axis=(1, 3))  # rows from the north
    x = t.x.values.reshape(-1, per).mean(axis=1)
    y = t.y.values.reshape(-1, per).mean(axis=1)
    cells = solution.surface_temperature.isel(time=-1).values
    for i, yy in enumerate(y):
        for j, xx in enumerate(x):
            k = int(np.argmin(np.hypot(solution.x.values - xx, solution.y.values - yy)))
            assert blocks[i, j] == pytest.approx(float(cells[k]), abs=1e-3)
    assert float(np.ptp(t.values)) > 0.0 and len(np.unique(np.round(t.values, 6))) > 16  # not one value per cell
