"""Radiometric closure: a rendered Lambertian plate against 6S's apparent reflectance.

A scene file — a 20 km plate of reflectance ρ, a map camera at the top of the atmosphere or
3 km up, nadir or 40° off nadir at 90° from the sun — goes through ``radscene render`` with the
``sixs`` engine, and the image's band radiance, as an apparent reflectance ρ* = π L / (μ_s E_0)
with radscene's own solar spectrum, is compared with 6S's apparent reflectance of the same
plate (Py6S, homogeneous Lambertian ground; the figures and the script that made them are in
``closure_references.py`` and ``scripts/make_closure_references.py``). 6S's ρ* is its band
integral weighted by its own solar spectrum; across these 20–100 nm bands the two weightings
differ by < 0.1 %.

Tolerance: 1 % of ρ* (the issue's figure for the ``sixs`` engine), or 2·10⁻⁵ in ρ* for the
black plate in the short-wave infrared, where ρ* ≈ 7·10⁻⁴ is the path alone (a fifth of a
real sensor's noise-equivalent reflectance difference).
"""

from __future__ import annotations

import importlib.util
from pathlib import Path

import numpy as np
import pytest

from radscene.sun import toa_solar_irradiance


def _load_references():
    path = Path(__file__).with_name("closure_references.py")
    spec = importlib.util.spec_from_file_location("closure_references", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


ref = _load_references()

TOLERANCE = 0.01
ABSOLUTE = 2e-5
AEROSOL = {"cont": "rural", "mari": "maritime"}


def _scene(rho, aerosol, aot, sensor, view_zenith, atmosphere=None):
    bands = [{"name": f"b{lo:.2f}", "min": f"{lo} um", "max": f"{hi} um"}
             for lo, hi in ref.BANDS_UM]
    altitude = "700 km" if sensor == "toa" else f"{ref.AIRCRAFT_ALTITUDE_KM} km"
    return {
        "name": "closure_plate",
        "environment": {
            "location": {"latitude": 0.0, "longitude": 0.0, "altitude": "0 m"},
            "sun": {"zenith": ref.SUN_ZENITH, "azimuth": ref.SUN_AZIMUTH, "distance": 1.0},
            "atmosphere": atmosphere or {"type": "sixs", "profile": "us_standard",
                                         "aerosol": AEROSOL[aerosol], "aot550": aot},
        },
        "materials": {"plate": {"reflectance": rho}},
        "objects": [{"name": "plate", "shape": {"type": "plate", "width": "20 km",
                                                "length": "20 km"},
                     "material": "plate", "temperature": "290 K"}],
        "bands": bands,
        "observers": [{"name": "cam", "type": "orthographic", "center": [0, 0], "gsd": "50 m",
                       "shape": [12, 12], "altitude": altitude, "zenith": view_zenith,
                       "azimuth": 270.0}],
        # the reflected sky is a Monte Carlo estimate: with 16 rays per pixel over these 144
        # pixels its standard error under maritime AOT 0.5 (a bright aureole) was about 1 %
        # (measured -0.9 % against the engine's own E_dif at 0.87 um; +0.27 % with 64)
        "render": {"sky_samples": 64},
    }


def _apparent_reflectance(ds) -> dict:
    mu_s = np.cos(np.radians(ref.SUN_ZENITH))
    out = {}
    for lo, hi in ref.BANDS_UM:
        wl = np.linspace(lo, hi, 4001)
        e0 = np.trapezoid(toa_solar_irradiance(wl, 1.0), wl)
        radiance = float(ds["radiance"].sel(band=f"b{lo:.2f}").mean())
        out[(lo, hi)] = np.pi * radiance / (mu_s * e0)
    return out


def _case_id(aerosol, aot, sensor, view_zenith, band, rho, visibility=None):
    lo, hi = band
    condition = f"aot{aot:.2f}" if visibility is None else f"vis{int(visibility)}"
    return (f"{aerosol}-{condition}-{'toa' if sensor == 'toa' else 'air3km'}-"
            f"vz{int(view_zenith):02d}-b{0.5 * (lo + hi):.2f}-r{rho:.2f}")


def _compare(render, tmp_path, condition, references, tolerance, atmosphere=None,
             visibility=None,
             rhos=ref.RHOS):
    """Render the plate at each of ``rhos`` and list the bands beyond tolerance."""
    aerosol, aot, sensor, view_zenith = condition
    failures = []
    for rho in rhos:
        ds = render(tmp_path / f"r{rho}", _scene(rho, aerosol, aot, sensor, view_zenith,
                                                  atmosphere))
        for band, value in _apparent_reflectance(ds).items():
            case = _case_id(aerosol, aot, sensor, view_zenith, band, rho, visibility)
            expected = references[case]["apparent_reflectance"]
            error = value / expected - 1.0
            if abs(error) > tolerance and abs(value - expected) > ABSOLUTE:
                failures.append(f"{case}: radscene {value:.5f}, 6S {expected:.5f} "
                                f"({100 * error:+.2f} %)")
    return failures


CONDITIONS = [(aer, aot, sensor, vz) for aer in ("cont", "mari") for aot in ref.AOTS
              for sensor in ("toa", "air") for vz in (0.0, 40.0)]
#: The one condition of the quick suite; the others run with ``make validate``.
QUICK = ("cont", 0.1, "toa", 0.0)
def _marks(condition):
    return [] if condition == QUICK else [pytest.mark.slow]


@pytest.mark.parametrize("condition", [
    pytest.param(c, marks=_marks(c), id="-".join(str(v) for v in c)) for c in CONDITIONS])
def test_rendered_plate_equals_6s_apparent_reflectance(render_scene, tmp_path, condition):
    failures = _compare(render_scene, tmp_path, condition, ref.HOMOGENEOUS, TOLERANCE)
    assert not failures, "\n".join(failures)


#: The shipped database's conditions (6S's aerosol models at a visibility) against 6S run at
#: the same visibility; the quick suite takes one, ``make validate`` the rest.
DATABASE_TOLERANCE = 0.03
DATABASE_QUICK = ("cont", 23.0, "toa", 0.0)
DATABASE_CONDITIONS = [(aer, vis, sensor, vz) for aer, vis in ref.DATABASE_CONDITIONS
                       for sensor in ("toa", "air") for vz in (0.0, 40.0)]


def _database(aerosol, visibility):
    return {"type": "database", "profile": "us_standard", "aerosol": AEROSOL[aerosol],
            "visibility": f"{visibility} km"}


@pytest.mark.parametrize("condition", [
    pytest.param(c, marks=() if c == DATABASE_QUICK else pytest.mark.slow,
                 id=f"{c[0]}-vis{int(c[1])}-{c[2]}-{int(c[3])}") for c in DATABASE_CONDITIONS])
def test_rendered_plate_with_the_database_equals_6s_within_3_percent(
        render_scene, tmp_path, condition):
    """ρ = 0.2 and 0.5 within 3 % in all 12 conditions (the visibilities become AOT550 0.235
    and 0.78 on the database's continuous axis); measured within 1.7 % (continental 5 km,
    3 km up, 40 deg, 0.45 um: +1.67 %). The black plate (the path alone) is the next test."""
    aerosol, visibility, sensor, view_zenith = condition
    failures = _compare(render_scene, tmp_path, (aerosol, None, sensor, view_zenith), ref.DATABASE,
                        DATABASE_TOLERANCE, _database(aerosol, visibility), visibility,
                        rhos=(0.2, 0.5))
    assert not failures, "\n".join(failures)


#: Black-plate conditions still beyond 3 %, with the figures measured (0.45, 0.55, 0.66,
#: 0.87, 1.63, 2.15 um bands): none. With the sun-zenith nodes 0 and 40 deg only (the sun is at
#: 30 deg), read linearly, continental 5 km from the top at 40 deg (+3.85 %) and from 3 km
#: (+4.84, +5.86 %) were here; maritime 23 km from 3 km at nadir was +4.45 % until the
#: aircraft levels were read relative to the top (+3.26 %), and +1.53 % since the factor turns
#: to the excess in the glory region (database._GLORY_BLEND).
BLACK_PLATE_GAPS: dict = {}
#: What a gap here would be: the maritime aerosol near backscatter, where 6S's radiance does not
#: follow the phase function's structure (the dip near 140-150 deg and the glory).
MARITIME_NADIR = ("interpolation of the single-scattering-normalised factor between the "
                  "sun-zenith nodes near the maritime phase function's backscatter structure")


def _black_plate_marks(condition):
    marks = [] if condition == DATABASE_QUICK else [pytest.mark.slow]
    gap = BLACK_PLATE_GAPS.get(condition)
    if gap:
        marks.append(pytest.mark.xfail(
            reason=f"known gap: the database's path radiance {gap} against 6S "
            f"({MARITIME_NADIR})", strict=True))
    return marks


@pytest.mark.parametrize("condition", [
    pytest.param(c, marks=_black_plate_marks(c), id=f"{c[0]}-vis{int(c[1])}-{c[2]}-{int(c[3])}")
    for c in DATABASE_CONDITIONS])
def test_black_plate_with_the_database_equals_6s_path_within_3_percent(
        render_scene, tmp_path, condition):
    """The path radiance alone. Measured (largest of the six bands): continental 23 km from
    the top +0.44 % (40 deg: -0.40), from 3 km +1.02 % (40 deg: -0.88; before the database's
    single scattering weighed the layer below the observer by its own mixture and its phase
    functions were tabulated at 6S's 20 wavelengths, +7.1 and +7.3 %); continental 5 km from
    the top -0.46 and -0.81 %, from 3 km +2.11 and +1.90 %; maritime 23 km from the top +2.74 %
    (40 deg: +0.38; +2.46 % since the single-scattering normaliser's phase function is averaged
    near backscatter), from 3 km at 40 deg -0.74 %; maritime 23 km at nadir from the top
    +1.13 %, from 3 km +1.53 % (+4.45 % before the aircraft levels were read relative to the
    top and the factor turned to the excess near backscatter)."""
    aerosol, visibility, sensor, view_zenith = condition
    failures = _compare(render_scene, tmp_path, (aerosol, None, sensor, view_zenith), ref.DATABASE,
                        DATABASE_TOLERANCE, _database(aerosol, visibility), visibility,
                        rhos=(0.0,))
    assert not failures, "\n".join(failures)


def _database_aot(aerosol, aot):
    return {"type": "database", "profile": "us_standard", "aerosol": AEROSOL[aerosol],
            "aot550": aot}


@pytest.mark.slow
@pytest.mark.parametrize("condition", [
    pytest.param(c, id="-".join(str(v) for v in c)) for c in CONDITIONS])
def test_rendered_plate_with_the_database_at_the_6s_aot_within_3_percent(
        render_scene, tmp_path, condition):
    """The issue's target: AOT550 0.1 and 0.5 (continental and maritime; 0.5 lies between the
    database's nodes 0.3 and 0.6), ρ = 0.2 and 0.5, against the same 6S references as the
    ``sixs`` engine. Measured within 1.11 % (maritime 0.5, 3 km up, 40 deg, 2.15 um)."""
    aerosol, aot, sensor, view_zenith = condition
    failures = _compare(render_scene, tmp_path, condition, ref.HOMOGENEOUS, DATABASE_TOLERANCE,
                        _database_aot(aerosol, aot), rhos=(0.2, 0.5))
    assert not failures, "\n".join(failures)


#: Black plates at the 6S AOT550 beyond 3 % (0.45, 0.55, 0.66, 0.87, 1.63, 2.15 um bands):
#: none. Before the sun-zenith node 20 deg and the spline, continental 0.5 from the top at 40
#: deg and from 3 km, and maritime 0.5 at 40 deg, were here (+3.0 to +5.1 %); maritime 0.5 at
#: nadir from 3 km until the factor turned to the excess near backscatter (+3.80 %; +5.55 %
#: before the aircraft levels were read relative to the top).
BLACK_PLATE_AOT_GAPS: dict = {}


def _black_plate_aot_marks(condition):
    gap = BLACK_PLATE_AOT_GAPS.get(condition)
    return [pytest.mark.slow] + ([pytest.mark.xfail(
        reason=f"known gap: the database's path radiance {gap} against 6S ({MARITIME_NADIR})",
        strict=True)] if gap else [])


@pytest.mark.parametrize("condition", [
    pytest.param(c, marks=_black_plate_aot_marks(c), id="-".join(str(v) for v in c))
    for c in CONDITIONS])
def test_black_plate_with_the_database_at_the_6s_aot_within_3_percent(
        render_scene, tmp_path, condition):
    """The path radiance alone at AOT550 0.1 and 0.5. Measured (largest of the six bands): AOT
    0.1 within 1.7 % everywhere (continental 3 km up, nadir, 2.15 um: +1.70 %); continental
    0.5 within 2.2 % (3 km up, nadir, 0.45 um: +2.18 %); maritime 0.5 at 40 deg within 2.0 %,
    at nadir from the top +0.17, +0.11, -0.23, +0.08, +1.32, +1.35 % and from 3 km +0.73,
    +0.25, -0.16, +0.41, +1.17, +1.08 % (+2.90 and +3.80 % at worst before the factor turned
    to the excess near backscatter, database._GLORY_BLEND)."""
    aerosol, aot, sensor, view_zenith = condition
    failures = _compare(render_scene, tmp_path, condition, ref.HOMOGENEOUS, DATABASE_TOLERANCE,
                        _database_aot(aerosol, aot), rhos=(0.0,))
    assert not failures, "\n".join(failures)


def _disc_scene(radius_km):
    scene = _scene(ref.HET_RO_ENV, ref.HET_AEROSOL, ref.HET_AOT, "toa", 0.0)
    scene["bands"] = [{"name": f"b{lo:.2f}", "min": f"{lo} um", "max": f"{hi} um"}
                      for lo, hi in ref.HET_BANDS_UM]
    scene["objects"][0]["shape"] = {"type": "plate", "width": "40 km", "length": "40 km"}
    scene["materials"]["target"] = {"reflectance": ref.HET_RO_TARGET}
    scene["objects"].append({"name": "target", "material": "target", "temperature": "290 K",
                             "shape": {"type": "cylinder", "radius": f"{radius_km} km",
                                       "height": "0.05 m", "sections": 256}})
    scene["observers"][0].update(gsd="50 m", shape=[161, 161])
    return scene


@pytest.mark.parametrize("radius_km", ref.HET_RADII_KM)
def test_dark_disc_in_bright_surroundings_equals_6s_heterogeneous_ground(
        render_scene, tmp_path, radius_km):
    """6S's heterogeneous Lambertian ground: ρ* at the centre of a dark disc within 3 %; the
    adjacency layer brightens the disc, more towards its edge."""
    ds = render_scene(tmp_path, _disc_scene(radius_km))
    mu_s = np.cos(np.radians(ref.SUN_ZENITH))
    failures = []
    for lo, hi in ref.HET_BANDS_UM:
        band = ds.sel(band=f"b{lo:.2f}")
        wl = np.linspace(lo, hi, 4001)
        e0 = np.trapezoid(toa_solar_irradiance(wl, 1.0), wl)
        centre = float(band["radiance"].values[79:82, 79:82].mean())
        got = np.pi * centre / (mu_s * e0)
        case = f"cont-aot{ref.HET_AOT:.2f}-toa-vz00-b{0.5 * (lo + hi):.2f}-het-rad{radius_km}"
        expected = ref.HETEROGENEOUS[case]["apparent_reflectance"]
        if abs(got / expected - 1.0) > 0.03:
            failures.append(f"{case}: radscene {got:.5f}, 6S {expected:.5f} "
                            f"({100 * (got / expected - 1):+.2f} %)")
        # inside the disc, ring by ring (each ring's mean: the pixels' own sky-fan noise
        # averages out), brighter towards the edge
        adjacency = band["adjacency"].values
        offsets = (np.arange(161) - 80) * 50.0
        r = np.hypot(*np.meshgrid(offsets, offsets, indexing="ij"))
        edges = np.arange(0.0, radius_km * 1000.0 - 50.0, 125.0)
        rings = np.array([adjacency[(r >= a) & (r < b)].mean()
                          for a, b in zip(edges[:-1], edges[1:], strict=True)])
        assert np.all(np.diff(rings) > -2e-3 * rings.max()), (case, rings)
        assert rings[-1] > rings[0] > 0.0, (case, rings)
    assert not failures, "\n".join(failures)
