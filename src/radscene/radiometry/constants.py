"""Radiation constants, derived from CODATA 2018 values in :mod:`scipy.constants`.

Since the 2019 SI revision h, c and k are exact, so the derived constants below are exact to
double precision (σ and Wien's b to the precision of their defining numbers).

References
----------
E. Tiesinga, P. J. Mohr, D. B. Newell and B. N. Taylor, "CODATA recommended values of the
fundamental physical constants: 2018", Rev. Mod. Phys. 93, 025010 (2021),
https://doi.org/10.1103/RevModPhys.93.025010
"""

from __future__ import annotations

import math

from scipy import constants as _sc

__all__ = ["C1", "C1L", "C2", "SIGMA", "WIEN_B"]

# First radiation constant, for spectral exitance: c1 = 2 π h c²  [W m²]
C1: float = 2.0 * math.pi * _sc.h * _sc.c**2

# First radiation constant for spectral radiance: c1L = 2 h c²  [W m² sr-1]
C1L: float = 2.0 * _sc.h * _sc.c**2

# Second radiation constant: c2 = h c / k  [m K]
C2: float = _sc.h * _sc.c / _sc.k

# Stefan-Boltzmann constant: σ = 2 π⁵ k⁴ / (15 h³ c²)  [W m-2 K-4]
SIGMA: float = _sc.Stefan_Boltzmann

# Wien wavelength displacement constant: b = c2 / x_w with x_w = 5 + W0(-5 e^-5),
# the root of x = 5 (1 - e^-x)  [m K]
WIEN_B: float = _sc.Wien
