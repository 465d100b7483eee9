"""The sea reflects the scene (docs/sea.md): a hot object's mirror image in a calm sea through
the reflected-background term, against Fresnel's reflectance of water; the sun's glint on a
wavy sea, against Cox & Munk's (1954) slope distribution (doi:10.1364/JOSA.44.000838)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import quad

import radscene
from radscene.geometry.sea import wind_at_height
from radscene.materials.brdf.coxmunk import mean_square_slope
from radscene.materials.water import water_reflectance
from radscene.radiometry.planck import spectral_radiance

#: The reflection against ∫ R(λ, θ) B(λ, T) dλ over the band: the background pass reflects with
#: the sea's BRDF at the band's centre (docs/sea.md), R(10 um, 60 deg) = 0.0388 against the
#: band's B-weighted 0.0421: measured -7.2 % [-].
MIRROR_BAND_REL = 0.10
#: The reflection against R(10 um, 60 deg) B over the band, what the pass computes; 64 paths
#: per pixel, 528 pixels: measured +0.8 % [-].
MIRROR_CENTRE_REL = 0.03
#: The reflection's far edge (where it falls to half) against the mirror geometry [m]; the
#: calm sea's facets (sigma^2 = 0.003) blur it by about 2 m at that distance; measured 1.1 m
#: further south.
MIRROR_EDGE_ABS = 2.0
#: The glint's radiance-weighted centroid against Cox & Munk's [m] (spread 17 m; measured
#: 0.5 m for seeds 1-3: one realisation of the waves).
GLINT_CENTROID_ABS = 1.5
#: The glint's rms radius against Cox & Munk's [-]; measured +0.05 % to +1.6 % for seeds 1-3.
#: Half the variance (about the mesh's share at 3 m/s alone) gives 0.67 times it, the centroid
#: 2.4 m west.
GLINT_SPREAD_REL = 0.10

T_OBJECT = 400.0  # [K]
VIEW_ZENITH = 60.0  # [deg]
HEIGHT = 20.0  # the object's [m]
SOUTH_FACE = 15.0  # y of the object's south face [m]


def _ground_points(camera, z=0.0):
    """Where each pixel's centre ray meets the plane ``z`` (x, y) [m], as (ny, nx) maps."""
    rays = camera.rays()
    t = (z - rays.origins[:, 2]) / rays.directions[:, 2]
    points = rays.origins + t[:, None] * rays.directions
    out = np.empty((rays.shape[0] * rays.shape[1], 2))
    out[rays.pixel] = points[:, :2]
    return out[:, 0].reshape(rays.shape), out[:, 1].reshape(rays.shape)


def test_a_hot_object_is_mirrored_in_a_calm_sea_with_the_fresnel_reflectance():
    """A black 20 m tall box at 400 K standing in a calm sea, seen 60 deg off nadir from the
    south in 8-12 um, no sun, no atmosphere. A sea point d metres south of the box's south face
    reflects the ray that climbs at 30 deg and meets the face at height d tan 30 deg: the box
    is mirrored in the sea from its foot to d = 20 / tan 30 = 34.6 m south. There the
    background term is the sea's reflectance at 60 deg times the box's radiance; beside the
    box (no object in the mirror direction) it is zero."""
    scene = {
        "name": "sea-mirror",
        "environment": {"sun": {"zenith": 120.0, "azimuth": 0.0}, "atmosphere": {"type": "none"}},
        "terrain": {"type": "sea", "wind_speed": 0, "tile": 32, "resolution": 1.0, "size": [160, 160],
                    "origin": [-80, -80], "temperature": "290 K"},
        "materials": {"black": {"reflectance": 0.0}},
        "objects": [{"name": "box", "shape": {"type": "box", "size": [20, 10, HEIGHT]},
                     "position": [0, SOUTH_FACE + 5, 0], "material": "black", "temperature": f"{T_OBJECT} K"}],
        "bands": [{"name": "lwir", "min": 8.0, "max": 12.0}],
        "observers": [{"name": "cam", "type": "orthographic", "center": [0, 0], "gsd": 0.5,
                       "shape": [96, 128], "altitude": 200, "zenith": VIEW_ZENITH, "azimuth": 180.0}],
        "render": {"sky_samples": 4, "background_bounces": 1, "background_samples": 64},
    }
    loaded = radscene.load_scene(scene)
    ds = radscene.render(loaded, "cam")
    x, y = _ground_points(loaded.observer("cam").camera)
    ids = ds.object_id.values
    sea = ids == 0
    background = ds.background_reflected.values[0]
    box = ds.radiance.values[0][ids == 1]
    np.testing.assert_allclose(box, box[0], rtol=1e-12)  # a black body's radiance
    # well inside the mirror image, and beside it at the same distances
    mirror = sea & (np.abs(x) < 6.0) & (y > -12.0) & (y < 10.0)
    beside = sea & (np.abs(x) > 20.0) & (y > -12.0) & (y < 10.0)
    assert mirror.sum() > 400 and beside.sum() > 800
    reflected = float(background[mirror].mean())
    assert float(np.abs(background[beside]).max()) < 1e-3 * reflected
    # Fresnel: the band's sum of R(lambda, 60 deg) B(lambda, 400 K), and R at the band's centre
    band = quad(lambda wl: float(water_reflectance(wl, VIEW_ZENITH) * spectral_radiance(wl, T_OBJECT)),
                8.0, 12.0, limit=200)[0]
    assert reflected == pytest.approx(band, rel=MIRROR_BAND_REL)
    assert reflected / float(box[0]) == pytest.approx(float(water_reflectance(10.0, VIEW_ZENITH)),
                                                      rel=MIRROR_CENTRE_REL)
    # the mirror image ends where the climbing ray passes over the box's top
    rows = np.flatnonzero((sea | (np.abs(x) >= 6.0)).all(axis=1))  # rows of sea in the middle
    profile_y = y[rows, 64]
    profile = np.array([background[r][sea[r] & (np.abs(x[r]) < 6.0)].mean() for r in rows])
    order = np.argsort(profile_y)  # from the south
    below = np.flatnonzero(profile[order] < 0.5 * reflected)
    k = below[-1]  # the northernmost row under half, then the next one north
    y0, y1 = profile_y[order][k], profile_y[order][k + 1]
    p0, p1 = profile[order][k], profile[order][k + 1]
    edge = y0 + (0.5 * reflected - p0) * (y1 - y0) / (p1 - p0)
    assert edge == pytest.approx(SOUTH_FACE - HEIGHT / math.tan(math.radians(90.0 - VIEW_ZENITH)),
                                 abs=MIRROR_EDGE_ABS)


def _cox_munk_glint(u, v, sun_zenith, variance):
    """The glint of isotropic Gaussian slopes of total ``variance`` seen along tangent-plane
    directions (u, v) from straight above, the sun at ``sun_zenith`` [deg] in the east, up to a
    constant (Cox & Munk 1954 eq. 1, Fresnel taken constant): p(z_x, z_y) / (4 cos θ_v cos⁴ β)."""
    rho = np.sqrt(1.0 + u**2 + v**2)
    view = np.stack([-u, -v, np.ones_like(u)], axis=-1) / rho[..., None]
    sun = np.array([math.sin(math.radians(sun_zenith)), 0.0, math.cos(math.radians(sun_zenith))])
    half = view + sun
    half /= np.linalg.norm(half, axis=-1)[..., None]
    zx, zy = -half[..., 0] / half[..., 2], -half[..., 1] / half[..., 2]
    return np.exp(-(zx**2 + zy**2) / variance) / (4.0 * view[..., 2] * half[..., 2] ** 4)


def _moments(weight, x, y):
    w = weight / weight.sum()
    cx, cy = float((w * x).sum()), float((w * y).sum())
    return cx, cy, math.sqrt(float((w * ((x - cx) ** 2 + (y - cy) ** 2)).sum()))


def test_the_glint_of_a_wavy_sea_spreads_as_cox_and_munk_slopes_say():
    """A 3 m/s sea (Pierson-Moskowitz, its waves on a 0.5 m mesh, the rest in the facets'
    roughness) under a camera 50 m up looking straight down, the sun 20 deg from the zenith
    in the east, visible band, no sky: the image is the glint. Its radiance-weighted centroid
    and rms radius on the sea are those of Cox & Munk's glint of the same total slope variance
    (0.0187): the centroid 22.8 m east — beyond the specular point H tan 20 deg = 18.2 m, as
    the 1 / (cos θ_v cos⁴ β) weighting skews it — and a radius of 16.9 m."""
    height, sun_zenith, wind, n = 50.0, 20.0, 3.0, 100
    scene = {
        "name": "glint",
        "environment": {"sun": {"zenith": sun_zenith, "azimuth": 90.0}, "atmosphere": {"type": "none"}},
        "terrain": {"type": "sea", "wind_speed": f"{wind} m/s", "tile": 16, "resolution": 0.5,
                    "size": [160, 160], "origin": [-80, -80], "temperature": "290 K", "seed": 1},
        "bands": [{"name": "vis", "min": 0.5, "max": 0.6}],
        "observers": [{"name": "cam", "type": "perspective", "position": [0, 0, height],
                       "attitude": [0, -90, 0], "fov": 100, "shape": [n, n], "supersample": 2}],
        "render": {"sky_samples": 1, "specular_samples": 1, "background_bounces": 0, "shadows": False},
    }
    loaded = radscene.load_scene(scene)
    image = radscene.render(loaded, "cam").radiance.values[0]
    x, y = _ground_points(loaded.observer("cam").camera)
    variance = float(mean_square_slope(wind_at_height(wind, 12.5)))
    expected = _cox_munk_glint(x / height, y / height, sun_zenith, variance)
    cx, cy, radius = _moments(image, x, y)
    ex, ey, expected_radius = _moments(expected, x, y)
    assert (ex, ey) == pytest.approx((22.8, 0.0), abs=0.1)
    assert (cx, cy) == pytest.approx((ex, ey), abs=GLINT_CENTROID_ABS)
    assert radius == pytest.approx(expected_radius, rel=GLINT_SPREAD_REL)
    # the specular point of a flat sea lies inside the glint, a fraction of its radius off
    assert math.hypot(cx - height * math.tan(math.radians(sun_zenith)), cy) < 0.3 * radius
