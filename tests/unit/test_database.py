"""The ``database`` engine on the database shipped with radscene (no 6S, no Fortran)."""

from __future__ import annotations

import numpy as np
import pytest

from radscene.atmosphere import sixs_model as m
from radscene.atmosphere.base import SkyGeometry
from radscene.atmosphere.database import DatabaseAtmosphere, open_database, shipped_databases
from radscene.errors import ConfigError

REL = 1e-9


@pytest.fixture(scope="module")
def db():
    return DatabaseAtmosphere(profile="midlatitude_summer", aerosol="rural", visibility="23 km",
                              sun_zenith=40.0, sun_azimuth=150.0)


def test_the_default_database_ships_and_holds_the_common_conditions():
    assert "default" in shipped_databases()
    ds = open_database("default")
    assert set(ds["profile"].values) == {"us_standard", "midlatitude_summer",
                                         "midlatitude_winter", "subarctic_summer",
                                         "subarctic_winter", "tropical", "none"}
    nodes = {(str(a), round(float(t), 6)) for a, t in zip(ds["aerosol_model"].values,
                                                         ds["aot550"].values, strict=True)}
    assert nodes == {("none", 0.0)} | {(m, t) for m in ("rural", "maritime", "urban", "desert")
                                       for t in (0.1, 0.3, 0.6, 1.0)}
    assert ds.attrs["layout"] == "radscene-atmosphere-database/1"
    assert "config" in ds.attrs and "created" in ds.attrs
    # 95.3 MB: 61 MB of LOWTRAN's tables at nine water-vapour columns (12-bit), left on disk
    # until a scaled column asks for them; below the 100 MB a single file may have
    assert shipped_databases()["default"].stat().st_size < 96e6
    assert {"thermal_observer_height", "path_length"} <= set(ds.coords)
    assert not any(k.startswith("thermal_water_") for k in ds.data_vars)


@pytest.mark.parametrize(("params", "match"), [
    ({"profile": "martian"}, "profile 'martian' is not in default.nc; it holds: "),
    ({"aerosol": "volcanic"}, "aerosol 'volcanic' is not in default.nc"),
    ({"visibility": "2 km"}, r"visibility 2 km \(AOT550 1.8\d\) is outside the rural aerosol's "
                             r"range in default.nc: AOT550 0-1"),
    ({"visibility": 0}, "must be > 0"),
    ({"visibility": "-5 km"}, "must be > 0"),
    ({"file": "/no/such/atm.nc"}, "no database '/no/such/atm.nc'"),
    ({"surface_albedo": -0.1}, r"must lie in \[0, 1\]"),
])
def test_bad_parameters_name_the_key(params, match):
    with pytest.raises(ConfigError, match=match):
        DatabaseAtmosphere(**params)


@pytest.mark.parametrize(("call", "match"), [
    (lambda a: a.path(1e5, 0.0, 0.0, [0.29]), "covers 0.3"),
    (lambda a: a.path(1e5, 0.0, 0.0, [25.0]), "covers 0.3"),
    (lambda a: a.path(1e5, -800.0, 0.0, [0.55]), "below the ground"),
    (lambda a: a.path(2e5, 1.5e5, 0.0, [0.55]), "above the atmosphere"),
    (lambda a: a.path(1e5, 9000.0, 0.0, [0.55]), "surface altitudes up to"),
    (lambda a: a.path(1e3, 0.0, 120.0, [0.55]), "contradicts the altitudes"),
    (lambda a: DatabaseAtmosphere().path(1e5, 0.0, 0.0, [0.55]), "needs the sun position"),
])
def test_bad_queries_are_refused(db, call, match):
    with pytest.raises(ConfigError, match=match):
        call(db)


def test_path_broadcasts_and_behaves(db):
    wl = np.array([0.45, 0.55, 0.865, 1.65, 2.2])
    p = db.path(np.array([[1e5], [3000.0]]), 0.0, np.array([[0.0, 30.0, 60.0]]), wl)
    assert p.transmittance.shape == p.scattered_radiance.shape == (2, 3, 5)
    tau, rad = p.transmittance, p.scattered_radiance
    assert np.all((tau > 0) & (tau < 1))
    assert np.all(np.diff(tau, axis=1) < 0)  # longer slant paths transmit less
    assert np.all(tau[1] > tau[0])  # an aircraft sees through less air than a satellite
    assert np.all(rad[1] < rad[0])
    assert np.all(np.diff(rad[0, :, :3], axis=-1) < 0)  # bluer is brighter (visible)
    # one geometry at a time gives the same numbers
    one = db.path(3000.0, 0.0, 30.0, wl)
    assert one.transmittance == pytest.approx(tau[1, 1], rel=1e-12)
    # a path of no length
    zero = db.path(700.0, 700.0, 10.0, wl)
    assert zero.transmittance == pytest.approx(np.ones(5)) and np.all(zero.radiance == 0)


def test_table_nodes_are_reproduced_exactly(db):
    """At a node of every axis (top of the atmosphere, sea level, sun and view at table
    zeniths, relative azimuth 0, a 6S scattering wavelength) the path reflectance is the
    stored one, with the stored gases: the single-scattering normalisation cancels."""
    db = DatabaseAtmosphere(profile="midlatitude_summer", aerosol="rural", aot550=0.3,
                            sun_zenith=40.0, sun_azimuth=150.0)
    ds = db.source
    assert len(db._nodes) == 1  # a node of the AOT550 axis
    ia, ip = db._nodes[0][0], db._ip
    lam = float(ds["scattering_wavelength"].values[7])
    i_sun = list(ds["sun_zenith"].values).index(40.0)
    i_view = list(ds["view_zenith"].values).index(60.0)
    rho_mix = float(ds["rho_mixture"].values[ia, 7, 0, -1, i_sun, i_view, 0])
    rho_ray = float(ds["rho_rayleigh"].values[ia, 7, 0, -1, i_sun, i_view, 0])
    m_tot = 1 / np.cos(np.radians(40.0)) + 1 / np.cos(np.radians(60.0))
    grid, logm = ds["wavelength"].values, np.log(ds["airmass"].values)

    def gas(name):
        per_m = [np.interp(lam, grid, ds[name].values[ip, :, 0, k]) for k in range(logm.size)]
        return np.interp(np.log(m_tot), logm, per_m)

    expected = m.path_reflectance(rho_mix, rho_ray, gas("gas_column"),
                                  gas("gas_column_no_water"))
    got = db.components(1e5, 0.0, 60.0, [lam], sun_zenith=40.0, relative_azimuth=0.0)
    assert got["path_reflectance"][0, 0] == pytest.approx(expected, rel=1e-9)


def test_sun_is_beer_lambert_on_the_stored_optical_depths(db):
    wl = np.array([0.55, 0.865])
    c = db.components(1e5, 0.0, 0.0, wl, sun_zenith=50.0, relative_azimuth=0.0)
    tau = c["optical_depth_rayleigh"][0] + c["optical_depth_aerosol"][0]
    expected = np.exp(-tau / np.cos(np.radians(50.0))) * c["gas_transmittance_down"][0]
    s = db.sun(0.0, 50.0, wl, np.array([1900.0, 980.0]))
    assert s.transmittance == pytest.approx(expected, rel=1e-12)
    assert s.irradiance == pytest.approx(expected * [1900.0, 980.0], rel=1e-12)
    assert np.all(db.sun(0.0, 95.0, wl, np.ones(2)).transmittance == 0.0)


def test_path_nodes_mix_at_most_eight_nodes(db):
    rng = np.random.default_rng(4)
    n = 500
    obs = np.full(n, 1750.0)
    tgt = rng.uniform(1150.0, 1260.0, n)
    vz = rng.uniform(20.0, 78.0, n)
    nodes = db.path_nodes(obs, tgt, vz)
    # one observer altitude adds no corners: 2 x 2 (target altitude x view zenith)
    assert nodes.index.shape == nodes.weight.shape == (n, 4)
    assert nodes.weight.sum(axis=1) == pytest.approx(np.ones(n), rel=1e-12)
    mix = lambda v: (v[nodes.index] * nodes.weight).sum(axis=1)  # noqa: E731
    # linear in air mass (1 / cos of the view zenith)
    assert mix(1.0 / np.cos(np.radians(nodes.view_zenith))) == pytest.approx(
        1.0 / np.cos(np.radians(vz)), rel=1e-12)
    assert mix(nodes.target_altitude) == pytest.approx(tgt, rel=1e-12)
    # spectra mixed from the nodes ≈ spectra at the pixels
    wl = np.array([0.55, 0.865])
    at_nodes = db.path(nodes.observer_altitude, nodes.target_altitude, nodes.view_zenith, wl)
    mixed = np.einsum("nk,nkq->nq", nodes.weight, at_nodes.transmittance[nodes.index])
    direct = db.path(obs, tgt, vz, wl).transmittance
    assert mixed == pytest.approx(direct, rel=2e-3)


def test_sky_integrates_to_the_diffuse_irradiance(db):
    wl = np.array([0.47, 0.865])
    geom = SkyGeometry(0.0, 40.0, 150.0)
    nz, na = 45, 72
    zen = (np.arange(nz) + 0.5) * 90.0 / nz
    az = (np.arange(na) + 0.5) * 360.0 / na
    zz, aa = np.meshgrid(zen, az, indexing="ij")
    sky = db.sky(zz, aa, wl, geom)
    assert sky.shape == (nz, na, 2) and np.all(sky > 0)
    w = np.cos(np.radians(zz)) * np.sin(np.radians(zz)) * np.radians(2.0) * np.radians(5.0)
    c = db.components(1e5, 0.0, 0.0, wl, sun_zenith=40.0, relative_azimuth=0.0)
    assert np.einsum("za,zaq->q", w, sky) == pytest.approx(c["diffuse_irradiance"][0], rel=1e-2)
    assert db.sky(30.0, 150.0, wl, geom)[0] > db.sky(30.0, 330.0, wl, geom)[0]
    nodes = db.sky_azimuth_nodes()
    assert np.all(np.diff(nodes) > 0) and 150.0 in nodes


def test_surroundings_brighten_the_sky():
    dark = DatabaseAtmosphere(surface_albedo=0.0).sky(30.0, 0.0, [0.55],
                                                       SkyGeometry(0.0, 30.0, 0.0))
    bright = DatabaseAtmosphere(surface_albedo=0.5).sky(30.0, 0.0, [0.55],
                                                         SkyGeometry(0.0, 30.0, 0.0))
    assert bright[0] > dark[0]


def test_thermal_tables_when_present(db):
    if not db.thermal:
        pytest.skip("this database holds no thermal tables (LOWTRAN was not built)")
    wl = np.array([4.0, 10.0, 15.0])
    p = db.path(3000.0, 0.0, 30.0, wl)
    assert np.all((p.transmittance > 0) & (p.transmittance <= 1))
    assert p.thermal_radiance[1] > 0 and p.scattered_radiance[1] == 0
    assert p.transmittance[2] < p.transmittance[1]  # CO2 at 15 um
    night = db.sky([0.0, 80.0], [0.0, 0.0], wl, SkyGeometry(0.0, 120.0, 0.0))
    assert np.all(night[:, 1:] > 0)
    assert night[1, 1] > night[0, 1]  # the horizon is warmer at 10 um



def test_from_3_um_every_transmittance_is_the_thermal_tables(db):
    """Where both tables hold (3-4 um) the line of sight, the sun's path and the coupling's
    gases are the thermal tables': the path's transmittance is theirs, the sun's is their path
    from the top, and the coupling's scattered light crosses the same gases as the direct
    (t_d / τ = the scattering tables' diffuse over direct share); below 3 um, 6S's."""
    if not db.thermal:
        pytest.skip("this database holds no thermal tables (LOWTRAN was not built)")
    wl = np.array([2.2, 3.2, 3.77, 3.95])
    upper, lower, zen = (np.array([v]) for v in (2500.0, 0.0, 60.0))
    t_thermal, _, inside = db._thermal_path(upper, lower, zen, wl)
    assert list(inside) == [False, True, True, True]
    p = db.path(2500.0, 0.0, 60.0, wl)
    assert p.transmittance[inside] == pytest.approx(t_thermal[0, inside], rel=REL)
    c = db.components(2500.0, 0.0, 60.0, wl[:1])
    assert p.transmittance[0] == pytest.approx(c["transmittance"][0, 0], rel=REL)
    top, _, _ = db._thermal_path(np.array([1e5]), lower, np.array([40.0]), wl)
    assert db.sun(0.0, 40.0, wl, np.ones(4)).transmittance[inside] == pytest.approx(
        top[0, inside], rel=REL)
    c = db.components(2500.0, 0.0, 60.0, wl)
    assert c["transmittance"][0, inside] == pytest.approx(t_thermal[0, inside], rel=REL)
    share = c["diffuse_transmittance_up"][0] / c["direct_transmittance_up"][0]
    t_d = db.coupling(2500.0, 0.0, 60.0, wl).diffuse_transmittance
    assert t_d[inside] / p.transmittance[inside] == pytest.approx(share[inside], rel=1e-9)
    # and the sun's scattered light, down to the ground and along the line of sight
    c40 = db.components(2500.0, 0.0, 60.0, wl, sun_zenith=40.0)
    assert (c40["gas_transmittance_down"][0, inside] * c40["direct_transmittance_down"][0, inside]
            == pytest.approx(top[0, inside], rel=REL))
    assert c40["gas_transmittance_total"][0, inside] == pytest.approx(
        c40["gas_transmittance_down"][0, inside] * c40["gas_transmittance_up"][0, inside], rel=REL)

def test_with_sun_copies_and_checks_the_sun(db):
    moved = db.with_sun(60.0, 370.0, day_of_year=80, view_azimuth=45.0)
    assert (moved.sun_zenith, moved.sun_azimuth, moved.view_azimuth) == (60.0, 10.0, 45.0)
    assert (db.sun_zenith, db.sun_azimuth) == (40.0, 150.0)  # the original keeps its sun
    assert moved.t is db.t  # tables shared, not copied
    with pytest.raises(ConfigError, match="sun_zenith"):
        db.with_sun(181.0, 0.0)
    with pytest.raises(ConfigError, match="sun_azimuth"):
        db.with_sun(30.0, float("nan"))


def test_path_reflectances_are_never_negative():
    """Every stored path reflectance, molecules and mixture, at every level, is ≥ 0 (the
    aircraft levels are interpolated from ratios; where the aerosol's share changes sign the
    mixture's own ratio is used, see radscene.atmosphere.build)."""
    ds = open_database()
    for name in ("rho_mixture", "rho_rayleigh"):
        values = ds[name].values
        assert np.all(np.isfinite(values)), name
        assert values.min() >= 0.0, name


def test_every_shipped_table_is_finite_and_phase_functions_positive():
    """No NaN anywhere in the shipped file (6S prints NaN for its maritime phase function at
    3 deg in the visible: the build fills those from larger angles), and the sky near the sun
    is finite for every aerosol."""
    ds = open_database()
    for name, var in ds.data_vars.items():
        if np.issubdtype(var.dtype, np.floating):
            assert np.all(np.isfinite(var.values)), name
    assert ds["phase_aerosol"].values.min() > 0.0
    for aerosol in ("rural", "maritime"):
        atm = DatabaseAtmosphere(profile="us_standard", aerosol=aerosol, sun_zenith=30.0,
                                 sun_azimuth=180.0)
        near_sun = atm.sky([30.0, 31.0], [180.0, 182.0], [0.45, 0.55, 0.65],
                           SkyGeometry(0.0, 30.0, 180.0))
        assert np.all(np.isfinite(near_sun)) and np.all(near_sun > 0.0), aerosol


def test_kept_tables_follow_the_wavelength_grid_and_the_sun():
    """The gas tables of the last wavelength grid and the path tables at the last sun are
    kept between queries: queries on alternating grids and suns give what a fresh engine
    gives."""
    def fresh(sun_zenith):
        return DatabaseAtmosphere(profile="midlatitude_summer", aerosol="rural",
                                  visibility="23 km", sun_zenith=sun_zenith, sun_azimuth=150.0)

    atm = fresh(40.0)
    grids = (np.linspace(0.45, 0.9, 7), np.linspace(1.5, 2.3, 5))
    geometry = (np.array([9000.0, 9000.0]), np.array([1200.0, 1500.0]), np.array([0.0, 20.0]))
    for wl in (*grids, grids[0]):
        assert np.array_equal(atm.path(*geometry, wl).scattered_radiance,
                              fresh(40.0).path(*geometry, wl).scattered_radiance)
        assert np.array_equal(atm.coupling(*geometry, wl).diffuse_transmittance,
                              fresh(40.0).coupling(*geometry, wl).diffuse_transmittance)
    moved = atm.with_sun(55.0, 150.0)
    for engine in (moved, atm):
        sun = engine.sun_zenith
        assert np.array_equal(engine.path(*geometry, grids[1]).scattered_radiance,
                              fresh(sun).path(*geometry, grids[1]).scattered_radiance)


def test_the_water_vapour_tables_are_read_a_condition_at_a_time():
    from radscene.atmosphere.database import water_tables

    path = shipped_databases()["default"]
    ds = open_database()
    tables = water_tables(path, 1, 2)
    assert set(tables) == {"transmittance", "path_radiance", "sky_radiance", "sky_transmittance",
                           "level_transmittance", "level_path_radiance"}
    n = ds.sizes["water_scale"]
    assert tables["transmittance"].shape == (n,) + ds["thermal_transmittance"].shape[2:]
    assert np.all((tables["transmittance"] >= 0) & (tables["transmittance"] <= 1))
    with pytest.raises(ConfigError, match="atmosphere.file: .* changed on disk"):
        water_tables(path, 1, 2, mtime=path.stat().st_mtime - 1.0)


def test_a_packed_variable_read_back_is_written_as_floats(tmp_path):
    """Only variables the writer packed itself are stored as scaled integers."""
    import h5py
    import xarray as xr

    from radscene.io import write_netcdf

    ds = xr.Dataset({"x": (("a", "b"), np.linspace(0.0, 1.0, 6).reshape(2, 3))})
    ds["x"].encoding.update({"dtype": "uint16", "scale_factor": 1e-3, "_FillValue": 65535})
    write_netcdf(ds, tmp_path / "read_back.nc")
    ds["x"].encoding["radscene_packed"] = True
    write_netcdf(ds, tmp_path / "packed.nc")
    with h5py.File(tmp_path / "read_back.nc") as f, h5py.File(tmp_path / "packed.nc") as g:
        assert f["x"].dtype == np.float32 and g["x"].dtype == np.uint16
