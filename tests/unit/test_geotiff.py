"""Tests of radscene.io.geotiff: map products in the frame's CRS or UTM, GCP-georeferenced images."""

import datetime as dt

import numpy as np
import pytest
import rasterio
import xarray as xr
from pyproj import Transformer

from radscene.errors import ConfigError
from radscene.io.geotiff import read_geotiff, write_geotiff, write_geotiff_gcps
from radscene.platform import OrthographicCamera
from radscene.platform.config import build_observer
from radscene.platform.geolocation import LocalFrame, geolocation_truth

# rasterio/rioxarray's own use of affine's `*` operator
pytestmark = pytest.mark.filterwarnings("ignore::PendingDeprecationWarning")

MM = 1e-3  # [m]
FRAME = LocalFrame(46.5, 6.6, 400.0)


def _map_product(shape=(30, 40), gsd=10.0):
    cam = OrthographicCamera((200.0, -100.0), shape, gsd=gsd)
    x, y = cam.pixel_coordinates()
    data = np.stack([x, y, np.hypot(x, y)])
    return xr.DataArray(data, dims=("band", "y", "x"),
                        coords={"band": ["east", "north", "range"], "y": y[:, 0], "x": x[0]},
                        attrs={"units": "m", "long_name": "coordinates"})


def test_map_product_in_the_frame_crs(tmp_path):
    da = _map_product()
    path = write_geotiff(da, tmp_path / "sub" / "map.tif", crs=FRAME)
    assert path.is_file() and not list(path.parent.glob(".*.tmp*"))
    back = read_geotiff(path)
    assert back.shape == (3, 30, 40)
    # pixel centres are the frame's x/y; the values came back (float32)
    assert back.x.values == pytest.approx(da.x.values, abs=MM)
    assert back.y.values == pytest.approx(da.y.values, abs=MM)
    assert back.values[0] == pytest.approx(da.values[0], rel=1e-6)
    with rasterio.open(path) as src:
        assert src.descriptions == ("east", "north", "range")
        assert src.tags()["units"] == "m"
        assert src.res == pytest.approx((10.0, 10.0))
        # the CRS: a point on the ellipsoid maps to its frame coordinates
        to_map = Transformer.from_crs("EPSG:4326", src.crs, always_xy=True)
    lat, lon = 46.52, 6.63
    enu = FRAME.from_geodetic(lat, lon, 0.0)
    assert to_map.transform(lon, lat) == pytest.approx(tuple(enu[:2]), abs=MM)


def test_reprojection_to_utm_keeps_values_at_their_places(tmp_path):
    da = _map_product(shape=(60, 60), gsd=5.0)
    path = write_geotiff(da, tmp_path / "utm.tif", crs=FRAME, dst_crs="utm", resolution=5.0,
                         resampling="bilinear")
    back = read_geotiff(path)
    assert back.rio.crs.to_epsg() == 32632  # UTM zone 32 N at 6.6 E
    # the "east" band holds the frame x: sample it at a UTM point and compare
    x0, y0 = 180.0, -80.0
    lat, lon, _ = FRAME.to_geodetic([x0, y0, 0.0])
    e, n = Transformer.from_crs("EPSG:4326", "EPSG:32632", always_xy=True).transform(lon, lat)
    value = back.sel(band=1).interp(x=e, y=n).item()
    assert value == pytest.approx(x0, abs=0.5)  # within a tenth of a pixel


def test_image_geometry_product_with_gcps(tmp_path):
    t = dt.datetime(2023, 6, 1, 10, 30, tzinfo=dt.UTC)
    pb = build_observer({"type": "pushbroom", "name": "p", "shape": [40, 30], "gsd": 30.0,
                         "orbit": {"overpass": {"altitude": 705e3}}}, FRAME, t)
    truth = geolocation_truth(pb, FRAME)
    da = truth["ground_x"]
    path = write_geotiff_gcps(da, truth.latitude, truth.longitude, tmp_path / "l1.tif", step=5)
    with rasterio.open(path) as src:
        gcps, crs = src.gcps
        assert crs.to_epsg() == 4326
        rows = {(g.row, g.col): g for g in gcps}
        assert len(gcps) == 9 * 7  # rows 0, 5, ..., 35, 39 x cols 0, 5, ..., 25, 29
        g = rows[(5.5, 10.5)]
        assert g.y == pytest.approx(float(truth.latitude[5, 10]), abs=1e-12)
        assert g.x == pytest.approx(float(truth.longitude[5, 10]), abs=1e-12)
    # warped through the GCPs to UTM, the ground_x band still reads x at its place
    path = write_geotiff_gcps(da, truth.latitude, truth.longitude, tmp_path / "l1_utm.tif",
                              step=5, dst_crs="utm", resolution=30.0)
    back = read_geotiff(path)
    assert back.rio.crs.to_epsg() == 32632
    lat, lon = float(truth.latitude[20, 15]), float(truth.longitude[20, 15])
    e, n = Transformer.from_crs("EPSG:4326", "EPSG:32632", always_xy=True).transform(lon, lat)
    value = back.sel(band=1).interp(x=e, y=n).item()
    assert value == pytest.approx(float(truth.ground_x[20, 15]), abs=3.0)  # 0.1 pixel


def test_bad_input_is_refused(tmp_path):
    da = _map_product()
    with pytest.raises(ConfigError, match="data: must be an xarray.DataArray"):
        write_geotiff(da.to_dataset(name="v"), tmp_path / "a.tif", crs=FRAME)
    bent = da.assign_coords(x=da.x.values ** 1.01)
    with pytest.raises(ConfigError, match="x: coordinates must be equally spaced"):
        write_geotiff(bent, tmp_path / "a.tif", crs=FRAME)
    with pytest.raises(ConfigError, match="resampling: unknown resampling 'spline'"):
        write_geotiff(da, tmp_path / "a.tif", crs=FRAME, dst_crs="utm", resampling="spline")
    with pytest.raises(ConfigError, match="crs: not a coordinate reference system"):
        write_geotiff(da, tmp_path / "a.tif", crs="EPSG:0")
    with pytest.raises(ConfigError, match=r"latitude: must have the image's shape \(30, 40\)"):
        write_geotiff_gcps(da, np.zeros((2, 2)), np.zeros((2, 2)), tmp_path / "b.tif")
    with pytest.raises(ConfigError, match="no such file"):
        read_geotiff(tmp_path / "missing.tif")


def test_cog_refuses_a_layer_without_crs_and_an_unknown_level(tmp_path):
    from radscene.io.cog import map_layers, write_cog

    with pytest.raises(ConfigError, match="no CRS"):
        write_cog(_map_product(), tmp_path / "a.tif")
    with pytest.raises(ConfigError, match="--geotiff: unknown GeoTIFF level 'every'; known: "
                                          "none, radiance, maps, all"):
        map_layers(xr.Dataset(), "every")
    assert not list(tmp_path.iterdir())


def test_envi_refuses_what_is_not_band_radiance(tmp_path):
    from radscene.io import write_envi

    with pytest.raises(ConfigError, match=r"DataArray \(band, y, x\)"):
        write_envi(_map_product().transpose("y", "x", "band"), tmp_path / "a.img")
    with pytest.raises(ConfigError, match="wavelength_center, equivalent_width"):
        write_envi(_map_product(), tmp_path / "a.img")
    assert not list(tmp_path.iterdir())
