"""The BRDF contract shared by every registered model: frame, conventions, parameters.

Frame and angle conventions
---------------------------
Every model is written in the surface's **local frame**: +z along the outward surface normal,
x and y in the tangent plane. Directions are unit vectors that point **away from the surface**:

* ``wi`` — towards the source (the sun, a sky patch): the direction light *comes from*;
* ``wo`` — towards the viewer (the sensor): the direction light *leaves in*.

With ``normal=None`` the vectors are taken in that local frame (``cos θ = w_z``); with a
``normal`` ``(..., 3)`` they are world vectors (radscene's world frame is east-north-up) and
``cos θ = w · n``. All the registered models are isotropic: they depend on the directions only
through three invariants, which is why no tangent is needed —

* ``cos_incidence`` μ_i = wi · n, ``cos_view`` μ_o = wo · n;
* ``cos_phase`` cos g = wi · wo, g the *phase angle* between the directions to the sun and to
  the viewer (g = 0 in the hot spot, g = θ_i + θ_o in the specular direction).

Angles at the public interface are in degrees: zenith from the normal, azimuth clockwise from
north (or from the local +y axis). The **relative azimuth** is ``Δφ = φ_o − φ_i``, the azimuth
of the view direction minus that of the sun direction, so

* Δφ = 0° is **backscatter**: the viewer on the sun's side, the hot spot at θ_o = θ_i;
* Δφ = 180° is **forward scatter**: the viewer opposite the sun, the specular direction,

and cos g = μ_i μ_o + sin θ_i sin θ_o cos Δφ. This is the MODIS kernel convention (Lucht et
al. 2000). libRadtran and DISORT count the other way: their ``phi`` is 180° − Δφ (their
``phi = 0`` is forward scatter); the validation tests against libRadtran check the sign.

A BRDF f [sr-1] relates reflected radiance to incident irradiance,
:math:`dL_o = f\\,L_i\\cos\\theta_i\\,d\\omega_i`; the bidirectional reflectance factor is
BRF = π f [-] (a Lambertian surface of reflectance ρ has BRF ≡ ρ). Parameters of the models
that are usually published as BRF (RPV ρ_0, Ross–Li f_iso, f_vol, f_geo) are BRF-normalised;
see each module.

The contract
------------
Every model is a :class:`BRDF` with

* :meth:`BRDF.f` (ω_i, ω_o, λ) [sr-1], reciprocal: f(ω_i, ω_o) = f(ω_o, ω_i);
* :meth:`BRDF.albedo` (ω_i, λ): directional-hemispherical reflectance ρ_dh ≤ 1 [-];
* :meth:`BRDF.transmittance` (ω_i, λ): directional-hemispherical transmittance τ_dh [-]
  (0 except for transmitting models);
* :meth:`BRDF.emissivity` (ω_i, λ) = 1 − ρ_dh − τ_dh by Kirchhoff's law, the directional
  emissivity into ω_i [-]; :meth:`BRDF.hemispherical_emissivity` (λ) its cosine-weighted mean
  over the hemisphere, for the heat balance;
* :meth:`BRDF.sample` (ω_o, u_1, u_2, λ) → (ω_i, pdf) and :meth:`BRDF.pdf`: importance
  sampling of incident directions with the density it reports [sr-1].

The tests in ``tests/unit/test_brdf_contract.py`` check all of it for every registered model.
Reflecting models are one-sided: at or below the horizon (μ ≤ 0) they neither reflect nor emit
(f, ρ_dh, τ_dh and ε are 0 there).
"""

from __future__ import annotations

import numbers
from pathlib import Path
from typing import Any, ClassVar

import numpy as np

from radscene.errors import ConfigError
from radscene.geometry.frames import orthonormal_basis
from radscene.materials.brdf.hemisphere import (
    CHUNK,
    QUADRATURE_NODES,
    albedo_quadrature,
    albedo_sampling,
    bihemispherical,
)
from radscene.materials.brdf.parameters import REQUIRED, Parameter, parameter_table
from radscene.materials.spectrum import Spectrum, make_spectrum, union_wavelengths

__all__ = [
    "BRDF",
    "Parameter",
    "REQUIRED",
    "cos_phase_from_angles",
    "cosine_hemisphere",
    "parameter_table",
    "unit_interval",
]


def unit_interval(u, key: str) -> np.ndarray:
    """``u`` as a float array, refused unless every value lies in [0, 1]."""
    u = np.asarray(u, dtype=float)
    if not np.all((u >= 0.0) & (u <= 1.0)):
        raise ConfigError("random numbers must lie in [0, 1]", key=key)
    return u


def cos_phase_from_angles(incidence_zenith, view_zenith, relative_azimuth):
    """μ_i, μ_o and cos g from zenith angles and the relative azimuth [deg].

    Parameters
    ----------
    incidence_zenith, view_zenith : array_like
        θ_i, θ_o from the normal [deg].
    relative_azimuth : array_like
        Δφ = φ_o − φ_i [deg]; 0 is backscatter (the hot spot), 180 forward scatter.

    Returns
    -------
    cos_incidence, cos_view, cos_phase : numpy.ndarray
        Broadcast shape [-].

    Examples
    --------
    >>> [round(float(x), 12) for x in cos_phase_from_angles(30.0, 30.0, 0.0)]
    [0.866025403784, 0.866025403784, 1.0]
    """
    ti = np.radians(np.asarray(incidence_zenith, dtype=float))
    to = np.radians(np.asarray(view_zenith, dtype=float))
    dphi = np.radians(np.asarray(relative_azimuth, dtype=float))
    ti, to, dphi = np.broadcast_arrays(ti, to, dphi)
    mu_i, mu_o = np.cos(ti), np.cos(to)
    cos_g = mu_i * mu_o + np.sin(ti) * np.sin(to) * np.cos(dphi)
    return mu_i, mu_o, np.clip(cos_g, -1.0, 1.0)


def cosine_hemisphere(u1, u2, sign=1.0) -> np.ndarray:
    """Cosine-weighted local directions (Malley's method), density |μ|/π on one hemisphere.

    Parameters
    ----------
    u1, u2 : array_like
        Uniform numbers in [0, 1] [-].
    sign : array_like, optional
        +1 for the upper hemisphere (z > 0), −1 for the lower.

    Returns
    -------
    numpy.ndarray
        Local unit vectors ``(..., 3)`` [-].
    """
    r = np.sqrt(u1)
    phi = 2.0 * np.pi * u2
    z = np.sqrt(np.maximum(1.0 - u1, 0.0)) * sign
    r, phi, z = np.broadcast_arrays(r, phi, z)
    return np.stack([r * np.cos(phi), r * np.sin(phi), z], axis=-1)


def _dot(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Dot products along the last axis, broadcasting the leading ones."""
    if a.shape == b.shape:
        return np.einsum("...k,...k->...", a, b)
    if b.ndim == 1:
        return a @ b
    if a.ndim == 1:
        return b @ a
    return np.sum(a * b, axis=-1)


class BRDF:
    """Base class of the registered BRDF models (see the module docstring for conventions).

    A subclass sets :attr:`name`, :attr:`PARAMETERS` and implements :meth:`_kernel` (the BRDF
    of μ_i, μ_o, cos g for directions above the horizon); it may override :meth:`_sample_local`
    and :meth:`_pdf` (default: cosine-weighted) and :meth:`_hemispherical` (default: numerical
    quadrature, or importance sampling when :attr:`albedo_rule` is ``"sampling"``).

    Parameters
    ----------
    key : str, optional
        Config key path, used in error messages (``materials.paint.brdf``).
    base_dir : path-like, optional
        Directory that relative file paths are relative to.
    **params
        The model's parameters (its :attr:`PARAMETERS`); unknown names are refused.

    Raises
    ------
    ConfigError
        An unknown parameter, a missing one, or a value out of its bounds (naming the key and
        what is accepted).
    """

    #: Registry name (lower case).
    name: ClassVar[str] = ""
    #: Parameters by name.
    PARAMETERS: ClassVar[dict[str, Parameter]] = {}
    #: ``"quadrature"`` (smooth models) or ``"sampling"`` (peaked lobes) for ρ_dh and τ_dh.
    albedo_rule: ClassVar[str] = "quadrature"
    #: True for models that reflect and transmit on both faces (thin sheets, leaves).
    two_sided: ClassVar[bool] = False

    def __init__(self, *, key: str = "brdf", base_dir=None, **params):
        self.key = str(key)
        unknown = sorted(set(params) - set(self.PARAMETERS))
        if unknown:
            raise ConfigError(
                f"unknown parameter {unknown[0]!r} for BRDF {self.name!r}; accepted: "
                f"{', '.join(self.PARAMETERS)}",
                key=f"{self.key}.{unknown[0]}",
            )
        self._spectra: dict[str, Spectrum] = {}
        self._values: dict[str, Any] = {}
        for pname, p in self.PARAMETERS.items():
            if pname in params:
                value = params[pname]
            elif p.default is REQUIRED:
                raise ConfigError(
                    f"BRDF {self.name!r} needs {pname!r} [{p.unit}]: {p.meaning}",
                    key=f"{self.key}.{pname}",
                )
            else:
                value = p.default
            self._set(pname, p, value, base_dir)
        self._check()

    # ------------------------------------------------------------------ parameters
    def _set(self, pname: str, p: Parameter, value, base_dir) -> None:
        key = f"{self.key}.{pname}"
        if value is None and p.default is None:  # an optional parameter left out
            self._values[pname] = None
            return
        if p.kind == "spectrum":
            spec = make_spectrum(value, key=key, base_dir=base_dir)
            knots = spec.values
            bad = p.violates(np.atleast_1d(knots))
            if np.any(bad):
                i = int(np.argmax(bad))
                where = "" if spec.is_constant else f" at {spec.wavelength[i]:g} µm"
                raise ConfigError(
                    f"{pname} must satisfy {p.bounds_text()} [{p.unit}]; got "
                    f"{float(np.atleast_1d(knots)[i]):g}{where}",
                    key=key,
                )
            self._spectra[pname] = spec
        elif p.kind == "number":
            if isinstance(value, bool) or not isinstance(value, numbers.Real):
                raise ConfigError(
                    f"{pname} must be a number [{p.unit}]; got {value!r}", key=key
                )
            if p.violates(np.array(float(value))):
                raise ConfigError(
                    f"{pname} must satisfy {p.bounds_text()} [{p.unit}]; got {value!r}", key=key
                )
            self._values[pname] = float(value)
        elif p.kind == "choice":
            text = str(value).lower()
            if text not in p.choices:
                raise ConfigError(
                    f"{pname} must be one of {', '.join(p.choices)}; got {value!r}", key=key
                )
            self._values[pname] = text
        elif p.kind == "bool":
            if not isinstance(value, bool):
                raise ConfigError(f"{pname} must be true or false; got {value!r}", key=key)
            self._values[pname] = value
        elif p.kind == "path":
            if not isinstance(value, str | Path):
                raise ConfigError(f"{pname} must be a file path; got {value!r}", key=key)
            path = Path(value)
            if base_dir is not None and not path.is_absolute():
                path = Path(base_dir) / path
            self._values[pname] = path
        else:  # text
            self._values[pname] = "" if value is None else str(value)

    def _check(self) -> None:
        """Cross-parameter checks of a subclass (e.g. ρ + τ ≤ 1); raise ConfigError."""

    def _check_sum_at_most_one(self, names: tuple[str, ...]) -> None:
        """Refuse spectra whose sum exceeds 1 at some tabulated wavelength."""
        spectra = [self._spectra[n] for n in names]
        wl = union_wavelengths(spectra)
        grid = np.array([1.0]) if wl.size == 0 else wl
        total = sum(
            np.full(grid.shape, float(s.values)) if s.is_constant else s(grid) for s in spectra
        )
        if np.any(total > 1.0 + 1e-12):
            i = int(np.argmax(total))
            where = "" if wl.size == 0 else f" at {grid[i]:g} µm"
            raise ConfigError(
                f"{' + '.join(names)} must not exceed 1 (energy conservation); got "
                f"{total[i]:g}{where}",
                key=f"{self.key}.{names[-1]}",
            )

    def parameter(self, pname: str, wavelength=None):
        """Value of a parameter; spectral ones evaluated at ``wavelength`` [um].

        Returns a Python float for constants (and non-spectral numbers) and an array of the
        shape of ``wavelength`` for tabulated spectra; choices, booleans and paths as given;
        None for an optional parameter left out.

        Raises
        ------
        ConfigError
            A tabulated parameter without ``wavelength``, or a wavelength outside its table.
        """
        if pname in self._spectra:
            spec = self._spectra[pname]
            if spec.is_constant:
                return float(spec.values)
            if wavelength is None:
                raise ConfigError(
                    f"{pname} of BRDF {self.name!r} varies with wavelength; pass wavelength "
                    "[µm]",
                    key=f"{self.key}.{pname}",
                )
            return np.asarray(spec(wavelength))
        return self._values[pname]

    def spectrum(self, pname: str) -> Spectrum:
        """The :class:`~radscene.materials.Spectrum` of a spectral parameter."""
        return self._spectra[pname]

    @property
    def is_spectral(self) -> bool:
        """True when some parameter is tabulated in wavelength."""
        return any(not s.is_constant for s in self._spectra.values())

    def config(self) -> dict:
        """The type-tagged mapping that :func:`~radscene.materials.brdf.make_brdf` rebuilds it
        from (spectra as :class:`Spectrum` objects, paths as strings)."""
        out: dict[str, Any] = {"type": self.name}
        for pname in self.PARAMETERS:
            if pname in self._spectra:
                s = self._spectra[pname]
                out[pname] = float(s.values) if s.is_constant else s
            else:
                v = self._values[pname]
                out[pname] = str(v) if isinstance(v, Path) else v
        return out

    def __repr__(self) -> str:
        items = ", ".join(f"{k}={v!r}" for k, v in self.config().items() if k != "type")
        return f"{type(self).__name__}({items})"

    # ------------------------------------------------------------------ geometry
    @staticmethod
    def _cosines(wi, wo, normal):
        wi = np.asarray(wi, dtype=float)
        wo = np.asarray(wo, dtype=float)
        if normal is None:
            mu_i, mu_o = wi[..., 2], wo[..., 2]
        else:
            n = np.asarray(normal, dtype=float)
            mu_i, mu_o = _dot(wi, n), _dot(wo, n)
        return mu_i, mu_o, np.clip(_dot(wi, wo), -1.0, 1.0)

    @staticmethod
    def _cos(w, normal) -> np.ndarray:
        w = np.asarray(w, dtype=float)
        return w[..., 2] if normal is None else _dot(w, np.asarray(normal, dtype=float))

    # ------------------------------------------------------------------ evaluation
    def f(self, wi, wo, wavelength=None, normal=None) -> np.ndarray:
        """The BRDF f(ω_i, ω_o, λ).

        Parameters
        ----------
        wi : array_like
            Unit directions towards the source, ``(..., 3)`` [-].
        wo : array_like
            Unit directions towards the viewer, ``(..., 3)`` [-].
        wavelength : array_like, optional
            [um], broadcastable with ``wi[..., 0]``; needed when a parameter is tabulated.
        normal : array_like, optional
            Unit surface normals ``(..., 3)`` when ``wi``, ``wo`` are world vectors; ``None``
            for the local frame (z = normal).

        Returns
        -------
        numpy.ndarray
            f [sr-1], shape ``broadcast(wi[..., 0], wo[..., 0], wavelength)``; 0 where a
            direction is at or below the horizon (for one-sided models).
        """
        mu_i, mu_o, cos_g = self._cosines(wi, wo, normal)
        return self.kernel(mu_i, mu_o, cos_g, wavelength)

    def kernel(self, cos_incidence, cos_view, cos_phase, wavelength=None) -> np.ndarray:
        """The BRDF as a function of the three invariants (module docstring).

        Parameters
        ----------
        cos_incidence, cos_view : array_like
            μ_i = ω_i · n and μ_o = ω_o · n [-].
        cos_phase : array_like
            cos g = ω_i · ω_o [-].
        wavelength : array_like, optional
            [um].

        Returns
        -------
        numpy.ndarray
            f [sr-1], broadcast shape of the arguments; 0 where μ_i ≤ 0 or μ_o ≤ 0 for
            one-sided models; NaN where an argument is NaN.
        """
        mu_i = np.asarray(cos_incidence, dtype=float)
        mu_o = np.asarray(cos_view, dtype=float)
        cos_g = np.asarray(cos_phase, dtype=float)
        shape = np.broadcast_shapes(mu_i.shape, mu_o.shape, cos_g.shape,
                                    np.shape(wavelength) if wavelength is not None else ())
        below = (mu_i <= 0.0) | (mu_o <= 0.0)  # NaN is not below: it propagates
        with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
            if not np.any(below):
                value = self._kernel(mu_i, mu_o, cos_g, wavelength)
            else:
                # evaluate on harmless stand-ins, then zero what lies below the horizon
                value = np.where(
                    below,
                    0.0,
                    self._kernel(np.where(below, 1.0, mu_i), np.where(below, 1.0, mu_o),
                                 np.where(below, 1.0, cos_g), wavelength),
                )
        value = np.asarray(value, dtype=float)
        if value.shape != shape:
            value = np.array(np.broadcast_to(value, shape))
        return value

    def f_angles(self, incidence_zenith, view_zenith, relative_azimuth, wavelength=None):
        """The BRDF from angles [deg]: θ_i, θ_o and Δφ = φ_o − φ_i (0 = backscatter).

        Returns
        -------
        numpy.ndarray
            f [sr-1]; multiply by π for the BRF.
        """
        return self.kernel(*cos_phase_from_angles(incidence_zenith, view_zenith,
                                                  relative_azimuth), wavelength)

    def _kernel(self, mu_i, mu_o, cos_g, wavelength):  # pragma: no cover - abstract
        raise NotImplementedError

    # ------------------------------------------------------------------ sampling
    def sample(self, wo, u1, u2, wavelength=None, normal=None):
        """Draw incident directions ω_i for a given ω_o, with their density.

        Parameters
        ----------
        wo : array_like
            Unit directions towards the viewer ``(..., 3)`` [-].
        u1, u2 : array_like
            Uniform numbers [-] in [0, 1], broadcastable with ``wo[..., 0]``.
        wavelength : array_like, optional
            [um]; sets the mixture weights of multi-lobe models.
        normal : array_like, optional
            Unit surface normals (world vectors in and out); ``None`` for the local frame.

        Returns
        -------
        wi : numpy.ndarray
            Unit vectors ``(..., 3)``; they may lie below the horizon, where f is 0 (or, for a
            two-sided model, where it transmits).
        pdf : numpy.ndarray
            Their density :meth:`pdf` with respect to solid angle [sr-1].
        """
        u1 = unit_interval(u1, "u1")
        u2 = unit_interval(u2, "u2")
        wo = np.asarray(wo, dtype=float)
        if normal is None:
            shape = np.broadcast_shapes(wo.shape[:-1], u1.shape, u2.shape,
                                        np.shape(wavelength) if wavelength is not None else ())
            wo_l = np.broadcast_to(wo, shape + (3,))
            wi = self._sample_local(wo_l, np.broadcast_to(u1, shape),
                                    np.broadcast_to(u2, shape), wavelength)
            wi = np.array(np.broadcast_to(wi, shape + (3,)))
        else:
            n = np.asarray(normal, dtype=float)
            t, b = orthonormal_basis(n)
            wo_l = np.stack([_dot(wo, t), _dot(wo, b), _dot(wo, n)], axis=-1)
            shape = np.broadcast_shapes(wo_l.shape[:-1], u1.shape, u2.shape,
                                        np.shape(wavelength) if wavelength is not None else ())
            wi_l = self._sample_local(np.broadcast_to(wo_l, shape + (3,)),
                                      np.broadcast_to(u1, shape), np.broadcast_to(u2, shape),
                                      wavelength)
            wi = wi_l[..., 0:1] * t + wi_l[..., 1:2] * b + wi_l[..., 2:3] * n
            wi = np.array(np.broadcast_to(wi, shape + (3,)))
        return wi, self.pdf(wo, wi, wavelength, normal)

    def pdf(self, wo, wi, wavelength=None, normal=None) -> np.ndarray:
        """Density of :meth:`sample` drawing ``wi`` given ``wo`` [sr-1] (over the sphere)."""
        mu_i, mu_o, cos_g = self._cosines(wi, wo, normal)
        with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
            value = self._pdf(mu_o, mu_i, cos_g, wavelength)
        shape = np.broadcast_shapes(mu_i.shape, mu_o.shape,
                                    np.shape(wavelength) if wavelength is not None else ())
        value = np.where(np.isfinite(value), value, 0.0)
        return np.array(np.broadcast_to(value, shape), dtype=float)

    def _sample_local(self, wo, u1, u2, wavelength):
        """Default: cosine-weighted on the upper hemisphere."""
        return cosine_hemisphere(u1, u2)

    def _pdf(self, mu_o, mu_i, cos_g, wavelength):
        """Default density of :meth:`_sample_local`: max(μ_i, 0)/π."""
        return np.maximum(mu_i, 0.0) / np.pi

    def _mixture_weight(self, first: str, second: str, wavelength) -> Any:
        """Probability of sampling the lobe of ``first`` rather than that of ``second``.

        Proportional to the two albedos at ``wavelength``; 1/2 when both vanish, or when they
        are tabulated and no wavelength is given.
        """
        try:
            a = np.asarray(self.parameter(first, wavelength), dtype=float)
            b = np.asarray(self.parameter(second, wavelength), dtype=float)
        except ConfigError:
            return 0.5
        total = a + b
        with np.errstate(divide="ignore", invalid="ignore"):
            return np.where(total > 0.0, a / np.where(total > 0.0, total, 1.0), 0.5)

    # ------------------------------------------------------------------ hemispherical
    def albedo(self, wi, wavelength=None, normal=None) -> np.ndarray:
        """Directional-hemispherical reflectance ρ_dh(ω_i, λ) = ∫ f cos θ_o dω_o [-].

        Parameters
        ----------
        wi : array_like
            Unit directions towards the source ``(..., 3)`` [-].
        wavelength : array_like, optional
            [um], broadcastable with ``wi[..., 0]``.
        normal : array_like, optional
            Unit normals for world vectors; ``None`` for the local frame.

        Returns
        -------
        numpy.ndarray
            ρ_dh [-], shape ``broadcast(wi[..., 0], wavelength)``.
        """
        return self._hemispherical(self._cos(wi, normal), wavelength)[0]

    def transmittance(self, wi, wavelength=None, normal=None) -> np.ndarray:
        """Directional-hemispherical transmittance τ_dh(ω_i, λ) [-]: 0 for opaque models."""
        return self._hemispherical(self._cos(wi, normal), wavelength)[1]

    def emissivity(self, wi, wavelength=None, normal=None) -> np.ndarray:
        """Directional emissivity by Kirchhoff's law, ε(ω, λ) = 1 − ρ_dh − τ_dh [-].

        ``wi`` is the direction in which the surface emits (towards the viewer): by
        reciprocity the absorptance of a beam from ω equals the emissivity into ω.
        One-sided models emit nothing at or below their horizon (ε = 0 there).
        """
        mu = self._cos(wi, normal)
        rho, tau = self._hemispherical(mu, wavelength)
        eps = 1.0 - rho - tau
        if not self.two_sided:
            eps = np.where(mu > 0.0, eps, 0.0)
        return np.asarray(eps)

    def bihemispherical_reflectance(self, wavelength=None) -> np.ndarray:
        """Bihemispherical ("white-sky") reflectance ρ_bh = 2 ∫ ρ_dh(μ) μ dμ [-].

        The reflectance under isotropic illumination; for a Lambertian surface it is ρ.

        Parameters
        ----------
        wavelength : array_like, optional
            [um].

        Returns
        -------
        numpy.ndarray
            ρ_bh [-], shape of ``wavelength`` (0-d without it).
        """
        return bihemispherical(self, wavelength)[0]

    def hemispherical_emissivity(self, wavelength=None) -> np.ndarray:
        """Hemispherical emissivity ε_h = 2 ∫ ε(μ) μ dμ = 1 − ρ_bh − τ_bh [-].

        The emissivity of the surface's total (hemispherical) thermal emission, for the heat
        balance: the exitance is ε_h σ T⁴ for a grey surface.

        Parameters
        ----------
        wavelength : array_like, optional
            [um].

        Returns
        -------
        numpy.ndarray
            ε_h [-], shape of ``wavelength`` (0-d without it).
        """
        rho, tau = bihemispherical(self, wavelength)
        return np.asarray(1.0 - rho - tau)

    def _hemispherical(self, mu_i, wavelength):
        """ρ_dh and τ_dh at cos θ_i (arrays of the broadcast shape) [-]."""
        mu_i = np.asarray(mu_i, dtype=float)
        wl = None if wavelength is None else np.asarray(wavelength, dtype=float)
        shape = np.broadcast_shapes(mu_i.shape, () if wl is None else wl.shape)
        mu_flat = np.broadcast_to(mu_i, shape).ravel()
        wl_flat = None if wl is None else np.broadcast_to(wl, shape).ravel()
        rho = np.zeros(mu_flat.size)
        tau = np.zeros(mu_flat.size)
        integrate = albedo_quadrature if self.albedo_rule == "quadrature" else albedo_sampling
        todo = mu_flat != 0.0 if self.two_sided else mu_flat > 0.0
        index = np.flatnonzero(todo)
        rows = max(1, CHUNK // (QUADRATURE_NODES[0] * QUADRATURE_NODES[1]))
        for start in range(0, index.size, rows):
            sel = index[start:start + rows]
            r, t = integrate(self, mu_flat[sel], None if wl_flat is None else wl_flat[sel])
            rho[sel] = r
            tau[sel] = t
        return rho.reshape(shape), tau.reshape(shape)
