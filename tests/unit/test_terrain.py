"""Tests of radscene.geometry.terrain."""


import numpy as np
import pytest

from radscene.errors import ConfigError
from radscene.geometry import Heightfield, procedural_terrain

EXACT = 1e-9  # [m], a few double roundings on coordinates of 1e3..1e6 m


def _ramp(ny=4, nx=5, a=0.3, b=-0.2, c=100.0, origin=(1000.0, 2000.0), spacing=(10.0, 20.0)):
    """A plane z = a x + b y + c sampled on the grid of a Heightfield."""
    x = origin[0] + spacing[0] * np.arange(nx)
    y = origin[1] + spacing[1] * np.arange(ny - 1, -1, -1)  # row 0 north
    z = a * x[None, :] + b * y[:, None] + c
    return Heightfield(z, origin=origin, spacing=spacing), (a, b, c)


def test_layout_row_zero_is_north_column_zero_is_west():
    z = np.arange(12.0).reshape(3, 4)
    hf = Heightfield(z, origin=(100.0, 200.0), spacing=(10.0, 5.0))
    assert hf.x == pytest.approx([100, 110, 120, 130], abs=0.0)
    assert hf.y == pytest.approx([210, 205, 200], abs=0.0)
    assert hf.extent == (100.0, 130.0, 200.0, 210.0)
    # south-west sample is row 2, column 0; north-east is row 0, column 3
    assert float(hf.height_at(100.0, 200.0)) == pytest.approx(z[2, 0], abs=EXACT)
    assert float(hf.height_at(130.0, 210.0)) == pytest.approx(z[0, 3], abs=EXACT)
    assert float(hf.height_at(110.0, 205.0)) == pytest.approx(z[1, 1], abs=EXACT)


def test_bilinear_reproduces_a_plane_and_cell_centres():
    hf, (a, b, c) = _ramp()
    rng = np.random.default_rng(3)
    x0, x1, y0, y1 = hf.extent
    x = rng.uniform(x0, x1, (7, 9))
    y = rng.uniform(y0, y1, (7, 9))
    h = hf.height_at(x, y)
    assert h.shape == (7, 9)
    assert h == pytest.approx(a * x + b * y + c, abs=EXACT)
    # A non-planar cell: the centre is the mean of the four corners.
    z = np.array([[0.0, 4.0], [2.0, 10.0]])
    assert float(Heightfield(z, spacing=2.0).height_at(1.0, 1.0)) == pytest.approx(4.0, abs=EXACT)


def test_normal_of_a_plane_and_broadcasting():
    hf, (a, b, _) = _ramp()
    n = hf.normal_at(np.array([1005.0, 1031.0]), 2033.0)
    expected = np.array([-a, -b, 1.0]) / np.sqrt(a * a + b * b + 1.0)
    assert n.shape == (2, 3)
    assert n == pytest.approx(np.array([expected, expected]), abs=1e-12)


def test_points_outside_are_refused():
    hf, _ = _ramp()
    with pytest.raises(ConfigError, match="1 points lie outside the terrain extent"):
        hf.height_at([1000.0, 999.0], 2000.0)
    with pytest.raises(ConfigError, match="outside"):
        hf.normal_at(1000.0, 2061.0)


def test_nan_samples_are_counted_and_located():
    z = np.zeros((4, 5))
    z[1, 2] = np.nan
    z[3, 0] = np.nan
    z[2, 4] = np.inf
    with pytest.raises(ConfigError, match=r"2 NaN and 1 infinite.*\(row, col\) = \(1, 2\)"):
        Heightfield(z)


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [({"elevation": np.zeros((1, 5))}, "at least 2 x 2"),
     ({"elevation": np.zeros(5)}, "at least 2 x 2"),
     ({"elevation": np.zeros((2, 2)), "spacing": (1.0, 0.0)}, "spacing"),
     ({"elevation": np.zeros((2, 2)), "origin": (np.nan, 0.0)}, "origin")],
)
def test_bad_grids_are_refused(kwargs, match):
    with pytest.raises(ConfigError, match=match):
        Heightfield(**kwargs)


def test_cell_index_picks_the_nearest_sample():
    hf, _ = _ramp()  # x 1000..1040 step 10, y 2000..2060 step 20, 4 rows
    row, col = hf.cell_index([1000.0, 1014.9, 1015.1, 1044.0], [2060.0, 2029.0, 2031.0, 1991.0])
    assert row.tolist() == [0, 2, 1, 3]
    assert col.tolist() == [0, 1, 2, 4]
    assert row.dtype == np.int64
    with pytest.raises(ConfigError, match="outside"):
        hf.cell_index(1046.0, 2000.0)


def test_to_mesh_vertices_faces_and_upward_normals():
    hf, (a, b, c) = _ramp()
    m = hf.to_mesh()
    ny, nx = hf.shape
    assert m.name == "terrain"
    assert len(m.vertices) == ny * nx and len(m.faces) == 2 * (ny - 1) * (nx - 1)
    # vertex i * nx + j is sample (i, j)
    xx, yy = np.meshgrid(hf.x, hf.y)
    assert m.vertices == pytest.approx(np.column_stack([xx.ravel(), yy.ravel(),
                                                        hf.elevation.ravel()]), abs=0.0)
    expected = np.array([-a, -b, 1.0]) / np.sqrt(a * a + b * b + 1.0)
    assert m.face_normals == pytest.approx(np.tile(expected, (len(m.faces), 1)), abs=1e-12)
    assert m.area.sum() == pytest.approx(40.0 * 60.0 * np.sqrt(a * a + b * b + 1), rel=1e-12)


def test_to_mesh_face_pairs_belong_to_their_cell():
    hf = Heightfield(np.random.default_rng(0).normal(size=(5, 6)), spacing=(2.0, 3.0))
    m = hf.to_mesh()
    centres = m.vertices[m.faces].mean(axis=1)
    row, col = np.divmod(np.arange(len(m.faces)) // 2, hf.shape[1] - 1)
    x_west = hf.x[col]
    y_north = hf.y[row]
    assert ((centres[:, 0] > x_west) & (centres[:, 0] < x_west + 2.0)).all()
    assert ((centres[:, 1] < y_north) & (centres[:, 1] > y_north - 3.0)).all()
    assert (m.face_normals[:, 2] > 0).all()


def test_to_mesh_of_a_million_triangles_is_whole():
    z = np.random.default_rng(0).normal(size=(708, 708))
    hf = Heightfield(z, spacing=5.0)
    m = hf.to_mesh()
    assert len(m.faces) == 2 * 707 * 707 and len(m.vertices) == 708 * 708
    # every post is a vertex at its height, and every face spans one cell
    assert np.sort(m.vertices[:, 2]) == pytest.approx(np.sort(z.ravel()), abs=0.0)
    span = np.ptp(m.vertices[m.faces][:, :, :2], axis=1)
    assert span.max() == pytest.approx(5.0, abs=1e-9)
    assert (m.face_normals[:, 2] > 0).all()


def test_from_array_flips_to_north_up():
    z = np.arange(6.0).reshape(2, 3)  # rows at y = 0, 5 (ascending), columns x = 30, 20, 10
    hf = Heightfield.from_array(z, x=[30.0, 20.0, 10.0], y=[0.0, 5.0], crs="EPSG:32633")
    assert hf.origin == (10.0, 0.0) and hf.spacing == (10.0, 5.0) and hf.crs == "EPSG:32633"
    assert hf.elevation == pytest.approx(np.array([[5, 4, 3], [2, 1, 0]]), abs=0.0)
    assert float(hf.height_at(30.0, 0.0)) == pytest.approx(0.0, abs=0.0)
    with pytest.raises(ConfigError, match="regularly spaced"):
        Heightfield.from_array(z, x=[0.0, 1.0, 3.0], y=[0.0, 1.0])
    with pytest.raises(ConfigError, match="does not match"):
        Heightfield.from_array(z, x=[0.0, 1.0], y=[0.0, 1.0])


def _write_geotiff(path, z, nodata=None, crs="EPSG:32633", corner=(500000.0, 4600000.0),
                   pixel=30.0):
    import rasterio
    from rasterio.transform import from_origin

    transform = from_origin(*corner, pixel, pixel)  # west edge, north edge, pixel
    with rasterio.open(path, "w", driver="GTiff", height=z.shape[0], width=z.shape[1], count=1,
                       dtype="float32", crs=crs, transform=transform,
                       nodata=nodata) as dst:
        dst.write(z.astype(np.float32), 1)


@pytest.mark.filterwarnings("ignore::PendingDeprecationWarning")  # affine via rasterio
def test_from_geotiff_uses_pixel_centres_and_keeps_crs(tmp_path):
    z = np.arange(12.0).reshape(3, 4)
    path = tmp_path / "dem.tif"
    _write_geotiff(path, z)
    hf = Heightfield.from_geotiff(path)
    assert hf.crs == "EPSG:32633"
    assert hf.spacing == (30.0, 30.0)
    # centre of the south-west pixel: west edge + 15 m, north edge - 2.5 pixels
    assert hf.origin == pytest.approx((500015.0, 4600000.0 - 75.0), abs=EXACT)
    assert hf.elevation == pytest.approx(z, abs=0.0)  # the raster is north-up already


@pytest.mark.filterwarnings("ignore::PendingDeprecationWarning")
def test_from_geotiff_nodata_and_missing_file(tmp_path):
    z = np.arange(12.0).reshape(3, 4)
    z[2, 1] = -9999.0
    path = tmp_path / "holes.tif"
    _write_geotiff(path, z, nodata=-9999.0)
    with pytest.raises(ConfigError, match=r"1 NaN and 0 infinite.*\(2, 1\)"):
        Heightfield.from_geotiff(path)
    with pytest.raises(ConfigError, match="not found"):
        Heightfield.from_geotiff(tmp_path / "nothing.tif")


# -- procedural terrain ----------------------------------------------------------------------


def test_procedural_terrain_grid_relief_and_determinism():
    hf, water = procedural_terrain((400.0, 300.0), spacing=5.0, relief=40.0, seed=7)
    assert hf.shape == (61, 81) and water.shape == (61, 81) and not water.any()
    assert hf.extent == pytest.approx((-200.0, 200.0, -150.0, 150.0), abs=EXACT)
    assert np.ptp(hf.elevation) == pytest.approx(40.0, rel=1e-12)
    assert hf.elevation.min() == pytest.approx(0.0, abs=EXACT)
    again, _ = procedural_terrain((400.0, 300.0), spacing=5.0, relief=40.0, seed=7)
    other, _ = procedural_terrain((400.0, 300.0), spacing=5.0, relief=40.0, seed=8)
    assert np.array_equal(hf.elevation, again.elevation)
    assert not np.allclose(hf.elevation, other.elevation)


def test_default_hills_are_smooth():
    hf, _ = procedural_terrain()  # 1 km, 5 m, 40 m relief
    gy, gx = np.gradient(hf.elevation, 5.0)
    slope = np.degrees(np.arctan(np.hypot(gx, gy)))  # [deg]
    assert slope.max() < 35.0
    assert 3.0 < slope.mean() < 15.0


def test_lakes_are_flat_carved_and_contained():
    lakes = [(-100.0, 0.0, 60.0, 3.0), (120.0, 80.0, 40.0, 1.0)]
    bare, _ = procedural_terrain((500.0, 400.0), spacing=5.0, seed=2)
    hf, water = procedural_terrain((500.0, 400.0), spacing=5.0, seed=2, lakes=lakes)
    xx, yy = np.meshgrid(hf.x, hf.y)
    for lx, ly, radius, depth in lakes:
        disc = np.hypot(xx - lx, yy - ly) <= radius
        assert np.array_equal(water & disc, disc)
        band = max(radius / 2, 10.0)
        shore = (np.hypot(xx - lx, yy - ly) <= radius + band) & ~disc
        level = bare.elevation[disc | shore].min() - depth
        assert hf.elevation[disc] == pytest.approx(np.full(disc.sum(), level), abs=0.0)
        # no ground of the shore band lies below the water surface
        assert (hf.elevation[shore] > level).all()
    assert water.sum() == sum(int((np.hypot(xx - x, yy - y) <= r).sum()) for x, y, r, _ in lakes)
    far = np.hypot(xx + 100, yy) > 100 + 1e-9
    far &= np.hypot(xx - 120, yy - 80) > 70 + 1e-9
    assert np.array_equal(hf.elevation[far], bare.elevation[far])  # untouched away from lakes


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [({"spacing": 0.0}, "spacing"), ({"size": (100.0, -1.0)}, "size"),
     ({"relief": -1.0}, "relief"),
     ({"lakes": [(0.0, 0.0, 10.0)]}, r"lakes\[0\]: must be 4 finite numbers"),
     ({"lakes": [(0.0, 0.0, 0.0, 1.0)]}, r"lakes\[0\]: radius must be > 0"),
     ({"lakes": [(900.0, 0.0, 10.0, 1.0)]}, r"lakes\[0\]: centre .* outside"),
     ({"lakes": [(0.0, 0.0, 30.0, 1.0), (50.0, 0.0, 30.0, 1.0)]}, r"lakes\[1\]: overlaps"),
     ({"lakes": [(1.0, 1.0, 0.5, 1.0)]}, "covers no sample")],
)
def test_procedural_terrain_rejects_bad_input(kwargs, match):
    with pytest.raises(ConfigError, match=match):
        procedural_terrain(**{"size": (200.0, 200.0), **kwargs})


@pytest.mark.filterwarnings("ignore::PendingDeprecationWarning")
@pytest.mark.parametrize("crs, corner, pixel, match", [
    ("EPSG:4326", (5.0, 45.0), 0.001, r"geographic coordinates \(EPSG:4326, degrees\); reproject"),
    ("EPSG:2263", (1000000.0, 200000.0), 100.0, r"x, y in US survey foot"),
])
def test_a_dem_not_in_metres_is_refused_never_read_as_metres(tmp_path, crs, corner, pixel, match):
    """A DEM in degrees (or feet) would be read as metres: 0.001° pixels, a 3 cm terrain."""
    path = tmp_path / "dem.tif"
    _write_geotiff(path, np.arange(12.0).reshape(3, 4), crs=crs, corner=corner, pixel=pixel)
    with pytest.raises(ConfigError, match=match):
        Heightfield.from_geotiff(path)
    _write_geotiff(path, np.arange(12.0).reshape(3, 4), crs=None, corner=corner, pixel=pixel)
    assert Heightfield.from_geotiff(path).spacing == pytest.approx((pixel, pixel), rel=1e-9)  # as given
