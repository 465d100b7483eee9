"""Semi-transparent sheets (:mod:`radscene.render.sheets`) against closed forms.

Each test renders a scene dict through ``radscene.render``: grey plates marked
``transmissive`` (a camouflage net) above a grey ground, no atmosphere, no reflected
background. A sheet of reflectance ρ and transmittance τ emits ε = 1 − ρ − τ (Kirchhoff) and
lets τ of the light from behind through; sheets in series multiply (τ_1 τ_2); the direct sun
reaching the ground under a sheet is τ of the unshadowed (seed 000's transmitted term;
Willers et al.).
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.integrate import quad

from radscene import render
from radscene.radiometry import spectral_radiance

LWIR = {"name": "lwir", "min": 8.0, "max": 12.0}
VIS = {"name": "vis", "min": 0.5, "max": 0.6}
#: radscene's band quadrature against scipy's adaptive one.
BAND_REL = 1e-7
#: Ratios in which the band integrals cancel.
EXACT_REL = 1e-10
NET_T, GROUND_T, UPPER_T = 320.0, 300.0, 280.0


def _band_planck(temperature):
    value, _ = quad(lambda wl: float(spectral_radiance(wl, temperature)), LWIR["min"],
                    LWIR["max"], epsabs=0.0, epsrel=1e-11, limit=200)
    return value


def _scene(rho=0.2, tau=0.5, sun_zenith=120.0, ground=0.0, second=None, center=(0.0, 0.0),
           gsd=1.0):
    objects = [{"name": "ground", "shape": {"type": "plate", "width": 300, "length": 300},
                "material": "ground", "temperature": GROUND_T},
               {"name": "net", "shape": {"type": "plate", "width": 40, "length": 40},
                "position": [0, 0, 3], "material": "net", "temperature": NET_T,
                "transmissive": True}]
    materials = {"ground": {"reflectance": ground},
                 "net": {"reflectance": rho, "transmittance": tau}}
    if second is not None:
        materials["upper"] = {"reflectance": 0.1, "transmittance": second}
        objects.append({"name": "upper", "shape": {"type": "plate", "width": 40, "length": 40},
                        "position": [0, 0, 6], "material": "upper", "temperature": UPPER_T,
                        "transmissive": True})
    return {
        "name": "net",
        "environment": {"sun": {"zenith": sun_zenith, "azimuth": 180.0},
                        "atmosphere": {"type": "none"}},
        "materials": materials,
        "objects": objects,
        "bands": [VIS, LWIR],
        "observers": [{"name": "cam", "type": "orthographic", "center": list(center),
                       "gsd": gsd, "shape": [9, 9], "altitude": 1000}],
        "render": {"background_bounces": 0},
    }


@pytest.mark.parametrize(("rho", "tau"), [(0.2, 0.5), (0.05, 0.9), (0.6, 0.1)])
def test_sheet_over_a_black_ground_in_the_thermal_infrared(rho, tau):
    ds = render(_scene(rho, tau)).sel(band="lwir")
    emission = (1.0 - rho - tau) * _band_planck(NET_T)
    assert ds["thermal_emission"].values == pytest.approx(np.full((9, 9), emission),
                                                          rel=BAND_REL)
    assert ds["transmitted"].values == pytest.approx(
        np.full((9, 9), tau * _band_planck(GROUND_T)), rel=BAND_REL)
    assert ds["radiance"].values == pytest.approx(
        np.full((9, 9), emission + tau * _band_planck(GROUND_T)), rel=BAND_REL)


def test_two_sheets_in_series():
    ds = render(_scene(0.2, 0.5, second=0.7)).sel(band="lwir")
    upper = (1.0 - 0.1 - 0.7) * _band_planck(UPPER_T)
    lower = (1.0 - 0.2 - 0.5) * _band_planck(NET_T)
    expected = upper + 0.7 * (lower + 0.5 * _band_planck(GROUND_T))
    assert ds["radiance"].values == pytest.approx(np.full((9, 9), expected), rel=BAND_REL)


@pytest.mark.parametrize("sun_zenith", [0.0, 40.0])
@pytest.mark.parametrize("tau", [0.3, 0.8])
def test_partial_shadow_of_a_sheet(tau, sun_zenith):
    """The ground seen beside the net, in its shadow: τ of the sunlit ground's sun term;
    with the sun overhead, seen through the net: τ² of it."""
    # the net covers |y| <= 20 m at 3 m; its shadow reaches 3 tan θ_0 m further north: a
    # 9 x 9 patch of 0.2 m pixels in the middle of that strip
    shift = 3.0 * np.tan(np.radians(sun_zenith))
    center = (0.0, 0.0) if sun_zenith == 0.0 else (0.0, 20.0 + shift / 2.0)
    ds = render(_scene(0.2, tau, sun_zenith=sun_zenith, ground=0.4, center=center, gsd=0.2))
    clear = _scene(0.2, tau, sun_zenith=sun_zenith, ground=0.4, center=center, gsd=0.2)
    clear["objects"] = clear["objects"][:1]
    lit = render(clear)
    if sun_zenith == 0.0:
        ratio = ds["transmitted"].sel(band="vis").values / lit["radiance"].sel(band="vis").values
        assert ratio == pytest.approx(np.full((9, 9), tau * tau), rel=EXACT_REL)
    else:
        ratio = (ds["sun_diffuse"].sel(band="vis").values
                 / lit["sun_diffuse"].sel(band="vis").values)
        assert ratio == pytest.approx(np.full((9, 9), tau), rel=EXACT_REL)
        assert ds["shadow_fraction"].values == pytest.approx(np.full((9, 9), 1.0 - tau),
                                                             rel=EXACT_REL)


def _net_over_asphalt(tau, start, hemisphere_samples):
    """A flat asphalt ground, 40 m square, half under a 20 × 40 m net of grey transmittance τ
    2 m up (an opaque plate for τ = 0), the sun fixed at 20 deg; the heat balance from
    ``start`` (HH:MM) to noon of 21 June 2024."""
    return {
        "name": "net",
        "environment": {"sun": {"zenith": 20.0, "azimuth": 180.0},
                        "time": "2024-06-21T12:00:00+00:00",
                        "location": {"latitude": 45.0, "longitude": 0.0},
                        "atmosphere": {"type": "uniform", "transmittance": 1.0}},
        "terrain": {"type": "flat", "size": [40, 40], "spacing": 2, "material": "asphalt"},
        "materials": {"net": {"reflectance": 0.1, "transmittance": tau}},
        "objects": [{"name": "net", "shape": {"type": "plate", "width": 20, "length": 40},
                     "position": [10, 20, 2], "material": "net", "temperature": 300.0,
                     "transmissive": tau > 0.0}],
        "bands": [LWIR],
        "observers": [{"name": "cam", "type": "orthographic", "center": [20, 20], "gsd": 1.0,
                       "shape": [4, 4], "altitude": 1000}],
        "thermal": {"start": f"2024-06-21T{start}:00+00:00", "end": "2024-06-21T12:00:00+00:00",
                    "step": "30 min", "hemisphere_samples": hemisphere_samples,
                    "spin_up": False},
    }


@pytest.mark.parametrize("tau", [0.0, 0.3, 0.7])
def test_the_heat_balance_sees_the_partial_shadow_of_a_sheet(tau):
    """``radscene.solve_thermal`` of a flat asphalt ground half under a net of grey
    transmittance τ, the sun fixed at 20 deg: the cells under the net are sunlit τ (the share
    of the direct sun the net lets through; 0 for an opaque plate), the open cells 1; and
    the ground under the net ends cooler than the open ground, the more so the smaller τ."""
    import radscene

    solved = radscene.solve_thermal(_net_over_asphalt(tau, "09:00", hemisphere_samples=4))
    ground = solved.object.values == "terrain"
    x = solved.x.values
    y = solved.y.values
    # the net spans x 0..20 m, y 0..40 m, 2 m up; its shadow (sun zenith 20 deg, to the south)
    # lies 0.73 m north of it: cells 1 m clear of its edges are wholly under it or wholly open
    under = ground & (x < 19.0) & (np.abs(y - 20.0) < 15.0)
    open_ = ground & (x > 21.0) & (np.abs(y - 20.0) < 15.0)
    assert under.sum() >= 20 and open_.sum() >= 20
    lit = solved.sunlit.isel(time=-1).values
    np.testing.assert_allclose(lit[under], tau, atol=1e-12)
    np.testing.assert_allclose(lit[open_], 1.0, atol=1e-12)
    t = solved.surface_temperature.isel(time=-1).values
    assert t[under].mean() < t[open_].mean() - 1.0  # K


def _view_factor_to_rectangle(x, y, x0, x1, y0, y1, h):
    """View factor from a horizontal point (x, y) to a parallel rectangle [x0, x1] × [y0, y1]
    h above it: the sum over the four sub-rectangles with a corner above the point of the
    corner form (Howell, *A Catalog of Radiation Heat Transfer Configuration Factors*, B-4)."""
    def corner(a, b):  # signed extents from the point
        sa, sb = np.sign(a), np.sign(b)
        a, b = np.abs(a) / h, np.abs(b) / h
        value = (a / np.sqrt(1 + a * a) * np.arctan(b / np.sqrt(1 + a * a))
                 + b / np.sqrt(1 + b * b) * np.arctan(a / np.sqrt(1 + b * b))) / (2 * np.pi)
        return sa * sb * value
    return (corner(x1 - x, y1 - y) - corner(x0 - x, y1 - y) - corner(x1 - x, y0 - y)
            + corner(x0 - x, y0 - y))


@pytest.mark.parametrize("tau", [0.0, 0.3, 0.7])
def test_the_heat_balance_sky_view_passes_a_sheet(tau):
    """Under a net of grey transmittance τ the heat balance's sky view is 1 − F (1 − τ), F the
    view factor from the cell to the net (closed form): the net hides 1 − τ of its part of the
    hemisphere, not all of it; the rest of that part is the net's own (view factor F (1 − τ))."""
    import radscene

    solved = radscene.solve_thermal(_net_over_asphalt(tau, "11:00", hemisphere_samples=256))
    ground = solved.object.values == "terrain"
    x, y = solved.x.values, solved.y.values
    under = ground & (x < 19.0) & (x > 1.0) & (np.abs(y - 20.0) < 15.0)
    f = _view_factor_to_rectangle(x[under], y[under], 0.0, 20.0, 0.0, 40.0, 2.0)
    sky = solved.sky_view.values[under]
    # 256 cosine rays a cell: a view factor's standard error is about 0.03; over the cells'
    # mean about 0.005
    assert sky.mean() == pytest.approx(np.mean(1.0 - f * (1.0 - tau)), abs=0.015)
    # a grey net passes the diffuse sky's light as it passes the long-wave
    np.testing.assert_allclose(solved.sky_view_shortwave.values, solved.sky_view.values, rtol=1e-12)
    assert f.mean() > 0.6  # the net hides much of the sky: the test can tell τ from 0
