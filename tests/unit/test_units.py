"""Unit tests of radscene.radiometry.units.parse_quantity."""

import math

import pytest

from radscene.errors import ConfigError
from radscene.radiometry import CANONICAL_UNITS, UNITS, parse_quantity

REL = 1e-12


@pytest.mark.parametrize(
    ("value", "kind", "expected"),
    [
        ("300 K", "temperature", 300.0),
        ("25 degC", "temperature", 298.15),
        ("-40 °C", "temperature", 233.15),
        ("77 degF", "temperature", 298.15),
        ("-40 degF", "temperature", 233.15),  # -40 °F = -40 °C
        ("10 um", "wavelength", 10.0),
        ("10 µm", "wavelength", 10.0),  # micro sign U+00B5
        ("10 μm", "wavelength", 10.0),  # Greek mu U+03BC
        ("550 nm", "wavelength", 0.55),
        ("500 m", "length", 500.0),
        ("2 km", "length", 2000.0),
        ("1.5e3 mm", "length", 1.5),
        ("30 deg", "angle", 30.0),
        ("0.5 rad", "angle", 0.5 * 180.0 / math.pi),
        ("10 s", "time", 10.0),
        ("5 min", "time", 300.0),
        ("1 h", "time", 3600.0),
        ("1000 W m-2", "irradiance", 1000.0),
        ("1 mW cm-2", "irradiance", 10.0),
        ("2 W cm-2 sr-1", "radiance", 2.0e4),
        ("50 %", "dimensionless", 0.5),
        ("  42   ", "length", 42.0),
        (300, "temperature", 300.0),
        (0.55, "wavelength", 0.55),
    ],
)
def test_parse_quantity(value, kind, expected):
    assert parse_quantity(value, kind) == pytest.approx(expected, rel=REL)


@pytest.mark.parametrize("kind", sorted(UNITS))
def test_every_unit_in_the_table_parses_and_canonical_is_identity(kind):
    assert CANONICAL_UNITS[kind] in UNITS[kind]
    assert parse_quantity(f"7 {CANONICAL_UNITS[kind]}", kind) == pytest.approx(7.0, rel=REL)
    for unit, (factor, offset) in UNITS[kind].items():
        assert parse_quantity(f"300 {unit}", kind) == pytest.approx(
            300.0 * factor + offset, rel=REL
        )


def test_unknown_unit_lists_accepted_units():
    with pytest.raises(
        ConfigError, match=r"unknown temperature unit 'R'.*accepted: K, kelvin, degC"
    ):
        parse_quantity("500 R", "temperature")
    with pytest.raises(ConfigError, match=r"^scene.sun.time: unknown time unit 'fortnight'"):
        parse_quantity("1 fortnight", "time", key="scene.sun.time")


@pytest.mark.parametrize(
    ("value", "kind", "match"),
    [
        ("warm", "temperature", "expected '<number> <unit>'"),
        ("-5 K", "temperature", "temperature below 0 K"),
        ("-300 degC", "temperature", "temperature below 0 K"),
        (True, "length", "expected a number or a string"),
        ([1.0], "length", "expected a number or a string"),
        (float("nan"), "length", "must be finite"),
        ("1 um", "colour", "unknown quantity kind 'colour'; known: temperature"),
    ],
)
def test_bad_values_raise(value, kind, match):
    with pytest.raises(ConfigError, match=match):
        parse_quantity(value, kind)
