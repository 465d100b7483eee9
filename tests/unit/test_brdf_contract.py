"""The BRDF contract, generated from the registry: every registered model, one set of checks.

Reciprocity, energy conservation (ρ_dh + τ_dh ≤ 1 over a grid of incidence angles and
wavelengths), Kirchhoff emissivity, sampling consistent with evaluation (χ² of the sampled
directions against the reported pdf, the pdf integrating to at most 1 and positive wherever f
is, and the Monte Carlo estimate of ρ_dh from the samples), frame invariance, broadcasting and
NaN behaviour. A model registered without a case in CASES fails ``test_every_model_has_a_case``.
"""

import numpy as np
import pytest
from scipy import stats

from radscene.geometry.frames import direction_from_angles, normalize, to_world
from radscene.materials.brdf import BRDFS, make_brdf
from radscene.materials.brdf.tabulated import write_table

#: Reject a correct sampler 1 time in 1000 (fixed seeds: the outcome is deterministic).
CHI2_P_MIN = 1e-3
#: Relative tolerance of reciprocity (both orders evaluate the same floating-point formula up
#: to the order of operands).
RECIPROCITY_REL = 1e-10
#: Allowance on ρ_dh + τ_dh ≤ 1 for the quadrature error of the albedo integrators [-].
ENERGY_ABS = 2e-3
#: Monte Carlo standard errors allowed between the sample estimate of ρ_dh and albedo().
MC_SIGMAS = 5.0
#: Systematic error allowed on top: the deterministic albedo integrators [-].
ALBEDO_ABS = 2e-3
#: Quadrature error allowed on the integral of the pdf over the sphere [-].
PDF_SUM_ABS = 1e-3

WAVELENGTHS = np.array([0.45, 1.0, 10.0])  # [um]
INCIDENCE = np.array([0.0, 15.0, 30.0, 45.0, 60.0, 75.0, 85.0, 89.0])  # [deg]

_N_LEAF = {"wavelength": [0.4, 0.7, 1.0, 14.0], "values": [0.08, 0.45, 0.48, 0.02]}
_T_LEAF = {"wavelength": [0.4, 0.7, 1.0, 14.0], "values": [0.04, 0.40, 0.45, 0.0]}

#: Representative parameters of every registered model (some spectral, to exercise λ).
CASES = {
    "lambertian": {"reflectance": {"wavelength": [0.4, 2.5, 14.0], "values": [0.2, 0.6, 0.05]}},
    "phong": {"diffuse_reflectance": {"wavelength": [0.4, 14.0], "values": [0.5, 0.1]},
              "specular_reflectance": 0.3, "specular_exponent": 20.0},
    "ggx": {"roughness": 0.3, "refractive_index": {"wavelength": [0.4, 14.0],
                                                   "values": [1.5, 1.3]}},
    # aluminium-like conductor
    "beckmann": {"roughness": 0.15, "refractive_index": 0.96, "extinction_coefficient": 6.69},
    # plowed field (libRadtran example)
    "rpv": {"rho0": 0.076, "k": 0.648, "theta": -0.29},
    "rossli": {"f_iso": 0.3, "f_vol": 0.15, "f_geo": 0.03, "hotspot": True},
    "hapke": {"single_scattering_albedo": {"wavelength": [0.4, 14.0], "values": [0.95, 0.3]},
              "asymmetry": -0.3, "opposition_amplitude": 0.5, "opposition_width": 0.06},
    "coxmunk": {"wind_speed": 5.0},  # water, Hale & Querry index
    "lambertian_transmission": {"reflectance": _N_LEAF, "transmittance": _T_LEAF},
    "tabulated": {"file": None},  # filled by the table_file fixture
}


@pytest.fixture(scope="module")
def table_file(tmp_path_factory):
    """A BRDF table with a wavelength column, sampled from a Hapke surface."""
    source = make_brdf({"type": "hapke", "single_scattering_albedo": 0.7, "asymmetry": -0.2})
    zen = np.arange(0.0, 90.1, 7.5)
    phi = np.arange(0.0, 180.1, 15.0)
    ti, to, ph = np.meshgrid(np.minimum(zen, 89.0), np.minimum(zen, 89.0), phi, indexing="ij")
    f = source.f_angles(ti, to, ph)
    values = np.stack([f, 0.5 * f])  # darker at the long wavelength
    path = tmp_path_factory.mktemp("brdf") / "hapke_table.csv"
    return write_table(path, zen, zen, phi, values, wavelength=[0.4, 14.0],
                       comment="test table sampled from Hapke(w=0.7, b=-0.2)")


def _model(name, table_file):
    spec = dict(CASES[name])
    if name == "tabulated":
        spec["file"] = str(table_file)
    return make_brdf({"type": name, **spec})


def _sphere(rng, n):
    return normalize(rng.normal(size=(n, 3)))


def _upper(rng, n):
    v = _sphere(rng, n)
    v[:, 2] = np.abs(v[:, 2])
    return v


MODELS = sorted(BRDFS)


def test_every_model_has_a_case():
    assert sorted(CASES) == MODELS


@pytest.mark.parametrize("name", MODELS)
def test_reciprocity(name, table_file):
    model = _model(name, table_file)
    rng = np.random.default_rng(11)
    n = 4000
    draw = _sphere if model.two_sided else _upper
    wi, wo = draw(rng, n), draw(rng, n)
    wl = rng.choice(WAVELENGTHS, n)
    f1 = model.f(wi, wo, wl)
    f2 = model.f(wo, wi, wl)
    np.testing.assert_allclose(f1, f2, rtol=RECIPROCITY_REL, atol=0)
    assert np.all(f1 >= 0.0) and np.any(f1 > 0.0)
    # also in the world frame about a tilted normal
    normal = normalize(np.array([0.3, -0.4, 0.85]))
    wi_w, wo_w = to_world(wi, normal), to_world(wo, normal)
    g1 = model.f(wi_w, wo_w, wl, normal=normal)
    np.testing.assert_allclose(g1, model.f(wo_w, wi_w, wl, normal=normal),
                               rtol=RECIPROCITY_REL, atol=0)
    # frame invariance: the same local geometry gives the same value
    np.testing.assert_allclose(g1, f1, rtol=1e-9, atol=1e-12)


@pytest.mark.parametrize("name", MODELS)
def test_energy_conservation_and_kirchhoff(name, table_file):
    model = _model(name, table_file)
    wi = direction_from_angles(INCIDENCE, 0.0)[:, None, :]  # (8, 1, 3)
    wl = WAVELENGTHS[None, :]  # (1, 3)
    rho = model.albedo(wi, wl)
    tau = model.transmittance(wi, wl)
    eps = model.emissivity(wi, wl)
    assert rho.shape == tau.shape == eps.shape == (INCIDENCE.size, WAVELENGTHS.size)
    assert np.all(rho >= 0.0) and np.all(tau >= 0.0)
    assert np.all(rho + tau <= 1.0 + ENERGY_ABS), (rho + tau).max()
    np.testing.assert_allclose(eps, 1.0 - rho - tau, rtol=0, atol=1e-15)
    assert np.all(eps >= -ENERGY_ABS)
    eps_h = model.hemispherical_emissivity(WAVELENGTHS)
    assert eps_h.shape == WAVELENGTHS.shape
    assert np.all((eps_h >= -ENERGY_ABS) & (eps_h <= 1.0))


@pytest.mark.parametrize("name", MODELS)
def test_one_sided_models_do_not_reflect_or_emit_below_the_horizon(name, table_file):
    model = _model(name, table_file)
    below = normalize(np.array([0.5, 0.1, -0.6]))
    up = normalize(np.array([-0.2, 0.3, 0.9]))
    if model.two_sided:
        assert float(model.f(below, up, 1.0)) > 0.0  # transmits
        assert float(model.emissivity(below, 1.0)) == pytest.approx(
            float(model.emissivity(up, 1.0)), abs=1e-12)
    else:
        assert float(model.f(below, up, 1.0)) == 0.0
        assert float(model.f(up, below, 1.0)) == 0.0
        assert float(model.albedo(below, 1.0)) == 0.0
        assert float(model.emissivity(below, 1.0)) == 0.0


def _bin_probabilities(model, wo, wl, n_z, n_phi, order=8):
    """∫ pdf dω over equal-area bins (z = cos θ in [-1, 1], φ in [0, 2π)), by an
    order × order Gauss–Legendre rule in (z, φ) on each bin."""
    z_edges = np.linspace(-1.0, 1.0, n_z + 1)
    phi_edges = np.linspace(0.0, 2.0 * np.pi, n_phi + 1)
    x, w = np.polynomial.legendre.leggauss(order)
    dz, dphi = 2.0 / n_z, 2.0 * np.pi / n_phi
    zs = (z_edges[:-1, None] + 0.5 * dz * (x + 1.0)).ravel()
    ps = (phi_edges[:-1, None] + 0.5 * dphi * (x + 1.0)).ravel()
    zz, pp = np.meshgrid(zs, ps, indexing="ij")
    r = np.sqrt(1.0 - zz * zz)
    wi = np.stack([r * np.cos(pp), r * np.sin(pp), zz], axis=-1)
    density = model.pdf(wo, wi, wl).reshape(n_z, order, n_phi, order)
    weights = np.outer(w, w) * (0.25 * dz * dphi)
    prob = np.einsum("iajb,ab->ij", density, weights)
    return prob, z_edges, phi_edges


@pytest.mark.parametrize("view_zenith", [0.0, 40.0, 75.0])
@pytest.mark.parametrize("name", MODELS)
def test_sampling_chi2_against_pdf(name, view_zenith, table_file):
    model = _model(name, table_file)
    wl = 1.0
    wo = direction_from_angles(view_zenith, 30.0)
    rng = np.random.default_rng(int(view_zenith) + 7)
    n = 100_000
    wi, pdf = model.sample(wo, rng.random(n), rng.random(n), wl)
    assert wi.shape == (n, 3) and pdf.shape == (n,)
    np.testing.assert_allclose(np.linalg.norm(wi, axis=-1), 1.0, rtol=0, atol=1e-9)
    np.testing.assert_allclose(pdf, model.pdf(wo, wi, wl), rtol=1e-9, atol=0)
    assert np.all(pdf > 0.0)
    n_z, n_phi = 24, 48
    prob, z_edges, phi_edges = _bin_probabilities(model, wo, wl, n_z, n_phi)
    counts, _, _ = np.histogram2d(wi[:, 2], np.arctan2(wi[:, 1], wi[:, 0]) % (2 * np.pi),
                                  bins=[z_edges, phi_edges])
    if model.two_sided:
        # both hemispheres carry energy; the pdf is smooth on the whole sphere
        assert prob.sum() == pytest.approx(1.0, abs=PDF_SUM_ABS)
        expected, observed = prob.ravel() * n, counts.ravel()
    else:
        # one-sided: the directions below the horizon (f = 0 there) are pooled into one bin of
        # probability 1 - P(upper). (Microfacet densities have an integrable singularity at
        # wi = -wo there, which a fixed quadrature rule cannot integrate.)
        upper = slice(n_z // 2, n_z)
        p_upper = prob[upper].sum()
        assert p_upper <= 1.0 + PDF_SUM_ABS
        expected = np.append(prob[upper].ravel(), max(1.0 - p_upper, 0.0)) * n
        observed = np.append(counts[upper].ravel(), counts[: n_z // 2].sum())
    # pool the bins expected to hold fewer than 5 samples into one (as Mitsuba's chi2 test)
    small = expected < 5.0
    exp_pooled = np.append(expected[~small], expected[small].sum())
    obs_pooled = np.append(observed[~small], observed[small].sum())
    keep = exp_pooled > 0.0
    chi2 = np.sum((obs_pooled[keep] - exp_pooled[keep]) ** 2 / exp_pooled[keep])
    dof = keep.sum() - 1
    p_value = stats.chi2.sf(chi2, dof)
    assert p_value > CHI2_P_MIN, (chi2, dof)


@pytest.mark.parametrize("name", MODELS)
def test_sample_weights_estimate_albedo(name, table_file):
    """E[f cos θ / pdf] over the sampler equals ρ_dh (+ τ_dh): sampling agrees with f."""
    model = _model(name, table_file)
    rng = np.random.default_rng(23)
    n = 200_000
    for zenith in (10.0, 60.0):
        wo = direction_from_angles(zenith, 200.0)
        wi, pdf = model.sample(wo, rng.random(n), rng.random(n), 1.0)
        weight = model.f(wi, wo, 1.0) * np.abs(wi[:, 2]) / pdf
        estimate, error = weight.mean(), weight.std() / np.sqrt(n)
        total = model.albedo(wo, 1.0) + model.transmittance(wo, 1.0)
        assert estimate == pytest.approx(float(total), abs=MC_SIGMAS * error + ALBEDO_ABS)


@pytest.mark.parametrize("name", MODELS)
def test_pdf_positive_wherever_f_is(name, table_file):
    model = _model(name, table_file)
    rng = np.random.default_rng(31)
    wi, wo = _sphere(rng, 20_000), _upper(rng, 20_000)
    f = model.f(wi, wo, 1.0)
    p = model.pdf(wo, wi, 1.0)
    assert np.all(p[f > 0.0] > 0.0)


@pytest.mark.parametrize("name", MODELS)
def test_broadcasting_shapes(name, table_file):
    model = _model(name, table_file)
    wi = direction_from_angles(np.array([0.0, 20.0, 40.0, 60.0]), 0.0)[:, None, :]  # (4,1,3)
    wo = direction_from_angles(np.linspace(0.0, 80.0, 5), 180.0)[None, :, :]  # (1,5,3)
    wl = np.array([0.5, 1.0, 2.0, 8.0, 10.0])  # (5,)
    assert model.f(wi, wo, wl).shape == (4, 5)
    assert model.f_angles(np.zeros((2, 1)), np.zeros(3), 0.0, 1.0).shape == (2, 3)
    assert model.albedo(wi[:, 0, :], wl[:2, None]).shape == (2, 4)
    assert model.emissivity(wi[:, 0, :], 1.0).shape == (4,)
    d, p = model.sample(wo[0], np.full((2, 1), 0.3), 0.6, 1.0)
    assert d.shape == (2, 5, 3) and p.shape == (2, 5)
    # a scalar geometry still returns a numpy array
    assert isinstance(model.f([0, 0, 1.0], [0, 0, 1.0], 1.0), np.ndarray)


@pytest.mark.parametrize("name", MODELS)
def test_nan_direction_gives_nan(name, table_file):
    model = _model(name, table_file)
    wi = np.array([[np.nan, 0.0, np.nan], [0.0, 0.0, 1.0]])
    wo = np.array([[0.0, 0.0, 1.0], [0.0, 0.0, 1.0]])
    f = model.f(wi, wo, 1.0)
    assert np.isnan(f[0]) and np.isfinite(f[1])


@pytest.mark.parametrize("name", MODELS)
def test_config_round_trip(name, table_file):
    model = _model(name, table_file)
    again = make_brdf(model.config())
    rng = np.random.default_rng(41)
    wi, wo = _upper(rng, 100), _upper(rng, 100)
    np.testing.assert_array_equal(again.f(wi, wo, 1.0), model.f(wi, wo, 1.0))
    assert type(again) is type(model)
