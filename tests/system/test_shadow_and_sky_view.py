"""System tests (c) and (d): a box's shadow area, an open plane's and a V-trench's sky view."""

from __future__ import annotations

import numpy as np
import pytest

from radscene import load_scene, render


def _scene(objects, observer, sun=(40.0, 135.0), sky_samples=16, materials=None):
    return {
        "name": "geometry",
        "environment": {"sun": {"zenith": sun[0], "azimuth": sun[1]}, "atmosphere": {"type": "none"}},
        "materials": materials or {"grey": {"reflectance": 0.5}},
        "objects": objects,
        "bands": [{"name": "vis", "min": 0.5, "max": 0.6}],
        "observers": [observer],
        "render": {"sky_samples": sky_samples, "seed": 3},
    }


@pytest.mark.parametrize(("zenith", "azimuth"), [(40.0, 135.0), (60.0, 200.0), (25.0, 90.0)])
def test_box_shadow_area_matches_the_analytic_area(zenith, azimuth):
    a, b, h = 10.0, 20.0, 8.0  # box extent along x (east), y (north), height [m]
    objects = [
        {"name": "ground", "shape": {"type": "plate", "width": 300, "length": 300},
         "position": [0, 0, 0], "material": "grey"},
        {"name": "box", "shape": {"type": "box", "size": [a, b, h]}, "position": [0, 0, 0],
         "material": "grey"},
    ]
    gsd, n = 0.25, 320  # an 80 m square around the box
    observer = {"name": "nadir", "type": "orthographic", "center": [0, 0], "gsd": gsd,
                "shape": [n, n], "supersample": 3, "altitude": 500}
    ds = render(load_scene(_scene(objects, observer, sun=(zenith, azimuth), sky_samples=1)))
    measured = float(ds["shadow_fraction"].sum()) * gsd * gsd
    # the shadow on the ground is the footprint swept along the anti-sun direction, minus the
    # footprint the roof covers: h tan(z) (|sin az| b + |cos az| a)
    t = h * np.tan(np.radians(zenith))
    expected = t * (abs(np.sin(np.radians(azimuth))) * b + abs(np.cos(np.radians(azimuth))) * a)
    assert measured == pytest.approx(expected, rel=0.01)


def test_open_plane_sees_the_whole_sky():
    objects = [{"name": "ground", "shape": {"type": "plate", "width": 100, "length": 100},
                "position": [0, 0, 0], "material": "grey"}]
    observer = {"name": "nadir", "type": "orthographic", "center": [0, 0], "gsd": 2.0,
                "shape": [20, 20]}
    ds = render(load_scene(_scene(objects, observer, sky_samples=64)))
    assert ds["sky_view_fraction"].values == pytest.approx(np.ones((20, 20)), abs=1e-12)


def _v_trench_obj(path, opening_angle, wall=10.0, length=400.0):
    half = np.radians(opening_angle / 2.0)
    top_x, top_z = wall * np.sin(half), wall * np.cos(half)
    y0, y1 = -length / 2, length / 2
    vertices = [(-top_x, y0, top_z), (-top_x, y1, top_z), (0, y0, 0), (0, y1, 0),
                (top_x, y0, top_z), (top_x, y1, top_z)]
    faces = [(1, 3, 4), (1, 4, 2), (3, 5, 6), (3, 6, 4)]  # 1-based, OBJ
    lines = [f"v {x:.9f} {y:.9f} {z:.9f}" for x, y, z in vertices]
    lines += [f"f {i} {j} {k}" for i, j, k in faces]
    path.write_text("\n".join(lines) + "\n")
    return top_x


@pytest.mark.parametrize("opening_angle", [60.0, 90.0, 120.0])
def test_v_trench_sky_view_matches_the_analytic_view_factor(tmp_path, opening_angle):
    top_x = _v_trench_obj(tmp_path / "trench.obj", opening_angle)
    objects = [{"name": "trench", "shape": {"type": "mesh", "file": str(tmp_path / "trench.obj")},
                "position": [0, 0, 0], "on_ground": False, "material": "grey"}]
    n = 40
    gsd = 2 * top_x / n  # pixel centres sample both walls evenly, rim to rim
    observer = {"name": "nadir", "type": "orthographic", "center": [0, 0], "gsd": gsd,
                "shape": [n, n]}
    ds = render(load_scene(_scene(objects, observer, sky_samples=256)))
    # crossed strings (Hottel): each wall of an infinite V groove sees the opening with
    # F = o / (2 w) = sin(opening / 2); the opening shows only sky
    expected = np.sin(np.radians(opening_angle / 2.0))
    assert float(ds["sky_view_fraction"].mean()) == pytest.approx(expected, rel=0.02)
