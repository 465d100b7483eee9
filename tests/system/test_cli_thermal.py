"""``radscene thermal``: the heat balance of a scene file to CF NetCDF and PNGs; bad input exits 2
and writes nothing."""

import numpy as np
import pytest
import xarray as xr
import yaml
from typer.testing import CliRunner

from radscene.cli import app

runner = CliRunner()

_SCENE = {
    "name": "yard",
    "environment": {"location": {"latitude": 35.0, "longitude": 0.0}, "time": "2026-06-21T12:00:00Z"},
    "terrain": {"type": "dem", "elevation": np.zeros((11, 11)).tolist(), "spacing": [2.0, 2.0],
                "origin": [-10.0, -10.0], "material": "asphalt"},
    "objects": [{"name": "van", "shape": {"type": "box", "size": [2.0, 4.0, 2.0]}, "position": [0.0, 0.0, 0.3],
                 "material": "painted_metal"}],
    "bands": [{"name": "lwir", "min": "8 um", "max": "12 um"}],
    "observers": [{"name": "map", "type": "orthographic", "center": [0.0, 0.0], "gsd": 1.0, "shape": [16, 16]}],
    "thermal": {"step": "30 min", "hemisphere_samples": 16},
}


@pytest.fixture()
def scene_file(tmp_path):
    path = tmp_path / "yard.yaml"
    path.write_text(yaml.safe_dump(_SCENE))
    return path


def test_thermal_writes_cf_netcdf_and_figures(scene_file, tmp_path):
    out = tmp_path / "out" / "yard_thermal.nc"
    result = runner.invoke(app, ["thermal", str(scene_file), "-o", str(out)])
    assert result.exit_code == 0, result.output
    ds = xr.open_dataset(out, engine="h5netcdf")
    assert ds.surface_temperature.dims == ("time", "element")
    assert ds.surface_temperature.attrs["units"] == "K"
    assert {"q_a", "q_sky", "q_t"} <= set(ds.data_vars)
    assert ds.sizes["time"] == 49  # a day at 30 min, both ends
    assert set(np.unique(ds.object.values)) == {"terrain", "van"}
    assert (tmp_path / "out" / "yard_thermal_diurnal.png").is_file()
    assert len(list((tmp_path / "out" / "yard_thermal_maps").glob("*.png"))) == 4
    # the van's roof in the noon sun is hotter than the air
    roof = (ds.object == "van") & (ds.normal_z > 0.9)
    assert float(ds.surface_temperature.isel(time=-1).where(roof).max()) > float(ds.air_temperature[-1]) + 5.0


@pytest.mark.parametrize("args, message", [
    (["--step", "0 s"], "--step"),
    (["--start", "2026-06-21T13:00:00Z"], "not before the end"),
    (["--step", "2 d"], "longer than the span"),
    (["--start", "2026-06-21T10:00"], "UTC offset"),
])
def test_thermal_bad_input_exits_2_and_writes_nothing(scene_file, tmp_path, args, message, one_line_refusal):
    out = tmp_path / "bad.nc"
    result = runner.invoke(app, ["thermal", str(scene_file), "-o", str(out), *args])
    assert result.exit_code == 2
    one_line_refusal(result.output, message)
    assert not out.exists()


def _write(tmp_path, changes):
    import copy

    scene = copy.deepcopy(_SCENE)
    scene["thermal"].update(changes)
    path = tmp_path / "bad.yaml"
    path.write_text(yaml.safe_dump(scene))
    return path


@pytest.mark.parametrize("changes, message", [
    ({"materials": {"painted_metal": {"layers": [{"thickness": 0.001, "conductivity": 0.0, "density": 7800,
                                                  "specific_heat": 450}]}}}, "conductivity"),
    ({"materials": {"painted_metal": {"layers": [{"thickness": 0.001, "conductivity": 50, "density": -1,
                                                  "specific_heat": 450}]}}}, "density"),
    ({"materials": {"painted_metal": {"layers": [{"thickness": 0.0, "conductivity": 50, "density": 7800,
                                                  "specific_heat": 450}]}}}, "thickness"),
    ({"materials": {"paint": {"solar_absorptance": 0.5}}}, "thermal.materials.paint"),
    ({"objects": {"lorry": {"internal_power": "1 kW"}}}, "thermal.objects.lorry"),
    ({"step": "-5 min"}, "thermal.step"),
])
def test_thermal_bad_scene_exits_2_naming_the_key(tmp_path, changes, message, one_line_refusal):
    out = tmp_path / "bad.nc"
    result = runner.invoke(app, ["thermal", str(_write(tmp_path, changes)), "-o", str(out)])
    assert result.exit_code == 2, result.output
    one_line_refusal(result.output, message)
    assert not out.exists()


def test_thermal_weather_file_with_a_gap_exits_2_naming_the_row(tmp_path, one_line_refusal):
    rows = ["# latitude: 35.0", "# longitude: 0.0",
            "time [UTC],air_temperature [degC],relative_humidity [%],wind_speed [m/s],cloud_cover [%],pressure [hPa]"]
    for hour in range(30):  # hourly from 2026-06-20T00:00, the air temperature missing at 12:00
        day, hh = divmod(hour, 24)
        value = "" if hour == 12 else "20"
        rows.append(f"2026-06-{20 + day}T{hh:02d}:00,{value},50,2,0,1013")
    (tmp_path / "site.csv").write_text("\n".join(rows) + "\n")
    path = _write(tmp_path, {"weather": {"file": "site.csv"}})
    out = tmp_path / "bad.nc"
    result = runner.invoke(app, ["thermal", str(path), "-o", str(out)])
    assert result.exit_code == 2, result.output
    one_line_refusal(result.output, "site.csv", "line 16")
    assert not out.exists()


def _wth_file(tmp_path, sky="0.80"):
    """48 h of 15-minute THERM entries from local midnight (13 fields, sky exposure in field 9)."""
    lines = ["193 0.250000"]
    for k in range(193):
        lines.append(f"{0.25 * k:.2f} 20.00 1013.00  0.50  9.27   2.00     0.00     0.00 {sky}  0  0   0.00  0.00")
    (tmp_path / "site.wth").write_text("\n".join(lines) + "\n")


@pytest.mark.parametrize("weather, sky, message", [
    ({"fields": {7: "direct_normal_shortwave [Ly/h]"}}, "0.80", "direct_normal_shortwave without diffuse_shortwave"),
    ({"fields": {3: "cloud_cover [1]"}}, "0.80", "field 3 is read as pressure"),
    ({"cloud_cover": 0.2}, "0.80", "the file carries its sky exposure (field 9"),
    ({}, "8.00", "line 2: sky exposure 8 (field 9) outside [0, 1]"),
])
def test_thermal_wth_declaration_or_field_wrong_exits_2_naming_it(tmp_path, weather, sky, message, one_line_refusal):
    _wth_file(tmp_path, sky)
    path = _write(tmp_path, {"weather": {"file": "site.wth", "start": "2026-06-20T00:00:00Z", **weather}})
    out = tmp_path / "bad.nc"
    result = runner.invoke(app, ["thermal", str(path), "-o", str(out)])
    assert result.exit_code == 2, result.output
    one_line_refusal(result.output, "site.wth", message)
    assert not out.exists()
