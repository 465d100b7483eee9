"""The heat balance's state through ``radscene.solve_thermal``: the layers' temperatures and the
nodes' profiles in the output, the sign of every term, the spin-up of runs shorter than a day
or whose steps miss the next day's instant, and a start from given temperatures."""

import copy

import numpy as np
import pytest

import radscene
from radscene.errors import ConfigError
from radscene.scene import load_scene

_SCENE = {
    "name": "yard",
    "environment": {"location": {"latitude": 35.0, "longitude": 0.0}, "time": "2026-06-21T12:00:00Z"},
    "terrain": {"type": "dem", "elevation": np.zeros((5, 5)).tolist(), "spacing": [4.0, 4.0],
                "origin": [-8.0, -8.0], "material": "asphalt"},
    "objects": [{"name": "van", "shape": {"type": "box", "size": [2.0, 4.0, 2.0]}, "position": [0.0, 0.0, 0.3],
                 "material": "painted_metal"}],
    "bands": [{"name": "lwir", "min": "8 um", "max": "12 um"}],
    "observers": [{"name": "map", "type": "orthographic", "center": [0.0, 0.0], "gsd": 1.0, "shape": [8, 8]}],
    "thermal": {"step": "30 min", "hemisphere_samples": 8},
}


def _solve(**thermal):
    scene = copy.deepcopy(_SCENE)
    scene["thermal"].update(thermal)
    return radscene.solve_thermal(load_scene(scene, base_dir="."))


@pytest.fixture(scope="module")
def day():
    return _solve(profiles=True)


def test_every_term_sums_to_zero_into_the_surface(day):
    """Seed 001 eq. 5: Q_a + Q_sky + Q_env + Q_t + Q_k + Q_v + Q_i + Q_d = 0, every term into the
    surface positive; q_d is the heat the stack gives back to the surface."""
    names = [v for v in day.data_vars if v.startswith("q_")]
    assert "q_d" in names
    total = sum(day[v].isel(time=slice(1, None)).values.astype(float) for v in names)
    scale = max(float(np.abs(day[v].isel(time=slice(1, None))).max()) for v in names)
    assert np.max(np.abs(total)) < 1e-4 * scale
    # the asphalt stores heat by day: its stack draws from the surface (q_d < 0) around noon
    noon = day.time.values[-1]
    asphalt = (day.object == "terrain").values
    assert float(day.q_d.sel(time=noon).values[asphalt].mean()) < -50.0


def test_layers_are_written_at_their_middles(day):
    """layer_temperature(time, element, layer) at the middle of each layer of given thickness;
    NaN where a stack has fewer layers; read from the node profile linearly in depth."""
    ds = day
    assert ds.layer_temperature.dims == ("time", "element", "layer")
    assert ds.layer_temperature.attrs["units"] == "K"
    van = np.flatnonzero(ds.object.values == "van")
    ground = np.flatnonzero(ds.object.values == "terrain")
    depth, names = ds.layer_depth.values, ds.layer_name.values
    n_van = int(np.sum(np.isfinite(depth[van[0]])))
    assert n_van >= 2  # paint and steel at least
    assert np.all(np.diff(depth[van[0], :n_van]) > 0)
    assert all(names[van[0], j] for j in range(n_van))
    # each layer's temperature is the node profile's at its depth
    z, profile = ds.node_depth.values, ds.node_temperature.values
    for e in (van[0], ground[0]):
        for j in np.flatnonzero(np.isfinite(depth[e])):
            want = np.array([np.interp(depth[e, j], z[e], p[e]) for p in profile])
            np.testing.assert_allclose(ds.layer_temperature.values[:, e, j], want, atol=2e-3)
    # fewer layers: NaN
    short = [e for e in (van[0], ground[0]) if not np.all(np.isfinite(depth[e]))]
    for e in short:
        assert np.all(np.isnan(ds.layer_temperature.values[:, e, ~np.isfinite(depth[e])]))
    # the node at the surface is the surface temperature
    np.testing.assert_allclose(profile[:, :, 0], ds.surface_temperature.values, atol=1e-3)


def test_a_run_shorter_than_a_day_is_spun_up_on_its_own_day(day):
    """Two hours before noon, spun up on the day that begins at their start, give what the whole
    spun-up day gives at the same instants."""
    short = _solve(start="2026-06-21T10:00:00Z")
    assert short.attrs["spin_up_days"] >= 2
    assert short.attrs["spin_up_change_K"] < 0.05
    same = day.sel(time=short.time.values)
    assert float(np.max(np.abs(short.surface_temperature - same.surface_temperature))) < 0.3


def test_a_step_that_misses_the_next_day_still_spins_up():
    ds = _solve(start="2026-06-20T00:00:00Z", step="7 min", spin_up_tolerance="0.2 K")
    assert ds.attrs["spin_up_days"] >= 2


def test_a_start_from_given_temperatures():
    ds = _solve(start="2026-06-21T10:00:00Z", initial_temperature={"asphalt": "30 degC"})
    assert ds.attrs["spin_up_days"] == 0
    first = ds.isel(time=0)
    asphalt = first.object.values == "terrain"
    np.testing.assert_allclose(first.surface_temperature.values[asphalt], 303.15, atol=1e-3)
    np.testing.assert_allclose(first.layer_temperature.values[asphalt, 0], 303.15, atol=1e-3)
    van = first.surface_temperature.values[~asphalt]
    assert np.all(np.abs(van - 303.15) > 1.0)  # the others from the mean air temperature


@pytest.mark.parametrize("thermal, key, message", [
    ({"initial_temperature": "300 K", "spin_up": True}, "thermal", "exclude each other"),
    ({"initial_temperature": {"granite": "300 K"}}, "thermal.initial_temperature.granite", "no solved surface"),
])
def test_bad_start_states_are_refused(thermal, key, message):
    with pytest.raises(ConfigError) as err:
        _solve(start="2026-06-21T10:00:00Z", **thermal)
    assert err.value.key.startswith(key) and message in str(err.value)


def _hourly_file(tmp_path, skip=()):
    rows = ["# latitude: 35.0", "# longitude: 0.0",
            "time [UTC],air_temperature [degC],relative_humidity [%],wind_speed [m/s],cloud_cover [%],pressure [hPa]"]
    for hour in range(48):  # hourly from 2026-06-20T00:00
        if hour in skip:
            continue
        d, hh = divmod(hour, 24)
        rows.append(f"2026-06-{20 + d}T{hh:02d}:00,{15 + 8 * np.sin((hh - 9) * np.pi / 12):.2f},50,2,0,1013")
    path = tmp_path / "site.csv"
    path.write_text("\n".join(rows) + "\n")
    return str(path)


@pytest.mark.parametrize("extra", [{"t_max": "30 degC"}, {"wind_speed": 5.0}, {"cloud_cover": 0.5},
                                   {"start": "2026-06-20T00:00:00Z"}])
def test_a_weather_files_own_figures_cannot_be_given_beside_it(tmp_path, extra):
    """A figure the file gives, or a .wth file's date, beside a CSV file would be ignored: refused."""
    scene = copy.deepcopy(_SCENE)
    scene["thermal"]["weather"] = {"file": _hourly_file(tmp_path), **extra}
    with pytest.raises(ConfigError) as err:
        load_scene(scene, base_dir=".")
    assert "thermal.weather" in err.value.key and "ignored" in str(err.value)


def test_a_weather_gap_is_bridged_up_to_max_gap(tmp_path):
    path = _hourly_file(tmp_path, skip=(14, 15, 16))  # a 4 h gap, beyond 3 x the hourly step
    with pytest.raises(ConfigError, match="gap of 4"):
        _solve(start="2026-06-20T12:00:00Z", end="2026-06-20T18:00:00Z", spin_up=False,
               weather={"file": path})
    ds = _solve(start="2026-06-20T12:00:00Z", end="2026-06-20T18:00:00Z", spin_up=False,
                weather={"file": path, "max_gap": "4 h"})
    assert ds.sizes["time"] == 13


def test_a_key_under_an_object_named_like_a_shape_is_named_in_full():
    """An object called 'box': the refusal names thermal.objects.box.layers, and does not
    suggest the refused key itself."""
    scene = copy.deepcopy(_SCENE)
    scene["objects"][0]["name"] = "box"
    scene["thermal"]["objects"] = {"box": {"wetness": 0.5}}
    with pytest.raises(ConfigError) as err:
        load_scene(scene, base_dir=".")
    assert err.value.key == "thermal.objects.box.wetness"
    scene["objects"][0]["shape"]["sise"] = [1.0, 1.0, 1.0]
    with pytest.raises(ConfigError) as err:
        load_scene(scene, base_dir=".")
    assert err.value.key == "objects[0].shape.sise"  # the shape's tag is still left out


def _two_vans(**thermal):
    scene = copy.deepcopy(_SCENE)
    scene["objects"].append({"name": "twin", "shape": {"type": "box", "size": [2.0, 4.0, 2.0]},
                             "position": [6.0, 0.0, 0.3], "material": "painted_metal"})
    scene["thermal"].update({"start": "2026-06-21T06:00:00Z", "spin_up": False, **thermal})
    return radscene.solve_thermal(load_scene(scene, base_dir="."))


def _roof(ds, name, time=-1):
    sel = (ds.object.values == name) & (ds.normal_z.values > 0.9)
    return float(ds.surface_temperature.isel(time=time).values[sel].mean())


def test_an_object_keeps_its_own_stack_optics_and_wetness():
    """Two vans of one paint: the one with a white coat of its own (absorptance 0.2), or a thick
    insulating skin, or wet, ends the morning at another temperature than its twin."""
    base = _two_vans()
    assert abs(_roof(base, "van") - _roof(base, "twin")) < 1.0
    white = _two_vans(objects={"van": {"solar_absorptance": 0.2}})
    assert _roof(white, "van") < _roof(white, "twin") - 5.0
    assert float(white.absorptance.values[white.object.values == "van"].max()) == pytest.approx(0.2)
    skin = [{"thickness": 0.05, "conductivity": 1.0, "density": 2000.0, "specific_heat": 900.0}]
    thick = _two_vans(objects={"van": {"layers": skin, "bottom": "insulated"}})
    van = thick.object.values == "van"
    assert set(thick.layer_name.values[van, 0]) != set(thick.layer_name.values[~van & (thick.object.values == "twin"), 0])
    np.testing.assert_allclose(thick.layer_depth.values[van, 0], 0.025)
    assert abs(_roof(thick, "van") - _roof(thick, "twin")) > 2.0
    wet = _two_vans(objects={"van": {"moisture_availability": 1.0}})
    assert float(wet.q_v.isel(time=-1).values[wet.object.values == "van"].mean()) < -50.0
    assert float(np.abs(wet.q_v.isel(time=-1).values[wet.object.values == "twin"]).max()) == 0.0


def test_internal_sources_on_a_group_of_faces():
    """5 kW on the van's top faces only: the roof warms, the sides do not take it."""
    ds = _two_vans(objects={"van": {"internal_power": "5 kW", "internal_faces": "top"}})
    van = ds.object.values == "van"
    top, sides = van & (ds.normal_z.values > 0.5), van & (np.abs(ds.normal_z.values) <= 0.5)
    q_i = ds.q_i.isel(time=-1).values
    np.testing.assert_allclose((q_i[top] * ds.area.values[top]).sum(), 5000.0, rtol=1e-6)
    assert np.all(q_i[sides] == 0.0)
    assert _roof(ds, "van") > _roof(ds, "twin") + 5.0


def test_a_material_temperature_fixes_its_surfaces():
    scene = copy.deepcopy(_SCENE)
    scene["objects"][0]["temperature"] = "350 K"  # the van's own stays
    scene["thermal"].update({"start": "2026-06-21T06:00:00Z", "spin_up": False,
                             "materials": {"painted_metal": {"temperature": "300 K"}}})
    scene["objects"].append({"name": "twin", "shape": {"type": "box", "size": [2.0, 4.0, 2.0]},
                             "position": [6.0, 0.0, 0.3], "material": "painted_metal"})
    loaded = load_scene(scene, base_dir=".")
    twin = next(o for o in loaded.objects if o.name == "twin")
    van = next(o for o in loaded.objects if o.name == "van")
    assert np.all(twin.face_fixed) and np.all(twin.face_temperature == 300.0)
    assert np.all(van.face_temperature == 350.0)
    ds = radscene.solve_thermal(loaded)
    assert set(np.unique(ds.object.values)) == {"terrain"}


def test_an_object_on_a_trajectory_is_heated_by_its_own_speed():
    """A drone flying at 200 m/s from the scene's instant on (and parked before): the heat
    balance takes its speed from the trajectory, with the recovery temperature's ram heating,
    and none while it stands."""
    scene = copy.deepcopy(_SCENE)
    scene["objects"].append({"name": "drone", "shape": {"type": "box", "size": [1.0, 1.0, 0.3]},
                             "position": [0.0, 0.0, 50.0], "material": "painted_metal",
                             "trajectory": {"waypoints": [[0, 0, 0, 50], [600, 120000, 0, 50]]}})
    scene["thermal"].update({"start": "2026-06-21T11:00:00Z", "end": "2026-06-21T12:10:00Z", "step": "5 min",
                             "spin_up": False})
    ds = radscene.solve_thermal(load_scene(scene, base_dir="."))
    drone = ds.object.values == "drone"
    before = ds.q_i.sel(time=np.datetime64("2026-06-21T11:55")).values[drone]
    flying = ds.q_i.sel(time=np.datetime64("2026-06-21T12:05")).values[drone]
    assert np.all(before == 0.0)
    # h (T_r - T_air) with T_r - T_air = r u^2 / (2 c_p), r = Pr^(1/3): about 18 K at 200 m/s
    assert np.all(flying > 18.0 * 50.0)
    van = ds.object.values == "van"
    assert np.all(ds.q_i.values[:, van][1:] == 0.0)


def _field(**thermal):
    scene = {
        "name": "field",
        "environment": {"location": {"latitude": 45.0, "longitude": 0.0}, "time": "2026-06-21T12:00:00Z",
                        "atmosphere": {"type": "database", "profile": "midlatitude_summer", "aerosol": "rural",
                                       "visibility": "23 km"}},
        "terrain": {"type": "dem", "elevation": np.zeros((3, 3)).tolist(), "spacing": [4.0, 4.0],
                    "origin": [-4.0, -4.0], "material": "green_vegetation"},
        "bands": [{"name": "lwir", "min": "8 um", "max": "12 um"}],
        "observers": [{"name": "map", "type": "orthographic", "center": [0.0, 0.0], "gsd": 1.0, "shape": [4, 4]}],
        "thermal": {"step": "30 min", "hemisphere_samples": 8, "spin_up": False, **thermal},
    }
    ds = radscene.solve_thermal(load_scene(scene, base_dir="."))
    e = 0
    light = (ds.direct_irradiance.values * np.cos(np.radians(ds.sun_zenith.values)).clip(0) * ds.sunlit.values[:, e]
             + ds.diffuse_irradiance.values * ds.sky_view_shortwave.values[e])
    day = (light > 50.0) & (np.arange(light.size) > 0)  # row 0: the start, no step yet
    return ds, ds.q_a.values[day, e] / light[day], ds.sun_zenith.values[day]


def test_the_absorptance_follows_the_spectra_of_the_beam_and_the_sky():
    """Vegetation's absorptance of sunlight changes with the sun's height, as the spectra of the
    beam and the sky at the ground change (from the engine, at each step); a given absorptance
    stays itself."""
    from radscene.atmosphere import make_atmosphere
    from radscene.materials import get_material
    from radscene.materials.thermal import solar_absorptance
    from radscene.thermal.irradiance import shortwave_table

    ds, alpha, zenith = _field()
    assert np.ptp(alpha) > 0.003
    assert alpha[np.argmin(zenith)] > alpha[np.argmax(zenith)]  # the low sun's redder beam
    # at the highest sun, the beam's and the sky's absorptance from the table's node spectra
    atm = make_atmosphere({"type": "database", "profile": "midlatitude_summer", "aerosol": "rural",
                           "visibility": "23 km"})
    table = shortwave_table(atm, 0.0, 172, 1.016)
    leaf = get_material("green_vegetation")
    a_dir = [solar_absorptance(leaf, irradiance=(table.wavelength, s)) for s in table.direct_spectrum[:3]]
    a_dif = [solar_absorptance(leaf, irradiance=(table.wavelength, s)) for s in table.diffuse_spectrum[:3]]
    lo, hi = min(a_dir + a_dif), max(a_dir + a_dif)
    assert lo - 1e-3 <= alpha[np.argmin(zenith)] <= hi + 1e-3
    given, alpha_given, _ = _field(materials={"green_vegetation": {"solar_absorptance": 0.7}})
    np.testing.assert_allclose(alpha_given, 0.7, rtol=1e-6)  # q_a is written in single precision


def test_a_tag_that_is_also_a_key_is_left_out_of_a_refused_key():
    """A material map of type 'file' has a 'file' key too: a bad 'classes' is
    terrain.material_map.classes."""
    scene = copy.deepcopy(_SCENE)
    scene["terrain"]["material_map"] = {"type": "file", "file": "classes.tif", "classes": "asphalt"}
    with pytest.raises(ConfigError) as err:
        load_scene(scene, base_dir=".")
    assert err.value.key == "terrain.material_map.classes"


def test_an_objects_own_layers_stand_for_a_material_without_a_thermal_description():
    scene = copy.deepcopy(_SCENE)
    scene["materials"] = {"mypaint": {"reflectance": 0.3}}
    scene["objects"][0]["material"] = "mypaint"
    scene["thermal"].update({"start": "2026-06-21T10:00:00Z", "spin_up": False})
    with pytest.raises(ConfigError) as err:
        radscene.solve_thermal(load_scene(scene, base_dir="."))
    assert err.value.key == "thermal.materials.mypaint"
    scene["thermal"]["objects"] = {"van": {"layers": [{"thickness": 0.002, "conductivity": 50.0, "density": 7800.0,
                                                       "specific_heat": 450.0}], "bottom": "insulated"}}
    ds = radscene.solve_thermal(load_scene(scene, base_dir="."))
    van = ds.object.values == "van"
    assert van.any() and np.all(np.isfinite(ds.surface_temperature.values[:, van]))
    np.testing.assert_allclose(ds.layer_depth.values[van, 0], 0.001)


def test_the_spin_up_day_must_be_in_the_weather(tmp_path):
    """A 6 h run spun up on its own day needs the weather of that day: a file of the run's
    hours alone is refused, naming thermal.spin_up, before any solve."""
    rows = ["# latitude: 35.0", "# longitude: 0.0",
            "time [UTC],air_temperature [degC],relative_humidity [%],wind_speed [m/s],cloud_cover [%],pressure [hPa]"]
    rows += [f"2026-06-21T{hh:02d}:00,20,50,2,0,1013" for hh in range(6, 13)]
    (tmp_path / "six.csv").write_text("\n".join(rows) + "\n")
    with pytest.raises(ConfigError) as err:
        _solve(start="2026-06-21T06:00:00Z", weather={"file": str(tmp_path / "six.csv")})
    assert err.value.key == "thermal.spin_up" and "does not cover" in str(err.value)
    ds = _solve(start="2026-06-21T06:00:00Z", spin_up=False, weather={"file": str(tmp_path / "six.csv")})
    assert ds.sizes["time"] == 13


def test_a_place_tolerance_beside_a_wth_file_is_refused():
    scene = copy.deepcopy(_SCENE)
    scene["thermal"]["weather"] = {"file": "site.wth", "start": "2026-06-20T00:00:00Z", "place_tolerance": 2.0}
    with pytest.raises(ConfigError, match="place_tolerance would be ignored"):
        load_scene(scene, base_dir=".")


def test_a_resolved_scene_loads_again(tmp_path):
    """The resolved scene (every key with its default, as the outputs record it) loads again,
    the weather's and the start state's keys included."""
    scene = copy.deepcopy(_SCENE)
    scene["thermal"]["initial_temperature"] = "20 degC"
    spec = load_scene(scene, base_dir=".").spec
    again = load_scene(spec.model_dump(mode="json"), base_dir=".").spec
    assert again.thermal == spec.thermal and not again.thermal.spins_up


def test_lateral_conduction_runs_through_a_painted_skin():
    """thermal.lateral across the van's faces goes through its paint and its steel (Σ k t of the
    stack's layers), not the 50 µm of paint alone: the roof feeds the shaded sides."""
    ds = _solve(start="2026-06-21T06:00:00Z", spin_up=False, lateral=True)
    van = ds.object.values == "van"
    q_lat = ds.q_lat.values[1:].astype(float)
    assert np.max(np.abs(q_lat[:, van])) > 0.1  # 0.87 W m-2; 2.5e-4 through the paint alone
    np.testing.assert_allclose((q_lat * ds.area.values).sum(axis=1), 0.0, atol=1e-3)


@pytest.mark.parametrize("thermal, key", [
    ({"objects": {"van": {"bottom": {"interior_air": 295, "h": -1}}}}, "thermal.objects.van.bottom.h"),
    ({"materials": {"asphalt": {"bottom": "granite"}}}, "thermal.materials.asphalt.bottom"),
    ({"convection": "jurges"}, "thermal.convection"),
    ({"start": "2026-06-20T00:00:00Z", "end": "2026-06-21T06:00:00Z"}, "thermal.end"),
    ({"objects": {"truck": {"internal_power": 10}}}, "thermal.objects.truck"),
])
def test_check_and_render_refuse_a_bad_heat_balance_before_writing(tmp_path, thermal, key, one_line_refusal):
    import yaml
    from typer.testing import CliRunner

    from radscene.cli import app

    scene = copy.deepcopy(_SCENE)
    scene["thermal"].update(thermal)
    path = tmp_path / "bad.yaml"
    path.write_text(yaml.safe_dump(scene))
    runner = CliRunner()
    checked = runner.invoke(app, ["check", str(path)])
    assert checked.exit_code == 2
    one_line_refusal(checked.output, key)
    out = tmp_path / "out"
    rendered = runner.invoke(app, ["render", str(path), "-o", str(out)])
    assert rendered.exit_code == 2
    one_line_refusal(rendered.output, key)
    assert not out.exists() or not any(out.iterdir())


def test_map_times_need_a_solved_terrain_and_thicknesses_take_units(tmp_path, one_line_refusal):
    import yaml
    from typer.testing import CliRunner

    from radscene.cli import app

    scene = copy.deepcopy(_SCENE)
    scene["terrain"]["temperature"] = "300 K"
    path = tmp_path / "fixed.yaml"
    path.write_text(yaml.safe_dump(scene))
    out = tmp_path / "t.nc"
    result = CliRunner().invoke(app, ["thermal", str(path), "-o", str(out), "--map-time", "2026-06-21T10:00:00Z"])
    assert result.exit_code == 2
    one_line_refusal(result.output, "--map-time")
    assert not out.exists()
    skin = [{"thickness": "5 cm", "conductivity": 1.0, "density": 2000.0, "specific_heat": 900.0}]
    ds = _solve(start="2026-06-21T10:00:00Z", spin_up=False, materials={"asphalt": {"layers": skin, "bottom": "insulated"}})
    np.testing.assert_allclose(ds.layer_depth.values[ds.object.values == "terrain", 0], 0.025)
