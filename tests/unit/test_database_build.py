"""Building a database: configuration checks, the adaptive grid, a small build end to end."""

from __future__ import annotations

import numpy as np
import pytest

from radscene.atmosphere import sixs_runner as sr
from radscene.atmosphere.build import DEFAULT_CONFIG, adaptive_grid, build_database, load_config
from radscene.atmosphere.database import DatabaseAtmosphere
from radscene.errors import ConfigError

AVAILABLE, REASON = sr.sixs_available()


def test_adaptive_grid_keeps_linear_interpolation_within_tolerance():
    x = np.linspace(0.0, 10.0, 2001)
    y = np.stack([np.sin(x), 0.5 * np.cos(3 * x)])
    for tol in (0.1, 0.01, 0.001):
        idx = adaptive_grid(x, y, tol)
        assert idx[0] == 0 and idx[-1] == x.size - 1
        for row in y:
            assert np.abs(np.interp(x, x[idx], row[idx]) - row).max() <= tol
    # flat stretches need nothing but their ends
    assert list(adaptive_grid(x, np.ones_like(x), 1e-6)) == [0, x.size - 1]


def test_each_aerosol_condition_has_its_own_name_and_progress_stage():
    from radscene.atmosphere.build import _condition_name

    names = [_condition_name(c) for c in load_config(None)["_conditions"]]
    # four conditions of one model: four tables, and four progress stages (two of a model
    # once shared one bar, which then showed the time of the first only)
    assert names[:5] == ["none", "rural_aot0.1", "rural_aot0.3", "rural_aot0.6", "rural_aot1"]
    assert len(set(names)) == len(names)
    assert _condition_name({"aerosol": "none", "visibility": None}) == "none"
    assert _condition_name({"aerosol": "rural", "visibility": 5.0, "aot550": None}) == "rural_5km"


def test_default_configuration_is_valid_and_complete():
    """Six standard profiles and none; four aerosol models on an AOT550 axis, and none."""
    cfg = load_config(None)
    assert cfg["profiles"] == DEFAULT_CONFIG["profiles"]
    assert set(cfg["profiles"]) == set(sr.PROFILES)
    models = {c["aerosol"] for c in cfg["_conditions"]}
    assert models == {"none", "rural", "maritime", "urban", "desert"}
    for m in models - {"none"}:
        aots = [c["aot550"] for c in cfg["_conditions"] if c["aerosol"] == m]
        assert aots == [0.1, 0.3, 0.6, 1.0]
    assert cfg["wavelength"]["min"] == 0.3


@pytest.mark.parametrize(("config", "match"), [
    ({"colour": 1}, r"unknown keys \['colour'\]"),
    ({"profiles": ["jovian"]}, "unknown profile 'jovian'"),
    ({"aerosols": [{"model": "rural", "visibility": 0}]}, r"aerosols\[0\].visibility"),
    ({"aerosols": [{"visibility": "5 km"}]}, r"aerosols\[0\]"),
    ({"aerosols": [{"model": "rural", "aot550": [0.5, 0.1]}]}, r"aerosols\[0\].aot550"),
    ({"aerosols": [{"model": "rural", "aot550": [0.1], "visibility": "5 km"}]}, "not both"),
    ({"aerosols": [{"model": "rural", "aot550": 0.1}, {"model": "rural", "aot550": 0.1}]},
     "given twice"),
    ({"grid": {"sun_zenith": [0, 60, 30]}}, r"grid.sun_zenith: an increasing list"),
    ({"grid": {"sun_zenith": [10, 60]}}, "start at 0"),
    ({"grid": {"airmass_pairs": [[0, 95]]}}, "airmass_pairs"),
    ({"grid": {"phase_wavelengths": [0.55]}}, r"grid.phase_wavelengths: at least two"),
    ({"wavelength": {"min": 0.4, "max": 5.0}}, r"max <= 4 µm \(6S\)"),
    ({"wavelength": {"smoothing": -0.01}}, "wavelength.smoothing"),
    ({"wavelength": {"dry_reference": "yes"}}, "wavelength.dry_reference: true or false"),
    ({"strategy": "quick"}, "reduced or full"),
    ({"thermal": {"engine": "modtran"}}, "none, lowtran or auto"),
    ({"thermal": {"water_scales": [0.5, 0.2]}}, r"thermal.water_scales: an increasing list"),
    ({"thermal": {"ozone_scales": [0.0, 2.0]}}, r"thermal.ozone_scales: an increasing list"),
    ({"thermal": {"water_scales": "wet"}}, r"thermal.water_scales"),
    ({"thermal": {"water_scales": [5.0]}}, r"thermal.water_scales: 5 times the tropical "
                                           r"profile's 4.11 g cm-2 is beyond the lowtran "
                                           r"engine's 15 g cm-2"),
    ({"thermal": {"ozone_scales": [4.5]}}, r"thermal.ozone_scales: 4.5 times"),
    ({"thermal": {"observer_height": [1000, 300]}},
     r"thermal.observer_height: an increasing list of at least 1 within \[1, 99000\] m"),
    ({"thermal": {"observer_height": "high"}}, r"thermal.observer_height"),
    ({"thermal": {"path_length": [0, 10]}}, r"thermal.path_length: an increasing list"),
    ({"thermal": {"path_length": [1e6]}}, r"within \[1, 300000\] m"),
    ({"thermal": {"path_length": [100]}}, r"thermal.path_length: an increasing list of at "
                                          r"least 2"),
])
def test_bad_configurations_name_the_key(config, match):
    with pytest.raises(ConfigError, match=match):
        load_config(config)


def test_thermal_column_nodes_leave_the_main_tables_to_themselves():
    cfg = load_config({"thermal": {"water_scales": [0.5, 1.0, 2.0], "ozone_scales": [0.5]}})
    assert cfg["thermal"]["water_scales"] == [0.5, 2.0]  # 1: the main tables
    assert cfg["thermal"]["ozone_scales"] == [0.5, 1.0]  # the ozone tables' own reference


def test_configuration_from_yaml(tmp_path):
    path = tmp_path / "atm.yaml"
    path.write_text("profiles: [tropical]\naerosols: [{model: maritime, visibility: 10 km}]\n")
    cfg = load_config(path)
    assert cfg["profiles"] == ["tropical"]
    assert cfg["_conditions"][0]["visibility"] == pytest.approx(10.0)
    (tmp_path / "bad.yaml").write_text("profiles: [tropical\n")
    with pytest.raises(ConfigError, match="not valid YAML"):
        load_config(tmp_path / "bad.yaml")


@pytest.mark.slow
@pytest.mark.skipif(not AVAILABLE, reason=f"6S cannot run here: {REASON}")
def test_a_small_build_round_trips(tmp_path):
    cfg = {"profiles": ["us_standard"], "aerosols": [{"model": "rural", "visibility": "23 km"}],
           "grid": {"surface_altitude": [0, 2000], "observer_height": [2000],
                    "sun_zenith": [0, 40, 70], "view_zenith": [0, 40, 70],
                    "coarse_zenith": [0, 70], "ratio_wavelengths": [0.55, 0.86],
                    "phase_wavelengths": [0.55, 0.86], "airmass_pairs": [[0, 60], [70, 80]],
                    "partial_zenith": [0, 60, 80]},
           "wavelength": {"min": 0.5, "max": 0.9, "tolerance": 0.02},
           "thermal": {"engine": "none"}, "cache": str(tmp_path / "cache")}
    ds = build_database(cfg)
    assert ds.attrs["sixs_runs"] > 0 and "config" in ds.attrs
    path = tmp_path / "small.nc"
    ds.to_netcdf(path, engine="h5netcdf")
    db = DatabaseAtmosphere(file=path, sun_zenith=40.0)
    p = db.path(1e5, 0.0, 40.0, [0.55, 0.65])
    assert np.all((p.transmittance > 0.5) & (p.transmittance < 1.0))
    with pytest.raises(ConfigError, match="covers 0.5–0.9 µm"):
        db.path(1e5, 0.0, 40.0, [1.6])


def test_the_thermal_column_tables_are_lowtrans_at_those_columns():
    """Each node of the thermal build is the lowtran engine's own run at that column."""
    from radscene.atmosphere import build
    from radscene.atmosphere.lowtran import LowtranAtmosphere, lowtran_available
    from radscene.atmosphere.lowtran.profiles import model_columns

    if not lowtran_available():
        pytest.skip("LOWTRAN is not built (make lowtran)")
    cfg = load_config({
        "profiles": ["midlatitude_summer", "none"],
        "aerosols": [{"model": "rural", "aot550": [0.3]}],
        "grid": {"surface_altitude": [0, 1500], "observer_height": [1000],
                 "view_zenith": [0, 60]},
        "thermal": {"engine": "lowtran", "wavelength": {"min": 8, "max": 12, "step": 100},
                    "water_scales": [0.5, 2], "ozone_scales": [0.5],
                    "observer_height": [1000], "path_length": [100, 3000]}})
    cfg["_conditions"][0]["thermal_visibility"] = 16.09
    th = build._thermal(cfg, lambda *a: None)
    w0, o0 = model_columns("midlatitude_summer")
    assert th["water_scale"].tolist() == [0.5, 2.0] and th["ozone_scale"].tolist() == [0.5, 1.0]
    assert np.allclose(th["columns"][0], (w0, o0)) and np.all(th["columns"][1] == 0)
    wet = LowtranAtmosphere(model="midlatitude_summer", aerosol="rural", visibility=16.09,
                            water=2.0 * w0).path(np.full(2, 1e5), 1500.0, np.array([0.0, 60.0]),
                                                 th["wavelength"])
    tau, rad, _sky, _sky_tau, level_tau, level_rad = th["water"]
    assert np.allclose(tau[0, 0, 1, :, 1, -1, :], wet.transmittance.T)  # surface 1.5 km, top
    assert np.allclose(rad[0, 0, 1, :, 1, -1, :], wet.thermal_radiance.T)
    assert th["observer_height"].tolist() == [0.0, 1000.0, 1e5]
    level = LowtranAtmosphere(model="midlatitude_summer", aerosol="rural", visibility=16.09,
                              water=2.0 * w0).level_path(1500.0, np.array([100.0, 3000.0]),
                                                         th["wavelength"])
    assert np.allclose(level_tau[0, 0, 1, :, 1, :], level.transmittance.T)
    assert np.allclose(level_rad[0, 0, 1, :, 1, :], level.thermal_radiance.T)
    assert level_tau[0, 0, 1, :, 1, 1].mean() < level_tau[0, 0, 1, :, 1, 0].mean() < 1.0
    dry_ozone = LowtranAtmosphere(model="midlatitude_summer", aerosol="none", visibility=None,
                                  water=0.5 * w0, ozone=0.5 * o0).path(
        np.full(2, 1000.0), 0.0, np.array([0.0, 60.0]), th["wavelength"])
    assert np.allclose(th["ozone"][1][0, 0, :, 0, 1, :], dry_ozone.thermal_radiance.T)
    assert np.all(th["main"][0][1] == 1.0) and np.all(th["main"][1][1] == 0.0)  # no gas
