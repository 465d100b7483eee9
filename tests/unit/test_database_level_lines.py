"""Lines of sight near the ground and the horizon in the shipped database: the mixes of short
and long level lines, lines above the tables' highest surface altitude, and the spans beyond
which a line is not read as level air."""

from __future__ import annotations

import numpy as np

from radscene.atmosphere.database import DatabaseAtmosphere


def test_short_and_long_level_lines_together():
    """Lines shorter than the level tables' first length beside longer ones, in one call:
    the transmittance falls with the length."""
    db = DatabaseAtmosphere(sun_zenith=40.0, visibility=23000.0)
    tau = db.path([1.0, 5.0, 50.0, 2.0], 0.0, [0.0, 0.0, 0.0, 89.9], [10.0]).transmittance[:, 0]
    assert np.all(np.diff(tau) < 0) and tau[0] < 1.0 and tau[-1] > 0.5


def test_level_lines_above_the_highest_surface_altitude():
    """A mast on a 3 km plateau and an aircraft's line near the horizon: the reflective range
    reads the level air at the top surface altitude instead of refusing."""
    db = DatabaseAtmosphere(sun_zenith=40.0, visibility=23000.0)
    for geometry in ((3200.0, 3000.0, 60.0), (10000.0, 0.0, 86.0), (2.0, 0.0, 89.99)):
        p = db.path(*geometry, [0.55, 10.0])
        assert np.all((p.transmittance > 0.0) & (p.transmittance < 1.0))
        assert np.all(np.isfinite(p.scattered_radiance)) and p.scattered_radiance[0] > 0.0


def test_a_long_span_near_the_horizon_is_not_level_air():
    """Spanning 18 km at 88 deg the line climbs through the atmosphere: not the level air of its
    mean altitude (that would be opaque at 10 um), the tables' 85 deg instead."""
    db = DatabaseAtmosphere(profile="us_standard", sun_zenith=40.0, visibility=23000.0)
    steep = db.path(20000.0, 2000.0, 85.0, [10.0]).transmittance
    assert db.path(20000.0, 2000.0, 88.0, [10.0]).transmittance == steep
