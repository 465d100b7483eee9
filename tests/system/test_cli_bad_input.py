"""Bad input on the command line: one clear line naming the key, exit code 2, nothing written."""

from __future__ import annotations

import subprocess
import sys
import textwrap
from pathlib import Path

import pytest
from typer.testing import CliRunner

from radscene.cli import app

GOOD = textwrap.dedent("""
    name: tiny
    environment:
      sun: {zenith: 30 deg, azimuth: 180 deg}
      atmosphere: {type: none}
    materials:
      paint: {reflectance: 0.4}
    objects:
      - {name: plate, shape: {type: plate, width: 50 m, length: 50 m}, material: paint,
         temperature: 300 K}
    bands:
      - {name: vis, min: 0.5 um, max: 0.6 um}
      - {name: lwir, min: 8 um, max: 12 um}
    observers:
      - {name: nadir, type: orthographic, center: [0, 0], gsd: 1 m, shape: [4, 4]}
""")

VOLUME = ("volumes:\n  - {name: smoke, shape: {type: box, size: [4 m, 4 m, 2 m]}, "
          "position: [0, 0, 5 m], density: 1, optical_depth: 0.5, temperature: 350 K}\n")

runner = CliRunner()


def _run(tmp_path: Path, text: str | None, *extra):
    scene = tmp_path / "scene.yaml"
    if text is not None:
        scene.write_text(text)
    out = tmp_path / "out"
    result = runner.invoke(app, ["render", str(scene), "-o", str(out), *extra])
    return result, out


def test_good_scene_renders_and_writes(tmp_path):
    result, out = _run(tmp_path, GOOD)
    assert result.exit_code == 0, result.output
    assert (out / "nadir.nc").is_file()
    assert (out / "nadir" / "vis.png").is_file()
    assert (out / "nadir_terms.png").is_file()


BAD = {
    "missing mesh file": (
        GOOD.replace("shape: {type: plate, width: 50 m, length: 50 m}",
                     "shape: {type: mesh, file: nowhere.obj}"),
        "objects[0].shape.file"),
    "reflectance above one": (GOOD.replace("reflectance: 0.4", "reflectance: 1.4"),
                              "materials.paint"),
    "negative temperature": (GOOD.replace("temperature: 300 K", "temperature: -5 K"),
                             "objects[0].temperature"),
    "unknown material": (GOOD.replace("material: paint", "material: asfalt"),
                         "objects[0].material"),
    "unknown band": (GOOD.replace("shape: [4, 4]}", "shape: [4, 4], bands: [swir]}"),
                     "observers[0].bands[0]"),
    "unknown unit": (GOOD.replace("gsd: 1 m", "gsd: 1 furlong"), "observers[0].gsd"),
    "malformed yaml": ("name: [unclosed\nbands: {", "malformed YAML"),
    "empty yaml": ("", "empty"),
    "a list": ("- a\n- b\n", "mapping"),
    "unknown atmosphere": (GOOD.replace("type: none", "type: modtran9"),
                           "environment.atmosphere.type"),
    "database AOT beyond its nodes": (
        GOOD.replace("type: none", "type: database, aerosol: maritime, aot550: 3"),
        "atmosphere.aot550: AOT550 3 is outside the maritime aerosol's range in default.nc: "
        "AOT550 0-1"),
    "database aerosol it does not hold": (
        GOOD.replace("type: none", "type: database, aerosol: volcanic"),
        "it holds: desert, maritime, none, rural, urban"),
    "database water column beyond its range": (
        GOOD.replace("type: none", "type: database, profile: tropical, water: 20"),
        "atmosphere.water: 20 g cm-2 is outside 0-12.4 g cm-2"),
    "database water column beyond its thermal tables": (
        GOOD.replace("type: none", "type: database, profile: tropical, water: 0.02"),
        "atmosphere.water: 0.02 g cm-2 is outside the thermal tables' 0.0411-12.3 g cm-2"),
    "volume with a negative density": (
        GOOD.replace("bands:", VOLUME.replace("density: 1", "density: -0.5") + "bands:", 1),
        "volumes[0].density"),
    "volume without a temperature": (
        GOOD.replace("bands:", VOLUME.replace(", temperature: 350 K", "") + "bands:", 1),
        "volumes[0].temperature: required key is missing"),
    "volume with a negative extinction": (
        GOOD.replace("bands:", VOLUME.replace(
            "optical_depth: 0.5", "extinction: {wavelength: [0.4, 14], values: [0.1, -0.2]}")
            + "bands:", 1), "volumes[0].extinction: must be finite and >= 0"),
    "volume with extinction and optical depth": (
        GOOD.replace("bands:", VOLUME.replace("optical_depth: 0.5",
                                              "optical_depth: 0.5, extinction: 0.1")
                     + "bands:", 1), "volumes[0]: give exactly one of"),
    "gaussian volume without sigma": (
        GOOD.replace("bands:", VOLUME.replace("density: 1", "density: 1, profile: {type: "
                                              "gaussian}") + "bands:", 1),
        "volumes[0].profile: a gaussian profile needs 'sigma'"),
    "transmittance above one": (GOOD.replace("reflectance: 0.4",
                                             "reflectance: 0.4, transmittance: 1.2"),
                                "materials.paint"),
    "reflectance plus transmittance above one": (
        GOOD.replace("reflectance: 0.4", "reflectance: 0.4, transmittance: 0.7"),
        "reflectance + transmittance = 1.1"),
    "ragged inline elevation": (
        GOOD.replace("objects:", "terrain: {type: dem, elevation: [[1, 2], [3]], spacing: [1 m, 1 m], "
                     "material: paint}\nobjects:"),
        "terrain.elevation: rows must all have the same length: row 0 has 2 samples, row 1 has 1"),
    "naive time": (GOOD.replace("sun: {zenith: 30 deg, azimuth: 180 deg}",
                                "time: '2026-01-01T12:00:00'"), "environment.time"),
}


@pytest.mark.parametrize("case", sorted(BAD))
def test_bad_input_is_one_line_exit_2_and_writes_nothing(tmp_path, case):
    text, expected = BAD[case]
    result, out = _run(tmp_path, text)
    assert result.exit_code == 2, result.output
    message = result.output.strip()
    assert expected in message
    assert "Traceback" not in message
    assert len(message.splitlines()) == 1, message
    assert not out.exists()


def test_dem_with_nan_holes_is_refused(tmp_path, one_line_refusal):
    import numpy as np

    dem = np.zeros((10, 10))
    dem[3, 4] = np.nan
    np.save(tmp_path / "dem.npy", dem)
    start = GOOD.index("objects:")
    end = GOOD.index("bands:")
    text = (GOOD[:start]
            + "terrain: {type: dem, file: dem.npy, spacing: [10 m, 10 m], material: paint}\n"
            + GOOD[end:])
    result, out = _run(tmp_path, text)
    assert result.exit_code == 2, result.output
    one_line_refusal(result.output, "terrain", "NaN")
    assert not out.exists()


def test_missing_scene_file(tmp_path, one_line_refusal):
    result, out = _run(tmp_path, None)
    assert result.exit_code == 2
    one_line_refusal(result.output, "no such scene file")


def test_check_command_and_version(tmp_path):
    scene = tmp_path / "scene.yaml"
    scene.write_text(GOOD)
    result = runner.invoke(app, ["check", str(scene)])
    assert result.exit_code == 0, result.output
    assert "valid" in result.output and "2 faces" not in result.output
    result = runner.invoke(app, ["--version"])
    assert result.exit_code == 0 and result.output.startswith("radscene ")


def test_examples_lists_and_copies(tmp_path, one_line_refusal):
    result = runner.invoke(app, ["examples"])
    assert result.exit_code == 0 and "demo" in result.output
    result = runner.invoke(app, ["examples", "demo", "--copy", str(tmp_path)])
    assert result.exit_code == 0
    assert (tmp_path / "demo.yaml").is_file()
    result = runner.invoke(app, ["examples", "nosuch"])
    assert result.exit_code == 2 and one_line_refusal(result.output, "unknown example 'nosuch'")


def test_console_script_exit_code_is_2(one_line_refusal):
    """The installed entry point, run as a process, exits 2 on a bad scene."""
    proc = subprocess.run([sys.executable, "-m", "radscene", "check", "/nonexistent.yaml"],
                          capture_output=True, text=True, check=False)
    assert proc.returncode == 2
    one_line_refusal(proc.stderr, "no such scene file")


def test_map_products_carry_geolocation_and_a_geotiff(tmp_path):
    result, out = _run(tmp_path, GOOD.replace("sun: {zenith: 30 deg, azimuth: 180 deg}",
                                              "sun: {zenith: 30 deg, azimuth: 180 deg}\n"
                                              "  location: {latitude: 10.0, longitude: 20.0}"))
    assert result.exit_code == 0, result.output
    import rioxarray  # noqa: F401
    import xarray as xr

    from radscene.io import read_netcdf

    ds = read_netcdf(out / "nadir.nc")
    assert float(ds["latitude"].mean()) == pytest.approx(10.0, abs=1e-4)
    assert float(ds["longitude"].mean()) == pytest.approx(20.0, abs=1e-4)
    assert float(ds["view_zenith"].max()) == pytest.approx(0.0, abs=1e-6)
    tif = xr.open_dataarray(out / "nadir_radiance.tif", engine="rasterio")
    assert tif.shape == (2, 4, 4)
    assert float(tif.isel(band=0).mean()) == pytest.approx(float(ds["radiance"].isel(band=0).mean()),
                                                           rel=1e-5)


def test_a_camera_below_the_terrain_is_refused(tmp_path, one_line_refusal):
    import yaml
    from typer.testing import CliRunner

    from radscene.cli import app

    scene = {
        "environment": {"location": {"latitude": 0.0, "longitude": 0.0}, "time": "2026-06-21T12:00:00Z"},
        "terrain": {"type": "dem", "elevation": [[50.0, 50.0], [50.0, 50.0]], "spacing": [10.0, 10.0],
                    "temperature": "300 K"},
        "bands": [{"name": "red", "min": "0.63 um", "max": "0.69 um"}],
        "observers": [{"name": "cam", "type": "perspective", "position": [5.0, 5.0, 20.0],
                       "look_at": [5.0, 6.0, 0.0], "shape": [4, 4]}],
    }
    path = tmp_path / "below.yaml"
    path.write_text(yaml.safe_dump(scene))
    result = CliRunner().invoke(app, ["check", str(path)])
    assert result.exit_code == 2
    one_line_refusal(result.output, "observers[0].position", "30 m below the terrain")


def test_help_shows_units_in_brackets():
    from typer.testing import CliRunner

    from radscene.cli import app

    result = CliRunner().invoke(app, ["atmosphere", "los", "--help"])
    assert result.exit_code == 0
    assert "Sun zenith [deg]" in result.output and "[g cm-2]" in result.output


def test_volume_grid_of_wrong_dimensions_is_refused(tmp_path):
    import numpy as np

    np.save(tmp_path / "smoke.npy", np.ones((8, 8)))
    volume = VOLUME.replace("density: 1", "density: 1, profile: {type: grid, file: smoke.npy}")
    result, out = _run(tmp_path, GOOD.replace("bands:", volume + "bands:", 1))
    assert result.exit_code == 2, result.output
    message = result.output.strip()
    assert "volumes[0].profile.file" in message and "(8, 8)" in message
    assert len(message.splitlines()) == 1 and "Traceback" not in message, message
    assert not out.exists()


def test_scene_with_a_volume_and_a_sheet_renders_and_writes_its_layers(tmp_path):
    import xarray as xr

    text = GOOD.replace("bands:", VOLUME + "bands:", 1).replace(
        "reflectance: 0.4}", "reflectance: 0.4}\n  net: {reflectance: 0.2, transmittance: 0.5}"
    ).replace("temperature: 300 K}", "temperature: 300 K}\n  - {name: net, shape: {type: plate, "
              "width: 2 m, length: 2 m}, position: [1, 1, 1 m], material: net, temperature: "
              "310 K, transmissive: true}")
    result, out = _run(tmp_path, text)
    assert result.exit_code == 0, result.output
    with xr.open_dataset(out / "nadir.nc", engine="h5netcdf") as ds:
        for name in ("transmitted", "volume_emission", "volume_scattered",
                     "volume_transmittance"):
            assert name in ds
        assert float(ds["volume_transmittance"].min()) < 1.0
        assert float(ds["transmitted"].sel(band="lwir").max()) > 0.0


def test_brackets_in_a_message_are_printed_not_taken_for_markup(tmp_path, one_line_refusal):
    """Units in brackets ("[m, m]", "name [unit]") reach the user; Rich markup would drop them."""
    import numpy as np

    np.save(tmp_path / "dem.npy", np.zeros((4, 4)))
    start, end = GOOD.index("objects:"), GOOD.index("bands:")
    text = GOOD[:start] + "terrain: {type: dem, file: dem.npy, material: paint}\n" + GOOD[end:]
    result, out = _run(tmp_path, text)
    assert result.exit_code == 2, result.output
    one_line_refusal(result.output, "a .npy DEM needs 'spacing' [m, m]")


@pytest.mark.parametrize("name, message", [
    ("temps.png", "a temperature map holds kelvin: give a .npy array or a GeoTIFF (.tif, .tiff) "
                  "of temperatures; 'temps.png' is neither (a PNG or JPEG holds 8- or 16-bit "
                  "levels, not temperatures)"),
    ("temps.jpg", "a temperature map holds kelvin: give a .npy array or a GeoTIFF"),
    ("temps.npy", "every value is at most 1 K (the largest 0.784314): these are image levels "
                  "scaled to 0-1, not temperatures"),
])
def test_a_temperature_map_of_image_levels_is_refused(tmp_path, one_line_refusal, name, message):
    """`radscene check` and `radscene render`: exit code 2, one line naming
    terrain.temperature_map, nothing written; the same map as kelvin renders."""
    import numpy as np
    from PIL import Image

    levels = np.full((8, 8), 200, np.uint8)
    if name.endswith(".npy"):
        np.save(tmp_path / name, levels / 255.0)  # an 8-bit image as it is read into 0-1
    else:
        Image.fromarray(levels).save(tmp_path / name)
    text = GOOD.replace("bands:", "terrain: {type: flat, size: [20 m, 20 m], spacing: 1 m, "
                        f"material: paint, temperature_map: {name}}}\nbands:", 1)
    (tmp_path / "scene.yaml").write_text(text)
    result = runner.invoke(app, ["check", str(tmp_path / "scene.yaml")])
    assert result.exit_code == 2, result.output
    one_line_refusal(result.output, f"error: terrain.temperature_map: {message}")
    result, out = _run(tmp_path, text)
    assert result.exit_code == 2, result.output
    one_line_refusal(result.output, f"error: terrain.temperature_map: {message}")
    assert not out.exists()
    np.save(tmp_path / "kelvin.npy", np.full((8, 8), 300.0))
    result, out = _run(tmp_path, text.replace(f"temperature_map: {name}",
                                              "temperature_map: kelvin.npy"))
    assert result.exit_code == 0, result.output
    assert (out / "nadir.nc").is_file()


SUGGESTED = {
    "material name": (["check"], GOOD.replace("material: paint", "material: paintt"),
                      "objects[0].material: unknown material 'paintt'", "known: ", "paint"),
    "library material name": (["check"], GOOD.replace("material: paint", "material: asfalt"),
                              "objects[0].material: unknown material 'asfalt'", "known: ",
                              "asphalt"),
    "atmosphere engine": (["check"], GOOD.replace("type: none", "type: databse"),
                          "environment.atmosphere.type: unknown atmosphere engine 'databse'",
                          "known: none, uniform", "database"),
    "observer type": (["check"], GOOD.replace("type: orthographic", "type: orthographc"),
                      "observers[0].type: unknown type 'orthographc'",
                      "known: orthographic, perspective", "orthographic"),
    "observer on the command line": (["render", "--observer", "nadri"], GOOD,
                                     "--observer: unknown observer 'nadri'", "known: nadir",
                                     "nadir"),
}


@pytest.mark.parametrize("case", SUGGESTED, ids=list(SUGGESTED))
def test_a_misspelt_name_gets_a_suggestion(tmp_path, case, one_line_refusal):
    """An unknown name is refused in one line naming its key, listing the known names and
    suggesting the closest one."""
    command, text, start, known, closest = SUGGESTED[case]
    scene = tmp_path / "scene.yaml"
    scene.write_text(text)
    extra = ["-o", str(tmp_path / "out")] if command[0] == "render" else []
    result = runner.invoke(app, [command[0], str(scene), *command[1:], *extra])
    assert result.exit_code == 2, result.output
    line = one_line_refusal(result.output, start, known)
    assert line.endswith(f"; did you mean {closest!r}?"), line
    assert not (tmp_path / "out").exists()


def test_a_misspelt_example_gets_a_suggestion(one_line_refusal):
    result = runner.invoke(app, ["examples", "dem"])
    assert result.exit_code == 2
    line = one_line_refusal(result.output, "name: unknown example 'dem'", "known: convoy_motion")
    assert line.endswith("; did you mean 'demo'?"), line
    result = runner.invoke(app, ["examples", "zzzzzz"])  # nothing close: no suggestion
    assert result.exit_code == 2 and "did you mean" not in result.output
