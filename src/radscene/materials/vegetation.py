"""Vegetation: leaves from PROSPECT-D and canopies from 4SAIL, as radscene materials.

Models (through the ``prosail`` package, J. Gómez-Dans, GPL-3, an optional dependency):

* **PROSPECT-D** — leaf directional-hemispherical reflectance and transmittance, 0.4-2.5 um at
  1 nm, from the structure parameter N and the leaf's chlorophyll, carotenoids, anthocyanins,
  brown pigments, water and dry matter (Féret et al. 2017).
* **4SAIL** — a turbid-medium canopy of those leaves over a Lambertian soil, with a leaf
  inclination distribution and the hot spot (Verhoef 1984; Verhoef et al. 2007). It gives the
  four reflectance factors of the canopy: bidirectional (``bidirectional``), directional-
  hemispherical (``directional_hemispherical``, sun → hemisphere), hemispherical-directional
  (``hemispherical_directional``, hemisphere → view) and bi-hemispherical (``bihemispherical``).
* **Thermal** — the same 4SAIL with the leaves' and soil's thermal-infrared reflectance
  (1 − emissivity, leaves opaque) gives the canopy emissivity: directional
  ε(θ_v) = 1 − hemispherical-directional reflectance and hemispherical ε = 1 − bi-hemispherical
  reflectance (Kirchhoff). Multiple scattering between leaves (the cavity effect) makes a dense
  canopy more emissive than its leaves.

Parameters (names as in the functions; PROSPECT's units):

=====================  ===========  =======  =================================================
parameter              unit         default  meaning
=====================  ===========  =======  =================================================
structure              [-]          1.5      N, number of compact layers in the leaf (1-3)
chlorophyll            [ug cm-2]    40       C_ab, chlorophyll a + b
carotenoids            [ug cm-2]    8        C_car
anthocyanins           [ug cm-2]    0        C_ant
brown_pigments         [-]          0        C_brown (senescence), 0-1
water                  [g cm-2]     0.01     C_w, equivalent water thickness (= cm of water)
dry_matter             [g cm-2]     0.009    C_m, leaf mass per area
lai                    [m2 m-2]     3        leaf area index
leaf_angle             [deg] or str 57       mean leaf inclination (Campbell ellipsoidal), or a
                                             Verhoef distribution name (:data:`LEAF_ANGLE_DISTRIBUTIONS`)
hotspot                [-]          0.01     leaf size / canopy height
leaf_emissivity        [-]          0.97     thermal-infrared leaf emissivity (3-20 um)
=====================  ===========  =======  =================================================

Config snippet: ``{lai: 3, chlorophyll: 40, water: 0.012, leaf_angle: spherical}``.

Spectral rules (stated, not silent): leaf and canopy spectra are computed on 0.4-2.5 um; a
material made from them is tabulated there every ``vswir_step`` (10 nm by default, the model's
1 nm output sampled, not smoothed), and on 3-20 um from the thermal model; it is linear in
wavelength in between (2.5-3.0 um). Leaves are opaque (τ = 0) from 3 um on.

References
----------
J.-B. Féret, A. A. Gitelson, S. D. Noble, S. Jacquemoud, "PROSPECT-D: towards modeling leaf
optical properties through a complete lifecycle", Remote Sens. Environ. 193, 204-215 (2017),
doi:10.1016/j.rse.2017.03.004.
W. Verhoef, "Light scattering by leaf layers with application to canopy reflectance modeling:
the SAIL model", Remote Sens. Environ. 16, 125-141 (1984), doi:10.1016/0034-4257(84)90057-9.
W. Verhoef, L. Jia, Q. Xiao, Z. Su, "Unified optical-thermal four-stream radiative transfer theory
for homogeneous vegetation canopies", IEEE Trans. Geosci. Remote Sens. 45, 1808-1822 (2007),
doi:10.1109/TGRS.2007.895844.
S. Jacquemoud et al., "PROSPECT + SAIL models: a review of use for vegetation characterization",
Remote Sens. Environ. 113, S56-S66 (2009), doi:10.1016/j.rse.2008.01.026.
C. Ribeiro da Luz, J. K. Crowley, "Spectral reflectance and emissivity features of broad leaf
plants: prospects for remote sensing in the thermal infrared (8.0-14.0 um)", Remote Sens.
Environ. 109, 393-405 (2007), doi:10.1016/j.rse.2007.01.008 (leaf 8-14 um reflectance of a
few percent: emissivity 0.95-0.99).
"""

from __future__ import annotations

import math
import numbers
from dataclasses import dataclass

import numpy as np

from radscene.errors import ConfigError

__all__ = [
    "LeafOptics",
    "CanopyReflectance",
    "CanopyEmissivity",
    "LEAF_ANGLE_DISTRIBUTIONS",
    "DEFAULT_LEAF_EMISSIVITY",
    "leaf_optics",
    "canopy_reflectance",
    "canopy_emissivity",
    "leaf_material",
    "canopy_material",
]

#: Verhoef (1998) two-parameter leaf inclination distributions (a, b).
LEAF_ANGLE_DISTRIBUTIONS = {
    "planophile": (1.0, 0.0),
    "erectophile": (-1.0, 0.0),
    "plagiophile": (0.0, -1.0),
    "extremophile": (0.0, 1.0),
    "spherical": (-0.35, -0.15),
    "uniform": (0.0, 0.0),
}

#: Thermal-infrared emissivity of a green leaf, 3-20 um: the mid-point of the 0.95-0.99 that
#: Ribeiro da Luz & Crowley (2007) measured for leaves in 8-14 um, held flat over 3-20 um [-].
DEFAULT_LEAF_EMISSIVITY = 0.97

#: Default thermal-infrared grid of canopy emissivity [um].
THERMAL_GRID = np.array([3.0, 3.5, 4.0, 4.5, 5.0, 6.0, 7.0, 8.0, 9.0, 10.0, 11.0, 12.0, 13.0,
                         14.0, 16.0, 18.0, 20.0])

_INSTALL = (
    "vegetation models need the optional package 'prosail' (PROSPECT-D + 4SAIL): "
    "`pip install prosail` (from a radscene clone: `pip install '.[vegetation]'`)"
)


def _prosail():
    try:
        import prosail
        from prosail.FourSAIL import foursail
    except ImportError:
        raise ConfigError(_INSTALL, key="prosail") from None
    return prosail, foursail


def _number(value, key: str, low: float, high: float = math.inf, low_open=False) -> float:
    if isinstance(value, bool) or not isinstance(value, numbers.Real) or not math.isfinite(value):
        raise ConfigError(f"must be a finite number; got {value!r}", key=key)
    value = float(value)
    if value < low or value > high or (low_open and value == low):
        bracket = "(" if low_open else "["
        raise ConfigError(f"must be in {bracket}{low:g}, {high:g}]; got {value:g}", key=key)
    return value


@dataclass(frozen=True)
class LeafOptics:
    """Leaf directional-hemispherical reflectance and transmittance (PROSPECT-D).

    Attributes
    ----------
    wavelength : numpy.ndarray
        [um], 0.4-2.5 at 1 nm.
    reflectance, transmittance : numpy.ndarray
        [-].
    parameters : dict
        The PROSPECT inputs (units as in the module table).
    """

    wavelength: np.ndarray
    reflectance: np.ndarray
    transmittance: np.ndarray
    parameters: dict

    @property
    def absorptance(self) -> np.ndarray:
        """1 − ρ − τ [-]."""
        return 1.0 - self.reflectance - self.transmittance


def leaf_optics(
    *,
    structure: float = 1.5,
    chlorophyll: float = 40.0,
    carotenoids: float = 8.0,
    anthocyanins: float = 0.0,
    brown_pigments: float = 0.0,
    water: float = 0.01,
    dry_matter: float = 0.009,
) -> LeafOptics:
    """Leaf reflectance and transmittance from PROSPECT-D, 0.4-2.5 um.

    Parameters
    ----------
    structure : float
        N [-], 1-3.
    chlorophyll, carotenoids, anthocyanins : float
        [ug cm-2], ≥ 0.
    brown_pigments : float
        [-], 0-1.
    water : float
        Equivalent water thickness [g cm-2], ≥ 0.
    dry_matter : float
        Leaf mass per area [g cm-2], > 0.

    Returns
    -------
    LeafOptics

    Raises
    ------
    ConfigError
        A parameter out of range (naming it), or prosail not installed.

    Examples
    --------
    >>> leaf = leaf_optics(chlorophyll=40.0)            # doctest: +SKIP
    >>> bool(leaf.reflectance[150] < leaf.reflectance[450])   # 0.55 < 0.85 um  # doctest: +SKIP
    True
    """
    params = {
        "structure": _number(structure, "structure", 1.0, 3.5),
        "chlorophyll": _number(chlorophyll, "chlorophyll", 0.0, 200.0),
        "carotenoids": _number(carotenoids, "carotenoids", 0.0, 50.0),
        "anthocyanins": _number(anthocyanins, "anthocyanins", 0.0, 50.0),
        "brown_pigments": _number(brown_pigments, "brown_pigments", 0.0, 1.0),
        "water": _number(water, "water", 0.0, 0.1),
        "dry_matter": _number(dry_matter, "dry_matter", 0.0, 0.1, low_open=True),
    }
    prosail, _ = _prosail()
    wv, rho, tau = prosail.run_prospect(
        params["structure"],
        params["chlorophyll"],
        params["carotenoids"],
        params["brown_pigments"],
        params["water"],
        params["dry_matter"],
        ant=params["anthocyanins"],
        prospect_version="D",
    )
    return LeafOptics(
        wavelength=np.asarray(wv, dtype=float) * 1e-3,
        reflectance=np.asarray(rho, dtype=float),
        transmittance=np.asarray(tau, dtype=float),
        parameters=params,
    )


def _lidf(leaf_angle) -> tuple[float, float, int]:
    """(lidfa, lidfb, typelidf) for 4SAIL."""
    if isinstance(leaf_angle, str):
        key = leaf_angle.strip().lower()
        if key not in LEAF_ANGLE_DISTRIBUTIONS:
            raise ConfigError(
                f"unknown leaf angle distribution {leaf_angle!r}; known: "
                f"{', '.join(LEAF_ANGLE_DISTRIBUTIONS)} or a mean leaf angle in degrees",
                key="leaf_angle",
            )
        a, b = LEAF_ANGLE_DISTRIBUTIONS[key]
        return a, b, 1
    angle = _number(leaf_angle, "leaf_angle", 0.0, 90.0)
    # Campbell's ellipsoidal distribution is singular at exactly 0 and 90 deg
    return min(max(angle, 0.5), 89.5), 0.0, 2


@dataclass(frozen=True)
class CanopyReflectance:
    """The four reflectance factors of a 4SAIL canopy [-] at ``wavelength`` [um]."""

    wavelength: np.ndarray
    bidirectional: np.ndarray
    directional_hemispherical: np.ndarray
    hemispherical_directional: np.ndarray
    bihemispherical: np.ndarray
    parameters: dict


def _soil_values(soil, wavelength: np.ndarray, key: str, thermal: bool) -> np.ndarray:
    """Soil reflectance at ``wavelength`` from a number, Spectrum or Material."""
    from radscene.materials.material import Material
    from radscene.materials.spectrum import make_spectrum

    if isinstance(soil, Material):
        values = soil.reflectance(wavelength)
    else:
        values = make_spectrum(soil, key=key)(wavelength)
    values = np.asarray(values, dtype=float) * np.ones_like(wavelength)
    if np.any(values < 0.0) or np.any(values > 1.0):
        raise ConfigError(f"soil {'thermal ' if thermal else ''}reflectance must be in [0, 1]", key=key)
    return values


def _run_sail(rho, tau, soil, lai, leaf_angle, hotspot, sun_zenith, view_zenith, relative_azimuth):
    _, foursail = _prosail()
    lai = _number(lai, "lai", 0.0, 15.0)
    hotspot = _number(hotspot, "hotspot", 0.0, 1.0)
    sun_zenith = _number(sun_zenith, "sun_zenith", 0.0, 89.0)
    view_zenith = _number(view_zenith, "view_zenith", 0.0, 89.0)
    relative_azimuth = _number(relative_azimuth, "relative_azimuth", 0.0, 360.0)
    a, b, kind = _lidf(leaf_angle)
    if kind == 1 and abs(a) + abs(b) > 1.0:
        raise ConfigError("Verhoef leaf angle parameters need |a| + |b| <= 1", key="leaf_angle")
    out = foursail(rho, tau, a, b, kind, max(lai, 1e-9), hotspot, sun_zenith, view_zenith,
                   relative_azimuth, soil)
    rddt, rsdt, rdot, rsot = out[12], out[13], out[14], out[17]
    return [np.asarray(v, dtype=float) * np.ones_like(rho) for v in (rsot, rsdt, rdot, rddt)]


def canopy_reflectance(
    leaf: LeafOptics | None = None,
    *,
    lai: float = 3.0,
    leaf_angle=57.0,
    hotspot: float = 0.01,
    soil=0.2,
    sun_zenith: float = 30.0,
    view_zenith: float = 0.0,
    relative_azimuth: float = 0.0,
) -> CanopyReflectance:
    """Canopy reflectance factors from 4SAIL, 0.4-2.5 um.

    Parameters
    ----------
    leaf : LeafOptics, optional
        Leaf optics; default :func:`leaf_optics` with its defaults.
    lai : float
        Leaf area index [m2 m-2], 0-15.
    leaf_angle : float or str
        Mean leaf inclination [deg] (Campbell ellipsoidal) or a name of
        :data:`LEAF_ANGLE_DISTRIBUTIONS`.
    hotspot : float
        Leaf size / canopy height [-].
    soil : float, Spectrum, Material or spectrum mapping
        Background (Lambertian) reflectance [-].
    sun_zenith, view_zenith : float
        [deg], 0-89.
    relative_azimuth : float
        Angle between the azimuths of the sun and of the sensor, both seen from the target
        [deg]; 0 puts the sensor on the sun's side (backscatter, the hot spot).

    Returns
    -------
    CanopyReflectance
        On the leaf's wavelengths [um].
    """
    leaf = leaf if leaf is not None else leaf_optics()
    soil_r = _soil_values(soil, leaf.wavelength, "soil", thermal=False)
    rsot, rsdt, rdot, rddt = _run_sail(
        leaf.reflectance, leaf.transmittance, soil_r, lai, leaf_angle, hotspot,
        sun_zenith, view_zenith, relative_azimuth,
    )
    return CanopyReflectance(
        wavelength=leaf.wavelength,
        bidirectional=rsot,
        directional_hemispherical=rsdt,
        hemispherical_directional=rdot,
        bihemispherical=rddt,
        parameters={
            **leaf.parameters, "lai": lai, "leaf_angle": leaf_angle, "hotspot": hotspot,
            "sun_zenith": sun_zenith, "view_zenith": view_zenith,
            "relative_azimuth": relative_azimuth,
        },
    )


@dataclass(frozen=True)
class CanopyEmissivity:
    """Thermal-infrared emissivity of a canopy over soil [-] at ``wavelength`` [um]."""

    wavelength: np.ndarray
    directional: np.ndarray
    hemispherical: np.ndarray
    view_zenith: float


def canopy_emissivity(
    wavelength=None,
    *,
    lai: float = 3.0,
    leaf_angle=57.0,
    hotspot: float = 0.01,
    leaf_emissivity=DEFAULT_LEAF_EMISSIVITY,
    soil_emissivity=0.95,
    view_zenith: float = 0.0,
) -> CanopyEmissivity:
    """Canopy emissivity by 4SAIL with opaque leaves (Verhoef et al. 2007) and Kirchhoff's law.

    Parameters
    ----------
    wavelength : array_like, optional
        [um]; default :data:`THERMAL_GRID` (3-20 um).
    lai, leaf_angle, hotspot : see :func:`canopy_reflectance`.
    leaf_emissivity : float, Spectrum or mapping
        [-]; leaves' thermal reflectance is 1 − ε_leaf, their transmittance 0.
    soil_emissivity : float, Spectrum, Material or mapping
        [-] (a Material gives its Kirchhoff emissivity).
    view_zenith : float
        [deg].

    Returns
    -------
    CanopyEmissivity
        ``directional`` = 1 − r_do(θ_v), ``hemispherical`` = 1 − r_dd.

    Examples
    --------
    >>> e = canopy_emissivity([10.0], lai=6.0, leaf_emissivity=0.97, soil_emissivity=0.9)  # doctest: +SKIP
    >>> bool(e.hemispherical[0] > 0.97)   # the cavity effect  # doctest: +SKIP
    True
    """
    from radscene.materials.material import Material
    from radscene.materials.spectrum import make_spectrum

    wl = THERMAL_GRID if wavelength is None else np.atleast_1d(np.asarray(wavelength, dtype=float))
    eps_leaf = np.asarray(make_spectrum(leaf_emissivity, key="leaf_emissivity")(wl)) * np.ones_like(wl)
    if np.any(eps_leaf < 0) or np.any(eps_leaf > 1):
        raise ConfigError("must be in [0, 1]", key="leaf_emissivity")
    if isinstance(soil_emissivity, Material):
        soil_r = soil_emissivity.reflectance(wl) * np.ones_like(wl)
    else:
        eps_soil = np.asarray(make_spectrum(soil_emissivity, key="soil_emissivity")(wl)) * np.ones_like(wl)
        if np.any(eps_soil < 0) or np.any(eps_soil > 1):
            raise ConfigError("must be in [0, 1]", key="soil_emissivity")
        soil_r = 1.0 - eps_soil
    _, _, rdot, rddt = _run_sail(
        1.0 - eps_leaf, np.zeros_like(wl), soil_r, lai, leaf_angle, hotspot, 0.0, view_zenith, 0.0
    )
    return CanopyEmissivity(
        wavelength=wl, directional=1.0 - rdot, hemispherical=1.0 - rddt, view_zenith=float(view_zenith)
    )


def _vswir_grid(step: float) -> np.ndarray:
    step = _number(step, "vswir_step", 0.001, 0.1)
    n = int(round((2.5 - 0.4) / step))
    return np.round(0.4 + step * np.arange(n + 1), 6)


def _sample(grid, wavelength, values):
    return np.interp(grid, wavelength, values)


def leaf_material(
    name: str = "leaf",
    *,
    leaf: LeafOptics | None = None,
    leaf_emissivity: float = DEFAULT_LEAF_EMISSIVITY,
    vswir_step: float = 0.01,
    **prospect,
):
    """A single green leaf as a translucent :class:`~radscene.materials.Material`.

    Parameters
    ----------
    name : str
    leaf : LeafOptics, optional
        Precomputed optics; otherwise ``**prospect`` goes to :func:`leaf_optics`.
    leaf_emissivity : float
        Thermal-infrared emissivity, 3-20 um [-]; the leaf is opaque there.
    vswir_step : float
        Sampling of the PROSPECT output in the material [um].

    Returns
    -------
    Material
        ρ and τ from PROSPECT-D on 0.4-2.5 um; ρ = 1 − ε_leaf, τ = 0 on 3-20 um; linear between.
    """
    from radscene.materials.material import Material
    from radscene.materials.spectrum import Spectrum

    leaf = leaf if leaf is not None else leaf_optics(**prospect)
    eps = _number(leaf_emissivity, "leaf_emissivity", 0.0, 1.0)
    grid = _vswir_grid(vswir_step)
    wl = np.concatenate([grid, THERMAL_GRID])
    rho = np.concatenate([_sample(grid, leaf.wavelength, leaf.reflectance),
                          np.full(THERMAL_GRID.size, 1.0 - eps)])
    tau = np.concatenate([_sample(grid, leaf.wavelength, leaf.transmittance),
                          np.zeros(THERMAL_GRID.size)])
    p = leaf.parameters
    source = (
        "MODEL: PROSPECT-D (Feret et al. 2017, doi:10.1016/j.rse.2017.03.004) via prosail, "
        f"N={p['structure']:g}, Cab={p['chlorophyll']:g} ug cm-2, Car={p['carotenoids']:g} ug cm-2, "
        f"Cant={p['anthocyanins']:g} ug cm-2, Cbrown={p['brown_pigments']:g}, Cw={p['water']:g} g cm-2, "
        f"Cm={p['dry_matter']:g} g cm-2, 0.4-2.5 µm sampled every {vswir_step:g} µm; 3-20 µm: "
        f"leaf emissivity {eps:g}, flat (default: the mid-point of the 0.95-0.99 MEASURED in "
        "8-14 µm by Ribeiro da Luz & Crowley 2007, doi:10.1016/j.rse.2007.01.008), opaque; "
        "linear 2.5-3.0 µm"
    )
    return Material.create(
        name,
        reflectance=Spectrum.from_table(wl, rho, name=f"{name}.reflectance", source=source),
        transmittance=Spectrum.from_table(wl, tau, name=f"{name}.transmittance", source=source),
        source=source,
        description="single green leaf (PROSPECT-D)",
        category="vegetation",
    )


def canopy_material(
    name: str = "canopy",
    *,
    leaf: LeafOptics | None = None,
    lai: float = 3.0,
    leaf_angle=57.0,
    hotspot: float = 0.01,
    soil=0.2,
    leaf_emissivity: float = DEFAULT_LEAF_EMISSIVITY,
    vswir_step: float = 0.01,
    **prospect,
):
    """A vegetation canopy over soil as an opaque Lambertian :class:`~radscene.materials.Material`.

    The material's reflectance is the canopy's bi-hemispherical reflectance (white-sky albedo)
    from 4SAIL on 0.4-2.5 um, and 1 − hemispherical canopy emissivity (:func:`canopy_emissivity`)
    on 3-20 um; linear in between.

    Parameters
    ----------
    name : str
    leaf : LeafOptics, optional
        Otherwise ``**prospect`` goes to :func:`leaf_optics`.
    lai, leaf_angle, hotspot : see :func:`canopy_reflectance`.
    soil : Material, float, Spectrum or mapping
        Background: a Material gives both its VSWIR reflectance and its thermal emissivity; a
        number or spectrum must cover 0.4-20 um (it is the soil reflectance everywhere).
    leaf_emissivity : float
        [-], 3-20 um.
    vswir_step : float
        Sampling of the 4SAIL output [um].

    Returns
    -------
    Material
    """
    from radscene.materials.material import Material
    from radscene.materials.spectrum import Spectrum

    leaf = leaf if leaf is not None else leaf_optics(**prospect)
    canopy = canopy_reflectance(leaf, lai=lai, leaf_angle=leaf_angle, hotspot=hotspot, soil=soil)
    soil_thermal = soil if isinstance(soil, Material) else {
        "wavelength": THERMAL_GRID.tolist(),
        "values": (1.0 - _soil_values(soil, THERMAL_GRID, "soil", thermal=True)).tolist(),
    }
    emis = canopy_emissivity(
        THERMAL_GRID, lai=lai, leaf_angle=leaf_angle, hotspot=hotspot,
        leaf_emissivity=leaf_emissivity, soil_emissivity=soil_thermal,
    )
    grid = _vswir_grid(vswir_step)
    wl = np.concatenate([grid, THERMAL_GRID])
    rho = np.concatenate([_sample(grid, canopy.wavelength, canopy.bihemispherical),
                          1.0 - emis.hemispherical])
    p = canopy.parameters
    soil_name = soil.name if isinstance(soil, Material) else repr(soil)
    source = (
        "MODEL: 4SAIL (Verhoef et al. 2007, doi:10.1109/TGRS.2007.895844) bi-hemispherical "
        "reflectance of a PROSPECT-D leaf canopy (Feret et al. 2017) via prosail: "
        f"LAI={p['lai']:g}, leaf angle={p['leaf_angle']}, hotspot={p['hotspot']:g}, "
        f"N={p['structure']:g}, Cab={p['chlorophyll']:g} ug cm-2, Car={p['carotenoids']:g} ug cm-2, "
        f"Cw={p['water']:g} g cm-2, Cm={p['dry_matter']:g} g cm-2, Cbrown={p['brown_pigments']:g}, "
        f"soil {soil_name}; 0.4-2.5 µm sampled every {vswir_step:g} µm. 3-20 µm: 1 - hemispherical "
        f"emissivity of the same canopy by thermal 4SAIL with leaf emissivity "
        f"{leaf_emissivity:g}, flat (default: the mid-point of the 0.95-0.99 MEASURED in 8-14 µm "
        "by Ribeiro da Luz & Crowley 2007, doi:10.1016/j.rse.2007.01.008) and the soil's "
        "emissivity; linear 2.5-3.0 µm"
    )
    return Material.create(
        name,
        reflectance=Spectrum.from_table(wl, rho, name=f"{name}.reflectance", source=source),
        source=source,
        description=f"vegetation canopy, LAI {p['lai']:g}, over {soil_name}",
        category="vegetation",
    )
