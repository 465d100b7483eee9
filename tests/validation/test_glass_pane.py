"""The built-in ``glass`` as a semi-transparent sheet, against closed forms.

Each test renders a scene dict through ``radscene.render``: a 40 m pane of ``glass`` marked
``transmissive`` 3 m above a grey Lambertian ground, no atmosphere, no reflected background,
seen from above. In a visible band the pane lets through its band-mean transmittance τ_b of
what lies behind it, and what lies behind is the ground in the pane's shadow, itself lit by τ_b
of the sun (:mod:`radscene.render.sheets`): the light through the pane is τ_b² of the open
ground's. τ_b is computed here from the measured spectrum of the source file (IGDB NFRC 102,
piecewise linear at 10 nm). In the thermal infrared the pane is opaque: it shows its own
emission, 0.84 of a blackbody's, and nothing of the warmer ground behind it.
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.integrate import quad

from radscene import render
from radscene.materials.library import LIBRARY_DIR
from radscene.radiometry import spectral_radiance

VIS = {"name": "vis", "min": 0.5, "max": 0.6}
MWIR = {"name": "mwir", "min": 3.5, "max": 4.8}
LWIR = {"name": "lwir", "min": 8.0, "max": 12.0}
GROUND_RHO = 0.6
PANE_T, GROUND_T = 290.0, 310.0
#: Phong exponent of the library's glass [-].
EXPONENT = 2000.0
#: radscene's band quadrature against scipy's adaptive one.
BAND_REL = 1e-7
#: Ratios in which the band integrals cancel.
EXACT_REL = 1e-10


def _measured():
    path = LIBRARY_DIR / "sources" / "transmittance_igdb_clear_glass_nfrc102.csv"
    lines = [ln for ln in path.read_text(encoding="utf-8").splitlines()
             if ln.strip() and not ln.startswith("#")]
    rows = np.array([[float(v) for v in ln.split(",")] for ln in lines[1:]])
    return rows[:, 0], rows[:, 1], rows[:, 2]  # wavelength [um], T, Rf


def _band_mean(wl, values, band):
    """Mean of the piecewise-linear spectrum over a rectangular band whose edges are knots."""
    inside = (wl >= band["min"] - 1e-9) & (wl <= band["max"] + 1e-9)
    assert np.isclose(wl[inside][0], band["min"]) and np.isclose(wl[inside][-1], band["max"])
    return float(np.trapezoid(values[inside], wl[inside]) / (band["max"] - band["min"]))


def _band_planck(temperature, band):
    value, _ = quad(lambda wl: float(spectral_radiance(wl, temperature)), band["min"],
                    band["max"], epsabs=0.0, epsrel=1e-11, limit=200)
    return value


def _scene(sun_zenith, bands, pane=True):
    objects = [{"name": "ground", "shape": {"type": "plate", "width": 300, "length": 300},
                "material": "ground", "temperature": GROUND_T}]
    if pane:
        objects.append({"name": "pane", "shape": {"type": "plate", "width": 40, "length": 40},
                        "position": [0, 0, 3], "material": "glass", "temperature": PANE_T,
                        "transmissive": True})
    return {
        "name": "pane",
        "environment": {"sun": {"zenith": sun_zenith, "azimuth": 180.0},
                        "atmosphere": {"type": "none"}},
        "materials": {"ground": {"reflectance": GROUND_RHO}},
        "objects": objects,
        "bands": bands,
        "observers": [{"name": "cam", "type": "orthographic", "center": [0, 0], "gsd": 1.0,
                       "shape": [5, 5], "altitude": 1000}],
        "render": {"background_bounces": 0},
    }


def test_a_pane_passes_its_measured_transmittance_in_the_visible():
    """Sun overhead, nadir view: through the pane the ground is τ_b² of the open ground
    (τ_b = 0.9016 over 0.5-0.6 um); the pane reflects no sunlight diffusely, and its glint
    along the mirror direction is ρ_s (n + 1) / (2π) of the sun, against ρ_g / π for the open
    ground, ρ_s the measured reflectance (between its band extremes, 0.081-0.084, as the
    band's sun-weighted mean must be)."""
    wl, t, rf = _measured()
    tau_b = _band_mean(wl, t, VIS)
    assert tau_b == pytest.approx(0.9016, abs=1e-4)
    pane = render(_scene(0.0, [VIS])).sel(band="vis")
    ground = render(_scene(0.0, [VIS], pane=False)).sel(band="vis")
    open_ground = ground["radiance"].values
    assert np.all(open_ground > 0.0)
    assert pane["transmitted"].values / open_ground == pytest.approx(
        np.full((5, 5), tau_b**2), rel=EXACT_REL)
    assert np.all(pane["sun_diffuse"].values == 0.0)
    rho_s = pane["sun_specular"].values / open_ground * (2.0 * GROUND_RHO / (EXPONENT + 1.0))
    inside = (wl >= VIS["min"]) & (wl <= VIS["max"])
    assert np.all((rho_s >= rf[inside].min()) & (rho_s <= rf[inside].max()))
    assert np.ptp(rho_s) < 1e-12
    assert pane["radiance"].values == pytest.approx(
        pane["sun_specular"].values + pane["transmitted"].values, rel=1e-12)


@pytest.mark.parametrize("band", [MWIR, LWIR], ids=lambda b: b["name"])
def test_a_pane_is_opaque_in_the_thermal_infrared_and_emits_with_its_emissivity(band):
    """At night, no atmosphere: the pane's radiance is 0.84 B(T_pane), nothing of the warmer
    ground behind it comes through (its transmittance is 0 from 3 um on)."""
    ds = render(_scene(120.0, [band])).sel(band=band["name"])
    emission = 0.84 * _band_planck(PANE_T, band)
    assert ds["thermal_emission"].values == pytest.approx(np.full((5, 5), emission),
                                                          rel=BAND_REL)
    assert np.all(ds["transmitted"].values == 0.0)
    assert ds["radiance"].values == pytest.approx(np.full((5, 5), emission), rel=BAND_REL)



def _glass_roof(transmissive=True):
    """A flat asphalt ground, 40 m square, half under a 20 x 40 m pane of glass 2 m up (a sheet,
    or opaque), the sun fixed at 20 deg; the heat balance from 09:00 to noon of 21 June 2024 (as
    the net of test_sheets_closed_forms.py)."""
    return {
        "name": "glass roof",
        "environment": {"sun": {"zenith": 20.0, "azimuth": 180.0},
                        "time": "2024-06-21T12:00:00+00:00",
                        "location": {"latitude": 45.0, "longitude": 0.0},
                        "atmosphere": {"type": "uniform", "transmittance": 1.0}},
        "terrain": {"type": "flat", "size": [40, 40], "spacing": 2, "material": "asphalt"},
        "objects": [{"name": "pane", "shape": {"type": "plate", "width": 20, "length": 40},
                     "position": [10, 20, 2], "material": "glass",
                     "transmissive": transmissive}],
        "bands": [LWIR],
        "observers": [{"name": "cam", "type": "orthographic", "center": [20, 20], "gsd": 1.0,
                       "shape": [4, 4], "altitude": 1000}],
        "thermal": {"start": "2024-06-21T09:00:00+00:00", "end": "2024-06-21T12:00:00+00:00",
                    "step": "30 min", "hemisphere_samples": 64, "spin_up": False},
    }


def test_the_heat_balance_of_a_glass_roof():
    """``radscene.solve_thermal`` of the ground half under a glass roof: the cells under the
    pane are sunlit by its solar transmittance (0.806-0.830: the measured T weighted by the ASTM
    G173 extraterrestrial and global spectra); the pane is opaque to the long-wave hemisphere
    (its transmittance, 0 from 3 um, is held at 0 beyond the library's 20 um), so their sky view
    is that under the same pane not marked transmissive, while their short-wave sky view passes
    the pane's solar share; keeping most of the sun and the diffuse sky's light and none of
    their long-wave exchange with the sky, they end warmer than the open ground (a greenhouse)."""
    import radscene

    solved = radscene.solve_thermal(_glass_roof())
    plate = radscene.solve_thermal(_glass_roof(transmissive=False))
    ground = solved.object.values == "terrain"
    x, y = solved.x.values, solved.y.values
    under = ground & (x < 19.0) & (x > 1.0) & (np.abs(y - 20.0) < 15.0)
    open_ = ground & (x > 21.0) & (np.abs(y - 20.0) < 15.0)
    assert under.sum() >= 20 and open_.sum() >= 20
    lit = solved.sunlit.isel(time=-1).values[under]
    assert np.ptp(lit) < 1e-6 and 0.80 < lit.mean() < 0.84
    np.testing.assert_array_equal(solved.sky_view.values[under], plate.sky_view.values[under])
    # the diffuse sky's light passes it as the sun's does: the short-wave sky view under the
    # pane is 1 - F (1 - τ_sw), F = 1 - the opaque pane's sky view, τ_sw its solar share
    hidden = 1.0 - plate.sky_view.values[under]
    seen = solved.sky_view_shortwave.values[under]
    tau_sw = lit.mean()
    assert hidden.mean() > 0.5
    assert seen.mean() == pytest.approx(np.mean(1.0 - hidden * (1.0 - tau_sw)), abs=0.01)
    np.testing.assert_array_equal(plate.sky_view_shortwave.values, plate.sky_view.values)
    t = solved.surface_temperature.isel(time=-1).values
    assert t[under].mean() > t[open_].mean() + 5.0  # K
    assert np.all(np.isfinite(t[solved.object.values == "pane"]))
