"""The LOWTRAN runner and output parser, with a stand-in executable.

The stand-in is a small Python script that behaves as the radscene-lowtran7 executable does
(reads TAPE5, writes out/TAPE6 and radscene.out) and, on request, as LOWTRAN does when it
fails: a Fortran STOP (no result, exit status 0), a hang, a NaN. So these tests need no
Fortran compiler and can check what the real code cannot be made to do on demand.
"""

from __future__ import annotations

import os
import stat
import sys
import textwrap

import numpy as np
import pytest

from radscene.atmosphere.lowtran import runner as runner_module
from radscene.atmosphere.lowtran.parser import (
    DRIVER_COLUMNS,
    parse_driver_output,
    parse_tape6_summary,
    tape6_messages,
)
from radscene.atmosphere.lowtran.runner import NOT_BUILT, LowtranRunner, find_executable
from radscene.errors import ConfigError, EngineError

# W cm-2 -> W m-2 is exactly 1e4; the stand-in writes 8 significant digits
REL = 1e-7

FAKE = textwrap.dedent("""\
    import os, sys, time
    deck = open("TAPE5").read()
    counter = os.environ.get("FAKE_LOWTRAN_COUNTER")
    if counter:
        with open(counter, "a") as f:
            f.write("run\\n")
    if "FAKE:STOP" in deck:
        open("out/TAPE6", "w").write("0 INVALID PARAMETER :  Z\\n")
        print(" JOU: BAD PARAM")
        sys.exit(0)  # a Fortran STOP ends the process without an error status
    if "FAKE:HANG" in deck:
        time.sleep(30)
    nan = "FAKE:NAN" in deck
    rows = []
    for v in (1000.0, 1005.0, 1010.0):  # LOWTRAN writes increasing wavenumber
        tau = float("nan") if nan else 0.5 + (v - 1000.0) / 100.0
        rows.append((v, 1e4 / v, tau, 2e-4, 3e-5, 4e-5, 5e-6, 1.0, 1.0))
    with open("radscene.out", "w") as f:
        f.write("# radscene-lowtran7 1 points %d\\n" % len(rows))
        for r in rows:
            f.write("".join(" %16.8E" % x for x in r) + "\\n")
        f.write("# end\\n")
    open("out/TAPE6", "w").write(
        "0INTEGRATED ABSORPTION FROM 1000 TO 1010 CM-1 =      4.50 CM-1\\n"
        " AVERAGE TRANSMITTANCE = .5500\\n")
    if int(deck.splitlines()[0][10:15]) == 2:  # TAPE7: RFLS 6e-8, RFLSS 4e-8 per cm-1
        with open("out/TAPE7", "w") as f:
            f.write("  FREQ   TRANS     ATMOS   PATH     SINGLE   GROUND DIRECT   TOTAL RAD\\n")
            for r in rows:
                f.write("%7.0f%8.4f" % (r[0], r[2]) + "".join("%9.2E" % x for x in
                        (0.0, 1e-7, 1e-8, 6e-8, 4e-8, 2e-7)) + "%8.4f%8.4f\\n" % (0.3, 0.5))
            f.write(" -9999.\\n")
""")


def deck(mode: int, marker: str = "") -> str:
    """A raw TAPE5 whose card 1 carries IEMSCT = ``mode``; the stand-in reads the marker."""
    return f"    6    2{mode:5d}\n{marker}\n"


@pytest.fixture
def fake_exe(tmp_path):
    path = tmp_path / "fake-lowtran"
    path.write_text(f"#!{sys.executable}\n{FAKE}")
    path.chmod(path.stat().st_mode | stat.S_IXUSR)
    return path


@pytest.fixture
def counter(tmp_path, monkeypatch):
    path = tmp_path / "runs.txt"
    monkeypatch.setenv("FAKE_LOWTRAN_COUNTER", str(path))

    def count():
        return len(path.read_text().splitlines()) if path.exists() else 0
    return count


# -- parser ------------------------------------------------------------------------------------
def test_parse_driver_output_reads_every_column():
    text = ("# radscene-lowtran7 1 points 2\n"
            + " 1.0E+003 1.0E+001 0.5 1.0 2.0 3.0 4.0 0.9 0.8\n"
            + " 1.1E+003 9.0E+000 0.6 1.1 2.1 3.1 4.1 0.9 0.8\n# end\n")
    cols = parse_driver_output(text)
    assert list(cols) == list(DRIVER_COLUMNS)
    assert cols["wavenumber"].tolist() == [1000.0, 1100.0]
    assert cols["scattered_radiance"].tolist() == [4.0, 4.1]


@pytest.mark.parametrize("text, match", [
    ("", "empty output"),
    ("garbage\n", "not radscene-lowtran7 output"),
    ("# radscene-lowtran7 2 points 0\n# end\n", "version 2"),
    ("# radscene-lowtran7 1 points 0\n# end\n", "no spectral sample"),
    ("# radscene-lowtran7 1 points 2\n 1 2 3 4 5 6 7 8 9\n", "ends early"),
    ("# radscene-lowtran7 1 points 1\n 1 2 3\n# end\n", "9 columns"),
])
def test_parse_driver_output_refuses_incomplete_files(text, match):
    with pytest.raises(ValueError, match=match):
        parse_driver_output(text)


def test_tape6_summary_and_messages():
    # lines as LOWTRAN prints them (tape6 sample case 4)
    text = ("0INTEGRATED ABSORPTION FROM  990 TO 1090 CM-1 =     13.03 CM-1\n"
            " AVERAGE TRANSMITTANCE = .8697\n"
            "0 GNDALT GT 6.0 RESET TO ZERO, GNDALT WAS     7.000\n"
            "0 CARD 1  *****    6    2\n")
    assert parse_tape6_summary(text) == {"integrated_absorption": 13.03,
                                         "average_transmittance": 0.8697}
    assert tape6_messages(text) == ["GNDALT GT 6.0 RESET TO ZERO, GNDALT WAS     7.000"]


# -- runner ------------------------------------------------------------------------------------
def test_results_in_radscene_units_and_order(fake_exe, tmp_path):
    runner = LowtranRunner(executable=fake_exe, cache_dir=tmp_path / "cache")
    thermal, scatter, irr = runner.run([deck(1), deck(2), deck(3)], ["t", "s", "i"])
    assert thermal.wavenumber.tolist() == [1000.0, 1005.0, 1010.0]
    assert thermal.wavelength == pytest.approx([10.0, 1e4 / 1005, 1e4 / 1010], rel=REL)
    assert thermal.thermal_radiance == pytest.approx([2.0] * 3, rel=REL)  # 2e-4 W cm-2 ...
    assert thermal.scattered_radiance is None and thermal.solar_irradiance is None
    assert scatter.scattered_radiance == pytest.approx([0.05] * 3, rel=REL)
    # TAPE7's RFLS [W cm-2 sr-1 (cm-1)-1] as RFLSOL [W m-2 sr-1 um-1]: 6e-8 v^2
    assert scatter.ground_radiance == pytest.approx([6e-8 * v**2 for v in (1000, 1005, 1010)],
                                                    rel=REL)
    assert thermal.ground_radiance is None and irr.ground_radiance is None
    assert irr.solar_irradiance == pytest.approx([0.3] * 3, rel=REL)
    assert irr.toa_irradiance == pytest.approx([0.4] * 3, rel=REL)
    assert irr.thermal_radiance is None
    assert scatter.summary == {"integrated_absorption": 4.5, "average_transmittance": 0.55}
    ds = scatter.to_dataset()
    assert ds.wavelength.values.tolist() == sorted(ds.wavelength.values.tolist())
    assert ds.transmittance.values == pytest.approx([0.6, 0.55, 0.5], rel=REL)
    assert ds.scattered_radiance.attrs["units"] == "W m-2 sr-1 um-1"


def test_disk_cache_is_keyed_by_deck_and_executable(fake_exe, tmp_path, counter):
    cache = tmp_path / "cache"
    first = LowtranRunner(executable=fake_exe, cache_dir=cache).run([deck(0)])[0]
    again = LowtranRunner(executable=fake_exe, cache_dir=cache).run([deck(0)])[0]
    assert counter() == 1  # the second runner read the disk cache
    np.testing.assert_array_equal(again.transmittance, first.transmittance)
    assert again.deck == first.deck and again.summary == first.summary
    LowtranRunner(executable=fake_exe, cache_dir=cache).run([deck(0, "another case")])
    assert counter() == 2
    # a rebuilt executable invalidates every entry
    fake_exe.write_text(fake_exe.read_text() + "\n# rebuilt\n")
    os.utime(fake_exe, (1e9, 1e9))
    LowtranRunner(executable=fake_exe, cache_dir=cache).run([deck(0)])
    assert counter() == 3
    LowtranRunner(executable=fake_exe, cache_dir=cache, cache=False).run([deck(0)])
    assert counter() == 4
    assert len(list(cache.rglob("*.npz"))) == 3


@pytest.mark.parametrize("umask", [0o022, 0o002, 0o077])
def test_cache_entries_get_the_mode_of_other_new_files(fake_exe, tmp_path, umask):
    """0666 less the umask, as any output, so that colleagues sharing the cache folder
    (RADSCENE_CACHE_DIR on shared storage) read them; no temporary is left beside them."""
    cache = tmp_path / "cache"
    old = os.umask(umask)
    try:
        first = LowtranRunner(executable=fake_exe, cache_dir=cache).run([deck(0)])[0]
    finally:
        os.umask(old)
    (entry,) = [p for p in cache.rglob("*") if p.is_file()]
    assert entry.suffix == ".npz" and entry.stat().st_mode & 0o777 == 0o666 & ~umask
    again = LowtranRunner(executable=fake_exe, cache_dir=cache).run([deck(0)])[0]
    np.testing.assert_array_equal(again.transmittance, first.transmittance)


def test_a_failed_cache_write_leaves_neither_entry_nor_temporary(tmp_path):
    from radscene.atmosphere.cache_files import write_entry

    def fail(handle):
        handle.write(b"half")
        raise OSError("disk full")

    with pytest.raises(OSError, match="disk full"):
        write_entry(tmp_path / "entry.npz", fail)
    assert list(tmp_path.iterdir()) == []


def test_parallel_runs_share_identical_decks(fake_exe, tmp_path, counter):
    runner = LowtranRunner(executable=fake_exe, cache=False, workers=3)
    decks = [deck(0, f"case {i % 3}") for i in range(9)]
    results = runner.run(decks)
    assert counter() == 3 and runner.runs == 3
    assert [r.deck for r in results] == decks


def test_a_fortran_stop_is_an_engine_error_naming_the_case(fake_exe):
    runner = LowtranRunner(executable=fake_exe, cache=False)
    with pytest.raises(EngineError, match="'sky at dusk' failed.*INVALID PARAMETER"):
        runner.run([deck(2, "FAKE:STOP")], ["sky at dusk"])


def test_a_hanging_run_times_out(fake_exe):
    runner = LowtranRunner(executable=fake_exe, cache=False, timeout=0.5)
    with pytest.raises(EngineError, match=r"'slow' ran past its timeout of 0.5 s \(atmosphere\.timeout\)"):
        runner.run([deck(0, "FAKE:HANG")], ["slow"])


def test_non_finite_output_is_an_engine_error(fake_exe):
    runner = LowtranRunner(executable=fake_exe, cache=False)
    with pytest.raises(EngineError, match="'bad' returned non-finite transmittance"):
        runner.run([deck(0, "FAKE:NAN")], ["bad"])


def test_missing_executable_says_how_to_build(tmp_path, monkeypatch):
    monkeypatch.setattr(runner_module, "candidate_executable_paths",
                        lambda: [tmp_path / "nowhere" / "radscene-lowtran7"])
    monkeypatch.setenv("PATH", str(tmp_path))
    with pytest.raises(EngineError, match="make lowtran") as info:
        find_executable()
    assert NOT_BUILT in str(info.value)
    assert not runner_module.lowtran_available()


def test_bad_runner_options(tmp_path):
    with pytest.raises(ConfigError, match="not an executable") as info:
        find_executable(tmp_path / "missing")
    assert info.value.key == "executable"
    with pytest.raises(ConfigError, match="positive integer"):
        LowtranRunner(workers=0)
    with pytest.raises(ConfigError, match="> 0 s"):
        LowtranRunner(timeout=-1)
    with pytest.raises(ConfigError, match="one name per case"):
        LowtranRunner(cache=False).run([deck(0)], ["a", "b"])
    with pytest.raises(ConfigError, match="LowtranCase or a TAPE5"):
        LowtranRunner(cache=False).run([42])


def test_default_cache_dir_follows_the_environment(tmp_path, monkeypatch):
    monkeypatch.setenv("RADSCENE_CACHE_DIR", str(tmp_path / "rc"))
    assert runner_module.default_cache_dir() == tmp_path / "rc" / "lowtran"
    monkeypatch.delenv("RADSCENE_CACHE_DIR")
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "xdg"))
    assert runner_module.default_cache_dir() == tmp_path / "xdg" / "radscene" / "lowtran"
