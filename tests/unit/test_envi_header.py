"""The georeference of ENVI headers (radscene.io.envi.map_fields): ``map info`` and the
``coordinate system string`` from a map grid and its CRS, refused for grids they cannot
describe, absent without a map grid."""

from __future__ import annotations

import json

import numpy as np
import pytest
import xarray as xr
from pyproj import CRS

from radscene.errors import ConfigError
from radscene.io.envi import header_text, map_fields, pixel_size

pytest.importorskip("rioxarray")


def _layer(x, y, crs="EPSG:32632", units="m"):
    import rioxarray  # noqa: F401 - the .rio accessor

    da = xr.DataArray(np.zeros((1, len(y), len(x))), dims=("band", "y", "x"),
                      coords={"x": ("x", np.asarray(x, float), {"units": units}),
                              "y": ("y", np.asarray(y, float), {"units": units})})
    return da.rio.write_crs(crs) if crs else da


def test_utm_grid_gives_zone_hemisphere_corner_and_pixel_size():
    info, system = map_fields(_layer([500010.0, 500030.0, 500050.0], [5e6 + 50, 5e6 + 30]))
    assert info == "map info = {UTM, 1, 1, 500000, 5000060, 20, 20, 32, North, WGS-84, " \
                   "units=Meters}"
    assert system.startswith("coordinate system string = {PROJCS[") and system.endswith("]}")
    assert CRS.from_wkt(system.split("{", 1)[1][:-1]).equals(CRS.from_epsg(32632),
                                                             ignore_axis_order=True)
    south = map_fields(_layer([0.5, 1.5], [1.5, 0.5], "EPSG:32733"))[0]
    assert south == "map info = {UTM, 1, 1, 0, 2, 1, 1, 33, South, WGS-84, units=Meters}"


def test_a_single_row_takes_square_pixels_and_a_single_pixel_the_recorded_size():
    info = map_fields(_layer([10.0, 12.0, 14.0], [5.0]))[0]
    assert info.startswith("map info = {UTM, 1, 1, 9, 6, 2, 2,")
    attrs = {"observer_geometry": json.dumps({"gsd_m": 4.0, "shape": [1, 1]})}
    assert pixel_size(attrs) == 4.0 and pixel_size({}) is None
    info = map_fields(_layer([10.0], [5.0]), pixel_size(attrs))[0]
    assert info.startswith("map info = {UTM, 1, 1, 8, 7, 4, 4,")


@pytest.mark.parametrize("x, y, match", [
    ([0.0, 1.0], [0.0, 1.0], "north-up grid"),
    ([1.0, 0.0], [1.0, 0.0], "north-up grid"),
    ([0.0, 1.0, 3.0], [1.0, 0.0], "equally spaced"),
    ([1.0], [1.0], "pixel size"),
])
def test_grids_map_info_cannot_describe_are_refused(x, y, match):
    with pytest.raises(ConfigError, match=match):
        map_fields(_layer(x, y))


def test_no_map_grid_no_fields():
    assert map_fields(_layer([0.0, 1.0], [1.0, 0.0], crs=None)) == []
    assert map_fields(_layer([0, 1], [0, 1], units="px")) == []
    header = header_text((1, 2, 2), [0.55], [0.1], ["vis"], "d", "W m-2 sr-1")
    assert "map info" not in header


def test_header_places_the_fields_among_the_others():
    fields = map_fields(_layer([0.5, 1.5], [1.5, 0.5]))
    lines = header_text((1, 2, 2), [0.55], [0.1], ["vis"], "d", "W m-2 sr-1",
                        georeference=fields).splitlines()
    assert lines[0] == "ENVI"
    assert lines[lines.index("byte order = 0") + 1:][:2] == fields
