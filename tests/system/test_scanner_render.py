"""A pushbroom observer and bundled sensor bands, end to end through the renderer."""

from __future__ import annotations

import numpy as np
import pytest

from radscene import load_scene, render


def _scene(observer):
    return {
        "name": "pushbroom",
        "environment": {"location": {"latitude": 35.0, "longitude": -106.0, "altitude": 1500},
                        "time": "2026-06-21T17:30:00Z", "atmosphere": {"type": "none"}},
        "terrain": {"type": "procedural", "size": [600, 600], "spacing": 5, "relief": 10,
                    "origin": [-300, -300], "material": "dry_grass"},
        "objects": [{"name": "roof", "shape": {"type": "box", "size": [40, 40, 5]},
                     "position": [0, 0, 0], "material": "bare_aluminium"}],
        "bands": [{"name": "red", "sensor": "landsat8_oli", "band": "B4"},
                  {"name": "tir", "sensor": "landsat8_tirs", "band": "B10"}],
        "observers": [observer],
    }


def test_pushbroom_render_sees_the_roof_in_the_middle():
    observer = {"name": "push", "type": "pushbroom", "shape": [60, 60], "gsd": 5.0,
                "platform": {"position": [0, 0, 3000], "velocity": [0, 50, 0]}}
    scene = load_scene(_scene(observer))
    ds = render(scene)
    assert ds.sizes == {"band": 2, "y": 60, "x": 60, "vector": 3}
    roof = scene.objects[1].name
    ids = ds["object_id"].values
    assert ds["object_id"].attrs["flag_meanings"].split()[1] == roof
    rows, cols = np.nonzero(ids == 1)
    assert rows.mean() == pytest.approx(29.5, abs=2.0)
    assert cols.mean() == pytest.approx(29.5, abs=2.0)
    assert len(rows) == pytest.approx((40 / 5) ** 2, rel=0.3)
    assert np.isfinite(ds["brightness_temperature"].sel(band="tir")).all()


def test_library_band_needs_sensor_and_band():
    from radscene.errors import ConfigError

    data = _scene({"name": "map", "type": "orthographic", "center": [0, 0], "gsd": 10,
                   "shape": [4, 4]})
    data["bands"] = [{"name": "x", "sensor": "landsat8_oli"}]
    with pytest.raises(ConfigError, match=r"bands\[0\]"):
        load_scene(data)
    data["bands"] = [{"name": "x", "sensor": "landsat8_oli", "band": "B99"}]
    with pytest.raises(ConfigError, match="B99"):
        load_scene(data)
