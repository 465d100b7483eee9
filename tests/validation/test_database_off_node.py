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
def test_low_aircraft_under_thick_aerosol_at_a_low_sun(tmp_path):
    """1 km up under thick aerosol (rural AOT550 0.6), the sun at 67 deg between the nodes 60
    and 75 deg. Measured through the level's quotient to the top of the atmosphere
    (``DatabaseAtmosphere._levels_by_quotient``): -0.8 to +0.7 % over the three views and
    0.45-0.87 um; +9.2 to +14.7 % at 0.45 um when the level's factor was read linearly in the
    sun's airmass."""
    errors = _errors("rural", 0.6, 1000.0, 67.0, VIEWS, tmp_path)
    assert np.abs(errors).max() < 0.02, errors


#: Aircraft at 0.5-3 km, between the sun nodes 40-60-75 deg, and the greatest error measured
#: over the three views and four wavelengths (2026-11-25), in %. Maritime 0.5, 3 km, sun 67
#: deg: 2.4 % when the smooth factors were mixed linearly between the AOT550 nodes; 3.5 %
#: (0.45 um, view 30 deg in the backscatter plane) since each condition's own path
#: reflectance is (the nodes 0.3 and 0.6 are -3.6 and -3.2 % there themselves).
LOW_SUNS = [("rural", 0.6, 1000.0, 55.0, 2.0), ("rural", 0.6, 3000.0, 67.0, 2.2),
            ("maritime", 0.5, 3000.0, 67.0, 3.5), ("maritime", 0.3, 1000.0, 67.0, 3.3),
            ("rural", 0.3, 500.0, 67.0, 1.3), ("rural", 0.3, 500.0, 50.0, 3.1)]


@pytest.mark.slow
@pytest.mark.parametrize("aerosol, aot, height, sun, measured", LOW_SUNS)
def test_aircraft_between_low_sun_nodes(tmp_path, aerosol, aot, height, sun, measured):
    """Within 5 %, and within a point of what was measured."""
    errors = _errors(aerosol, aot, height, sun, VIEWS, tmp_path)
    assert np.abs(errors).max() < min(0.05, (measured + 1.0) / 100.0), errors


#: 1 km up, rural AOT550 0.6, the sun on the 80 deg node: the greatest error over the three views
#: and four wavelengths measured within 2.4 % (2026-11-26; +15 to +28 % at 0.45 um before the
#: node). Between the nodes it grows again: sun 78 deg +2.2 %, 82 deg +9.7 % (0.45 um), and
#: 2 km up at 80 deg +8.0 %, where the quotient to the top bends most.
@pytest.mark.slow
def test_low_aircraft_at_a_grazing_sun(tmp_path):
    errors = _errors("rural", 0.6, 1000.0, 80.0, VIEWS, tmp_path)
    assert np.abs(errors).max() < 0.05, errors


#: Aircraft between (and below) the observer-height nodes 1 and 4 km under a grazing sun
#: (the sun on its 85 deg node, rural AOT550 0.6), and the greatest error measured over the
#: three views and four wavelengths (2026-11-26), in %: at 0.45 um in the backscatter plane
#: (view 30 deg, between the view nodes 20 and 40 deg, where the nodes 1 and 4 km are +21 % and
#: +16 % themselves); nadir and across the plane within 8.5 % (2-3 km) and 12 % (0.5 km).
#: Before the levels below the highest aircraft node were read as ρ_ms / τ_l linear in τ_l
#: (``DatabaseAtmosphere._scattering_levels``): 2 km +202 %, 3 km +257 %, 0.5 km -62 %.
GRAZING_HEIGHTS = [(2000.0, 26.0), (3000.0, 22.0), (500.0, 12.7)]


@pytest.mark.slow
@pytest.mark.parametrize("height, measured", GRAZING_HEIGHTS)
def test_aircraft_between_height_nodes_under_a_grazing_sun(tmp_path, height, measured):
    errors = _errors("rural", 0.6, height, 85.0, VIEWS, tmp_path)
    assert np.abs(errors).max() < (measured + 1.0) / 100.0, errors


#: Aircraft between the AOT550 nodes 0.3 and 0.6 (rural 0.5) under a grazing sun (85 deg),
#: nadir, and the greatest error measured over the four wavelengths (2026-11-26), in %: 1 km
#: +3.01, +1.61, -1.09, -4.32 % and 2 km +8.86, +7.62, +0.20, -4.52 % at 0.45-1.63 um, where
#: the nodes 0.3, 0.6 and 1.0 (:func:`~radscene.atmosphere.database._quadratic_nodes`) are off
#: by as much themselves. With the levels' smooth factors mixed linearly in AOT550 instead of
#: each condition's own path reflectance: 1 km +73.6 % and 2 km +42.0 % at 0.45 um.
BETWEEN_AOT_NODES = [(1000.0, 4.4), (2000.0, 8.9)]


@pytest.mark.slow
@pytest.mark.parametrize("height, measured", BETWEEN_AOT_NODES)
def test_aircraft_between_aot_nodes_under_a_grazing_sun(tmp_path, height, measured):
    errors = _errors("rural", 0.5, height, 85.0, [(0.0, 90.0)], tmp_path)
    assert np.abs(errors).max() < (measured + 1.0) / 100.0, errors
