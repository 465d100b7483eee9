"""The reflected background (``background_reflected``) against closed forms.

* An infinitely long V-groove of grey Lambertian walls, one bounce, in the thermal infrared
  with no sun and no sky: a wall's background radiance is ρ_A F(s) ε_B B(T_B), with F(s) the
  two-dimensional view factor from a strip at distance s from the apex to the opposite wall,
  F = ½ (sin θ_2 − sin θ_1), θ the angles from the strip's normal to the wall's two edges
  (Modest, *Radiative Heat Transfer*, 3rd ed., Academic Press 2013, §4.4, eq. 4.39 and
  Hottel's crossed strings; Siegel & Howell, *Thermal Radiation Heat Transfer*, view factor
  catalogue, "differential strip to a parallel strip"). Its mean over the wall is
  F_12 = 1 − sin(α/2) for an opening angle α.
* Two facing grey plates: the path tracer's N-bounce radiance is the N-term partial sum of
  the geometric series of reflections between them, ρ_1 (ε_2B_2 + ρ_2 ε_1B_1) / (1 − ρ_1ρ_2)
  for N → ∞ (the radiosity of two infinite parallel plates, Siegel & Howell, ch. 6).
* A mirror beside a sunlit (or hot) wall shows the wall: ρ_s times the wall's radiance.

The estimator is unbiased with independent samples: the error of a pixel over its binomial
standard deviation ρ_A ε_B B √(F(1 − F)/N) is of order 1 for every N (the noise falls as
1/√N). A pixel's first paths take their diffuse directions from its stratified sky fan
(``sky_samples`` of them): the error is then at most of that order, and smaller while N is
at most the fan's size.
"""

from __future__ import annotations

import numpy as np
import pytest

from radscene import load_scene, render
from radscene.radiometry import band_radiance
from radscene.sun import toa_solar_irradiance

LWIR = {"name": "lwir", "min": 8.0, "max": 12.0}
NIGHT = {"sun": {"zenith": 120.0, "azimuth": 180.0}, "atmosphere": {"type": "none"}}

# the V-groove: opening angle, wall length [m], length along the groove [m]
OPENING = 60.0
WALL = 10.0
LENGTH = 4000.0
RHO_A, RHO_B = 0.4, 0.3
T_A, T_B = 290.0, 340.0


def _groove_obj(path):
    """An OBJ file of the two walls, apex along the y axis at z = 0."""
    half = np.radians(OPENING / 2.0)
    top_a = (WALL * np.sin(half), WALL * np.cos(half))
    top_b = (-WALL * np.sin(half), WALL * np.cos(half))
    y0, y1 = -LENGTH / 2.0, LENGTH / 2.0
    vertices = [(0, y0, 0), (0, y1, 0), (top_a[0], y1, top_a[1]), (top_a[0], y0, top_a[1]),
                (top_b[0], y1, top_b[1]), (top_b[0], y0, top_b[1])]
    lines = [f"v {x:.9f} {y:.9f} {z:.9f}" for x, y, z in vertices]
    lines += ["o wall", "f 1 2 3", "f 1 3 4"]
    path.write_text("\n".join(lines) + "\n")
    other = path.with_name("wall_b.obj")
    lines_b = [f"v {x:.9f} {y:.9f} {z:.9f}" for x, y, z in vertices]
    lines_b += ["f 1 5 2", "f 1 6 5"]
    other.write_text("\n".join(lines_b) + "\n")
    return path, other


def _groove_scene(tmp_path, samples, bounces=1, seed=0, sky_samples=16):
    wall_a, wall_b = _groove_obj(tmp_path / "wall_a.obj")
    gsd = 0.25
    return {
        "name": "v_groove",
        "environment": NIGHT,
        "materials": {"a": {"reflectance": RHO_A}, "b": {"reflectance": RHO_B}},
        "objects": [
            {"name": "wall_a", "shape": {"type": "mesh", "file": str(wall_a)},
             "on_ground": False, "material": "a", "temperature": T_A},
            {"name": "wall_b", "shape": {"type": "mesh", "file": str(wall_b)},
             "on_ground": False, "material": "b", "temperature": T_B}],
        "bands": [LWIR],
        # nadir pixels over wall A, clear of the apex and the rim
        "observers": [{"name": "cam", "type": "orthographic", "gsd": gsd, "shape": [4, 16],
                       "center": [WALL * np.sin(np.radians(OPENING / 2.0)) / 2.0, 0.0],
                       "altitude": 100.0}],
        "render": {"background_samples": samples, "background_bounces": bounces,
                   "seed": seed, "sky_samples": sky_samples},
    }


def strip_view_factor(s):
    """2-D view factor from a strip of wall A at distance ``s`` [m] from the apex to wall B
    (Modest 2013, §4.4): ½ (sin θ_Q − sin θ_O) with θ from A's normal to B's edges."""
    half = np.radians(OPENING / 2.0)
    t_a = np.array([np.sin(half), np.cos(half)])  # along wall A, from the apex (x, z)
    n_a = np.array([-np.cos(half), np.sin(half)])  # A's normal, into the groove
    top_b = WALL * np.array([-np.sin(half), np.cos(half)])
    p = np.multiply.outer(np.asarray(s, dtype=float), t_a)
    to_top = top_b - p
    theta_top = np.arctan2(to_top @ t_a, to_top @ n_a)
    return 0.5 * (np.sin(theta_top) - np.sin(-np.pi / 2.0))


def _groove_expected(ds):
    s = ds["x"].values / np.sin(np.radians(OPENING / 2.0))
    f = strip_view_factor(s)
    emitted = (1.0 - RHO_B) * float(band_radiance(8.0, 12.0, T_B))
    return f, RHO_A * emitted * f, RHO_A * emitted


def test_strip_view_factor_averages_to_the_crossed_strings_answer():
    s = np.linspace(0.0, WALL, 200_001)
    mean = np.mean(0.5 * (strip_view_factor(s[1:]) + strip_view_factor(s[:-1])))
    assert mean == pytest.approx(1.0 - np.sin(np.radians(OPENING / 2.0)), rel=1e-6)


def test_v_groove_one_bounce_equals_the_view_factor_closed_form(tmp_path):
    samples = 16384
    ds = render(load_scene(_groove_scene(tmp_path, samples)))
    f, expected, scale = _groove_expected(ds)
    got = ds["background_reflected"].sel(band="lwir").values  # (y, x)
    sigma = scale * np.sqrt(f * (1.0 - f) / samples)
    z = (got - expected[None, :]) / sigma[None, :]
    assert np.all(np.abs(z) < 4.5), z
    column = got.mean(axis=0)  # 4 rows: σ / 2
    assert np.all(np.abs(column - expected) < 4.5 * sigma / 2.0)  # false alarm ~1e-4
    assert column == pytest.approx(expected, rel=0.02)
    # the other layers: the wall's own emission, nothing from a black sky
    assert ds["thermal_emission"].sel(band="lwir").values == pytest.approx(
        np.full(got.shape, (1.0 - RHO_A) * float(band_radiance(8.0, 12.0, T_A))), rel=1e-6)
    assert np.all(ds["sky_reflected"].values == 0.0)


def _groove_errors(tmp_path, samples, seed, sky_samples):
    """The V-groove's pixels' errors (y, x) = (4, 16) over the binomial σ of N independent
    paths."""
    ds = render(load_scene(_groove_scene(tmp_path, samples, seed=seed,
                                         sky_samples=sky_samples)))
    f, expected, scale = _groove_expected(ds)
    got = ds["background_reflected"].sel(band="lwir").values
    sigma = scale * np.sqrt(f * (1.0 - f) / samples)
    return (got - expected[None, :]) / sigma[None, :]


@pytest.mark.parametrize("samples", [16, 256, 4096])
def test_v_groove_error_falls_as_one_over_root_samples(tmp_path, samples):
    """Independent paths (a sky fan of one direction, as random as the paths' own): the
    pixels' errors over the binomial σ ∝ 1/√N have an RMS near 1 for every N: no bias, and
    noise that falls as 1/√N (64 pixels; the RMS of 64 unit normals lies in [0.7, 1.3] with
    probability > 0.998)."""
    z = _groove_errors(tmp_path, samples, samples, sky_samples=1)
    rms = float(np.sqrt(np.mean(z**2)))
    assert 0.7 < rms < 1.3


@pytest.mark.parametrize("samples", [4, 16, 64, 256])
def test_v_groove_from_the_sky_fan_is_unbiased_and_no_noisier(tmp_path, samples):
    """The first paths' diffuse directions from the pixels' 16-direction stratified sky fans
    (the default): over 4 renders of 64 pixels, the mean error is zero within 4.5 standard
    errors, and the RMS over the binomial σ of independent paths is at most 1.15 (measured
    0.45-0.6 for N ≤ 16, where every path takes a fan direction; 0.9-1.0 beyond, where the
    paths past the fan's 16 are independent). The same pixels with independent paths: an
    RMS near 1."""
    z = np.stack([_groove_errors(tmp_path, samples, 100 + seed, 16) for seed in range(4)])
    rms = float(np.sqrt(np.mean(z**2)))
    assert abs(float(z.mean())) < 4.5 * rms / np.sqrt(z.size)
    assert rms < (0.8 if samples <= 16 else 1.15)
    independent = np.stack([_groove_errors(tmp_path, samples, 200 + seed, 1)
                            for seed in range(4)])
    assert abs(float(independent.mean())) < 4.5 / np.sqrt(independent.size)
    assert 0.8 < float(np.sqrt(np.mean(independent**2))) < 1.2
    if samples <= 16:
        assert rms < 0.8 * float(np.sqrt(np.mean(independent**2)))


def _plates_scene(bounces, rho1=0.3, rho2=0.5, t1=300.0, t2=350.0, samples=64):
    width, gap = 400.0, 2.0
    return {
        "name": "facing_plates",
        "environment": NIGHT,
        "materials": {"bottom": {"reflectance": rho1}, "top": {"reflectance": rho2}},
        "objects": [
            {"name": "bottom", "shape": {"type": "plate", "width": width, "length": width},
             "material": "bottom", "temperature": t1},
            {"name": "top", "shape": {"type": "plate", "width": width, "length": width},
             "position": [0, 0, gap], "on_ground": False, "material": "top",
             "temperature": t2}],
        "bands": [LWIR],
        "observers": [{"name": "cam", "type": "perspective", "position": [0, 0, gap / 2],
                       "look_at": [0, 0, 0], "fov": 10, "shape": [4, 4]}],
        "render": {"background_bounces": bounces, "background_samples": samples},
    }


def plates_partial_sum(bounces, rho1, rho2, emitted1, emitted2):
    """ρ_1 Σ_{k=1..N} of the reflections between two infinite plates seen on plate 1:
    ε_2B_2, ρ_2 ε_1B_1, ρ_2ρ_1 ε_2B_2, ... (k odd: from plate 2, k even: from plate 1)."""
    total = 0.0
    for k in range(1, bounces + 1):
        ratio = (rho1 * rho2) ** ((k - 1) // 2)
        total += ratio * (emitted2 if k % 2 else rho2 * emitted1)
    return rho1 * total


@pytest.mark.parametrize("bounces", [1, 2, 3, 4, 6])
def test_facing_plates_n_bounces_equal_the_partial_geometric_series(bounces):
    rho1, rho2 = 0.3, 0.5
    e1 = (1 - rho1) * float(band_radiance(8.0, 12.0, 300.0))
    e2 = (1 - rho2) * float(band_radiance(8.0, 12.0, 350.0))
    ds = render(load_scene(_plates_scene(bounces)))
    got = float(ds["background_reflected"].mean())
    # the plates are 200 gaps wide: a path leaves past their edges with probability ~1e-4
    assert got == pytest.approx(plates_partial_sum(bounces, rho1, rho2, e1, e2), rel=2e-3)
    if 1 < bounces <= 4:  # the last bounce adds its own term (≥ 3 % of the sum)
        last = (plates_partial_sum(bounces, rho1, rho2, e1, e2)
                - plates_partial_sum(bounces - 1, rho1, rho2, e1, e2))
        assert got - plates_partial_sum(bounces - 1, rho1, rho2, e1, e2) == pytest.approx(
            last, rel=0.1)


def test_facing_plates_converge_to_the_infinite_series():
    rho1, rho2 = 0.6, 0.7  # ρ_1ρ_2 = 0.42: 20 bounces leave 0.42^10 = 2e-4 of the sum
    e1 = (1 - rho1) * float(band_radiance(8.0, 12.0, 300.0))
    e2 = (1 - rho2) * float(band_radiance(8.0, 12.0, 350.0))
    infinite = rho1 * (e2 + rho2 * e1) / (1.0 - rho1 * rho2)
    ds = render(load_scene(_plates_scene(20, rho1, rho2, samples=32)))
    assert float(ds["background_reflected"].mean()) == pytest.approx(infinite, rel=3e-3)
    one = render(load_scene(_plates_scene(1, rho1, rho2, samples=32)))
    assert float(one["background_reflected"].mean()) < 0.8 * infinite


@pytest.mark.parametrize("extinction", [0.0, 1e-3, 5e-3])
def test_the_air_between_facing_plates_dims_and_glows_as_the_exponential_integral(
        monkeypatch, extinction):
    """Air of extinction k [m-1] between two infinite plates a gap D apart (the upper black,
    at 350 K; the lower grey, ρ = 0.3), under a uniform sky of band radiance L_s: one bounce
    of background on the lower plate is ρ [2 E₃(kD) B₂ + (1 − 2 E₃(kD)) L_s] — the upper
    plate's radiance dimmed along every slant path D/μ and the air's own radiance, that of a
    long horizontal path (the sky's at the horizon), over the rest (E₃ the exponential
    integral; Chandrasekhar 1960, the flux through a slab)."""
    from scipy.special import expn

    import radscene.render.band_setup as band_setup

    gap, rho, sky = 100.0, 0.3, 3.0  # [m], [-], [W m-2 sr-1 um-1]
    monkeypatch.setattr(band_setup, "air_extinction",
                        lambda atmosphere, altitude, quadrature: np.full(len(quadrature), extinction))
    scene = _plates_scene(1, rho1=rho, rho2=0.0, samples=256)
    scene["environment"] = {"sun": {"zenith": 120.0, "azimuth": 180.0},
                            "atmosphere": {"type": "uniform", "sky_radiance": sky}}
    for plate in scene["objects"]:
        plate["shape"] = {"type": "plate", "width": 200 * gap, "length": 200 * gap}
    scene["objects"][1]["position"] = [0, 0, gap]
    scene["observers"][0]["position"] = [0, 0, gap / 2]
    got = float(render(load_scene(scene))["background_reflected"].mean())
    slab = 2.0 * float(expn(3, extinction * gap))
    b2 = float(band_radiance(8.0, 12.0, 350.0))
    want = rho * (slab * b2 + (1.0 - slab) * sky * 4.0)  # the 8-12 um band: 4 um of sky
    assert got == pytest.approx(want, rel=5e-3)
    if extinction > 0.0:  # the air matters here: 8-37 % of the upper plate's light
        assert abs(got / (rho * b2) - 1.0) > 0.02


def _mirror_scene(band, wall_temperature):
    """A horizontal mirror (ρ_s = 0.9, n = 20 000) in front of a box whose south face is lit
    by a sun in the south at 30° zenith; the camera sees the face in the mirror."""
    return {
        "name": "mirror",
        "environment": {"sun": {"zenith": 30.0, "azimuth": 180.0},
                        "atmosphere": {"type": "none"}},
        "materials": {"mirror": {"reflectance": 0.9, "specular_reflectance": 0.9,
                                 "specular_exponent": 20000},
                      "wall": {"reflectance": 0.5}},
        "objects": [
            {"name": "mirror", "shape": {"type": "plate", "width": 200, "length": 200},
             "material": "mirror", "temperature": 280.0},
            {"name": "wall", "shape": {"type": "box", "size": [80, 2, 40]},
             "position": [0, 30, 0], "material": "wall", "temperature": wall_temperature}],
        "bands": [band],
        "observers": [{"name": "cam", "type": "perspective", "position": [0, -20, 20],
                       "look_at": [0, 10, 0], "fov": 4, "shape": [4, 4]}],
        "render": {"background_samples": 256, "sky_samples": 4},
    }


@pytest.mark.parametrize("band", [{"name": "vis", "min": 0.5, "max": 0.6}, LWIR])
def test_a_mirror_shows_the_sunlit_warm_wall(band):
    lo, hi = band["min"], band["max"]
    wl = np.linspace(lo, hi, 20001)
    e_sun = float(np.trapezoid(toa_solar_irradiance(wl), wl))
    cos_sun = np.sin(np.radians(30.0))  # the south face's normal is (0, -1, 0)
    wall = 0.5 / np.pi * e_sun * cos_sun + 0.5 * float(band_radiance(lo, hi, 400.0))
    ds = render(load_scene(_mirror_scene(band, 400.0)))
    got = ds["background_reflected"].sel(band=band["name"]).values
    # within the narrow lobe cos θ_i / max(cos θ_i, cos θ_o) departs from 1 by < 1 %
    assert got == pytest.approx(np.full(got.shape, 0.9 * wall), rel=0.015)
    assert np.all(ds["sun_diffuse"].values == 0.0)  # the mirror has no diffuse part
