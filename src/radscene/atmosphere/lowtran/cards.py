"""LOWTRAN7 card decks (``TAPE5``): one case, every card, checked before LOWTRAN sees it.

A :class:`LowtranCase` holds the fields of cards 1 to 5 under the names of the LOWTRAN7
user's manual (Kneizys et al. 1988, AFGL-TR-88-0177, §4), in LOWTRAN's own units because
they map one-to-one onto the cards: altitudes and ranges [km], angles [deg], pressure [mb],
temperature [K], wavenumbers [cm-1], visibility (meteorological range) [km], wind [m s-1],
rain rate [mm h-1]. :func:`write_tape5` writes the deck; :meth:`LowtranCase.check` raises
:class:`~radscene.errors.ConfigError` naming the field for anything LOWTRAN would refuse,
silently reset, or die on.

Cards written (optional ones only when their switch is set):

======  ==========================================================  ==========================
card    fields                                                      when
======  ==========================================================  ==========================
1       model itype iemsct imult m1..m6 mdef im noprt tbound salb   always
2       ihaze iseasn ivulcn icstl icld ivsa vis wss whh rainrt      always
        gndalt
2A      cthik calt cext iseed                                       icld in 18, 19, 20
2B      zcvsa ztvsa zinvsa                                          ivsa = 1
2C      ml ird1 ird2 title, then per level 2C1 (z p t wmol1-3       model 0 or 7, im = 1
        jchar), 2C2 (wmol4-12, ird1 = 1), 2C3 (aerosol, ird2 = 1)
2D      ireg(4), per region 2D1 (awccon title), 2D2 (47 rows)       ihaze = 7 or icld = 11
3       h1 h2 angle range beta ro len                               iemsct 0, 1, 2
3*      h1 h2 angle iday ro isourc anglem                           iemsct = 3
3A1     iparm iph iday isourc                                       iemsct = 2
3A2     parm1..parm4 time psipo anglem g                            iemsct = 2
3B1/2   user phase function (angles and four regions)               iemsct = 2, iph = 1
4       v1 v2 dv                                                    always
5       irpt = 0 (one case per deck; the runner runs decks apart)   always
======  ==========================================================  ==========================
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, fields

from radscene.errors import ConfigError, did_you_mean

__all__ = [
    "MODELS",
    "AEROSOLS",
    "SEASONS",
    "STRATOSPHERIC_AEROSOLS",
    "CLOUDS",
    "PHASE_FUNCTIONS",
    "AEROSOL_WAVELENGTHS",
    "ProfileLevel",
    "UserAerosolRegion",
    "LowtranCase",
    "write_tape5",
    "lookup",
]

#: Model atmospheres (card 1 MODEL); "user" profiles are MODEL = 7 with card 2C.
MODELS: dict[str, int] = {
    "tropical": 1,
    "midlatitude_summer": 2,
    "midlatitude_winter": 3,
    "subarctic_summer": 4,
    "subarctic_winter": 5,
    "us_standard": 6,
}

#: Boundary-layer aerosol models (card 2 IHAZE); visibility on card 2 overrides the default
#: meteorological range except where the model derives its own (navy maritime, desert).
AEROSOLS: dict[str, int] = {
    "none": 0,
    "rural": 1,
    "navy_maritime": 3,
    "maritime": 4,
    "urban": 5,
    "tropospheric": 6,
    "advective_fog": 8,
    "radiative_fog": 9,
    "desert": 10,
}

#: Aerosol season (card 2 ISEASN); "auto" follows the model atmosphere.
SEASONS: dict[str, int] = {"auto": 0, "spring_summer": 1, "fall_winter": 2}

#: Stratospheric aerosol type / profile (card 2 IVULCN).
STRATOSPHERIC_AEROSOLS: dict[str, int] = {
    "background": 0,
    "aged_moderate": 2,
    "fresh_high": 3,
    "aged_high": 4,
    "fresh_moderate": 5,
    "background_moderate": 6,
    "background_high": 7,
    "fresh_extreme": 8,
}

#: Cloud and rain models (card 2 ICLD).
CLOUDS: dict[str, int] = {
    "none": 0,
    "cumulus": 1,
    "altostratus": 2,
    "stratus": 3,
    "stratus_stratocumulus": 4,
    "nimbostratus": 5,
    "drizzle": 6,
    "light_rain": 7,
    "moderate_rain": 8,
    "heavy_rain": 9,
    "extreme_rain": 10,
    "standard_cirrus": 18,
    "subvisual_cirrus": 19,
    "noaa_cirrus": 20,
}

#: Aerosol phase functions for solar scattering (card 3A1 IPH; 1 = user tables on card 3B).
PHASE_FUNCTIONS: dict[str, int] = {"henyey_greenstein": 0, "mie": 2}

#: The 47 wavelengths [um] of LOWTRAN7's aerosol tables, the rows of card 2D2.
AEROSOL_WAVELENGTHS: tuple[float, ...] = (
    0.2, 0.3, 0.3371, 0.55, 0.6943, 1.06, 1.536, 2.0, 2.25, 2.5, 2.7, 3.0, 3.3923, 3.75,
    4.5, 5.0, 5.5, 6.0, 6.2, 6.5, 7.2, 7.9, 8.2, 8.7, 9.0, 9.2, 10.0, 10.591, 11.0, 11.5,
    12.5, 14.8, 15.0, 16.4, 17.2, 18.5, 21.3, 25.0, 30.0, 40.0, 50.0, 60.0, 80.0, 100.0,
    150.0, 200.0, 300.0,
)

#: Highest wavenumber LOWTRAN computes [cm-1] and its finest sampling [cm-1].
WAVENUMBER_MAX = 50000.0
WAVENUMBER_STEP_MIN = 5.0
#: Most samples the radscene driver stores per run.
MAX_SAMPLES = 10010
#: Levels of a user profile (card 2C ML).
MAX_LEVELS = 34
#: Top of LOWTRAN's atmosphere [km].
TOP_ALTITUDE = 100.0


def lookup(table: dict[str, int], name, key: str, what: str) -> int:
    """Code of ``name`` in a name → code table, case-insensitive; ConfigError otherwise."""
    if isinstance(name, str):
        code = table.get(name.strip().lower().replace("-", "_").replace(" ", "_"))
        if code is not None:
            return code
    raise ConfigError(f"unknown {what} {name!r}; known: {', '.join(table)}"
                      f"{did_you_mean(name, table)}", key=key)


@dataclass(frozen=True)
class ProfileLevel:
    """One level of a user atmosphere (cards 2C1, 2C2, 2C3).

    Attributes
    ----------
    z : float
        Altitude [km].
    p, t : float
        Pressure and temperature in the units ``jchar[0]``, ``jchar[1]`` select
        (blank/A: mb and K).
    wmol : tuple of float
        The 12 amounts H2O, CO2, O3, N2O, CO, CH4, O2, NO, SO2, NO2, NH3, HNO3, in the units
        ``jchar[2:]`` select (A ppmv, B cm-3, C g/kg, D g m-3, E mb, F/G dew point K/C,
        H relative humidity % (H2O only), 1-6 the default of that model atmosphere).
    jchar : str
        Up to 14 unit flags: pressure, temperature, then the 12 species.
    aerosol : tuple, optional
        Card 2C3: (ahaze [km-1], eqlwcz [g m-3], rratz [mm h-1], iha1, icld1, ivul1, isea1,
        ichr); needs ``ird2 = 1``.
    """

    z: float
    p: float
    t: float
    wmol: tuple[float, ...] = (0.0,) * 12
    jchar: str = ""
    aerosol: tuple | None = None


@dataclass(frozen=True)
class UserAerosolRegion:
    """User aerosol optical properties for one region (cards 2D1, 2D2).

    Attributes
    ----------
    awccon : float
        Equivalent liquid water content [g m-3].
    extinction, absorption, asymmetry : tuple of float
        47 values each, at :data:`AEROSOL_WAVELENGTHS`; extinction and absorption normalised
        to the extinction at 0.55 um [-], asymmetry parameter [-].
    title : str
        Label (up to 60 characters).
    """

    awccon: float
    extinction: tuple[float, ...]
    absorption: tuple[float, ...]
    asymmetry: tuple[float, ...]
    title: str = ""


@dataclass(frozen=True)
class LowtranCase:
    """Every field of one LOWTRAN7 run (see the module table for the cards).

    Field names are the manual's, lower-case; units are LOWTRAN's (module docstring).
    ``levels`` are the user profile (MODEL 0 or 7 with IM = 1); ``ireg`` and
    ``aerosol_regions`` the user aerosols (IHAZE = 7 or ICLD = 11); ``phase_angles`` and
    ``phase_functions`` the user phase function (IPH = 1), one 4-tuple (boundary layer,
    troposphere, stratosphere, upper atmosphere) per angle.
    """

    model: int = 6
    itype: int = 2
    iemsct: int = 0
    imult: int = 0
    m1: int = 0
    m2: int = 0
    m3: int = 0
    m4: int = 0
    m5: int = 0
    m6: int = 0
    mdef: int = 0
    im: int = 0
    noprt: int = 0
    tbound: float = 0.0
    salb: float = 0.0
    # card 2
    ihaze: int = 0
    iseasn: int = 0
    ivulcn: int = 0
    icstl: int = 0
    icld: int = 0
    ivsa: int = 0
    vis: float = 0.0
    wss: float = 0.0
    whh: float = 0.0
    rainrt: float = 0.0
    gndalt: float = 0.0
    # card 2A (cirrus)
    cthik: float = 0.0
    calt: float = 0.0
    cext: float = 0.0
    iseed: int = 0
    # card 2B (army vertical structure)
    zcvsa: float = 0.0
    ztvsa: float = 0.0
    zinvsa: float = 0.0
    # card 2C (user atmosphere)
    ird1: int = 0
    ird2: int = 0
    title: str = ""
    levels: tuple[ProfileLevel, ...] = ()
    # card 2D (user aerosols)
    ireg: tuple[int, int, int, int] = (0, 0, 0, 0)
    aerosol_regions: tuple[UserAerosolRegion, ...] = ()
    # card 3
    h1: float = 0.0
    h2: float = 0.0
    angle: float = 0.0
    range: float = 0.0
    beta: float = 0.0
    ro: float = 0.0
    len: int = 0
    # cards 3 (iemsct = 3) and 3A1/3A2 (iemsct = 2)
    iday: int = 0
    isourc: int = 0
    anglem: float = 0.0
    iparm: int = 2
    iph: int = 2
    parm1: float = 0.0
    parm2: float = 0.0
    parm3: float = 0.0
    parm4: float = 0.0
    time: float = 0.0
    psipo: float = 0.0
    g: float = 0.0
    # cards 3B (user phase function)
    phase_angles: tuple[float, ...] = ()
    phase_functions: tuple[tuple[float, float, float, float], ...] = field(default=())
    # card 4
    v1: float = 400.0
    v2: float = 40000.0
    dv: float = 5.0

    # ------------------------------------------------------------------------------------
    def replace(self, **changes) -> LowtranCase:
        """A copy with some fields changed (unknown names raise ConfigError)."""
        import dataclasses

        names = {f.name for f in fields(self)}
        bad = sorted(set(changes) - names)
        if bad:
            raise ConfigError(f"unknown LOWTRAN card field(s) {bad}", key="lowtran")
        return dataclasses.replace(self, **changes)

    @property
    def n_samples(self) -> int:
        """Number of spectral samples LOWTRAN will compute."""
        v1 = math.floor(self.v1 / 5.0 + 0.1) * 5.0
        v2 = math.floor(self.v2 / 5.0 + 0.1) * 5.0
        return int((v2 - v1) // self.dv) + 2

    def check(self, key: str = "lowtran") -> LowtranCase:
        """Raise ConfigError for a field LOWTRAN would refuse or silently change.

        Returns the case itself, so ``write_tape5(case.check())`` reads naturally.
        """
        def choice(name, allowed):
            value = getattr(self, name)
            if not isinstance(value, int) or isinstance(value, bool) or value not in allowed:
                raise ConfigError(f"must be one of {sorted(allowed)}; got {value!r}",
                                  key=f"{key}.{name}")

        def number(name, low=-math.inf, high=math.inf, low_open=False, high_open=False):
            value = getattr(self, name)
            try:
                x = float(value)
            except (TypeError, ValueError):
                raise ConfigError(f"must be a number; got {value!r}", key=f"{key}.{name}") from None
            bad_low = x <= low if low_open else x < low
            bad_high = x >= high if high_open else x > high
            if not math.isfinite(x) or bad_low or bad_high:
                lo = "(" if low_open else "["
                hi = ")" if high_open else "]"
                raise ConfigError(f"must lie in {lo}{low:g}, {high:g}{hi}; got {value!r}",
                                  key=f"{key}.{name}")

        choice("model", range(0, 8))
        choice("itype", range(1, 4))
        choice("iemsct", range(0, 4))
        choice("imult", (0, 1))
        for name in ("m1", "m2", "m3", "m4", "m5", "m6"):
            choice(name, range(0, 7))
        choice("mdef", (0, 1))
        choice("im", (0, 1))
        choice("noprt", (-1, 0, 1))
        number("tbound", 0.0, 1000.0)
        number("salb", 0.0, 1.0)
        choice("ihaze", range(0, 11))
        choice("iseasn", range(0, 3))
        choice("ivulcn", range(0, 9))
        choice("icstl", range(0, 11))
        choice("icld", (*range(0, 12), 18, 19, 20))
        choice("ivsa", (0, 1))
        for name in ("vis", "wss", "whh", "rainrt"):
            number(name, 0.0)
        number("gndalt", 0.0, 6.0, high_open=True)
        for name in ("cthik", "calt", "cext"):
            number(name, 0.0)
        for name in ("zcvsa", "ztvsa", "zinvsa"):
            number(name)
        choice("ird1", (0, 1))
        choice("ird2", (0, 1))
        user_profile = self.model in (0, 7) and self.im == 1
        if self.model == 0 and self.itype != 1:
            raise ConfigError("MODEL = 0 (meteorological data) allows only a horizontal path "
                              "(itype = 1)", key=f"{key}.itype")
        if self.model in (0, 7) and self.im != 1:
            raise ConfigError("a user atmosphere (model 0 or 7) needs im = 1 and its levels in "
                              "one deck (each run is a separate process)", key=f"{key}.im")
        if user_profile:
            if not 1 <= len(self.levels) <= MAX_LEVELS:
                raise ConfigError(f"a user atmosphere needs 1 to {MAX_LEVELS} levels; got "
                                  f"{len(self.levels)}", key=f"{key}.levels")
            if self.ivsa == 1:
                raise ConfigError("the army vertical structure (ivsa = 1) cannot be combined "
                                  "with a user atmosphere here", key=f"{key}.ivsa")
            z = [lv.z for lv in self.levels]
            if any(b <= a for a, b in zip(z, z[1:], strict=False)):
                raise ConfigError("level altitudes must increase strictly", key=f"{key}.levels")
            for i, lv in enumerate(self.levels):
                if len(lv.wmol) != 12:
                    raise ConfigError("12 amounts (H2O ... HNO3)", key=f"{key}.levels[{i}].wmol")
                if len(lv.jchar) > 14 or any(c not in " 123456ABCDEFGH" for c in lv.jchar):
                    raise ConfigError("up to 14 flags from ' 123456ABCDEFGH'",
                                      key=f"{key}.levels[{i}].jchar")
                if self.ird2 == 1 and (lv.aerosol is None or len(lv.aerosol) != 8):
                    raise ConfigError("ird2 = 1 needs 8 aerosol values per level (card 2C3)",
                                      key=f"{key}.levels[{i}].aerosol")
        elif self.levels:
            raise ConfigError("levels are read only for model 0 or 7 with im = 1",
                              key=f"{key}.levels")
        if self.ihaze == 7 or self.icld == 11:
            choice_regs = [r for r in self.ireg if r not in (0, 1)]
            if choice_regs or sum(self.ireg) != len(self.aerosol_regions):
                raise ConfigError("ireg: four 0/1 flags, one aerosol region per 1",
                                  key=f"{key}.ireg")
            for i, reg in enumerate(self.aerosol_regions):
                for name in ("extinction", "absorption", "asymmetry"):
                    if len(getattr(reg, name)) != len(AEROSOL_WAVELENGTHS):
                        raise ConfigError(f"{len(AEROSOL_WAVELENGTHS)} values",
                                          key=f"{key}.aerosol_regions[{i}].{name}")
        number("h1", 0.0, TOP_ALTITUDE)
        number("h2", 0.0, TOP_ALTITUDE)
        number("angle", 0.0, 180.0)
        number("range", 0.0)
        number("beta", 0.0, 180.0)
        number("ro", 0.0)
        choice("len", (0, 1))
        if self.itype == 1 and self.range <= 0:
            raise ConfigError("a horizontal path (itype = 1) needs range > 0 km",
                              key=f"{key}.range")
        if self.iemsct in (2, 3):
            if not (self.iday == -99 or 0 <= self.iday <= 366):
                raise ConfigError("day of year 1-366 (0 or -99: mean Earth-Sun distance)",
                                  key=f"{key}.iday")
            if self.isourc not in (0, 1, -99):
                raise ConfigError("0 (sun) or 1 (moon)", key=f"{key}.isourc")
        if self.iemsct == 2:
            choice("iph", (0, 1, 2))
            if self.iparm not in (0, 1, 2, -99):
                raise ConfigError("must be 0, 1 or 2", key=f"{key}.iparm")
            if self.iparm == 2:
                number("parm1", -180.0, 180.0)
                number("parm2", 0.0, 90.0, high_open=True)
            if self.iph == 0:
                number("g", -1.0, 1.0, low_open=True, high_open=True)
            if self.iph == 1:
                n = len(self.phase_angles)
                if not 2 <= n <= 50 or len(self.phase_functions) != n:
                    raise ConfigError("2 to 50 phase angles, with one 4-tuple of phase "
                                      "function values per angle", key=f"{key}.phase_angles")
        number("v1", 0.0, WAVENUMBER_MAX)
        number("v2", 0.0, WAVENUMBER_MAX)
        if self.v2 <= self.v1:
            raise ConfigError(f"v2 must exceed v1; got v1={self.v1}, v2={self.v2}",
                              key=f"{key}.v2")
        number("dv", WAVENUMBER_STEP_MIN)
        if abs(self.dv / 5.0 - round(self.dv / 5.0)) > 1e-9:
            raise ConfigError(f"a multiple of 5 cm-1; got {self.dv}", key=f"{key}.dv")
        if self.n_samples > MAX_SAMPLES:
            raise ConfigError(f"at most {MAX_SAMPLES} samples per run; (v2 - v1) / dv gives "
                              f"{self.n_samples}", key=f"{key}.dv")
        return self


# -- fixed-column formatting ----------------------------------------------------------------
def _int(value, width: int = 5, key: str = "") -> str:
    text = str(int(value))
    if len(text) > width:
        raise ConfigError(f"{value!r} does not fit in {width} columns", key=key or None)
    return text.rjust(width)


def _real(value, width: int = 10, key: str = "") -> str:
    """A real for an F or E input field, right-justified, always with a decimal point.

    The shortest text that reads back exactly is used when it fits; otherwise the most
    precise fixed or exponent form that does. (Without a decimal point Fortran would scale
    the digits by the field's implied decimals.)
    """
    x = float(value)
    if not math.isfinite(x):
        raise ConfigError(f"must be finite; got {value!r}", key=key or None)
    text = repr(x).upper()
    if "E" in text and "." not in text.split("E")[0]:
        mantissa, exponent = text.split("E")
        text = f"{mantissa}.0E{exponent}"
    if len(text) <= width:
        return text.rjust(width)
    best, best_err = None, math.inf
    for decimals in range(width - 2, -1, -1):
        text = f"{x:.{decimals}f}"
        if "." not in text:
            text += "."
        if len(text) <= width:
            best, best_err = text, abs(float(text) - x)
            break
    if x != 0.0:
        for digits in range(width - 6, -1, -1):
            text = f"{x:.{digits}E}"
            if len(text) <= width:
                if abs(float(text) - x) < best_err:
                    best = text
                break
    if best is None:
        raise ConfigError(f"{value!r} does not fit in {width} columns", key=key or None)
    return best.rjust(width)


def _text(value: str, width: int) -> str:
    if any(ord(c) < 32 or ord(c) > 126 for c in value):
        raise ConfigError("printable ASCII only", key="lowtran.title")
    return value[:width].ljust(width)


def write_tape5(case: LowtranCase, key: str = "lowtran") -> str:
    """The TAPE5 card deck of one case (checked first).

    Parameters
    ----------
    case : LowtranCase
    key : str
        Key path used in error messages.

    Returns
    -------
    str
        The deck, one card per line, ending with card 5 (IRPT = 0) and a newline.

    Examples
    --------
    >>> deck = write_tape5(LowtranCase(model=5, itype=3, h1=0.0, angle=0.0,
    ...                                v1=11111.111, v2=20000.0, dv=20.0))
    >>> deck.splitlines()[0]
    '    5    3    0    0    0    0    0    0    0    0    0    0    0     0.0    0.0'
    """
    c = case.check(key)
    k = key
    lines = []
    ints1 = (c.model, c.itype, c.iemsct, c.imult, c.m1, c.m2, c.m3, c.m4, c.m5, c.m6, c.mdef,
             c.im, c.noprt)
    lines.append("".join(_int(v, 5, k) for v in ints1)
                 + _real(c.tbound, 8, k) + _real(c.salb, 7, k))
    lines.append("".join(_int(v, 5, k) for v in (c.ihaze, c.iseasn, c.ivulcn, c.icstl, c.icld,
                                                  c.ivsa))
                 + "".join(_real(v, 10, k) for v in (c.vis, c.wss, c.whh, c.rainrt, c.gndalt)))
    if c.icld >= 18:
        lines.append("".join(_real(v, 10, k) for v in (c.cthik, c.calt, c.cext))
                     + _int(c.iseed, 10, k))
    if c.ivsa == 1:
        lines.append("".join(_real(v, 10, k) for v in (c.zcvsa, c.ztvsa, c.zinvsa)))
    if c.model in (0, 7) and c.im == 1:
        lines.append(_int(len(c.levels), 5, k) + _int(c.ird1, 5, k) + _int(c.ird2, 5, k)
                     + _text(c.title, 65).rstrip())
        for lv in c.levels:
            head = _real(lv.z, 10, k) + "".join(
                _real(v, 10, k) for v in (lv.p, lv.t, lv.wmol[0], lv.wmol[1], lv.wmol[2]))
            lines.append((head + lv.jchar).rstrip())
            if c.ird1 == 1:
                lines.append("".join(_real(v, 10, k) for v in lv.wmol[3:11]))
                lines.append(_real(lv.wmol[11], 10, k))
            if c.ird2 == 1:
                a = lv.aerosol
                lines.append(" " * 10 + "".join(_real(v, 10, k) for v in a[:3])
                             + "".join(_int(v, 5, k) for v in a[3:]))
    if c.ihaze == 7 or c.icld == 11:
        lines.append("".join(_int(v, 5, k) for v in c.ireg))
        for reg in c.aerosol_regions:
            lines.append(_real(reg.awccon, 10, k) + _text(reg.title, 60).rstrip())
            rows = list(zip(AEROSOL_WAVELENGTHS, reg.extinction, reg.absorption, reg.asymmetry,
                            strict=True))
            for i in range(0, len(rows), 3):
                lines.append("".join(
                    _real_fixed(w, 6, 2) + _real(e, 7, k) + _real(a, 7, k) + _real(g, 6, k)
                    for w, e, a, g in rows[i:i + 3]))
    if c.iemsct == 3:
        lines.append("".join(_real(v, 10, k) for v in (c.h1, c.h2, c.angle)) + _int(c.iday, 5, k)
                     + " " * 5 + _real(c.ro, 10, k) + _int(c.isourc, 5, k)
                     + _real(c.anglem, 10, k))
    else:
        lines.append("".join(_real(v, 10, k) for v in (c.h1, c.h2, c.angle, c.range, c.beta,
                                                        c.ro)) + _int(c.len, 5, k))
    if c.iemsct == 2:
        lines.append("".join(_int(v, 5, k) for v in (c.iparm, c.iph, c.iday, c.isourc)))
        lines.append("".join(_real(v, 10, k) for v in (c.parm1, c.parm2, c.parm3, c.parm4,
                                                        c.time, c.psipo, c.anglem, c.g)))
        if c.iph == 1:
            lines.append(_int(len(c.phase_angles), 5, k))
            for angle, funcs in zip(c.phase_angles, c.phase_functions, strict=True):
                lines.append("".join(_real(v, 10, k) for v in (angle, *funcs)))
    lines.append("".join(_real(v, 10, k) for v in (c.v1, c.v2, c.dv)))
    lines.append(_int(0, 5, k))
    return "\n".join(lines) + "\n"


def _real_fixed(value, width: int, decimals: int) -> str:
    """A real written exactly as Fortran Fw.d would (for the echo-style fields of card 1)."""
    text = f"{float(value):{width}.{decimals}f}"
    if len(text) > width:
        raise ConfigError(f"{value!r} does not fit in {width} columns", key="lowtran")
    return text
