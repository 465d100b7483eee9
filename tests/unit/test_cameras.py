"""Tests of radscene.platform.cameras."""

import numpy as np
import pytest

from radscene.errors import ConfigError
from radscene.geometry import direction_from_angles
from radscene.platform import OrthographicCamera, PerspectiveCamera

EXACT = 1e-9  # [m] on coordinates up to 1e4 m, or [-] on unit vectors
ANGLE = 1e-9  # [deg]


def _pixel_sums(bundle, values):
    return np.bincount(bundle.pixel, weights=values, minlength=bundle.shape[0] * bundle.shape[1])


# -- orthographic ----------------------------------------------------------------------------


def test_nadir_pixel_centres_tile_the_extent_exactly():
    cam = OrthographicCamera(center=(1000.0, -500.0), shape=(3, 5), gsd=2.0, altitude=800.0)
    xmin, xmax, ymin, ymax = cam.extent
    assert (xmin, xmax, ymin, ymax) == pytest.approx((995.0, 1005.0, -503.0, -497.0), abs=EXACT)
    x, y = cam.pixel_coordinates()
    assert x.shape == (3, 5)
    # row 0 is the north edge, column 0 the west edge; centres half a pixel in
    assert x == pytest.approx(np.tile(xmin + 2.0 * (np.arange(5) + 0.5), (3, 1)), abs=EXACT)
    assert y == pytest.approx(np.tile(ymax - 2.0 * (np.arange(3) + 0.5)[:, None], (1, 5)),
                              abs=EXACT)
    bundle = cam.rays()
    assert len(bundle) == 15 and bundle.shape == (3, 5)
    assert bundle.pixel.tolist() == list(range(15))
    assert bundle.directions == pytest.approx(np.tile([0.0, 0.0, -1.0], (15, 1)), abs=EXACT)
    assert bundle.origins[:, 2] == pytest.approx(np.full(15, 800.0), abs=EXACT)
    assert bundle.origins[:, 0] == pytest.approx(x.ravel(), abs=EXACT)
    assert bundle.origins[:, 1] == pytest.approx(y.ravel(), abs=EXACT)


def test_supersampling_grid_and_weights():
    cam = OrthographicCamera(center=(0.0, 0.0), shape=(2, 3), gsd=1.0)
    k = 3
    bundle = cam.rays(supersample=k)
    assert len(bundle) == 6 * k * k
    assert _pixel_sums(bundle, bundle.weight) == pytest.approx(np.ones(6), rel=1e-12)
    assert np.bincount(bundle.pixel).tolist() == [k * k] * 6
    assert sorted(set(bundle.subsample.tolist())) == list(range(k * k))
    # sub-samples are centred in their pixel, at the centres of a k x k grid of sub-cells
    centre_x, centre_y = cam.pixel_coordinates()
    mean_x = _pixel_sums(bundle, bundle.weight * bundle.origins[:, 0])
    assert mean_x == pytest.approx(centre_x.ravel(), abs=EXACT)
    first = bundle.origins[bundle.pixel == 0]  # pixel (0, 0): x in [-1.5, -0.5], y in [0, 1]
    assert sorted(set(np.round(first[:, 0], 9))) == pytest.approx([-1.5 + 1 / 6, -1.0,
                                                                   -0.5 - 1 / 6], abs=EXACT)
    assert sorted(set(np.round(first[:, 1], 9))) == pytest.approx([1 / 6, 0.5, 5 / 6], abs=EXACT)


def test_off_nadir_orthographic_view():
    zenith, azimuth = 40.0, 120.0
    cam = OrthographicCamera(center=(10.0, 20.0), shape=(5, 7), gsd=3.0, altitude=1000.0,
                             zenith=zenith, azimuth=azimuth)
    bundle = cam.rays()
    to_camera = direction_from_angles(zenith, azimuth)
    assert bundle.directions == pytest.approx(np.tile(-to_camera, (35, 1)), abs=EXACT)
    # origins lie in one plane perpendicular to the rays
    offsets = bundle.origins - cam.plane_center
    assert offsets @ to_camera == pytest.approx(np.zeros(35), abs=1e-9)
    assert cam.plane_center[2] == pytest.approx(1000.0, abs=EXACT)
    # the centre pixel's ray meets the ground at `center`
    x, y = cam.pixel_coordinates()
    assert (x[2, 3], y[2, 3]) == pytest.approx((10.0, 20.0), abs=EXACT)
    # image up keeps north up: positive northing, perpendicular to the view
    assert cam.up[1] > 0 and cam.up @ to_camera == pytest.approx(0.0, abs=EXACT)
    assert np.cross(cam.right, cam.up) == pytest.approx(to_camera, abs=EXACT)


def test_orthographic_rejects_bad_parameters():
    with pytest.raises(ConfigError, match="gsd"):
        OrthographicCamera((0, 0), (4, 4), gsd=0.0)
    with pytest.raises(ConfigError, match="shape"):
        OrthographicCamera((0, 0), (4, 0))
    with pytest.raises(ConfigError, match="shape"):
        OrthographicCamera((0, 0), (4.0, 4))
    with pytest.raises(ConfigError, match="zenith"):
        OrthographicCamera((0, 0), (4, 4), zenith=90.0)
    with pytest.raises(ConfigError, match="center"):
        OrthographicCamera((0, 0, 0), (4, 4))
    cam = OrthographicCamera((0, 0), (4, 4))
    for bad in (0, 2.0, True):
        with pytest.raises(ConfigError, match="supersample"):
            cam.rays(supersample=bad)


def test_window_selects_a_tile_with_global_pixel_indices():
    cam = OrthographicCamera((0, 0), (6, 8), gsd=1.0)
    full = cam.rays(supersample=2)
    tile = cam.rays(supersample=2, window=(2, 4, 3, 7))
    assert len(tile) == 2 * 4 * 4
    keep = np.isin(full.pixel, tile.pixel)
    assert np.array_equal(full.pixel[keep], tile.pixel)
    assert np.array_equal(full.origins[keep], tile.origins)
    assert set((tile.pixel // 8).tolist()) == {2, 3}
    with pytest.raises(ConfigError, match="window"):
        cam.rays(window=(0, 7, 0, 8))


def test_to_image_averages_sub_samples():
    cam = OrthographicCamera((0, 0), (2, 2), gsd=1.0)
    bundle = cam.rays(supersample=2)
    image = bundle.to_image(bundle.origins[:, 0])
    x, _ = cam.pixel_coordinates()
    assert image == pytest.approx(x, abs=EXACT)
    stacked = bundle.to_image(np.column_stack([np.ones(len(bundle)), 2 * np.ones(len(bundle))]))
    assert stacked.shape == (2, 2, 2)
    assert stacked[..., 1] == pytest.approx(np.full((2, 2), 2.0), rel=1e-12)


# -- perspective -----------------------------------------------------------------------------


def _horizontal_angle(cam, d):
    """Angle of directions left/right of the optical axis, in the camera's horizontal [deg]."""
    return np.degrees(np.arctan2(d @ cam.right, d @ cam.forward))


def test_centre_ray_points_at_look_at():
    position = np.array([100.0, -300.0, 250.0])
    target = np.array([-20.0, 40.0, 10.0])
    cam = PerspectiveCamera(position, (5, 7), fov=40.0, look_at=target)
    bundle = cam.rays()
    centre = bundle.directions[2 * 7 + 3]
    expected = (target - position) / np.linalg.norm(target - position)
    assert centre == pytest.approx(expected, abs=EXACT)
    assert bundle.origins == pytest.approx(np.tile(position, (35, 1)), abs=0.0)
    assert np.linalg.norm(bundle.directions, axis=1) == pytest.approx(np.ones(35), abs=1e-12)
    # level horizon: roll 0, image right is horizontal
    assert cam.right[2] == pytest.approx(0.0, abs=EXACT)


def test_edge_and_corner_angles_match_fov():
    fov, ny, nx = 50.0, 30, 40
    cam = PerspectiveCamera((0, 0, 10.0), (ny, nx), fov=fov, attitude=(30.0, -10.0, 0.0))
    # the left and right image edges are fov/2 off the axis
    edges = cam.directions_at([ny / 2, ny / 2], [0.0, nx])
    assert _horizontal_angle(cam, edges) == pytest.approx([-fov / 2, fov / 2], abs=ANGLE)
    # the corner pixel centre is half a pixel in
    p = 2 * np.tan(np.radians(fov / 2)) / nx
    corner = cam.rays().directions[0]
    assert _horizontal_angle(cam, corner) == pytest.approx(
        -np.degrees(np.arctan((nx / 2 - 0.5) * p)), abs=ANGLE)
    assert corner @ cam.up > 0  # row 0 is the top of the image
    vertical = np.degrees(np.arctan2(cam.directions_at(0.0, nx / 2) @ cam.up,
                                     cam.directions_at(0.0, nx / 2) @ cam.forward))
    assert 2 * vertical == pytest.approx(cam.fov_vertical, abs=ANGLE)
    assert cam.fov_vertical == pytest.approx(
        2 * np.degrees(np.arctan(np.tan(np.radians(fov / 2)) * ny / nx)), abs=ANGLE)


def test_attitude_convention():
    cam = PerspectiveCamera((0, 0, 0), (2, 2), attitude=(90.0, -30.0, 0.0))
    assert cam.forward == pytest.approx(direction_from_angles(120.0, 90.0), abs=EXACT)
    rolled = PerspectiveCamera((0, 0, 0), (2, 2), attitude=(0.0, 0.0, 90.0))
    assert rolled.forward == pytest.approx([0.0, 1.0, 0.0], abs=EXACT)
    assert rolled.right == pytest.approx([0.0, 0.0, -1.0], abs=EXACT)  # right side down


def test_look_straight_down_is_north_up():
    cam = PerspectiveCamera((5.0, 5.0, 100.0), (3, 3), fov=90.0, look_at=(5.0, 5.0, 0.0))
    assert cam.forward == pytest.approx([0.0, 0.0, -1.0], abs=EXACT)
    assert cam.up == pytest.approx([0.0, 1.0, 0.0], abs=EXACT)
    assert cam.right == pytest.approx([1.0, 0.0, 0.0], abs=EXACT)
    d = cam.rays().directions
    assert d[1, 1] > 0 and d[7, 1] < 0  # top row looks north, bottom row south
    assert d[3, 0] < 0 and d[5, 0] > 0  # left column looks west


def test_perspective_weights_sum_to_one():
    cam = PerspectiveCamera((0, 0, 10.0), (4, 6), look_at=(0, 50, 0))
    bundle = cam.rays(supersample=4)
    assert _pixel_sums(bundle, bundle.weight) == pytest.approx(np.ones(24), rel=1e-12)
    assert bundle.pixel.dtype == np.int64 and bundle.subsample.max() == 15


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [({"look_at": (0, 1, 0), "attitude": (0, 0, 0)}, "exactly one"),
     ({}, "exactly one"),
     ({"look_at": (0, 0, 10.0)}, "look_at: must differ"),
     ({"look_at": (0, 1, 0), "fov": 180.0}, "fov"),
     ({"look_at": (0, 1, 0), "fov": 0.0}, "fov"),
     ({"attitude": (0, np.nan, 0)}, "attitude")],
)
def test_perspective_rejects_bad_parameters(kwargs, match):
    with pytest.raises(ConfigError, match=match):
        PerspectiveCamera((0, 0, 10.0), (4, 4), **kwargs)


def test_map_axes_are_the_first_row_and_column_of_the_pixel_coordinates():
    cam = OrthographicCamera(center=(10.0, 20.0), shape=(5, 7), gsd=3.0, altitude=1000.0)
    x, y = cam.pixel_coordinates()
    xs, ys = cam.map_axes()
    assert np.array_equal(xs, x[0]) and np.array_equal(ys, y[:, 0])
    assert np.array_equal(x, np.broadcast_to(xs, x.shape))  # north-up: one easting per column
    assert np.array_equal(y, np.broadcast_to(ys[:, None], y.shape))
    with pytest.raises(ValueError, match="nadir"):
        OrthographicCamera((0, 0), (4, 4), gsd=1.0, zenith=20.0).map_axes()


@pytest.mark.parametrize("camera", [
    OrthographicCamera(center=(10.0, -5.0), shape=(6, 9), gsd=2.5, altitude=500.0, zenith=30.0,
                       azimuth=60.0),
    PerspectiveCamera((3.0, -40.0, 25.0), (6, 9), fov=50.0, attitude=(10.0, -20.0, 5.0))],
    ids=["orthographic", "perspective"])
def test_project_returns_the_pixel_whose_ray_passes_through_a_point(camera):
    rays = camera.rays()
    distance = np.linspace(30.0, 90.0, len(rays.origins))[:, None]
    row, col, in_front = camera.project(rays.origins + distance * rays.directions)
    ny, nx = camera.shape
    centre_row, centre_col = np.divmod(rays.pixel, nx)
    np.testing.assert_allclose(row, centre_row + 0.5, rtol=0, atol=1e-9)
    np.testing.assert_allclose(col, centre_col + 0.5, rtol=0, atol=1e-9)
    assert in_front.all()
    assert not camera.project(rays.origins - 10.0 * rays.directions)[2].any()
