r"""Exponential wide-band model of CO₂ and H₂O (Edwards 1976; Edwards & Balakrishnan 1973).

A band model, not line-by-line: each vibration–rotation band of a molecule is a smooth
envelope of many lines whose mean strength-to-spacing ratio falls off exponentially from the
band's centre (symmetric bands) or head (bands with a head at their upper wavenumber end),

.. math::

    \frac{\bar S}{d}(η) = \frac{α}{ω} e^{−2|η − η_c|/ω}
    \quad\text{or}\quad \frac{α}{ω} e^{−(η_u − η)/ω} \;(η ≤ η_u),

with the integrated band intensity α(T), the band-width parameter ω(T) = ω₀ √(T/T₀) and the
line-overlap parameter β(T, p) = β₀ √(T₀/T) Φ(T)/Φ(T₀) P_e, P_e = [p/p₀ (1 + (b − 1) x)]ⁿ
(x the gas's mole fraction, b its self-broadening ratio: 1.3 for CO₂, 8.6 √(T₀/T) + 0.5 for
H₂O). α(T) = α₀ Ψ(T)/Ψ(T₀), Ψ and Φ the harmonic-oscillator sums over the lower vibrational
states of the band and its hot bands (:func:`temperature_functions`); the H₂O rotational band
has α = α₀ exp[−9 (1 − √(T₀/T))] instead. T₀ = 100 K, p₀ = 1 atm; the parameters are in
``radscene/data/gas/edwards_wide_band.csv`` with their source. Sub-bands sharing a label
(H₂O 2.7 µm) are combined with α = Σ α_i, β = (Σ √(α_i β_i))² / α.

Within a band, the mean absorptance of a path of absorber amount X is taken in the three
limits of a statistical band of Lorentz lines — weak lines, strong isolated lines, opaque —

.. math::

    \bar a = \min\left(1,\; τ_w,\; \sqrt{τ_w β}\right), \qquad τ_w = \frac{\bar S}{d} X,

whose integral across an exponential band is exactly Edwards and Menard's four-region band
absorptance A = ω A*(τ₀, β) (τ₀ = αX/ω): τ₀, 2√(τ₀β) − β, ln(τ₀β) + 2 − β for β ≤ 1; τ₀,
ln τ₀ + 1 for β > 1 — the expression the parameters were fitted with (Edwards & Menard, Appl.
Opt. 3 (1964) 621, doi:10.1364/AO.3.000621; Modest 2013, §11.10). (The smooth Malkmus
narrow band with the same parameters would fall below it by up to (2 − 2γ) ω in the
logarithmic regime, γ Euler's constant.) Bands overlapping at a wavenumber multiply their
transmittances 1 − ā (:func:`transmittance`), or are merged into one band with k = Σ k_i,
β = (Σ √(k_i β_i))² / k (:func:`absorption`, what a volume carries: the same weak and strong
limits, exactly; Edwards's rule for sub-bands).

Resolution and validity: the spectral shape is the model's exponential envelope, meaningful
only as a mean over intervals of the order of ω (≈ 20–200 cm⁻¹); band-integrated quantities
are what the model was fitted to (against Leckner's total emissivities: docs/physics.md). Lorentz
lines (Doppler broadening neglected: pressures ≥ 0.1 atm), a homogeneous path (one T and p;
a non-isothermal path would need Curtis–Godson scaling, not done), no CO/soot/continuum.
:data:`TEMPERATURE_RANGE` and :data:`PRESSURE_RANGE` are the accepted ranges.

References
----------
D. K. Edwards, "Molecular gas band radiation", Advances in Heat Transfer 12 (1976) 115–193,
doi:10.1016/S0065-2717(08)70173-X. D. K. Edwards and A. Balakrishnan, "Thermal radiation by
combustion gases", Int. J. Heat Mass Transfer 16 (1973) 25–40,
doi:10.1016/0017-9310(73)90251-7. M. F. Modest, *Radiative Heat Transfer*, 3rd ed., Academic
Press 2013, §11.10 and Table 11.3.
"""

from __future__ import annotations

import csv
import math
from dataclasses import dataclass
from functools import lru_cache
from importlib import resources

import numpy as np
from scipy.constants import R, atm
from scipy.special import gammaln

from radscene.errors import ConfigError, did_you_mean

__all__ = ["absorptance", "combine", "GASES", "TEMPERATURE_RANGE", "PRESSURE_RANGE", "REFERENCE_TEMPERATURE",
           "BandParameters", "band_table", "temperature_functions", "band_parameters",
           "band_absorption", "absorption", "transmittance", "spectral_nodes"]

#: Reference temperature T₀ of the parameters [K] and reference pressure p₀ [Pa].
REFERENCE_TEMPERATURE = 100.0
REFERENCE_PRESSURE = atm
#: Temperatures [K] and total pressures [Pa] the model is accepted at (see the docstring).
TEMPERATURE_RANGE = (300.0, 2500.0)
PRESSURE_RANGE = (0.1 * atm, 10.0 * atm)
#: Exponent of the H₂O rotational band's temperature law, α = α₀ exp[−9 (1 − √(T₀/T))].
_ROTATIONAL_EXPONENT = 9.0
#: Vibrational quantum-number sums are cut here (terms below 1e-15 of the first at 2500 K).
_MAX_QUANTUM = 240


@dataclass(frozen=True)
class _Molecule:
    name: str
    molar_mass: float  # [kg mol-1]
    frequencies: tuple[float, float, float]  # harmonic wavenumbers η_k [cm-1]
    degeneracies: tuple[int, int, int]

    def self_broadening(self, temperature):
        """b, the ratio of self- to foreign-broadened line width [-]."""
        if self.name == "co2":
            return 1.3
        return 8.6 * math.sqrt(REFERENCE_TEMPERATURE / temperature) + 0.5


#: The gases of the model: molar mass, vibrational wavenumbers and degeneracies (Modest 2013,
#: Table 11.3, after Edwards 1976).
GASES = {
    "co2": _Molecule("co2", 44.0095e-3, (1351.0, 666.0, 2396.0), (1, 2, 1)),
    "h2o": _Molecule("h2o", 18.01528e-3, (3652.0, 1595.0, 3756.0), (1, 1, 1)),
}


@dataclass(frozen=True)
class BandParameters:
    """The bands of a gas mixture at one state, one entry per (combined) band.

    Attributes
    ----------
    gas, label : tuple of str
        The gas (``co2``, ``h2o``) and the band's label [um] as in the table.
    upper_head : numpy.ndarray
        bool: the band has a head at ``wavenumber`` and lies below it; else symmetric about it.
    wavenumber : numpy.ndarray
        Centre η_c or head η_u [cm-1].
    strength : numpy.ndarray
        α(T) [cm-1 / (g m-2)].
    width : numpy.ndarray
        ω(T) [cm-1].
    line_overlap : numpy.ndarray
        β(T, p, x) [-].
    density : numpy.ndarray
        The gas's partial density ρ_a = x p M / (R T) [g m-3].
    """

    gas: tuple[str, ...]
    label: tuple[str, ...]
    upper_head: np.ndarray
    wavenumber: np.ndarray
    strength: np.ndarray
    width: np.ndarray
    line_overlap: np.ndarray
    density: np.ndarray


@lru_cache(maxsize=1)
def band_table() -> tuple[dict, ...]:
    """The parameter table (``radscene/data/gas/edwards_wide_band.csv``), one dict per row."""
    path = resources.files("radscene") / "data" / "gas" / "edwards_wide_band.csv"
    lines = [ln for ln in path.read_text(encoding="utf-8").splitlines() if not ln.startswith("#")]
    rows = []
    for row in csv.DictReader(lines):
        rows.append({
            "gas": row["gas"], "label": row["band_um"], "upper_head": row["shape"] == "upper_head",
            "wavenumber": float(row["wavenumber"]),
            "delta": (int(row["delta1"]), int(row["delta2"]), int(row["delta3"])),
            "n": float(row["n"]), "alpha0": float(row["alpha0"]), "beta0": float(row["beta0"]),
            "omega0": float(row["omega0"])})
    return tuple(rows)


def temperature_functions(gas: str, delta, temperature) -> tuple[np.ndarray, np.ndarray]:
    r"""Edwards's Ψ(T) and Φ(T) [-] of the band of vibrational change ``delta`` of ``gas``.

    .. math::

        Ψ = \left(1 − e^{−Σ_k u_k δ_k}\right) Π_k (1 − e^{−u_k})^{g_k} Σ_{v} f_k(v),
        \qquad
        Φ = Π_k \frac{\left(Σ_v \sqrt{f_k(v)}\right)^2}{Σ_v f_k(v)}

    with u_k = c₂ η_k / T and, over the lower states v = 0, 1, … of mode k (degeneracy g_k),
    the harmonic-oscillator line-strength weights f_k(v) = (v + g_k + |δ_k| − 1)! /
    ((g_k − 1)! v!) e^{−u_k v}, times e^{−u_k |δ_k|} where δ_k < 0 (the state |δ_k| quanta
    above). Ψ is the band's intensity relative to a cold gas (stimulated emission and hot
    bands), Φ the growth of its line density. The sums factor by mode.

    Parameters
    ----------
    gas : {"co2", "h2o"}
    delta : sequence of int
        (δ₁, δ₂, δ₃).
    temperature : array_like
        [K].

    Returns
    -------
    psi, phi : numpy.ndarray
        Shaped as ``temperature``.
    """
    mol = GASES[gas]
    t = np.asarray(temperature, dtype=float)[..., None]
    v = np.arange(_MAX_QUANTUM, dtype=float)
    c2 = 1.438776877  # second radiation constant h c / k [cm K]
    psi = np.ones(t.shape[:-1])
    phi = np.ones(t.shape[:-1])
    transition = np.zeros(t.shape[:-1])
    for eta, g, d in zip(mol.frequencies, mol.degeneracies, delta, strict=True):
        u = c2 * eta / t  # (..., 1)
        log_f = (gammaln(v + g + abs(d)) - gammaln(g) - gammaln(v + 1.0)) - u * (v + max(-d, 0))
        f = np.exp(log_f)
        total = f.sum(axis=-1)
        psi = psi * total * (-np.expm1(-u[..., 0])) ** g
        phi = phi * np.sqrt(f).sum(axis=-1) ** 2 / total
        transition = transition + u[..., 0] * d
    return psi * -np.expm1(-transition), phi


def absorptance(weak_depth, line_overlap) -> np.ndarray:
    """Mean absorptance ā = min(1, τ_w, √(τ_w β)) of a path through one band [-].

    Parameters
    ----------
    weak_depth : array_like
        τ_w = (S̄/d) X, the optical depth of the path were every line weak [-], >= 0.
    line_overlap : array_like
        β [-], > 0.

    Examples
    --------
    >>> absorptance([0.01, 1.0, 100.0], 0.04).round(4).tolist()
    [0.01, 0.2, 1.0]
    """
    tau = np.asarray(weak_depth, dtype=float)
    return np.minimum(np.minimum(tau, np.sqrt(tau * np.asarray(line_overlap, dtype=float))), 1.0)


def combine(absorption, line_overlap, axis: int = 0) -> tuple[np.ndarray, np.ndarray]:
    """Overlapping bands as one: k = Σ k_i, β = (Σ √(k_i β_i))² / k (``inf`` where k = 0);
    ``absorption`` k_i [m-1] >= 0 and ``line_overlap`` β_i [-] > 0 along ``axis``."""
    k = np.asarray(absorption, dtype=float)
    beta = np.broadcast_to(np.asarray(line_overlap, dtype=float), k.shape)
    total = k.sum(axis=axis)
    root = np.sqrt(k * beta).sum(axis=axis)
    with np.errstate(divide="ignore", invalid="ignore"):
        return total, np.where(total > 0.0, root * root / total, np.inf)


def _rotational_strength(alpha0, temperature):
    """α of the H2O rotational band [cm-1 / (g m-2)]."""
    t0 = REFERENCE_TEMPERATURE
    return alpha0 * math.exp(-_ROTATIONAL_EXPONENT * (1.0 - math.sqrt(t0 / temperature)))


def _check_state(temperature, pressure, mole_fractions) -> None:
    lo, hi = TEMPERATURE_RANGE
    if not lo <= temperature <= hi:
        raise ConfigError(f"the Edwards wide-band model holds for {lo:g}-{hi:g} K; got "
                          f"{temperature:g} K", key="temperature")
    lo, hi = PRESSURE_RANGE
    if not lo <= pressure <= hi:
        raise ConfigError(f"the Edwards wide-band model holds for {lo / atm:g}-{hi / atm:g} atm "
                          f"(Lorentz lines); got {pressure / atm:g} atm", key="pressure")
    for gas, x in mole_fractions.items():
        if gas not in GASES:
            raise ConfigError(f"unknown gas {gas!r}; known: {', '.join(GASES)}"
                              f"{did_you_mean(gas, GASES)}", key=gas)
        if not 0.0 <= x <= 1.0:
            raise ConfigError(f"a mole fraction lies in 0-1; got {x:g}", key=gas)
    if sum(mole_fractions.values()) > 1.0 + 1e-12:
        raise ConfigError(f"the mole fractions sum to {sum(mole_fractions.values()):g} > 1",
                          key="mole_fractions")


def band_parameters(temperature: float, pressure: float, mole_fractions) -> BandParameters:
    """α, ω, β and the partial density of every band of the gases present.

    Parameters
    ----------
    temperature : float
        [K], within :data:`TEMPERATURE_RANGE`.
    pressure : float
        Total pressure [Pa], within :data:`PRESSURE_RANGE`.
    mole_fractions : mapping
        Gas name (``co2``, ``h2o``) → mole fraction [-] in 0–1, summing to at most 1.

    Returns
    -------
    BandParameters
        Bands of gases with a mole fraction above 0, in table order.

    Raises
    ------
    radscene.errors.ConfigError
        A state outside the ranges, an unknown gas, a bad mole fraction (the key names it).
    """
    temperature, pressure = float(temperature), float(pressure)
    fractions = {str(g).lower(): float(x) for g, x in dict(mole_fractions).items()}
    _check_state(temperature, pressure, fractions)
    t0 = REFERENCE_TEMPERATURE
    grouped: dict[tuple[str, str], list] = {}
    for row in band_table():
        if fractions.get(row["gas"], 0.0) > 0.0:
            grouped.setdefault((row["gas"], row["label"]), []).append(row)
    out = {k: [] for k in ("gas", "label", "upper_head", "wavenumber", "strength", "width",
                           "line_overlap", "density")}
    for (gas, label), rows in grouped.items():
        x = fractions[gas]
        mol = GASES[gas]
        alphas, betas = [], []
        for row in rows:
            pe = (pressure / REFERENCE_PRESSURE * (1.0 + (mol.self_broadening(temperature) - 1.0)
                                                   * x)) ** row["n"]
            psi, phi = temperature_functions(gas, row["delta"], temperature)
            psi0, phi0 = temperature_functions(gas, row["delta"], t0)
            if any(row["delta"]):
                alpha = row["alpha0"] * psi / psi0
            else:  # the H2O rotational band
                alpha = _rotational_strength(row["alpha0"], temperature)
            alphas.append(float(alpha))
            betas.append(float(row["beta0"] * math.sqrt(t0 / temperature) * phi / phi0 * pe))
        alpha, beta = combine(np.array(alphas), np.array(betas))
        first = rows[0]
        out["gas"].append(gas)
        out["label"].append(label)
        out["upper_head"].append(first["upper_head"])
        out["wavenumber"].append(first["wavenumber"])
        out["strength"].append(float(alpha))
        out["width"].append(first["omega0"] * math.sqrt(temperature / t0))
        out["line_overlap"].append(float(beta))
        # ρ_a = x p M / (R T) [g m-3]
        out["density"].append(x * pressure * mol.molar_mass * 1e3 / (R * temperature))
    return BandParameters(tuple(out["gas"]), tuple(out["label"]),
                          *(np.array(out[k], dtype=bool if k == "upper_head" else float)
                            for k in ("upper_head", "wavenumber", "strength", "width",
                                      "line_overlap", "density")))


def band_absorption(wavelength, bands: BandParameters) -> np.ndarray:
    """Weak-line absorption coefficient k_i(λ) = (S̄/d)_i ρ_a [m-1] of each band, (n_band,
    *shape of wavelength); ``wavelength`` [um] > 0."""
    eta = 1e4 / np.asarray(wavelength, dtype=float)[None, ...]  # [cm-1]
    shape = (-1,) + (1,) * (eta.ndim - 1)
    centre, width = bands.wavenumber.reshape(shape), bands.width.reshape(shape)
    head = bands.upper_head.reshape(shape)
    distance = np.where(head, centre - eta, 2.0 * np.abs(eta - centre)) / width
    envelope = np.where(head & (eta > centre), 0.0, np.exp(-np.abs(distance)))
    return (bands.strength * bands.density).reshape(shape) / width * envelope


def absorption(wavelength, bands: BandParameters) -> tuple[np.ndarray, np.ndarray]:
    """The mixture's bands at ``wavelength`` [um] merged into one (:func:`combine`): k [m-1]
    and β [-] (``inf`` where no band absorbs), shaped as ``wavelength``."""
    k = band_absorption(wavelength, bands)
    beta = bands.line_overlap.reshape((-1,) + (1,) * (k.ndim - 1))
    return combine(k, beta, axis=0)


def transmittance(wavelength, path_length, bands: BandParameters) -> np.ndarray:
    """Mean transmittance of a homogeneous path (the reference): the product over the bands of
    their transmittances, Π_i (1 − ā(k_i L, β_i)) [-].

    Parameters
    ----------
    wavelength : array_like
        [um] > 0.
    path_length : array_like
        [m] >= 0, broadcast against ``wavelength``.
    bands : BandParameters
        From :func:`band_parameters`.

    Examples
    --------
    >>> bands = band_parameters(1000.0, 101325.0, {"co2": 0.1})
    >>> t = transmittance([3.9, 4.3, 4.5], 1.0, bands)
    >>> bool(t[0] > 0.999 and t[1] < 0.01 and t[1] < t[2] < t[0])
    True
    """
    k = band_absorption(wavelength, bands)
    beta = bands.line_overlap.reshape((-1,) + (1,) * (k.ndim - 1))
    return np.prod(1.0 - absorptance(k * np.asarray(path_length, dtype=float), beta), axis=0)


def spectral_nodes(step: float = 10.0, lowest: float = 500.0, highest: float = 10000.0
                   ) -> np.ndarray:
    """Wavelengths [um] at which a band integral of the model is split: a uniform wavenumber
    grid of ``step`` [cm-1] from ``lowest`` to ``highest`` and every band centre and head."""
    eta = np.arange(lowest, highest + 0.5 * step, step)
    heads = np.array(sorted({row["wavenumber"] for row in band_table()}))
    return np.unique(1e4 / np.concatenate([eta, heads[heads >= lowest]]))
