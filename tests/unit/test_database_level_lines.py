"""Lines of sight near the ground and the horizon in the shipped database: the mixes of short
and long level lines, lines above the tables' highest surface altitude, and the spans beyond
which a line is not read as level air."""

from __future__ import annotations

import numpy as np
import pytest

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
    mean altitude (that would be opaque at 10 um) but the tables extrapolated in air mass m
    beyond 85 deg: the optical depth grows as m^p, 0.5 <= p <= 1, the power between the last two
    view-zenith nodes (80 and 85 deg)."""
    db = DatabaseAtmosphere(profile="us_standard", sun_zenith=40.0, visibility=23000.0)
    nodes = db.axes["thermal_wavelength"]
    j = int(np.argmin(np.abs(nodes - 10.0)))
    wl = [float(nodes[j])]  # a node: no spectral interpolation
    z1, z2 = (float(z) for z in db.axes["view_zenith"][-2:])
    d1, d85, d88 = (-np.log(db.path(20000.0, 2000.0, z, wl).transmittance[0])
                    for z in (z1, z2, 88.0))
    m1, m85, m88 = (1.0 / np.cos(np.radians(z)) for z in (z1, z2, 88.0))
    power = np.clip(np.log(d85 / d1) / np.log(m85 / m1), 0.5, 1.0)
    assert d88 == pytest.approx(d85 * (m88 / m85) ** power, rel=1e-6)
    level = db._level_thermal(np.array([11000.0]), np.array([18000.0 / np.cos(np.radians(88.0))]))
    assert np.exp(-d88) > 10.0 * level[0][0, j]


@pytest.mark.parametrize("zenith", [86.0, 88.0, 89.5])
def test_beyond_85_deg_a_line_is_continuous_in_its_span(zenith):
    """Beyond the tables' last view zenith the level air (spans up to 300 m), the 85 deg value
    with the level air of the extra length (to 1-3 km) and the extrapolation in air mass
    (beyond) meet without a step: a millimetre more span changes τ by under 0.1 %."""
    db = DatabaseAtmosphere(profile="us_standard", sun_zenith=40.0, visibility=23000.0)
    wl = [3.8, 4.6, 10.0]
    for span in (100.0, 300.0, 1000.0, 3000.0):
        below = db.path(span - 1e-3, 0.0, zenith, wl).transmittance
        above = db.path(span + 1e-3, 0.0, zenith, wl).transmittance
        assert above == pytest.approx(below, rel=1e-3), span


@pytest.mark.parametrize("profile", ["midlatitude_summer", "subarctic_winter"])
def test_the_sun_beyond_89_deg_is_the_same_in_sun_components_and_coupling(profile):
    """From 3 µm the sun's transmittance is the thermal tables' at the sun's own zenith, in
    the spherical air mass, whichever query asks (in dry air too, where it exceeds the
    scattering tables' plane-parallel direct transmittance); and it falls towards the
    horizon."""
    db = DatabaseAtmosphere(profile=profile, sun_zenith=40.0, visibility=23000.0)
    wl = np.array([3.5, 3.8, 10.0])
    previous = None
    for sun_zenith in (88.0, 89.0, 89.5, 89.9):
        sun = db.sun(0.0, sun_zenith, wl, np.ones(3)).transmittance
        c = db.components(1e5, 0.0, 0.0, wl, sun_zenith=sun_zenith)["sun_transmittance"][0]
        assert c == pytest.approx(sun, rel=1e-9)
        e_sun = np.cos(np.radians(sun_zenith)) * db._e0(wl[:2]) * sun[:2]
        coupled = db.with_sun(sun_zenith, 0.0).coupling(1e5, 0.0, 0.0, wl[:2])
        assert coupled.direct_irradiance == pytest.approx(e_sun, rel=1e-9)
        if previous is not None:
            assert np.all(sun <= previous)
        previous = sun


def test_a_line_from_just_below_the_top_is_the_line_from_space():
    """Beyond 85 deg the air mass goes from the flat scene's to the spherical shell's with the
    observer's height between the tables' highest node under the top and the top: no step
    there."""
    db = DatabaseAtmosphere(profile="us_standard", sun_zenith=40.0, visibility=23000.0)
    for zenith in (87.0, 89.0, 89.5):
        below = db.path(1e5 - 1.0, 0.0, zenith, [3.8, 10.0]).transmittance
        space = db.path(1e5, 0.0, zenith, [3.8, 10.0]).transmittance
        assert below == pytest.approx(space, rel=1e-3)


@pytest.mark.parametrize("zenith", [89.95, 89.99])
def test_a_longer_span_is_no_clearer_even_at_the_horizon(zenith):
    """Within a hundredth of a degree of the horizon a line spanning more altitude is at
    least as long: its transmittance does not rise with the span across the level air's
    100 and 300 m."""
    db = DatabaseAtmosphere(profile="us_standard", sun_zenith=40.0, visibility=23000.0)
    tau = [float(db.path(span, 0.0, zenith, [10.0]).transmittance[0])
           for span in (99.99, 100.01, 150.0, 299.0, 301.0)]
    assert np.all(np.diff(tau) <= 1e-12 + 1e-6 * np.array(tau[:-1]))


def test_the_shell_air_mass_is_the_chord_through_the_shell():
    """The spherical air mass of lines from space: the length a straight ray from the ground
    at zenith θ runs inside a shell 8 km thick over a 6371 km sphere, over 8 km, found by
    marching the ray (independent of the closed form); 1/cos θ at small zeniths."""
    from radscene.atmosphere.database import _shell_air_mass

    radius, thickness = 6.371e6, 8000.0
    for zenith in (0.0, 30.0, 85.0, 88.0, 89.9):
        direction = np.array([np.sin(np.radians(zenith)), np.cos(np.radians(zenith))])
        s = np.linspace(0.0, 400e3, 4_000_001)
        points = np.array([0.0, radius]) + s[:, None] * direction
        inside = np.hypot(points[:, 0], points[:, 1]) <= radius + thickness
        marched = s[inside][-1] / thickness
        assert _shell_air_mass(zenith) == pytest.approx(marched, rel=2e-4), zenith
    assert _shell_air_mass(30.0) == pytest.approx(1.0 / np.cos(np.radians(30.0)), rel=1e-3)
