"""Scene → render → sensor, from a scene file, through the API and the CLI."""

from __future__ import annotations

import numpy as np
import pytest
from typer.testing import CliRunner

import radscene
from radscene.cli import app
from radscene.errors import ConfigError


def _scene(**observer):
    obs = {"name": "ir", "type": "perspective", "position": [0, -300, 60],
           "look_at": [0, 0, 0], "sensor": "bolometer", "frames": 2}
    obs.update(observer)
    return {
        "name": "thermal",
        "environment": {"sun": {"zenith": 40, "azimuth": 160}, "atmosphere": {"type": "none"}},
        "objects": [
            {"name": "ground", "shape": {"type": "plate", "width": 2000, "length": 2000},
             "material": "dry_grass", "temperature": "295 K"},
            {"name": "truck", "shape": {"type": "box", "size": [3, 8, 3]}, "position": [0, 0, 0],
             "material": "painted_metal", "temperature": "330 K"},
        ],
        "bands": [{"name": "lwir", "min": "8 um", "max": "14 um"}],
        "sensors": {"bolometer": {"example": "lwir_microbolometer",
                                  "detector": {"shape": [16, 16]}}},
        "observers": [obs],
    }


def test_simulate_returns_signal_on_the_detector_grid():
    scene = radscene.load_scene(_scene())
    images, signal = radscene.simulate(scene)
    assert images.sizes["y"] == 64
    dn = signal["dn"]
    assert dn.sizes["frame"] == 2 and dn.sizes["y"] == 16 and dn.sizes["x"] == 16
    # the hot truck in the middle reads more DN than the ground at the image edge
    assert float(dn.isel(frame=0, band=0, y=8, x=8)) > float(dn.isel(frame=0, band=0, y=8, x=0))
    # independent temporal noise between frames
    assert not np.array_equal(dn.isel(frame=0).values, dn.isel(frame=1).values)


def test_field_of_view_comes_from_the_sensor_when_omitted():
    scene = radscene.load_scene(_scene())
    cam = scene.observers[0].camera
    # 16 detectors of 17 um behind 25 mm: 2 atan(8 * 17e-6 / 0.025)
    assert cam.fov == pytest.approx(np.degrees(2 * np.arctan(8 * 17e-6 / 0.025)), rel=1e-9)


def test_a_shape_that_disagrees_with_the_sensor_is_refused():
    with pytest.raises(ConfigError, match=r"observers\[0\].shape: sensor 'bolometer' records 16 x 16"):
        radscene.load_scene(_scene(shape=[50, 50]))


def test_unknown_sensor_is_named():
    with pytest.raises(ConfigError, match=r"observers\[0\].sensor: unknown sensor 'nosuch'"):
        radscene.load_scene(_scene(sensor="nosuch"))


def test_cli_writes_the_signal(tmp_path):
    import yaml

    path = tmp_path / "scene.yaml"
    path.write_text(yaml.safe_dump(_scene()))
    result = CliRunner().invoke(app, ["render", str(path), "-o", str(tmp_path / "out")])
    assert result.exit_code == 0, result.output
    assert (tmp_path / "out" / "ir_signal.nc").is_file()
    assert (tmp_path / "out" / "ir_signal" / "lwir.png").is_file()


def _pushbroom_scene(ifov_deg):
    data = _scene()
    # 150 urad detectors, 4 samples each; the record is 8 lines of 8 detectors
    data["sensors"] = {"mwir": {"example": "mwir_cooled", "detector": {"shape": [8, 8]}}}
    data["bands"] = [{"name": "mwir", "min": "3.7 um", "max": "4.8 um"}]
    data["observers"] = [{"name": "push", "type": "pushbroom", "sensor": "mwir", "frames": 2,
                          "shape": [32, 32], "ifov": ifov_deg,
                          "platform": {"position": [0, 0, 1000], "velocity": [0, 40, 0]}}]
    return data


def test_a_pushbroom_records_through_its_sensor():
    scene = radscene.load_scene(_pushbroom_scene(float(np.degrees(150e-6 / 4))))
    images, signal = radscene.simulate(scene)
    assert images.attrs["observer_type"] == "pushbroom"
    assert signal["dn"].shape == (2, 1, 8, 8)
    # the hot truck under the track reads more than the grass at the swath's edge
    dn = signal["dn"].isel(frame=0, band=0).values
    assert dn[3:5, 3:5].mean() > dn[:, 0].mean()


def test_a_pushbroom_sampling_that_disagrees_with_the_sensor_is_refused():
    with pytest.raises(ConfigError, match=r"observers\[0\]\.ifov: the scanner's sample is .* "
                                          r"sensor 'mwir_cooled' needs 4 samples per"):
        radscene.load_scene(_pushbroom_scene(0.01))
