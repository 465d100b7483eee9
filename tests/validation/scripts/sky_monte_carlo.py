"""A scalar backward Monte Carlo of the sky radiance at the bottom of a plane-parallel
atmosphere, and a forward one of its diffuse irradiance: the reference solver of
``make_sky_references.py``.

The atmosphere: molecules of optical depth τ_R with scale height H_R and aerosol of optical
depth τ_A, single-scattering albedo ω_A and scale height H_A, over a black ground; the sun
at zenith θ_s with unit irradiance above the atmosphere (results are radiance / E_0 [sr-1]
and irradiance / E_0). Phase functions are given as tables P(Θ) normalised to 4π, sampled by
their inverse cumulative distribution.

Backward estimator: a ray leaves the observer towards the sky direction; at each collision
(drawn along the ray's optical path) it scores the next-event estimate of the direct sun,
w ω(z) P(Θ)/(4π) e^{−τ(z)/μ_s}, then turns by the local phase function (molecule or aerosol
by their share of the scattering) with its weight multiplied by ω(z); it ends leaving the
top, reaching the ground, or by Russian roulette. Polarisation is neglected (scalar): for
the molecular sky that is a few per cent; with aerosol at 0.55 um less.

It does NOT import radscene.
"""
import math

import numpy as np

TOP_KM = 100.0
_LEVELS = np.linspace(0.0, TOP_KM, 20001)


class Atmosphere:
    """Vertical structure: optical depth from the top, and the mixture at each depth."""

    def __init__(self, tau_r, tau_a, omega_a, h_r=8.0, h_a=2.0):
        self.tau_r, self.tau_a, self.omega_a = float(tau_r), float(tau_a), float(omega_a)
        z = _LEVELS
        # optical depth above altitude z (exponential profiles, cut at the top)
        above_r = tau_r * (np.exp(-z / h_r) - math.exp(-TOP_KM / h_r)) / (1 - math.exp(-TOP_KM / h_r))
        above_a = tau_a * (np.exp(-z / h_a) - math.exp(-TOP_KM / h_a)) / (1 - math.exp(-TOP_KM / h_a))
        self.depth = above_r + above_a  # decreasing with z
        self.total = float(self.depth[0])
        beta_r = tau_r / h_r * np.exp(-z / h_r)
        beta_a = tau_a / h_a * np.exp(-z / h_a)
        self._omega = (beta_r + omega_a * beta_a) / (beta_r + beta_a)
        self._share_r = beta_r / (beta_r + omega_a * beta_a)  # of the scattering
        self._depth_up = self.depth[::-1]

    def at(self, depth):
        """(ω, molecular share of the scattering) at optical depths from the top."""
        omega = np.interp(depth, self._depth_up, self._omega[::-1])
        share = np.interp(depth, self._depth_up, self._share_r[::-1])
        return omega, share


class Phase:
    """A tabulated phase function P(Θ) (normalised to 4π), log-linear in Θ."""

    def __init__(self, angles_deg, values):
        grid = np.linspace(0.0, 180.0, 36001)
        logp = np.interp(grid, np.asarray(angles_deg, float), np.log(np.asarray(values, float)))
        p = np.exp(logp)
        theta = np.radians(grid)
        dens = p * np.sin(theta)
        cdf = np.concatenate([[0.0], np.cumsum(0.5 * (dens[1:] + dens[:-1]) * np.diff(theta))])
        norm = cdf[-1] / 2.0  # ∫ P sin Θ dΘ should be 2
        self.scale = 1.0 / norm
        self._grid, self._p = grid, p * self.scale
        self._cdf = cdf / cdf[-1]
        self._cos = np.cos(theta)

    def __call__(self, cos_angle):
        angle = np.degrees(np.arccos(np.clip(cos_angle, -1.0, 1.0)))
        return np.interp(angle, self._grid, self._p)

    def sample(self, u):
        return np.interp(u, self._cdf, self._cos)


def rayleigh(depolarisation=0.0):
    """The molecular phase function with a depolarisation factor, as a :class:`Phase`."""
    g = depolarisation / (2.0 - depolarisation)
    angles = np.linspace(0.0, 180.0, 361)
    c = np.cos(np.radians(angles))
    return Phase(angles, 3.0 / (4.0 * (1.0 + 2.0 * g)) * ((1.0 + 3.0 * g) + (1.0 - g) * c * c))


def henyey_greenstein(g):
    angles = np.linspace(0.0, 180.0, 3601)
    c = np.cos(np.radians(angles))
    return Phase(angles, (1.0 - g * g) / (1.0 + g * g - 2.0 * g * c) ** 1.5)


def _turn(d, cos_t, rng):
    """Directions d (n, 3) turned by polar cosines cos_t about a uniform azimuth."""
    n = d.shape[0]
    phi = rng.uniform(0.0, 2.0 * math.pi, n)
    helper = np.where(np.abs(d[:, 2:3]) < 0.9, [[0.0, 0.0, 1.0]], [[1.0, 0.0, 0.0]])
    u = np.cross(d, helper)
    u /= np.linalg.norm(u, axis=1)[:, None]
    v = np.cross(d, u)
    s = np.sqrt(np.maximum(1.0 - cos_t * cos_t, 0.0))
    out = cos_t[:, None] * d + s[:, None] * (np.cos(phi)[:, None] * u + np.sin(phi)[:, None] * v)
    return out / np.linalg.norm(out, axis=1)[:, None]


def sky_radiance(atm, phase_r, phase_a, sun_zenith, zenith, relative_azimuth, photons, seed):
    """Sky radiance / E_0 [sr-1] seen from the ground towards (zenith, relative azimuth)
    [deg], and its standard error."""
    rng = np.random.default_rng(seed)
    mu_s = math.cos(math.radians(sun_zenith))
    sun_dir = np.array([-math.sin(math.radians(sun_zenith)), 0.0, -mu_s])  # propagation
    tz, ta = math.radians(zenith), math.radians(relative_azimuth)
    view = np.array([math.sin(tz) * math.cos(ta), math.sin(tz) * math.sin(ta), math.cos(tz)])
    d = np.tile(view, (photons, 1))
    depth = np.full(photons, atm.total)
    weight = np.ones(photons)
    score = np.zeros(photons)
    index = np.arange(photons)
    while index.size:
        step = -np.log(rng.random(index.size))
        depth = depth - step * d[:, 2]
        inside = (depth > 0.0) & (depth < atm.total)
        index, d, depth, weight = index[inside], d[inside], depth[inside], weight[inside]
        if not index.size:
            break
        omega, share = atm.at(depth)
        # the photon travels -d; from the sun it came along sun_dir
        cos_sun = -(d @ sun_dir)
        p = share * phase_r(cos_sun) + (1.0 - share) * phase_a(cos_sun)
        np.add.at(score, index, weight * omega * p / (4.0 * math.pi) * np.exp(-depth / mu_s))
        weight = weight * omega
        molecular = rng.random(index.size) < share
        u = rng.random(index.size)
        cos_t = np.where(molecular, phase_r.sample(u), phase_a.sample(u))
        d = _turn(d, cos_t, rng)
        low = weight < 0.05
        survive = rng.random(index.size) < 0.5
        weight = np.where(low, weight * 2.0, weight)
        keep = ~low | survive
        index, d, depth, weight = index[keep], d[keep], depth[keep], weight[keep]
    return float(score.mean()), float(score.std() / math.sqrt(photons))


def diffuse_irradiance(atm, phase_r, phase_a, sun_zenith, photons, seed):
    """Diffuse irradiance / E_0 on the horizontal ground (forward photons from the sun), and
    the direct one, μ_s e^{−τ/μ_s}."""
    rng = np.random.default_rng(seed)
    mu_s = math.cos(math.radians(sun_zenith))
    d = np.tile([math.sin(math.radians(sun_zenith)), 0.0, -mu_s], (photons, 1))
    depth = np.zeros(photons)
    weight = np.ones(photons)
    scattered = np.zeros(photons, dtype=bool)
    arrived = 0.0
    while depth.size:
        step = -np.log(rng.random(depth.size))
        depth = depth - step * d[:, 2]
        ground = depth >= atm.total
        arrived += float(np.sum(weight[ground & scattered]))
        inside = (depth > 0.0) & ~ground
        d, depth, weight = d[inside], depth[inside], weight[inside]
        if not depth.size:
            break
        omega, share = atm.at(depth)
        weight = weight * omega
        molecular = rng.random(depth.size) < share
        u = rng.random(depth.size)
        cos_t = np.where(molecular, phase_r.sample(u), phase_a.sample(u))
        d = _turn(d, cos_t, rng)
        scattered = np.ones(depth.size, dtype=bool)
    return mu_s * arrived / photons, mu_s * math.exp(-atm.total / mu_s)
