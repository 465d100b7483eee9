"""Ross-Thick / Li-Sparse kernel-driven BRDF (the MODIS MCD43 model), with the hot-spot option.

The BRF is a linear combination of an isotropic term and two kernels (Wanner, Li & Strahler
1995; Lucht, Schaaf & Strahler 2000):

.. math::
    \\mathrm{BRF} = \\max\\left(0,\\ f_{iso} + f_{vol}\\,K_{vol} + f_{geo}\\,K_{geo}\\right),
    \\qquad f = \\mathrm{BRF}/\\pi\\ [\\mathrm{sr^{-1}}].

**Ross-Thick** (volume scattering of a dense leaf canopy), with ξ the phase angle (cos ξ =
ω_i · ω_o), in one of two normalisations that differ by the factor 3π/4 on K_vol:

.. math::
    X = \\frac{(\\pi/2 - \\xi)\\cos\\xi + \\sin\\xi}{\\mu_i + \\mu_o},\\qquad
    K_{vol} = \\begin{cases} X\\,H - \\pi/4 & \\text{MODIS (Lucht et al. 2000)}\\\\
    \\frac{4}{3\\pi}\\,X\\,H - \\frac13 & \\text{Maignan et al. (2004), DISORT 3}
    \\end{cases}

with the hot-spot factor :math:`H = 1 + (1 + \\xi/\\xi_0)^{-1}`, ξ_0 = 1.5° (Maignan, Bréon &
Lacaze 2004) when ``hotspot`` is on, else H = 1. MODIS MCD43 f_vol go with
``normalization: modis`` (the default); libRadtran and DISORT 3 use the Maignan form.

**Li-Sparse** (geometric-optical shadowing by sparse crowns of relative height h/b and shape
b/r), on the angles θ' = arctan((b/r) tan θ):

.. math::
    D^2 = \\tan^2\\theta_i' + \\tan^2\\theta_o' - 2\\tan\\theta_i'\\tan\\theta_o'\\cos\\Delta\\phi,
    \\quad
    \\cos t = \\frac{h}{b}\\,\\frac{\\sqrt{D^2 + (\\tan\\theta_i'\\tan\\theta_o'\\sin\\Delta\\phi)^2}}
              {\\sec\\theta_i' + \\sec\\theta_o'},

    O = \\frac1\\pi\\,(t - \\sin t\\cos t)(\\sec\\theta_i' + \\sec\\theta_o'),\\qquad
    \\cos\\xi' = \\cos\\theta_i'\\cos\\theta_o' + \\sin\\theta_i'\\sin\\theta_o'\\cos\\Delta\\phi,

    K_{geo} = O - \\sec\\theta_i' - \\sec\\theta_o' + \\tfrac12(1 + \\cos\\xi')\\,
              \\sec\\theta_i'\\sec\\theta_o'\\quad\\text{(Li-Sparse-Reciprocal, MODIS)},

or, for the original Li-Sparse, :math:`\\tfrac12(1 + \\cos\\xi')\\sec\\theta_o'` in the last term
— which is not reciprocal (:attr:`RossLi.reciprocal` is then False; the contract tests use the
reciprocal form). cos t is clipped to [−1, 1] (no overlap beyond total overlap).

The kernel sum can turn negative at large angles for some parameter sets; the BRF is floored at
0 there, as DISORT 3 does (``BDREF`` for Ross-Li).

**Conventions.** f_iso, f_vol, f_geo are BRF-normalised as in the MODIS MCD43 product (BRF =
f_iso + …). libRadtran / DISORT 3 (``brdf_rossli iso vol geo``) read the three numbers as a
BRDF in sr-1, i.e. BRF = π (iso + vol K_vol + geo K_geo), with the Maignan normalisation of
K_vol: to reproduce a libRadtran run multiply its iso, vol, geo by π and set
``normalization: maignan``. The relative azimuth Δφ is 0 for backscatter (the MODIS
kernel convention); libRadtran's ``phi`` is 180° − Δφ. Both conventions are checked against the
libRadtran table of DISORT 3 test case 14d in ``tests/validation``.

===============  ======  ===================  ===========================================
parameter        unit    default              meaning
===============  ======  ===================  ===========================================
f_iso            [-]     —                    isotropic weight ≥ 0 (spectrum)
f_vol            [-]     —                    Ross-Thick weight ≥ 0 (spectrum)
f_geo            [-]     —                    Li-Sparse weight ≥ 0 (spectrum)
hotspot          [-]     false                Maignan et al. (2004) hot-spot factor
hotspot_angle    [deg]   1.5                  ξ_0 > 0 of the hot-spot factor
crown_height     [-]     2                    h/b, crown centre height / vertical radius
crown_shape      [-]     1                    b/r, vertical / horizontal crown radius
geometric        [-]     sparse_reciprocal    ``sparse_reciprocal`` (MODIS) or ``sparse``
normalization    [-]     modis                K_vol form: ``modis`` or ``maignan``
===============  ======  ===================  ===========================================

Config snippet (MODIS-like deciduous forest, NIR): ``{type: rossli, f_iso: 0.30, f_vol: 0.15,
f_geo: 0.03, hotspot: true}``.

References
----------
W. Lucht, C. B. Schaaf, A. H. Strahler, "An algorithm for the retrieval of albedo from space
using semiempirical BRDF models", IEEE Trans. Geosci. Remote Sens. 38(2), 977–998 (2000),
doi:10.1109/36.841980.
W. Wanner, X. Li, A. H. Strahler, "On the derivation of kernels for kernel-driven models of
bidirectional reflectance", J. Geophys. Res. 100(D10), 21077–21089 (1995),
doi:10.1029/95JD02371.
F. Maignan, F.-M. Bréon, R. Lacaze, "Bidirectional reflectance of Earth targets: evaluation of
analytical models using a large set of spaceborne measurements with emphasis on the Hot Spot",
Remote Sens. Environ. 90(2), 210–220 (2004), doi:10.1016/j.rse.2003.12.006.
"""

from __future__ import annotations

import numpy as np

from radscene.materials.brdf._compiled import parallel_ufunc
from radscene.materials.brdf.base import BRDF, Parameter

__all__ = ["RossLi", "ross_thick", "li_sparse"]

#: K_vol = scale X H - offset (module docstring).
_VOLUME_NORMALIZATION = {"modis": (1.0, 0.25 * np.pi), "maignan": (4.0 / (3.0 * np.pi), 1.0 / 3.0)}


def ross_thick(mu_i, mu_o, cos_g, hotspot_angle=None, normalization="modis") -> np.ndarray:
    """Ross-Thick kernel K_vol [-] (numpy reference), with Maignan's hot spot if
    ``hotspot_angle`` [deg] is given; ``normalization`` ``"modis"`` or ``"maignan"``.

    Examples
    --------
    >>> round(float(ross_thick(1.0, 1.0, 1.0)), 12)   # nadir sun and view: pi/4 - pi/4
    0.0
    """
    mu_i = np.asarray(mu_i, dtype=float)
    mu_o = np.asarray(mu_o, dtype=float)
    cos_g = np.clip(np.asarray(cos_g, dtype=float), -1.0, 1.0)
    xi = np.arccos(cos_g)
    k = ((0.5 * np.pi - xi) * cos_g + np.sin(xi)) / (mu_i + mu_o)
    if hotspot_angle is not None:
        k = k * (1.0 + 1.0 / (1.0 + xi / np.radians(hotspot_angle)))
    scale, offset = _VOLUME_NORMALIZATION[normalization]
    return scale * k - offset


def li_sparse(mu_i, mu_o, cos_g, crown_height=2.0, crown_shape=1.0, reciprocal=True):
    """Li-Sparse(-Reciprocal) kernel K_geo [-] (numpy reference).

    Parameters
    ----------
    mu_i, mu_o : array_like
        Cosines of the incidence and view zenith angles, > 0 [-].
    cos_g : array_like
        ω_i · ω_o [-].
    crown_height, crown_shape : float
        h/b and b/r [-].
    reciprocal : bool
        Li-Sparse-Reciprocal (MODIS) if True, the original Li-Sparse otherwise.

    Examples
    --------
    >>> round(float(li_sparse(1.0, 1.0, 1.0)), 12)   # nadir: t = pi/2, O = 1, K = 1 - 2 + 1
    0.0
    """
    mu_i = np.asarray(mu_i, dtype=float)
    mu_o = np.asarray(mu_o, dtype=float)
    cos_g = np.asarray(cos_g, dtype=float)
    br2 = crown_shape * crown_shape
    tan2_i = br2 * (1.0 - mu_i * mu_i) / (mu_i * mu_i)
    tan2_o = br2 * (1.0 - mu_o * mu_o) / (mu_o * mu_o)
    # tan'_i tan'_o cos(dphi) = (b/r)^2 (cos g - mu_i mu_o) / (mu_i mu_o)
    tt_cos = br2 * (cos_g - mu_i * mu_o) / (mu_i * mu_o)
    d2 = np.maximum(tan2_i + tan2_o - 2.0 * tt_cos, 0.0)
    tt_sin2 = np.maximum(tan2_i * tan2_o - tt_cos * tt_cos, 0.0)
    sec_i = np.sqrt(1.0 + tan2_i)
    sec_o = np.sqrt(1.0 + tan2_o)
    cos_xi = (1.0 + tt_cos) / (sec_i * sec_o)
    cos_t = np.clip(crown_height * np.sqrt(d2 + tt_sin2) / (sec_i + sec_o), -1.0, 1.0)
    t = np.arccos(cos_t)
    overlap = (t - np.sin(t) * cos_t) * (sec_i + sec_o) / np.pi
    last = sec_i * sec_o if reciprocal else sec_o
    return overlap - sec_i - sec_o + 0.5 * (1.0 + cos_xi) * last


def _rossli_brdf_scalar(mu_i, mu_o, cos_g, f_iso, f_vol, f_geo, xi0, hb, br, last_pair,
                        vol_scale, vol_offset):  # pragma: no cover - compiled
    """f [sr-1] of one geometry, compiled by :func:`parallel_ufunc` (the fast path)."""
    if mu_i <= 0.0 or mu_o <= 0.0:
        return 0.0
    c = min(max(cos_g, -1.0), 1.0)
    xi = np.arccos(c)
    kvol = ((0.5 * np.pi - xi) * c + np.sin(xi)) / (mu_i + mu_o)
    if xi0 > 0.0:
        kvol = kvol * (1.0 + 1.0 / (1.0 + xi / xi0))
    kvol = vol_scale * kvol - vol_offset
    br2 = br * br
    tan2_i = br2 * (1.0 - mu_i * mu_i) / (mu_i * mu_i)
    tan2_o = br2 * (1.0 - mu_o * mu_o) / (mu_o * mu_o)
    tt_cos = br2 * (cos_g - mu_i * mu_o) / (mu_i * mu_o)
    d2 = max(tan2_i + tan2_o - 2.0 * tt_cos, 0.0)
    tt_sin2 = max(tan2_i * tan2_o - tt_cos * tt_cos, 0.0)
    sec_i = np.sqrt(1.0 + tan2_i)
    sec_o = np.sqrt(1.0 + tan2_o)
    cos_xi = (1.0 + tt_cos) / (sec_i * sec_o)
    cos_t = min(max(hb * np.sqrt(d2 + tt_sin2) / (sec_i + sec_o), -1.0), 1.0)
    t = np.arccos(cos_t)
    overlap = (t - np.sin(t) * cos_t) * (sec_i + sec_o) / np.pi
    last = sec_i * sec_o if last_pair > 0.0 else sec_o
    kgeo = overlap - sec_i - sec_o + 0.5 * (1.0 + cos_xi) * last
    brf = f_iso + f_vol * kvol + f_geo * kgeo
    return 0.0 if brf < 0.0 else brf / np.pi  # NaN propagates


class RossLi(BRDF):
    """Ross-Thick / Li-Sparse(-Reciprocal) BRDF (module docstring).

    Examples
    --------
    >>> # DISORT 3 test 14d (libRadtran UVSPEC_BRDF_ROSSLI): iso, vol, geo times pi
    >>> m = RossLi(f_iso=0.091 * np.pi, f_vol=0.02 * np.pi, f_geo=0.0086 * np.pi, hotspot=True,
    ...            normalization="maignan")
    >>> round(float(m.f_angles(30.0, 0.0, 0.0) * np.pi), 5)   # libRadtran BRF 0.26714
    0.26714
    """

    name = "rossli"
    PARAMETERS = {
        "f_iso": Parameter("-", "isotropic weight", kind="spectrum", low=0.0),
        "f_vol": Parameter("-", "Ross-Thick (volumetric) weight", kind="spectrum", low=0.0),
        "f_geo": Parameter("-", "Li-Sparse (geometric) weight", kind="spectrum", low=0.0),
        "hotspot": Parameter("-", "Maignan et al. (2004) hot-spot factor", False, kind="bool"),
        "hotspot_angle": Parameter("deg", "xi_0 of the hot-spot factor", 1.5, low=0.0,
                                   low_open=True),
        "crown_height": Parameter("-", "h/b, crown centre height over vertical radius", 2.0,
                                  low=0.0),
        "crown_shape": Parameter("-", "b/r, vertical over horizontal crown radius", 1.0,
                                 low=0.0, low_open=True),
        "geometric": Parameter("-", "Li kernel: sparse_reciprocal (MODIS) or sparse",
                               "sparse_reciprocal", kind="choice",
                               choices=("sparse_reciprocal", "sparse")),
        "normalization": Parameter("-", "K_vol normalisation: modis or maignan (DISORT 3)",
                                   "modis", kind="choice", choices=("modis", "maignan")),
    }

    @property
    def reciprocal(self) -> bool:
        """False for the original (non-reciprocal) Li-Sparse kernel."""
        return self.parameter("geometric") == "sparse_reciprocal"

    def _weights(self, wavelength):
        return tuple(self.parameter(n, wavelength) for n in ("f_iso", "f_vol", "f_geo"))

    def kernel(self, cos_incidence, cos_view, cos_phase, wavelength=None):
        # compiled fast path; the reference is BRDF.kernel → _kernel → ross_thick, li_sparse
        xi0 = np.radians(self.parameter("hotspot_angle")) if self.parameter("hotspot") else 0.0
        fast = parallel_ufunc(_rossli_brdf_scalar, 12)
        scale, offset = _VOLUME_NORMALIZATION[self.parameter("normalization")]
        with np.errstate(invalid="ignore", divide="ignore", over="ignore"):
            value = fast(cos_incidence, cos_view, cos_phase, *self._weights(wavelength), xi0,
                         self.parameter("crown_height"), self.parameter("crown_shape"),
                         1.0 if self.reciprocal else 0.0, scale, offset)
        return np.asarray(value, dtype=float)

    def _kernel(self, mu_i, mu_o, cos_g, wavelength):
        f_iso, f_vol, f_geo = self._weights(wavelength)
        hot = self.parameter("hotspot_angle") if self.parameter("hotspot") else None
        kvol = ross_thick(mu_i, mu_o, cos_g, hot, self.parameter("normalization"))
        brf = (f_iso + f_vol * kvol
               + f_geo * li_sparse(mu_i, mu_o, cos_g, self.parameter("crown_height"),
                                   self.parameter("crown_shape"), self.reciprocal))
        return np.maximum(brf, 0.0) / np.pi

    def kernel_reference(self, cos_incidence, cos_view, cos_phase, wavelength=None):
        """The numpy reference evaluation, the oracle of the compiled :meth:`kernel`."""
        return BRDF.kernel(self, cos_incidence, cos_view, cos_phase, wavelength)
