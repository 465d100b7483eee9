"""The 3-4 um window through the database against LOWTRAN7 run for each line of sight.

From 3 um on the database's transmittance is its thermal tables' (LOWTRAN runs), the one their
path radiance goes with, for the lines of sight and the sun's path alike
(:meth:`DatabaseAtmosphere.path`, :meth:`DatabaseAtmosphere.sun`). Below 4 um it used to be
its reflective tables' (6S runs), whose gases leave out water vapour's continuum and HDO band:
from an aircraft 2.5 km up, 60 deg from the nadir, 3.7-4.0 um, tropical, the transmittance was
0.919 against LOWTRAN's 0.678, and a 300 K ground came out 25 % too bright.

The reference of every comparison is the ``lowtran`` engine at the line of sight's own
geometry: LOWTRAN7 itself, at the database condition's visibility. Measured
(``pytest tests/validation/test_mwir_window.py -s``): the figures are in each test's
docstring.
"""

from __future__ import annotations

import numpy as np
import pytest

from radscene.atmosphere.lowtran import NOT_BUILT, lowtran_available
from radscene.radiometry import spectral_radiance

pytestmark = pytest.mark.skipif(not lowtran_available(), reason=NOT_BUILT)

#: MWIR bands below 4 um: the methane and water wing, the broad window, the 3.9 um channel
BANDS = {"3.0-3.5": (3.0, 3.5), "3.5-4.1": (3.5, 4.1), "3.7-4.0": (3.7, 4.0)}
#: (observer altitude, target altitude [m], view zenith [deg]): aircraft and space
GEOMETRIES = [(1000.0, 0.0, 0.0), (2500.0, 0.0, 0.0), (5000.0, 0.0, 0.0), (10000.0, 0.0, 0.0),
              (1000.0, 0.0, 60.0), (2500.0, 0.0, 60.0), (5000.0, 0.0, 60.0),
              (1e5, 0.0, 30.0), (3500.0, 1500.0, 45.0)]
#: (profile, aerosol, AOT550 node)
CONDITIONS = [("midlatitude_summer", "rural", 0.3), ("tropical", "rural", 0.3),
              ("subarctic_winter", "none", 0.0)]


def _band(spectra, wl):
    return np.trapezoid(spectra, wl, axis=-1)


@pytest.mark.parametrize("condition", CONDITIONS, ids=[c[0] for c in CONDITIONS])
def test_database_mwir_window_is_lowtrans(database_and_lowtran, condition):
    """Band-mean transmittance within 0.01 and the apparent radiance of a 300 K blackbody
    ground (τ B + L_path) within 1.5 % of LOWTRAN's over 9 lines of sight from 1 km to space,
    3.0-3.5, 3.5-4.1 and 3.7-4.0 um. Measured: transmittance within 0.0046, apparent radiance
    -1.15 % (5 km at 60 deg, between the 4 and 7 km nodes) to +0.41 %. With the reflective
    tables' transmittance the apparent radiance was -14 to +26 % (3.7-4.0 um: +2.6 to +26 %)
    and the transmittance 0.07 low to 0.24 high."""
    db, lo = database_and_lowtran(*condition)
    lines, bad = [], []
    for band, (w0, w1) in BANDS.items():
        wl = np.linspace(w0, w1, 61)
        blackbody = spectral_radiance(wl, 300.0)
        for geometry in GEOMETRIES:
            got, want = db.path(*geometry, wl), lo.path(*geometry, wl)
            g, w = (_band(p.transmittance * blackbody + p.thermal_radiance, wl)
                    for p in (got, want))
            tg, tw = got.transmittance.mean(), want.transmittance.mean()
            err = 100.0 * (g / w - 1.0)
            lines.append(f"{band} {geometry}: L {g:.4g} vs {w:.4g} ({err:+.2f} %), "
                         f"tau {tg:.4f} vs {tw:.4f}")
            if abs(err) > 1.5 or abs(tg - tw) > 0.01:
                bad.append(lines[-1])
    print("\n".join(lines))
    assert not bad, "\n".join(bad)


@pytest.mark.parametrize("sun_zenith", [0.0, 40.0, 70.0, 85.0, 88.0, 89.0])
def test_database_sun_transmittance_in_the_mwir_window_is_lowtrans(database_and_lowtran,
                                                                 sun_zenith):
    """The sun's direct transmittance to the ground, band mean over 3.5-4.1 um, within 0.015
    of LOWTRAN's path from the top of the atmosphere (midlatitude summer, rural AOT550 0.3).
    Measured: within 0.0003 at 0, 40 and 85 deg, 0.0105 at 70 deg (between the view-zenith
    nodes 60 and 75), 0.0027 and 0.0013 at 88 and 89 deg (beyond the last node, in the
    spherical air mass). With the reflective tables' it was 0.11-0.17 high at 0-85 deg."""
    db, lo = database_and_lowtran("midlatitude_summer", "rural", 0.3)
    wl = np.linspace(3.5, 4.1, 61)
    got = db.sun(0.0, sun_zenith, wl, np.ones(wl.size)).transmittance.mean()
    want = lo.path(1e5, 0.0, sun_zenith, wl).transmittance.mean()
    print(f"sun at {sun_zenith} deg: tau {got:.4f} vs {want:.4f}")
    assert got == pytest.approx(want, abs=0.015)


def test_a_night_mwir_aircraft_image_has_lowtrans_air_in_every_pixel(
        render_scene, database_and_lowtran, night_over_black_ground, tmp_path):
    """An aircraft 2.5 km up at night sees flat black ground at 300 K from 15 to 85 deg off the
    nadir (``radscene render``, database engine, tropical, rural AOT550 0.3). Each pixel's
    rendered path radiance, transmittance and radiance against LOWTRAN at the pixel's own line
    of sight (its view zenith from the image's truth maps); LOWTRAN's radiance is
    ∫ (τ B(300 K) + L_path) dλ, to which the render's radiance without its
    ``diffuse_transmitted`` layer compares. Within 3 % (path radiance), 0.02 (transmittance)
    and 1 % (radiance). Measured: path radiance -2.8 to -0.5 % (the path nodes'
    interpolation), transmittance within 0.013 (at 84.5 deg), radiance -0.07 to +0.37 %. With
    the reflective tables' transmittance the radiance was +16 to +59 %."""
    profile, aerosol, aot550 = "tropical", "rural", 0.3
    _, lo = database_and_lowtran(profile, aerosol, aot550)
    atmosphere = {"type": "database", "profile": profile, "aerosol": aerosol, "aot550": aot550}
    camera = {"position": ["100 m", "300 m", "2500 m"], "look_at": ["3080 m", "300 m", "0 m"],
              "fov": "5 deg", "shape": [64, 4]}
    bands = {name: band for name, band in BANDS.items() if name != "3.0-3.5"}
    scene = night_over_black_ground("mwir_aircraft", atmosphere, bands, 300.0, (40000, 600), 200,
                                    camera)
    ds = render_scene(tmp_path / "db", scene)
    zen = ds["view_zenith"].values[:, 2]
    rows = np.flatnonzero(np.isfinite(zen))
    assert zen[rows].min() < 20.0 and zen[rows].max() > 80.0
    lines, bad = [], []
    for band in ds["band"].values:
        w0, w1 = BANDS[str(band)]
        wl = np.linspace(w0, w1, 61)
        sel = ds.sel(band=band)
        for r in rows[::5]:
            vz = float(zen[r])
            want = lo.path(2500.0, 0.0, vz, wl)
            lw = _band(want.thermal_radiance, wl)
            tw = want.transmittance.mean()
            lg = float(sel["path_radiance"].values[r, 2])
            tg = float(sel["path_transmittance"].values[r, 2])
            # LOWTRAN's radiance mode carries the ground's emission by τ alone: what the air
            # scatters of it into the line of sight (diffuse_transmitted, from 6S's diffuse
            # transmittance) is not in it
            ag = float(sel["radiance"].values[r, 2] - sel["diffuse_transmitted"].values[r, 2])
            aw = _band(want.transmittance * spectral_radiance(wl, 300.0), wl) + lw
            errs = (100.0 * (lg / lw - 1.0), 100.0 * (ag / aw - 1.0))
            lines.append(f"{band} zenith {vz:5.1f}: L_path {lg:.4g} vs {lw:.4g} ({errs[0]:+.2f} %),"
                         f" tau {tg:.4f} vs {tw:.4f}, L {ag:.4g} vs {aw:.4g} ({errs[1]:+.2f} %)")
            if abs(errs[0]) > 3.0 or abs(errs[1]) > 1.0 or abs(tg - tw) > 0.02:
                bad.append(lines[-1])
    print("\n".join(lines))
    assert not bad, "\n".join(bad)
