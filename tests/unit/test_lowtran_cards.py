"""LOWTRAN7 card decks: fixed columns, optional cards, checks before LOWTRAN runs.

No LOWTRAN needed: these test the text radscene hands to it. Column layouts are those of the
LOWTRAN7 user's manual (Kneizys et al. 1988, AFGL-TR-88-0177, §4), as echoed card by card
in the original LOWTRAN7 sample run (space-physics/lowtran, archive/TAPE4_MasterTape6Reference.txt).
"""

from __future__ import annotations

import pytest

from radscene.atmosphere.lowtran.cards import (
    AEROSOL_WAVELENGTHS,
    LowtranCase,
    ProfileLevel,
    UserAerosolRegion,
    lookup,
    write_tape5,
)
from radscene.errors import ConfigError

# Fortran reads Fw.d fields with an explicit decimal point exactly; tolerances are the
# rounding of the shortest round-trip text (none) or of the widest fitting one.
EXACT = 0.0


def fields(line: str, widths: list[int]) -> list[str]:
    """Cut a card image into fixed-width fields (the Fortran view of it)."""
    out, pos = [], 0
    for w in widths:
        out.append(line[pos:pos + w])
        pos += w
    return out


def test_card1_and_card4_columns():
    # lowtran_pkg_vertical_sw geometry: subarctic winter, ground to space
    deck = write_tape5(LowtranCase(model=5, itype=3, iemsct=0, h1=0.0, angle=0.0,
                                   v1=1e7 / 900, v2=1e7 / 500, dv=20.0, tbound=288.15,
                                   salb=0.25))
    lines = deck.splitlines()
    assert len(lines) == 5  # cards 1, 2, 3, 4, 5
    card1 = fields(lines[0], [5] * 13 + [8, 7])
    assert [int(x) for x in card1[:13]] == [5, 3, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0]
    assert float(card1[13]) == pytest.approx(288.15, abs=EXACT)
    assert float(card1[14]) == pytest.approx(0.25, abs=EXACT)
    v1, v2, dv = (float(x) for x in fields(lines[3], [10, 10, 10]))
    assert v1 == pytest.approx(11111.111, abs=1e-3)  # 10 columns hold 1e7/900 to 1e-3
    assert (v2, dv) == (20000.0, 20.0)
    assert lines[4] == "    0"
    assert deck.endswith("\n")


def test_every_real_field_carries_a_decimal_point():
    # Without one Fortran would scale the digits by the field's implied decimals
    deck = write_tape5(LowtranCase(model=6, itype=2, ihaze=1, vis=23, h1=1, h2=6, angle=0,
                                   v1=990, v2=1090, dv=5))
    card3 = fields(deck.splitlines()[2], [10] * 6 + [5])
    assert all("." in f for f in card3[:6])
    assert [float(f) for f in card3[:3]] == [1.0, 6.0, 0.0]


def test_optional_cards_follow_their_switches():
    # tape6 sample case 7 (cirrus, card 2A) and case 10 (army VSA, card 2B)
    cirrus = write_tape5(LowtranCase(model=1, itype=2, ihaze=1, icld=19, h1=7, h2=12,
                                     range=500, v1=900, v2=1145)).splitlines()
    assert len(cirrus) == 6
    assert fields(cirrus[2], [10, 10, 10, 10])[3].strip() == "0"  # ISEED I10
    vsa = write_tape5(LowtranCase(model=6, itype=2, ihaze=6, ivsa=1, h1=0, h2=1.8, angle=45,
                                  v1=900, v2=1145)).splitlines()
    assert len(vsa) == 6 and [float(x) for x in fields(vsa[2], [10] * 3)] == [0.0] * 3


def test_solar_scattering_cards_3a1_3a2():
    deck = write_tape5(LowtranCase(model=2, itype=2, iemsct=2, imult=1, h1=3, h2=0.001,
                                   angle=150, iparm=2, iph=2, iday=172, parm1=-45.0,
                                   parm2=30.0, v1=10000, v2=25000)).splitlines()
    assert len(deck) == 7
    assert [int(x) for x in fields(deck[3], [5] * 4)] == [2, 2, 172, 0]
    assert [float(x) for x in fields(deck[4], [10] * 8)][:2] == [-45.0, 30.0]


def test_irradiance_mode_uses_the_alternate_card3():
    # lowtran_pkg_irradiance_60deg: H1, H2, ANGLE, IDAY, (5X), RO, ISOURC, ANGLEM
    deck = write_tape5(LowtranCase(model=5, itype=3, iemsct=3, h1=0, angle=60, iday=-99,
                                   isourc=-99, anglem=-99, v1=400, v2=50000, dv=20))
    card3 = deck.splitlines()[2]
    h1, h2, angle, iday, blank, ro, isourc, anglem = fields(card3, [10, 10, 10, 5, 5, 10, 5, 10])
    assert (float(angle), int(iday), blank, int(isourc), float(anglem)) == (60.0, -99, " " * 5,
                                                                            -99, -99.0)


def test_user_atmosphere_cards_2c():
    # tape6 sample case 9: one level, pressure mb, temperature degC, H2O as RH
    level = ProfileLevel(z=0.0, p=1013.0, t=10.0, wmol=(10.0,) + (0.0,) * 11,
                         jchar="ABH6A666666666")
    lines = write_tape5(LowtranCase(model=0, itype=1, im=1, ihaze=1, rainrt=10.0,
                                    title="NSM RUN", levels=(level,), range=0.3, v1=900,
                                    v2=1145)).splitlines()
    assert fields(lines[2], [5, 5, 5])[0].strip() == "1"
    assert lines[2][15:].strip() == "NSM RUN"
    z, p, t, h2o, co2, o3 = (float(x) for x in fields(lines[3], [10] * 6))
    assert (z, p, t, h2o) == (0.0, 1013.0, 10.0, 10.0)
    assert lines[3][60:74] == "ABH6A666666666"


def test_user_aerosol_cards_2d():
    region = UserAerosolRegion(awccon=0.0, extinction=(1.0,) * 47, absorption=(0.1,) * 47,
                               asymmetry=(0.7,) * 47, title="dust")
    lines = write_tape5(LowtranCase(model=6, itype=2, ihaze=7, ireg=(1, 0, 0, 0),
                                    aerosol_regions=(region,), h1=0, h2=1, angle=0, v1=900,
                                    v2=1145)).splitlines()
    assert lines[2] == "    1    0    0    0"
    rows = lines[4:4 + 16]  # 47 wavelengths, three per card
    first = fields(rows[0], [6, 7, 7, 6])
    assert float(first[0]) == pytest.approx(AEROSOL_WAVELENGTHS[0], abs=EXACT)
    assert [float(x) for x in first[1:]] == [1.0, 0.1, 0.7]
    assert len(rows[-1]) <= 26 * 2  # the 16th card holds wavelengths 46 and 47


@pytest.mark.parametrize("value, width", [(0.0, 10), (1e-5, 10), (94.466, 10),
                                          (33333.332, 10), (-99.0, 5), (1 / 3, 10),
                                          (6.02e23, 10), (1013.25, 7)])
def test_reals_fit_and_read_back(value, width):
    from radscene.atmosphere.lowtran.cards import _real

    text = _real(value, width)
    assert len(text) == width and "." in text
    assert float(text) == pytest.approx(value, rel=1e-4, abs=1e-12)


@pytest.mark.parametrize("changes, key, match", [
    ({"model": 9}, "model", "one of"),
    ({"ihaze": 11}, "ihaze", "one of"),
    ({"salb": 1.5}, "salb", r"\[0, 1\]"),
    ({"h1": 120.0}, "h1", r"\[0, 100\]"),
    ({"h2": -0.1}, "h2", r"\[0, 100\]"),
    ({"angle": 181.0}, "angle", r"\[0, 180\]"),
    ({"dv": 7.0}, "dv", "multiple of 5"),
    ({"v2": 50001.0}, "v2", "50000"),
    ({"v1": 2000.0, "v2": 1000.0}, "v2", "exceed v1"),
    ({"gndalt": 6.0}, "gndalt", r"\[0, 6\)"),
    ({"vis": -1.0}, "vis", r"\[0, inf\]"),
    ({"model": 0, "itype": 2}, "itype", "horizontal"),
    ({"model": 7}, "im", "im = 1"),
    ({"model": 7, "im": 1}, "levels", "1 to 34 levels"),
    ({"itype": 1, "range": 0.0}, "range", "range > 0"),
    ({"iemsct": 2, "parm2": 95.0}, "parm2", r"\[0, 90\)"),
    ({"iemsct": 2, "iph": 0, "g": 1.0}, "g", r"\(-1, 1\)"),
    ({"iemsct": 2, "iph": 1}, "phase_angles", "2 to 50"),
    ({"ihaze": 7, "ireg": (1, 0, 0, 0)}, "ireg", "one aerosol region"),
])
def test_bad_fields_are_refused_before_any_run(changes, key, match):
    case = LowtranCase(itype=2, h1=1.0, h2=0.0, angle=180.0, v1=900.0, v2=1100.0).replace(
        **changes)
    with pytest.raises(ConfigError, match=match) as info:
        write_tape5(case)
    assert info.value.key == f"lowtran.{key}"


def test_user_levels_are_checked():
    bad_order = (ProfileLevel(1.0, 900.0, 280.0), ProfileLevel(0.5, 950.0, 285.0))
    case = LowtranCase(model=7, im=1, levels=bad_order, itype=2, h1=1, h2=0.5, angle=180)
    with pytest.raises(ConfigError, match="increase strictly"):
        case.check()
    bad_flags = (ProfileLevel(0.0, 1000.0, 290.0, jchar="AAZ"),)
    with pytest.raises(ConfigError, match="flags") as info:
        LowtranCase(model=0, itype=1, im=1, levels=bad_flags, range=1.0).check()
    assert info.value.key == "lowtran.levels[0].jchar"


def test_replace_refuses_unknown_fields():
    with pytest.raises(ConfigError, match="unknown LOWTRAN card field"):
        LowtranCase().replace(visibility=23.0)


def test_lookup_is_case_insensitive_and_lists_the_known():
    from radscene.atmosphere.lowtran.cards import AEROSOLS

    assert lookup(AEROSOLS, "Navy-Maritime", "k", "aerosol") == 3
    with pytest.raises(ConfigError, match="known: none, rural"):
        lookup(AEROSOLS, "volcanic", "atmosphere.aerosol", "aerosol model")
