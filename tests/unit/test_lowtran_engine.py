"""The ``lowtran`` engine's mapping of Atmosphere queries onto LOWTRAN cases.

A stand-in executable answers every deck with flat spectra on LOWTRAN's own grid (V1 to V2
by DV from card 4) and logs the decks, so these tests check the queries, units, shapes and
the checks made before anything runs, without a Fortran compiler. LOWTRAN's physics is
tested in test_lowtran_physics.py and tests/validation/test_lowtran_reference.py.
"""

from __future__ import annotations

import datetime as dt
import stat
import sys
import textwrap

import numpy as np
import pytest

from radscene.atmosphere import SkyGeometry
from radscene.atmosphere.lowtran import LowtranAtmosphere
from radscene.atmosphere.lowtran.geometry import path_kind
from radscene.errors import ConfigError

# stand-in values in LOWTRAN's units (W cm-2 ...), and in radscene's (W m-2 ...)
TAU, THERMAL, TSOL, SOLAR, SCATTER = 0.8, 1e-4, 5e-2, 1e-1, 2e-5
REL = 1e-7  # the stand-in prints 8 significant digits

FAKE = textwrap.dedent("""\
    import os
    lines = open("TAPE5").read().splitlines()
    log = os.environ.get("FAKE_LOWTRAN_LOG")
    if log:
        with open(log, "a") as f:
            f.write("\\n".join(lines) + "\\n@@\\n")
    iemsct = int(lines[0][10:15])
    v1, v2, dv = (float(lines[-2][i:i + 10]) for i in (0, 10, 20))
    n = int(round((v2 - v1) / dv)) + 1
    with open("radscene.out", "w") as f:
        f.write("# radscene-lowtran7 1 points %d\\n" % n)
        for k in range(n):
            v = v1 + k * dv
            row = (v, 1e4 / v, 0.8, 1e-4, 5e-2, 1e-1, 2e-5, 1.0, 1.0)
            f.write("".join(" %16.8E" % x for x in row) + "\\n")
        f.write("# end\\n")
""")


@pytest.fixture
def decks(tmp_path, monkeypatch):
    """The decks the stand-in has run, as lists of card lines."""
    log = tmp_path / "decks.log"
    monkeypatch.setenv("FAKE_LOWTRAN_LOG", str(log))

    def read():
        if not log.exists():
            return []
        return [d.strip("\n").splitlines() for d in log.read_text().split("@@\n") if d.strip()]
    return read


@pytest.fixture
def make(tmp_path):
    exe = tmp_path / "fake-lowtran"
    exe.write_text(f"#!{sys.executable}\n{FAKE}")
    exe.chmod(exe.stat().st_mode | stat.S_IXUSR)

    def build(**params):
        params.setdefault("cache", False)
        return LowtranAtmosphere(executable=exe, **params)
    return build


def card(lines, index, widths):
    out, pos = [], 0
    for w in widths:
        out.append(lines[index][pos:pos + w])
        pos += w
    return out


WL = np.array([0.45, 0.55, 1.6, 10.0])


# -- queries ---------------------------------------------------------------------------------
def test_path_shapes_units_and_the_deck(make, decks):
    atm = make(aerosol="urban", visibility=8.0, albedo=0.2, sun_zenith=30.0, sun_azimuth=150.0)
    out = atm.path(3000.0, [[0.0], [100.0]], [0.0, 20.0, 40.0], WL)
    assert out.transmittance.shape == out.radiance.shape == (2, 3, 4)
    assert out.transmittance == pytest.approx(np.full((2, 3, 4), TAU), rel=REL)
    assert out.thermal_radiance == pytest.approx(np.full((2, 3, 4), THERMAL * 1e4), rel=REL)
    assert out.scattered_radiance == pytest.approx(np.full((2, 3, 4), SCATTER * 1e4), rel=REL)
    runs = decks()
    assert len(runs) == 6  # one per distinct geometry
    nadir = next(d for d in runs if float(card(d, 2, [10] * 3)[2]) == 180.0)
    c1 = card(nadir, 0, [5] * 13 + [8, 7])
    assert (int(c1[0]), int(c1[1]), int(c1[2]), int(c1[3])) == (2, 2, 2, 1)
    assert (float(c1[13]), float(c1[14])) == (0.0, 0.2)  # no boundary emission; albedo
    c2 = card(nadir, 1, [5] * 6 + [10] * 5)
    assert (int(c2[0]), float(c2[6])) == (5, 8.0)  # urban, visibility 8 km
    h1, h2, angle = (float(x) for x in card(nadir, 2, [10] * 3))
    assert h1 == 3.0 and angle == 180.0
    assert h2 in (0.001, 0.1)  # a target on the ground is lifted 1 m: no ground term
    iparm, iph, iday, isourc = (int(x) for x in card(nadir, 3, [5] * 4))
    assert (iparm, iph, iday, isourc) == (2, 2, 0, 0)
    parm1, parm2 = (float(x) for x in card(nadir, 4, [10] * 2))
    assert (parm1, parm2) == (90.0, 30.0)  # no view azimuth: 90 deg from the sun
    v1, v2, dv = (float(x) for x in card(nadir, 5, [10] * 3))
    assert (v1 <= 1e4 / 10.0 and v2 >= 1e4 / 0.45, dv) == (True, 5.0)


def test_path_without_the_sun_is_thermal_only(make, decks):
    for atm in (make(), make(sun_zenith=95.0, sun_azimuth=0.0)):
        out = atm.path(1000.0, 0.0, 10.0, WL)
        assert np.all(out.scattered_radiance == 0.0)
    assert [int(card(d, 0, [5] * 3)[2]) for d in decks()] == [1, 1]


def test_view_azimuth_sets_the_relative_azimuth_and_the_sun_at_the_observer(make, decks):
    atm = make(sun_zenith=40.0, sun_azimuth=200.0, view_azimuth=20.0)
    atm.path(20000.0, 0.0, 60.0, WL)
    parm1, parm2 = (float(x) for x in card(decks()[0], 4, [10] * 2))
    assert parm1 == 0.0  # looking back at the target the observer faces the sun's azimuth
    # the observer stands ~35 km from the target, away from the sun: the sun is lower there
    # by the central angle between them
    from radscene.atmosphere.lowtran.geometry import observer_geometry

    beta = float(observer_geometry(20000.0, 0.0, 60.0, 6371.23e3)[1])
    assert beta == pytest.approx(0.31, abs=0.01)
    assert parm2 == pytest.approx(40.0 + beta, abs=1e-4)


def test_zero_length_paths_need_no_run(make, decks):
    out = make().path(250.0, 250.0, 45.0, WL)
    assert np.all(out.transmittance == 1.0) and np.all(out.radiance == 0.0)
    assert decks() == []


def test_a_line_of_sight_near_the_horizon_is_the_flat_scenes(make, decks):
    """A camera 2 m above the ground at 89.9 deg sees 1146 m of air at 1 m (a level path,
    ITYPE 1, at the mean of its ends lifted 1 m off the ground); an aircraft 1 km up at 88 deg
    its 28.65 km straight line between the two altitudes (ITYPE 2 with the range), not the
    shorter one on the sphere."""
    atm = make()
    atm.path(2.0, 0.0, 89.9, WL)
    atm.path(1000.0, 0.0, 88.0, WL)
    chord, level = sorted(decks(), key=lambda d: int(card(d, 0, [5] * 2)[1]), reverse=True)
    assert int(card(level, 0, [5] * 2)[1]) == 1
    h1, h2, angle, length = (float(x) for x in card(level, 2, [10] * 4))
    assert (h1, angle) == (0.002, 0.0) and length == pytest.approx(2e-3 / np.cos(np.radians(
        89.9)), abs=1e-6)
    assert int(card(chord, 0, [5] * 2)[1]) == 2
    h1, h2, angle, length = (float(x) for x in card(chord, 2, [10] * 4))
    assert (h1, h2, angle) == (1.001, 0.001, 0.0)  # lifted whole, as the level path
    assert length == pytest.approx(1.0 / np.cos(np.radians(88.0)), abs=1e-5)


def test_a_level_path_in_sunlight_takes_its_sunlight_from_the_horizons_sky(make, decks):
    """A level path's scattered sunlight is the sky's 89 deg from the zenith along the line
    of sight (a second run, ITYPE 3 from the path's altitude) times 1 - τ."""
    atm = make(sun_zenith=40.0, sun_azimuth=180.0, view_azimuth=90.0)
    out = atm.path(2.0, 0.0, 89.9, WL)
    level, sky = sorted(decks(), key=lambda d: int(card(d, 0, [5] * 2)[1]))  # runs in any order
    assert int(card(level, 0, [5] * 2)[1]) == 1 and int(card(sky, 0, [5] * 2)[1]) == 3
    h1, _h2, angle = (float(x) for x in card(sky, 2, [10] * 3))
    assert (h1, angle) == (0.002, 89.0)
    assert card(sky, 4, [10] * 2) == card(level, 4, [10] * 2)  # the same sun and azimuth
    assert out.scattered_radiance == pytest.approx(np.full(4, SCATTER * 1e4 * (1 - TAU)),
                                                   rel=REL)


def test_line_of_sight_records_every_deck_it_ran(make, decks):
    """``radscene atmosphere los`` of a sunlit level path: its ``tape5`` attribute holds the
    level path's deck, the sun's and the horizon sky's that gives the path its sunlight."""
    atm = make(sun_zenith=40.0, sun_azimuth=180.0, view_azimuth=90.0)
    ds = atm.line_of_sight(2.0, 0.0, 89.9, wavelength=WL)
    recorded = [d.strip("\n").splitlines() for d in ds.attrs["tape5"].split("\n    0\n")]
    itypes = sorted(int(card(d, 0, [5] * 2)[1]) for d in decks())
    assert itypes == [1, 3, 3]  # the level path, the sun's path and the horizon's sky
    assert sorted(int(card(d, 0, [5] * 2)[1]) for d in recorded if d) == itypes


def test_a_path_near_the_ground_keeps_its_length(make, decks):
    """A path of 1 m up from the ground runs level, lifted 1 m off the ground whole: its
    metre of air at 1.5 m (a slant path would lose the lift from its length)."""
    make().path(1.0, 0.0, 0.0, WL)
    h1, h2, angle, length = (float(x) for x in card(decks()[0], 2, [10] * 4))
    assert (h1, angle, length) == (0.0015, 0.0, 0.001)
    assert path_kind(1.5, 0.5, 0.0)[0] == "horizontal"


@pytest.mark.parametrize("geometry, kind", [
    ((700.0, 0.0, 40.0), "slant"), ((100000.0, 0.0, 89.0), "slant"),
    ((2.0, 0.0, 80.0), "horizontal"), ((150.0, 0.0, 60.0), "slant"),
    ((2.0, 0.0, 89.9), "horizontal"),
    ((0.0, 2.0, 90.1), "horizontal"), ((1000.0, 0.0, 88.0), "chord"),
    ((300.0, 0.0, 89.9), "horizontal"), ((3.0, 3.0, 45.0), "none"),
    ((0.2, 0.0, 90.0), "none"), ((5.0, 0.0, 90.0), "contradiction"),
    ((0.0, 0.4, 80.0), "none"),  # within the ground-hit noise, either side
    ((5.0, 0.0, 95.0), "contradiction"),
])
def test_path_kind(geometry, kind):
    assert path_kind(*geometry)[0] == kind


def test_sun_transmittance_and_irradiance(make, decks):
    atm = make()
    toa = np.array([2000.0, 1800.0, 250.0, 0.5])
    out = atm.sun([0.0, 0.0, 500.0], [30.0, 100.0, 30.0], WL, toa)
    assert out.transmittance[0] == pytest.approx(np.full(4, TAU), rel=REL)
    assert np.all(out.transmittance[1] == 0.0)  # sun below the horizon
    assert out.irradiance == pytest.approx(out.transmittance * toa, rel=1e-12)
    runs = decks()
    assert len(runs) == 2
    assert [int(card(d, 0, [5] * 3)[2]) for d in runs] == [3, 3]
    h1, h2, angle, iday = card(runs[0], 2, [10, 10, 10, 5])
    assert (float(h1), float(angle)) in ((0.0, 30.0), (0.5, 30.0))


def test_sky_is_symmetric_about_the_sun(make, decks):
    atm = make()
    geometry = SkyGeometry(target_altitude=0.0, sun_zenith=35.0, sun_azimuth=120.0)
    out = atm.sky([60.0, 60.0], [90.0, 150.0], WL, geometry)
    assert out.shape == (2, 4)
    assert out == pytest.approx(np.full((2, 4), (THERMAL + SCATTER) * 1e4), rel=REL)
    runs = decks()
    assert len(runs) == 1  # 30 deg either side of the sun: one run
    assert int(card(runs[0], 0, [5] * 3)[1]) == 3  # path to space
    assert [float(x) for x in card(runs[0], 4, [10] * 2)] == [30.0, 35.0]
    atm.sky(0.0, 0.0, WL, SkyGeometry(0.0, 120.0, 0.0))  # night: thermal only
    assert int(card(decks()[-1], 0, [5] * 3)[2]) == 1


def test_node_tables(make):
    atm = make(sky_zenith=[0, 45, 80], sky_azimuth=[0, 90, 180, 270])
    assert atm.sky_zenith_nodes().tolist() == [0.0, 45.0, 80.0]
    assert atm.sky_azimuth_nodes().tolist() == [0.0, 90.0, 180.0, 270.0]
    nodes = atm.path_nodes(np.full(100, 3000.0), np.linspace(0, 300, 100),
                           np.linspace(0, 45, 100))
    assert nodes.weight.sum(axis=1) == pytest.approx(np.ones(100), abs=1e-12)
    assert atm.geometry_dependent


# -- datasets ----------------------------------------------------------------------------------
def test_line_of_sight_dataset(make):
    atm = make(sun_zenith=30.0, sun_azimuth=180.0, ground_temperature=300.0, albedo=0.1,
               wavenumber_step=20.0)
    ds = atm.line_of_sight(2000.0, 0.0, 0.0, wavelength_range=(8.0, 12.0))
    wn = ds.wavenumber.values
    assert np.all(np.diff(ds.wavelength.values) > 0)
    assert np.diff(wn) == pytest.approx(np.full(wn.size - 1, -20.0), abs=1e-9)
    assert wn.max() <= 1250.0 and wn.min() >= 1e4 / 12.0
    for name, value in (("transmittance", TAU), ("path_thermal_radiance", THERMAL * 1e4),
                        ("sun_transmittance", TAU), ("direct_solar_irradiance", TSOL * 1e4)):
        assert ds[name].values == pytest.approx(np.full(wn.size, value), rel=REL)
    # beyond 6 um the runs leave out scattered sunlight (documented); below they carry it
    assert np.all(ds.path_scattered_radiance.values == 0.0)
    vis = atm.line_of_sight(2000.0, 0.0, 0.0, wavelength=[0.5, 0.6])
    assert vis.path_scattered_radiance.values == pytest.approx([SCATTER * 1e4] * 2, rel=REL)
    from radscene.radiometry import spectral_radiance

    expected = 0.9 * spectral_radiance(ds.wavelength.values, 300.0) * TAU
    assert ds.boundary_radiance.values == pytest.approx(expected, rel=REL)
    assert ds.path_radiance.attrs["units"] == "W m-2 sr-1 um-1"
    assert "midlatitude_summer" in ds.attrs["parameters"]


def test_sky_radiance_dataset(make):
    ds = make(sun_zenith=30.0, sun_azimuth=0.0).sky_radiance([0, 30, 60], [0, 90],
                                                             wavelength=WL)
    assert ds.sky_radiance.dims == ("zenith", "azimuth", "wavelength")
    assert ds.sky_radiance.shape == (3, 2, 4)
    assert ds.sky_radiance.values == pytest.approx(
        ds.sky_thermal_radiance.values + ds.sky_scattered_radiance.values, rel=1e-12)


def test_sun_from_place_and_time(make):
    when = dt.datetime(2021, 6, 21, 10, 0, tzinfo=dt.UTC)
    atm = make(time=when, latitude=48.0, longitude=11.0)
    from radscene.sun import sun_position

    sun = sun_position(when, 48.0, 11.0)
    assert atm.sun_zenith == pytest.approx(float(sun.zenith), abs=1e-9)
    assert atm.day_of_year == 172
    moved = atm.with_sun(60.0, 90.0, view_azimuth=45.0)
    assert (moved.sun_zenith, moved.sun_azimuth, moved.view_azimuth) == (60.0, 90.0, 45.0)
    assert moved.runner is atm.runner


def test_scaled_columns_run_the_model_as_a_user_atmosphere(make, decks):
    """water/ozone: MODEL 7 at the model's 33 levels, pressure, temperature and the other gases
    flagged as the model's (JCHAR 1-6), H2O/O3 in ppmv times column / model column; the model's
    season and Earth radius given, since a user atmosphere has neither."""
    from radscene.atmosphere.lowtran.profiles import model_columns

    water, ozone = model_columns("midlatitude_winter")
    atm = make(model="midlatitude_winter", water=2.0 * water)
    atm.path(3000.0, 0.0, 0.0, WL)
    deck = decks()[-1]
    c1 = card(deck, 0, [5] * 13)
    assert (int(c1[0]), int(c1[11])) == (7, 1)  # MODEL 7, IM 1
    assert int(card(deck, 1, [5] * 2)[1]) == 2  # the winter model's season (ISEASN 2)
    assert int(card(deck, 2, [5])[0]) == 33  # ML: the model's levels
    first = deck[3]
    z, p, t, h2o, co2, o3 = (float(x) for x in card([first], 0, [10] * 6))
    assert (z, p, t, co2, o3) == (0.0, 1018.0, 272.2, 0.0, 0.0)
    assert h2o == pytest.approx(2.0 * 4316.0, rel=1e-3)  # the model's 4316 ppmv at the ground, doubled
    assert first[60:74] == "33A3" + "3" * 10  # P, T flagged; H2O in ppmv; the rest the model's
    top = deck[3 + 32]
    assert float(card([top], 0, [10])[0]) == 100.0
    radius = float(card(deck, 3 + 33, [10] * 6)[5])
    assert radius == pytest.approx(6371.23)
    tropical = make(model="tropical", ozone=0.3)
    tropical.path(3000.0, 0.0, 0.0, WL)
    deck = decks()[-1]
    assert deck[3][60:74] == "1111A" + "1" * 9 and int(card(deck, 1, [5] * 2)[1]) == 1
    assert float(card(deck, 3 + 33, [10] * 6)[5]) == pytest.approx(6378.39)  # its own radius
    assert float(card([deck[3]], 0, [10] * 6)[5]) == pytest.approx(
        0.02869 * 0.3 / model_columns("tropical")[1], rel=1e-3)


@pytest.mark.parametrize("params, key, match", [
    ({"water": 0.0}, "atmosphere.water", r"must lie in \(0, 15\] g cm-2"),
    ({"water": 16.0}, "atmosphere.water", r"must lie in \(0, 15\] g cm-2"),
    ({"ozone": 300.0}, "atmosphere.ozone", r"must lie in \(0, 1.5\] cm-atm"),
    ({"water": "lots"}, "atmosphere.water", "a number in g cm-2; got 'lots'"),
    ({"water": 2.0, "ground_altitude": 1500.0}, "atmosphere.ground_altitude",
     "water and ozone scale a model at sea level without clouds or rain"),
    ({"ozone": 0.3, "cloud": "stratus"}, "atmosphere.cloud", ".*; remove cloud or the columns"),
    ({"water": 2.0, "rain_rate": 2.0}, "atmosphere.rain_rate", ".*; remove rain_rate or the columns"),
    ({"model": "user", "profile": {"altitude": [0, 1000], "pressure": [1000, 900],
                                   "temperature": [290, 285]}, "water": 2.0},
     "atmosphere.water", "a user profile gives its own water vapour"),
])
def test_scaled_columns_refused(make, params, key, match):
    with pytest.raises(ConfigError, match=f"^{key}: {match}"):
        make(**params)


def test_model_columns_are_the_afgl_models_of_6s():
    """The models' water-vapour columns, integrated from LOWTRAN's own profiles, against the
    columns 6SV1.1 prints for the same McClatchey/AFGL models (sixs_runner.PROFILE_COLUMNS):
    within 1 %."""
    from radscene.atmosphere.lowtran.profiles import model_columns
    from radscene.atmosphere.sixs_runner import PROFILE_COLUMNS

    for model in ("tropical", "midlatitude_summer", "midlatitude_winter", "subarctic_summer",
                  "subarctic_winter", "us_standard"):
        water, ozone = model_columns(model)
        assert water == pytest.approx(PROFILE_COLUMNS[model][0], rel=0.01), model
        assert 0.27 < ozone < 0.38, model  # 277-377 DU


def test_the_renderers_sun_is_lowtrans_own(make):
    """LOWTRAN takes the Earth–Sun distance from its day of the year alone (its orbit table,
    three digits): a sun given by its distance gets the nearest day, and the renderer's direct
    sun is lit by LOWTRAN's spectrum at LOWTRAN's distance, the sun of its scattered light."""
    from types import SimpleNamespace

    from radscene.atmosphere.lowtran.engine import day_for_distance, orbit_factor
    from radscene.render.spectral import sun_toa
    from radscene.sun import toa_solar_irradiance

    atm = make()
    assert atm.day_of_year is None and atm.earth_sun_distance == 1.0  # IDAY 0
    assert atm.with_sun(30.0, 180.0, earth_sun_distance=1.0).day_of_year is None
    near = atm.with_sun(30.0, 180.0, earth_sun_distance=0.9833)  # early January
    assert near.day_of_year == 1 and near.earth_sun_distance == pytest.approx(1.034 ** -0.5)
    far = atm.with_sun(30.0, 180.0, earth_sun_distance=1.0167)  # early July
    assert orbit_factor(far.day_of_year) * 1.0167**2 == pytest.approx(1.0, abs=5e-4)
    dated = atm.with_sun(30.0, 180.0, day_of_year=182, earth_sun_distance=1.0167)
    assert dated.day_of_year == 182 and dated.earth_sun_distance == pytest.approx(0.967 ** -0.5)
    # an engine's own day (given, or from its time) outlives a copy set up by distance alone
    assert make(day_of_year=91).with_sun(30.0, 180.0, earth_sun_distance=1.0).day_of_year == 91
    timed = make(time=dt.datetime(2021, 1, 3, 10, 0, tzinfo=dt.UTC), latitude=48.0, longitude=11.0)
    assert timed.with_sun(60.0, 90.0, earth_sun_distance=1.0).day_of_year == 3
    wl = np.array([0.45, 2.2])
    sun = SimpleNamespace(distance=0.9833, zenith=30.0, azimuth=180.0)
    assert sun_toa(near, sun, wl) == pytest.approx(
        1.034 * toa_solar_irradiance(wl, 1.0, "lowtran"), rel=1e-12)
    assert orbit_factor(91) == pytest.approx(1.001) and orbit_factor(100) == pytest.approx(
        1.001 + 9 * (0.985 - 1.001) / 30)
    with pytest.raises(ConfigError, match=r"^earth_sun_distance: LOWTRAN's sun lies 0.9834-1.0169"):
        day_for_distance(0.95)


def test_the_heat_balance_short_wave_follows_the_engines_sun():
    """The ground's direct irradiance of the heat balance is the engine's transmittance times
    the engine's own sun: its spectrum at its Earth–Sun distance."""
    from radscene.atmosphere.uniform import UniformAtmosphere
    from radscene.sun import toa_solar_irradiance
    from radscene.thermal.irradiance import SHORTWAVE, shortwave_table

    class LowtranLike(UniformAtmosphere):
        solar_spectrum = "lowtran"
        earth_sun_distance = 1.034 ** -0.5

    table = shortwave_table(LowtranLike(transmittance=0.8, sky_radiance=0.0), 0.0, 1, 0.9833)
    expected = 0.8 * 1.034 * np.trapezoid(toa_solar_irradiance(SHORTWAVE, 1.0, "lowtran"),
                                          SHORTWAVE)
    assert table.direct_normal[0] == pytest.approx(expected, rel=1e-9)
    default = shortwave_table(UniformAtmosphere(transmittance=0.8, sky_radiance=0.0), 0.0, 1, 0.9833)
    assert default.direct_normal[0] == pytest.approx(
        0.8 * np.trapezoid(toa_solar_irradiance(SHORTWAVE, 0.9833), SHORTWAVE), rel=1e-9)


def test_visibility_with_its_unit(make):
    assert make(visibility="23 km")._vis == make(visibility="23000 m")._vis == make(
        visibility=23.0)._vis == 23.0


# -- bad input, before anything runs ----------------------------------------------------------
@pytest.mark.parametrize("params, key, match", [
    ({"visibility": 0.0}, "atmosphere.visibility", r"\(0, 10000\] km"),
    ({"visibility": -5.0}, "atmosphere.visibility", r"\(0, 10000\] km"),
    ({"visibility": "23 furlongs"}, "atmosphere.visibility", "unknown length unit 'furlongs'"),
    ({"model": "martian"}, "atmosphere.model", "unknown model atmosphere 'martian'; known: "
                                               "tropical"),
    ({"aerosol": "volcanic"}, "atmosphere.aerosol", "unknown aerosol model .* known: none"),
    ({"model": "user"}, "atmosphere.profile", "needs a profile"),
    ({"albedo": 1.2}, "atmosphere.albedo", r"\[0, 1\]"),
    ({"ground_temperature": -3.0}, "atmosphere.ground_temperature", "K"),
    ({"ground_altitude": 7000.0}, "atmosphere.ground_altitude", r"\[0, 6000\)"),
    ({"sun_zenith": 200.0}, "atmosphere.sun_zenith", r"\[0, 180\]"),
    ({"day_of_year": 400}, "atmosphere.day_of_year", "1-366"),
    ({"wavenumber_step": 12.0}, "atmosphere.wavenumber_step", "multiple of 5"),
    ({"sky_zenith": [0, 95]}, "atmosphere.sky_zenith", r"\[0, 90\]"),
    ({"sky_azimuth": [90, 0]}, "atmosphere.sky_azimuth", "increasing"),
    ({"multiple_scattering": "yes"}, "atmosphere.multiple_scattering", "true or false"),
    ({"air_mass_character": 11}, "atmosphere.air_mass_character", "1 .* to 10"),
    ({"time": dt.datetime(2021, 6, 21, tzinfo=dt.UTC)}, "atmosphere.latitude",
     "needs latitude"),
    ({"sun_zenith": 30.0, "time": dt.datetime(2021, 6, 21, tzinfo=dt.UTC),
      "latitude": 0.0, "longitude": 0.0}, "atmosphere.time", "not both"),
])
def test_bad_parameters(make, params, key, match):
    with pytest.raises(ConfigError, match=match) as info:
        make(**params)
    assert info.value.key == key


@pytest.mark.parametrize("query, key, match", [
    (lambda a: a.path(3000.0, -50.0, 0.0, WL), "target_altitude", "below the ground"),
    (lambda a: a.path(120000.0, 0.0, 0.0, WL), "observer_altitude", "ends at 100 km"),
    (lambda a: a.path(3000.0, 0.0, 0.0, [0.2, 0.5]), "wavelength", "0.25–28 µm"),
    (lambda a: a.path(3000.0, 0.0, 0.0, [10.0, 30.0]), "wavelength", "0.25–28 µm"),
    (lambda a: a.path(3000.0, 0.0, 120.0, WL), "view_zenith", "no line of sight"),
    (lambda a: a.path(3000.0, 0.0, 190.0, WL), "view_zenith", r"\[0, 180\]"),
    (lambda a: a.level_path(0.0, [100.0, 0.0], WL), "length", "finite and > 0"),
    (lambda a: a.level_path(-50.0, 100.0, WL), "altitude", "below the ground"),
    (lambda a: a.sun(-10.0, 30.0, WL, np.ones(4)), "target_altitude", "below the ground"),
    (lambda a: a.sky(95.0, 0.0, WL, SkyGeometry()), "zenith", r"\[0, 90\]"),
    (lambda a: a.line_of_sight(3000.0, 0.0, 0.0, wavelength_range=(12.0, 8.0)),
     "wavelength_range", "increasing"),
])
def test_bad_queries_run_nothing(make, decks, query, key, match):
    atm = make(sun_zenith=30.0, sun_azimuth=0.0, ground_altitude=0.0)
    with pytest.raises(ConfigError, match=match) as info:
        query(atm)
    assert info.value.key == key
    assert decks() == []


def test_a_raised_ground_is_the_bottom_of_every_path(make):
    atm = make(ground_altitude=1500.0)
    with pytest.raises(ConfigError, match="below the surface at 1500 m"):
        atm.path(3000.0, 1000.0, 0.0, WL)


def test_the_type_tagged_dict_builds_and_checks_the_engine(make, monkeypatch):
    # what the scene file's environment.atmosphere does once the lead registers the engine
    from radscene.atmosphere import ENGINES, make_atmosphere

    monkeypatch.setitem(ENGINES, "lowtran", LowtranAtmosphere)
    atm = make_atmosphere({"type": "LOWTRAN", "model": "tropical", "aerosol": "maritime",
                           "visibility": 40.0, "cache": False})
    assert isinstance(atm, LowtranAtmosphere) and atm.name == "lowtran"
    with pytest.raises(ConfigError, match="unknown aerosol model") as info:
        make_atmosphere({"type": "lowtran", "aerosol": "smog"})
    assert info.value.key == "atmosphere.aerosol"
    with pytest.raises(ConfigError, match="takes no key 'visibilty'.*did you mean 'visibility'") as info:
        make_atmosphere({"type": "lowtran", "visibilty": 10.0})
    assert info.value.key == "environment.atmosphere.visibilty"


def test_sky_parts_are_the_scattered_and_thermal_columns(make):
    atm = make()
    geometry = SkyGeometry(target_altitude=0.0, sun_zenith=35.0, sun_azimuth=120.0)
    parts = atm.sky_parts([60.0, 10.0], [90.0, 150.0], WL, geometry)
    assert parts.solar == pytest.approx(np.full((2, 4), SCATTER * 1e4), rel=REL)
    assert parts.thermal == pytest.approx(np.full((2, 4), THERMAL * 1e4), rel=REL)
    assert parts.solar + parts.thermal == pytest.approx(
        atm.sky([60.0, 10.0], [90.0, 150.0], WL, geometry), rel=1e-15)
    night = atm.sky_parts(0.0, 0.0, WL, SkyGeometry(0.0, 120.0, 0.0))
    assert np.all(night.solar == 0.0) and np.all(night.thermal > 0.0)
