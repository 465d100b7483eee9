"""Exchange with the surrounding scene surfaces, Q_env: long-wave from the neighbours and
short-wave reflected by them.

The caller gives the view factors F (a sparse n × n matrix, F_ij the fraction of the
hemisphere of element i, cosine-weighted, filled by element j; the ray engine's estimate) with
row sums ≤ 1 − V_sky. Every neighbour is a grey, opaque, diffuse (Lambertian) surface of
emissivity ε_j and solar absorptance α_j.

Long-wave: the radiosity of j, emission plus reflection of what reaches it,

.. math::
    J_j^{(0)} = \\varepsilon_j\\sigma T_j^4, \\qquad
    J_j^{(m)} = \\varepsilon_j\\sigma T_j^4 + (1 - \\varepsilon_j)\\big(E_{sky}V_{sky,j}
                + \\textstyle\\sum_k F_{jk} J_k^{(m-1)}\\big), \\qquad
    Q_{env,LW,i} = \\varepsilon_i \\textstyle\\sum_j F_{ij} J_j^{(m)}

with m the number of reflections followed (``reflections``; as m → ∞ the radiosity equations,
Modest 2013 ch. 5, are solved; m = 0 keeps emission only, ε_i Σ F_ij ε_j σ T_j⁴). The
temperatures T_j are those at the start of the step (explicit): Q_env is a known flux within a
step, lagging the neighbours by one step.

Short-wave: I_j = E_dir max(cos i_j, 0) lit_j + E_dif V_sky,j is the irradiance on j this
step from the sun and the sky (what :func:`radscene.thermal.radiation.absorbed_shortwave`
weights by α_j), reflected diffusely with 1 − α_j,

.. math::
    R_j^{(1)} = (1 - \\alpha_j) I_j, \\qquad
    R_j^{(m)} = (1 - \\alpha_j)\\big(I_j + \\textstyle\\sum_k F_{jk} R_k^{(m-1)}\\big), \\qquad
    Q_{env,SW,i} = \\alpha_i \\textstyle\\sum_j F_{ij} R_j^{(m)}

so that m = 1 is the short-wave reflected once by the neighbours, α_i Σ F_ij (1 − α_j) I_j.
Specular neighbours (glass, metal) are treated as diffuse, and the neighbours' reflection of
long-wave from beyond the scene (the sky) appears from m = 1 on.

References
----------
Modest, M. F. (2013). *Radiative Heat Transfer*, 3rd ed. Academic Press, ch. 4 (view factors)
and ch. 5 (radiative exchange between grey, diffuse surfaces).
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from radscene.errors import ConfigError

__all__ = ["check_view_factors", "environment_longwave", "environment_shortwave"]


def check_view_factors(view_factors, n_elements, key="exchange"):
    """Validate view factors F into a CSR matrix (n_elements × n_elements).

    Parameters
    ----------
    view_factors : scipy.sparse matrix or array_like
        F_ij ≥ 0 [-], row sums ≤ 1.
    n_elements : int
    key : str
        Config key for messages.

    Returns
    -------
    scipy.sparse.csr_array
    """
    try:
        f = sp.csr_array(view_factors, dtype=float)
    except (TypeError, ValueError) as exc:
        raise ConfigError(f"expected a sparse (n_elements x n_elements) matrix of view factors: {exc}", key=key) from None
    if f.shape != (n_elements, n_elements):
        raise ConfigError(f"shape {f.shape} is not (n_elements, n_elements) = {(n_elements, n_elements)}", key=key)
    f.sum_duplicates()
    if not np.all(np.isfinite(f.data)) or np.any(f.data < 0):
        raise ConfigError("view factors must be finite and >= 0", key=key)
    rows = np.asarray(f.sum(axis=1)).ravel()
    if rows.size and rows.max() > 1.0 + 1e-9:
        i = int(np.argmax(rows))
        raise ConfigError(f"row {i} sums to {rows[i]:.6g} > 1: the view factors of an element sum to at most 1", key=key)
    return f


def environment_longwave(view_factors, emissivity, exitance, sky_irradiance, reflections=1):
    """Long-wave from the neighbouring elements absorbed by each element, Q_env,LW ≥ 0 [W m-2].

    Parameters
    ----------
    view_factors : scipy.sparse.csr_array, (n, n)
        F [-].
    emissivity : ndarray, (n,)
        ε [-].
    exitance : ndarray, (n,)
        ε σ T⁴ of each element [W m-2] (at the start of the step in the balance).
    sky_irradiance : ndarray, (n,)
        Long-wave from the sky on each element, E_sky V_sky [W m-2].
    reflections : int, optional
        m ≥ 0: how many reflections on the way are followed (module docstring).

    Returns
    -------
    ndarray, (n,)
        [W m-2].

    Examples
    --------
    >>> import scipy.sparse as sp
    >>> f = sp.csr_array([[0.0, 1.0], [1.0, 0.0]])   # two facing, infinite plates
    >>> q = environment_longwave(f, np.array([1.0, 1.0]), np.array([400.0, 300.0]), np.zeros(2))
    >>> q.tolist()
    [300.0, 400.0]
    """
    radiosity = exitance
    for _ in range(int(reflections)):
        radiosity = exitance + (1.0 - emissivity) * (sky_irradiance + view_factors @ radiosity)
    return emissivity * (view_factors @ radiosity)


def environment_shortwave(view_factors, absorptance, irradiance, reflections=1):
    """Short-wave reflected by the neighbouring elements and absorbed, Q_env,SW ≥ 0 [W m-2].

    Parameters
    ----------
    view_factors : scipy.sparse.csr_array, (n, n)
        F [-].
    absorptance : ndarray, (n,)
        α [-].
    irradiance : ndarray, (n,)
        I, short-wave from the sun and the sky on each element [W m-2].
    reflections : int, optional
        m ≥ 0 (0: none).

    Returns
    -------
    ndarray, (n,)
        [W m-2].

    Examples
    --------
    >>> import scipy.sparse as sp
    >>> f = sp.csr_array([[0.0, 0.5], [0.0, 0.0]])
    >>> environment_shortwave(f, np.array([0.8, 0.4]), np.array([0.0, 1000.0])).tolist()
    [240.0, 0.0]
    """
    if int(reflections) < 1:
        return np.zeros_like(np.asarray(irradiance, float))
    reflected = (1.0 - absorptance) * irradiance
    for _ in range(int(reflections) - 1):
        reflected = (1.0 - absorptance) * (irradiance + view_factors @ reflected)
    return absorptance * (view_factors @ reflected)
