"""radscene.errors.unreadable: a library's reason for a bad file, quoting none of the file."""

from __future__ import annotations

import pytest

from radscene.errors import unreadable


@pytest.mark.parametrize("err, expected", [
    (ValueError("could not convert string to float: 'hunter2'"), "could not convert string to float: …"),
    (ValueError('bad token "hunter2" at 3'), "bad token … at 3"),
    (UnicodeDecodeError("utf-8", b"\xff", 0, 1, "invalid start byte"), "not a text (UTF-8) file"),
    (OSError(21, "Is a directory"), "Is a directory"),
    (ValueError("one\ntwo 'hunter2'"), "one"),
    (ValueError("xarray's backends ['h5netcdf']"), "xarray's backends […]"),
    (KeyError(), "KeyError"),
])
def test_a_reason_quotes_nothing_and_keeps_one_line(err, expected):
    assert unreadable(err) == expected


def test_a_long_reason_is_cut():
    text = unreadable(ValueError("x" * 500))
    assert len(text) == 120 and text.endswith("…")


@pytest.mark.parametrize("given, known, suggested", [
    ("asfalt", ["asphalt", "concrete"], "asphalt"),
    ("cma", ["map", "cam"], "cam"),  # two keys swapped: the same letters win a tie
    ("ASPHALT", ["asphalt"], "asphalt"),
    ("midlatitude_sumer", ["midlatitude_summer", "midlatitude_winter"], "midlatitude_summer"),
    ("qqq", ["asphalt"], None),
])
def test_did_you_mean(given, known, suggested):
    from radscene.errors import did_you_mean

    text = did_you_mean(given, known)
    assert text == (f"; did you mean {suggested!r}?" if suggested else "")
