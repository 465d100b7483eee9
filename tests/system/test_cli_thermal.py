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


def test_thermal_maps_at_chosen_times_and_the_spin_up_report(scene_file, tmp_path):
    """--map-time (repeatable, any UTC offset) draws the maps at the solved steps nearest to
    the times given instead of the four automatic ones; the last line reports the spin-up."""
    out = tmp_path / "out" / "yard_thermal.nc"
    result = runner.invoke(app, ["thermal", str(scene_file), "-o", str(out),
                                 "--map-time", "2026-06-21T06:00:00Z",
                                 "--map-time", "2026-06-21T14:00:00+02:00",  # the end, 12:00 UTC
                                 "--map-time", "2026-06-20T18:10:00Z"])  # nearest step 18:00
    assert result.exit_code == 0, result.output
    maps = sorted(p.name for p in (tmp_path / "out" / "yard_thermal_maps").glob("*.png"))
    assert maps == ["thermal_map_2026-06-20T1800.png", "thermal_map_2026-06-21T0600.png",
                    "thermal_map_2026-06-21T1200.png"]
    ds = xr.open_dataset(out, engine="h5netcdf")
    days, change = int(ds.attrs["spin_up_days"]), float(ds.attrs["spin_up_change_K"])
    assert days >= 1 and 0.0 <= change <= 0.05  # thermal.spin_up_tolerance
    last = result.output.strip().splitlines()[-1]
    assert last == f"spin-up: {days} day{'' if days == 1 else 's'}, last day-to-day change {change:.2g} K"
    # a run shorter than a day spins up on the day from its start, and says so
    short = runner.invoke(app, ["thermal", str(scene_file), "-o", str(tmp_path / "short.nc"),
                                "--start", "2026-06-21T06:00:00Z", "--no-plots"])
    assert short.exit_code == 0, short.output
    assert short.output.strip().splitlines()[-1].startswith("spin-up: ")
    assert "day-to-day change" in short.output.strip().splitlines()[-1]
    # a start from given temperatures says so
    started = _write(tmp_path, {"initial_temperature": "20 degC"})
    given = runner.invoke(app, ["thermal", str(started), "-o", str(tmp_path / "given.nc"),
                                "--start", "2026-06-21T06:00:00Z", "--no-plots"])
    assert given.exit_code == 0, given.output
    assert given.output.strip().splitlines()[-1] == "spin-up: none (started from thermal.initial_temperature)"


@pytest.mark.parametrize("args, message", [
    (["--map-time", "2026-06-21T12:30:00Z"], "lies outside the heat balance's span"),
    (["--map-time", "2026-06-20T13:00:00+02:00"], "lies outside the heat balance's span"),
    (["--start", "2026-06-21T06:00:00Z", "--map-time", "2026-06-21T05:00:00Z"],
     "2026-06-21T06:00:00+00:00 – 2026-06-21T12:00:00+00:00"),
    (["--map-time", "2026-06-21T10:00"], "UTC offset"),
    (["--map-time", "noon"], "not an ISO 8601 time"),
    (["--map-time", "2026-06-21T10:00:00Z", "--no-plots"], "no maps are drawn with --no-plots"),
])
def test_thermal_map_time_refused_before_the_balance_runs(scene_file, tmp_path, monkeypatch, args, message,
                                                          one_line_refusal):
    """A --map-time outside the span (a day up to the scene's 12:00 UTC, or --start to it), or
    unreadable, or with --no-plots: one line naming --map-time, exit code 2, no heat balance
    and no file."""
    import radscene.pipeline

    def no_balance(*args, **kwargs):
        raise AssertionError("the heat balance ran")

    monkeypatch.setattr(radscene.pipeline, "solve_thermal", no_balance)
    out = tmp_path / "out" / "bad.nc"
    result = runner.invoke(app, ["thermal", str(scene_file), "-o", str(out), *args])
    assert result.exit_code == 2, result.output
    one_line_refusal(result.output, "--map-time", message)
    assert not (tmp_path / "out").exists() or not any((tmp_path / "out").iterdir())


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
