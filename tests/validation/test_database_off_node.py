"""The shipped database's path reflectance between its angular nodes, against direct 6S.

Geometries off every sun- and view-zenith node of the database (sun at 10, 30 and 67 deg;
views at nadir, 30 deg in the backscatter plane and 50 deg across it), the continental
(``rural``) and maritime aerosols at an AOT550 node (0.3, 0.6) and between nodes (0.5), at
0.45, 0.55, 0.87 and 1.63 um. The reference is the ``sixs`` engine: 6S run at the exact
geometry (its agreement with 6S's own outputs is tests/validation/test_sixs_reference.py).

Measured on 2026-11-25 with the shipped file (sun and view nodes 0, 20, 40, 60, 75, 85 deg;
``DatabaseAtmosphere`` reading the top of the atmosphere through a cubic spline in angle):
from the top of the atmosphere the mean error over the 36 geometries × 4 wavelengths is given
in :data:`TOP_MEAN`, the worst in :data:`TOP_WORST`: measured 0.67 % and 2.97 % (maritime AOT550
0.5, sun 30 deg, nadir, 0.55 um); 4.5 % at worst (maritime, sun 10 deg, nadir, next to the
maritime glory at 180 deg, which 6S's multiple scattering does not follow) before the
single-scattering normaliser's phase function was averaged near backscatter. Linear in angle
on the nodes 0, 40, 60, 75, 85 deg the same set gave a mean of 2.85 % and a worst of 10.2 %.
"""

import numpy as np
import pytest

from radscene.atmosphere import DatabaseAtmosphere, SixSAtmosphere

WAVELENGTHS = np.array([0.45, 0.55, 0.87, 1.63])
CONDITIONS = [("maritime", 0.5), ("maritime", 0.3), ("rural", 0.6), ("rural", 0.3)]
SUNS = (10.0, 30.0, 67.0)
VIEWS = ((0.0, 90.0), (30.0, 180.0), (50.0, 90.0))  # (view zenith, relative azimuth) [deg]
TOP = 700_000.0
#: Per geometry, the largest error over the four wavelengths may not exceed this.
TOP_WORST = 0.05
#: The mean absolute error over every geometry and wavelength.
TOP_MEAN = 0.01


def _errors(aerosol, aot, observer, sun, views, cache):
    db = DatabaseAtmosphere(aerosol=aerosol, aot550=aot, sun_zenith=sun)
    sx = SixSAtmosphere(aerosol=aerosol, aot550=aot, sun_zenith=sun, cache=cache)
    out = []
    for view, azimuth in views:
        got = np.asarray(db.components(observer, 0.0, view, WAVELENGTHS,
                                       relative_azimuth=azimuth)["path_reflectance"]).ravel()
        want = np.asarray(sx.components(observer, 0.0, view, WAVELENGTHS,
                                        relative_azimuth=azimuth)["path_reflectance"]).ravel()
        out.append(got / want - 1.0)
    return np.array(out)


def test_one_off_node_geometry_from_the_top(tmp_path):
    """The quick suite's case: maritime AOT550 0.5 (between nodes), sun 30 deg, view 50 deg
    across the principal plane. Measured within 0.5 % (1.5-7 % linearly on the old nodes)."""
    errors = _errors("maritime", 0.5, TOP, 30.0, [(50.0, 90.0)], tmp_path)
    assert np.abs(errors).max() < 0.01, errors


@pytest.mark.slow
def test_off_node_geometries_from_the_top(tmp_path):
    errors = np.concatenate([_errors(aer, aot, TOP, sun, VIEWS, tmp_path)
                             for aer, aot in CONDITIONS for sun in SUNS])
    worst = np.abs(errors).max(axis=1)
    assert worst.max() < TOP_WORST, worst
    assert np.abs(errors).mean() < TOP_MEAN, np.abs(errors).mean()


@pytest.mark.slow
def test_aircraft_under_thick_aerosol_at_a_low_sun(tmp_path):
    """An aircraft 3 km up under thick aerosol at a low sun (rural AOT550 0.6, sun 67 deg,
    between the sun nodes 60 and 75 deg): measured with the 75 deg node among the aircraft
    levels' own 6S runs (coarse zeniths 0, 40, 60, 75, 85 deg), +2.2 to +4.8 % at 0.45 um and
    +0.8 to +3.3 % at 0.55 um (+7.0 to +9.9 % and +0.9 to +3.6 % when the build carried the
    75 deg node from 60 and 85 deg)."""
    errors = _errors("rural", 0.6, 3000.0, 67.0, VIEWS, tmp_path)
    assert np.abs(errors).max() < 0.05, errors


@pytest.mark.slow
@pytest.mark.xfail(strict=True, reason=(
    "known gap: 1 km up under thick aerosol (rural AOT550 0.6) with the sun at 67 deg, between "
    "the aircraft levels' sun nodes 60 and 75 deg, the path reflectance is +9.2 to +14.7 % at "
    "0.45 um and +4.2 to +8.0 % at 0.55 um (at the 75 deg node itself +0.4 % at 0.45 um, view "
    "60 deg): the level's ratio to the top of the atmosphere is read in the sun's airmass "
    "between nodes, and there it is not smooth enough"))
def test_low_aircraft_under_thick_aerosol_at_a_low_sun(tmp_path):
    errors = _errors("rural", 0.6, 1000.0, 67.0, VIEWS, tmp_path)
    assert np.abs(errors).max() < 0.05, errors
