"""``radscene atmosphere los | sky | build | build-lowtran`` and the Python functions behind them."""

from __future__ import annotations

import json

import numpy as np
import pytest
import xarray as xr
from typer.testing import CliRunner

from radscene.atmosphere.api import line_of_sight, sky_radiance
from radscene.cli.atmosphere import app
from radscene.errors import ConfigError

runner = CliRunner()


def test_los_table_json_netcdf_and_plot(tmp_path):
    out, png = tmp_path / "los.nc", tmp_path / "los.png"
    res = runner.invoke(app, ["los", "--observer-altitude", "100km", "--zenith", "30",
                              "--profile", "midlatitude_summer", "--sun-zenith", "40",
                              "--wavelength-min", "0.45", "--wavelength-max", "0.9",
                              "--band", "0.63,0.69", "--band", "760nm,900nm",
                              "--surface-albedo", "0.2", "-o", str(out), "--plot", str(png)])
    assert res.exit_code == 0, res.output
    assert "line of sight (database)" in res.output and "0.63–0.69" in res.output
    ds = xr.open_dataset(out, engine="h5netcdf")
    assert ds["path_radiance"].attrs["units"] == "W m-2 sr-1 um-1"
    assert ds.sizes["band"] == 2
    assert png.stat().st_size > 10_000
    res = runner.invoke(app, ["los", "--zenith", "10", "--wavelength-min", "0.5",
                              "--wavelength-max", "0.6", "--json"])
    assert res.exit_code == 0, res.output
    data = json.loads(res.output)
    assert data["attrs"]["engine"] == "database"
    assert len(data["data"]["transmittance"]["values"]) == len(data["coords"]["wavelength"])


def test_sky_table_and_plot(tmp_path):
    png = tmp_path / "sky.png"
    res = runner.invoke(app, ["sky", "--zenith", "0,30,60,85", "--azimuth", "0,90,180,270",
                              "--sun-zenith", "35", "--sun-azimuth", "90",
                              "--wavelength-min", "0.4", "--wavelength-max", "1.0",
                              "--plot", str(png)])
    assert res.exit_code == 0, res.output
    assert "diffuse irradiance" in res.output
    assert png.stat().st_size > 10_000


def test_los_and_sky_quiet_write_their_files_and_print_nothing(tmp_path):
    """With --quiet the tables are not printed, the -o and --plot files are written; --verbose
    adds the computation and each file with its size and time; --quiet refuses --json (all
    that it prints) and --verbose."""
    span = ["--wavelength-min", "0.5", "--wavelength-max", "0.6"]
    out, png = tmp_path / "los.nc", tmp_path / "sky.png"
    quiet = runner.invoke(app, ["los", *span, "-q", "-o", str(out)])
    assert quiet.exit_code == 0 and quiet.output == "", quiet.output
    assert xr.open_dataset(out, engine="h5netcdf").sizes["band"] == 1
    quiet = runner.invoke(app, ["sky", *span, "--zenith", "0,60", "--azimuth", "0,180",
                                "--quiet", "--plot", str(png)])
    assert quiet.exit_code == 0 and quiet.output == "", quiet.output
    assert png.stat().st_size > 10_000
    loud = runner.invoke(app, ["los", *span, "--verbose", "-o", str(tmp_path / "v.nc")])
    assert loud.exit_code == 0, loud.output
    for words in ("line of sight (database): 21 wavelength(s), 1 band(s) (",
                  f"wrote {tmp_path / 'v.nc'} (", "kB) (", "spectral samples"):
        assert words in loud.output, words
    loud = runner.invoke(app, ["sky", *span, "--zenith", "0,60", "--azimuth", "0,180", "-v"])
    assert loud.exit_code == 0 and "sky (database): 2×2 directions" in loud.output
    for command in ("los", "sky"):
        for flags in (["-q", "--json"], ["-q", "-v"]):
            res = runner.invoke(app, [command, *span, *flags, "-o", str(tmp_path / "x.nc")])
            assert isinstance(res.exception, ConfigError) and res.exception.key == "--quiet"
    assert not (tmp_path / "x.nc").exists()


def test_build_refuses_quiet_with_verbose_before_any_work(tmp_path):
    from radscene.cli import app as main_app

    out = tmp_path / "atm.nc"
    res = runner.invoke(main_app, ["atmosphere", "build", "default", "-o", str(out), "--quiet",
                                   "--verbose"])
    assert res.exit_code == 2 and "error: --quiet: give --quiet or --verbose" in res.output
    assert len(res.output.strip().splitlines()) == 1 and not out.exists()


@pytest.mark.parametrize(("args", "match"), [
    (["los", "--visibility", "0"], "visibility: must be > 0"),
    (["los", "--profile", "venus"], "profile 'venus'"),
    (["los", "--aerosol", "ash"], "aerosol 'ash'"),
    (["los", "--target-altitude", "-2km"], "below the ground"),
    (["los", "--target-altitude", "150km", "--observer-altitude", "200km"], "above the atmos"),
    (["los", "--engine", "sixs", "--wavelength-min", "3", "--wavelength-max", "5"],
     "covers 0.25–4 µm"),
    (["los", "--engine", "modtran"], "unknown engine 'modtran'"),
    (["los", "--single-scattering"], "always includes multiple scattering"),
    (["los", "--band", "0.7"], "'min,max'"),
    (["sky", "--zenith", "0,95"], r"zenith angles in \[0, 90\]"),
    (["los", "--wavelength-min", "0.5"], "give both"),
    (["build", "no-such.yaml", "-o", "x.nc"], "no such file"),
])
def test_bad_input_is_a_config_error(args, match):
    import re

    res = runner.invoke(app, args)
    assert isinstance(res.exception, ConfigError), res.output
    assert re.search(match, str(res.exception)), str(res.exception)


def test_python_functions_return_datasets_over_wavelength():
    wl = [0.5, 0.55, 0.6, 0.8, 0.865, 0.9]
    ds = line_of_sight(100_000.0, 0.0, 30.0, sun_zenith=40.0, wavelength=wl,
                       surface_albedo=0.25, surface_temperature=300.0,
                       bands=[(0.5, 0.6), (0.8, 0.9)])
    assert list(ds["wavelength"].values) == wl
    for name in ("transmittance", "path_radiance", "path_thermal_radiance",
                 "path_scattered_radiance", "sun_transmittance", "direct_solar_irradiance",
                 "apparent_radiance", "diffuse_irradiance"):
        assert ds[name].dims == ("wavelength",), name
    assert np.all(ds["apparent_radiance"].values > ds["path_radiance"].values)
    assert np.all(ds["path_radiance"].values > 0)
    assert ds["band_transmittance"].values.shape == (2,)
    sky = sky_radiance([0.0, 45.0], [0.0, 180.0], sun_zenith=30.0, sun_azimuth=180.0,
                       wavelength=[0.55])
    assert sky["sky_radiance"].dims == ("zenith", "azimuth", "wavelength")
    assert sky["sky_radiance"].sel(zenith=45.0, azimuth=180.0).item() > sky[
        "sky_radiance"].sel(zenith=45.0, azimuth=0.0).item()
    assert sky["downwelling_irradiance"].item() > 0


def test_band_values_integrate_the_spectrum():
    ds = line_of_sight(3000.0, 0.0, 0.0, sun_zenith=20.0, wavelength_range=(0.6, 0.7),
                       step=0.01, bands=[(0.6, 0.7)])
    wl = ds["wavelength"].values
    assert ds["band_path_radiance"].item() == pytest.approx(
        np.trapezoid(ds["path_radiance"].values, wl), rel=1e-12)
    assert ds["band_transmittance"].item() == pytest.approx(
        np.trapezoid(ds["transmittance"].values, wl) / 0.1, rel=1e-12)


def test_build_without_a_terminal_reports_each_stage(tmp_path):
    """Written to a log (no terminal), ``atmosphere build`` prints one line per finished
    stage instead of a live progress bar, then its summary; the file is a database. Built
    again from the cache, with --quiet and --verbose."""
    from radscene.atmosphere.sixs_runner import sixs_available

    ok, reason = sixs_available()
    if not ok:
        pytest.skip(f"6S cannot run here: {reason}")
    config = tmp_path / "tiny.yaml"
    config.write_text(
        "profiles: [us_standard]\naerosols: [{model: rural, visibility: 23 km}]\n"
        "wavelength: {min: 0.5, max: 0.6}\nthermal: {engine: none}\n"
        "grid: {surface_altitude: [0], observer_height: [1000], sun_zenith: [0, 40],\n"
        "       view_zenith: [0, 40], coarse_zenith: [0, 40], ratio_wavelengths: [0.55],\n"
        "       phase_wavelengths: [0.4, 0.86]}\n")
    out = tmp_path / "tiny.nc"
    res = runner.invoke(app, ["build", str(config), "-o", str(out), "--cache",
                              str(tmp_path / "cache")])
    assert res.exit_code == 0, res.output
    for stage in ("spectral grid", "gas", "phase functions", "scattering rural_23km"):
        assert f"{stage}: " in res.output
    assert "runs in" in res.output
    with xr.open_dataset(out) as ds:
        assert float(ds["rho_mixture"].min()) >= 0.0
    # again from the 6S cache, quick: --quiet prints nothing, --verbose each stage's time
    again = ["build", str(config), "--cache", str(tmp_path / "cache"), "-o"]
    quiet = runner.invoke(app, [*again, str(tmp_path / "q.nc"), "--quiet"])
    assert quiet.exit_code == 0 and quiet.output == "", quiet.output
    assert (tmp_path / "q.nc").is_file()
    loud = runner.invoke(app, [*again, str(tmp_path / "v.nc"), "--verbose"])
    assert loud.exit_code == 0, loud.output
    for words in ("configuration ", "phase functions: 60 runs (", f"wrote {tmp_path / 'v.nc'}",
                  "6S runs"):
        assert words in loud.output, words


def test_an_engine_failure_is_one_line_and_exit_code_1(tmp_path, monkeypatch):
    """An engine that fails during ``atmosphere build`` (through the radscene command) gives
    one error line, exit code 1, no traceback and no file."""
    from radscene.atmosphere import build as build_module
    from radscene.cli import app as main_app
    from radscene.errors import EngineError

    def failing(config, progress=None):
        raise EngineError("6S failed with exit code 3 for the case wavelength=0.55")

    monkeypatch.setattr(build_module, "build_database", failing)
    out = tmp_path / "atm.nc"
    res = runner.invoke(main_app, ["atmosphere", "build", "default", "-o", str(out)])
    assert res.exit_code == 1
    assert "error:" in res.output and "exit code 3 for the case wavelength=0.55" in res.output
    assert "Traceback" not in res.output and isinstance(res.exception, SystemExit)
    assert not out.exists()


def test_build_lowtran_builds_then_checks(tmp_path, monkeypatch):
    """``radscene atmosphere build-lowtran`` hands its options to the build, prints the
    executable, then the self-check's line; a failed check is one line and exit code 1."""
    from radscene.atmosphere.lowtran import build as build_module
    from radscene.atmosphere.lowtran import runner as runner_module
    from radscene.cli import app as main_app
    from radscene.errors import EngineError

    calls = {}

    def fake_build(output=None, source=None, compiler="gfortran", flags=(), verbose=False):
        calls.update(output=output, source=source, compiler=compiler)
        return output

    monkeypatch.setattr(build_module, "build_executable", fake_build)
    monkeypatch.setattr(runner_module, "self_check", lambda exe: f"self-check passed for {exe}")
    exe, source = tmp_path / "radscene-lowtran7", tmp_path / "lowtran7.f"
    res = runner.invoke(main_app, ["atmosphere", "build-lowtran", "-o", str(exe), "--source",
                                   str(source), "--compiler", "gfortran-13", "--check"])
    assert res.exit_code == 0, res.output
    assert calls == {"output": exe, "source": source, "compiler": "gfortran-13"}
    assert " ".join(res.output.split()) == f"built {exe} self-check passed for {exe}"

    def failed(exe):
        raise EngineError("LOWTRAN self-check failed: transmittance 0.5 at 11110 cm-1, expected 0.8772")

    monkeypatch.setattr(runner_module, "self_check", failed)
    res = runner.invoke(main_app, ["atmosphere", "build-lowtran", "-o", str(exe), "--check"])
    assert res.exit_code == 1
    assert "error: LOWTRAN self-check failed" in res.output and "Traceback" not in res.output


def test_build_lowtran_refuses_a_missing_compiler_or_source(tmp_path):
    """No compiler: exit code 1 and how to install one; a --source that is no file: exit code
    2 naming it. Both before anything is compiled or written."""
    import sys

    from radscene.cli import app as main_app

    exe = tmp_path / "out" / "radscene-lowtran7"
    res = runner.invoke(main_app, ["atmosphere", "build-lowtran", "-o", str(exe),
                                   "--compiler", "no-such-fortran"])
    assert res.exit_code == 1
    assert "Fortran compiler 'no-such-fortran' not found" in res.output
    missing = tmp_path / "lowtran7.f"
    res = runner.invoke(main_app, ["atmosphere", "build-lowtran", "-o", str(exe), "--source",
                                   str(missing), "--compiler", sys.executable])
    assert res.exit_code == 2
    assert f"error: source: no such file: {missing}" in " ".join(res.output.split())
    assert not exe.exists() and not exe.parent.exists()
