"""The ``Atmosphere`` interface that every engine implements.

An atmosphere answers three vectorised queries, each spectral over a wavelength array [um]
that is always the last axis of the result:

``path``
    The line of sight between an observer and a target: transmittance τ_a and path radiance
    (thermal emission and scattered sunlight) [W m-2 sr-1 um-1].
``sun``
    The sun-to-target path: transmittance τ_so and the direct solar irradiance on a surface
    normal to the beam at the target [W m-2 um-1].
``sky``
    The radiance of the sky seen from a target in given directions, scattered and emitted
    [W m-2 sr-1 um-1]; ``sky_parts`` the same split into the downwelled scattered sunlight
    and the downwelled emission of the air (seed 001 eq. 1's E_ds/π and E_de/π).

Speed comes from separating the spectrum from space (ARCHITECTURE.md): the renderer integrates
spectra over each band once per *node* and only interpolates between nodes per pixel. An engine
therefore also tells the renderer its nodes:

* ``path_nodes`` maps each pixel's line-of-sight geometry to a few node geometries and weights;
  an engine whose path does not depend on geometry returns a single node. An engine whose
  scattered path radiance depends on the line of sight's azimuth relative to the sun (the
  sun is up) adds a relative-azimuth axis (:mod:`radscene.atmosphere.nodes`) that only the
  path radiance is mixed on: transmittances do not depend on it;
* ``sky_zenith_nodes`` are the sky zenith angles [deg] at which the sky radiance is tabulated;
  between them the renderer interpolates linearly in zenith (a single node means an isotropic
  sky).
"""

from __future__ import annotations

import abc
from dataclasses import dataclass

import numpy as np

__all__ = [
    "Atmosphere",
    "SunDependentAtmosphere",
    "PathSpectra",
    "SunSpectra",
    "CouplingSpectra",
    "PathNodes",
    "SkyGeometry",
    "SkyParts",
    "SKY_CROSSOVER_WAVELENGTH",
    "zenith_hat_weights",
    "azimuth_hat_weights",
    "sky_node_weights",
]


@dataclass(frozen=True)
class PathSpectra:
    """Spectra of a line of sight; every array has wavelength on its last axis.

    Attributes
    ----------
    transmittance : numpy.ndarray
        Target-to-observer transmittance τ_a [-].
    thermal_radiance : numpy.ndarray
        Path radiance emitted by the atmosphere [W m-2 sr-1 um-1].
    scattered_radiance : numpy.ndarray
        Path radiance of sunlight scattered into the line of sight [W m-2 sr-1 um-1].
    """

    transmittance: np.ndarray
    thermal_radiance: np.ndarray
    scattered_radiance: np.ndarray

    @property
    def radiance(self) -> np.ndarray:
        """Total path radiance, thermal plus scattered [W m-2 sr-1 um-1]."""
        return self.thermal_radiance + self.scattered_radiance


@dataclass(frozen=True)
class SunSpectra:
    """Spectra of the sun-to-target path (wavelength on the last axis).

    Attributes
    ----------
    transmittance : numpy.ndarray
        Sun-to-target transmittance τ_so [-].
    irradiance : numpy.ndarray
        Direct solar irradiance at the target on a surface normal to the beam,
        τ_so times the top-of-atmosphere irradiance [W m-2 um-1].
    """

    transmittance: np.ndarray
    irradiance: np.ndarray


@dataclass(frozen=True)
class CouplingSpectra:
    """What couples the surface to the atmosphere beyond the direct beams (wavelength last).

    With them the radiance of a Lambertian surface of reflectance ρ amid surroundings of
    reflectance ρ_e is (6S's formulation, Vermote et al. 1997)::

        L = L_path + (E_dir + E_dif) / π / (1 - S ρ_e) · (ρ τ_a + ρ_e t_d)

    Attributes
    ----------
    diffuse_transmittance : numpy.ndarray
        Diffuse (scattered) target-to-observer transmittance t_d, gaseous absorption
        included [-]: the share of the radiance leaving the surroundings that reaches the
        observer along the line of sight.
    rayleigh_share : numpy.ndarray
        Share of t_d scattered by molecules (the rest by aerosol) [-]; it weights the two
        environment functions of the atmospheric point-spread function.
    spherical_albedo : numpy.ndarray
        Spherical albedo S of the atmosphere above the target [-].
    direct_irradiance, diffuse_irradiance : numpy.ndarray
        Direct and diffuse solar irradiance on a horizontal surface at the target over black
        ground [W m-2 um-1].
    """

    diffuse_transmittance: np.ndarray
    rayleigh_share: np.ndarray
    spherical_albedo: np.ndarray
    direct_irradiance: np.ndarray
    diffuse_irradiance: np.ndarray


@dataclass(frozen=True)
class PathNodes:
    """Line-of-sight geometries at which an engine evaluates its spectra, and how pixels mix them.

    Attributes
    ----------
    observer_altitude, target_altitude : numpy.ndarray
        Node geometry, shape (n_nodes,) [m].
    view_zenith : numpy.ndarray
        Zenith angle of the direction from target to observer at each node, shape (n_nodes,)
        [deg].
    index : numpy.ndarray
        Shape (n_pixels, k) int: the nodes each pixel mixes.
    weight : numpy.ndarray
        Shape (n_pixels, k): their weights, summing to 1 per pixel [-].
    relative_azimuth : numpy.ndarray or None
        The path radiance's second axis: azimuths of the line of sight (target → observer)
        relative to the sun's, folded into [0, 180], shape (n_azimuth,) [deg]; the path
        radiance of node ``j`` at azimuth node ``a`` is the engine's ``path`` at node ``j``'s
        geometry with ``view_azimuth = sun_azimuth + relative_azimuth[a]``. None: the path
        does not depend on the azimuth (or the engine's own ``view_azimuth`` stands).
    azimuth_index, azimuth_weight : numpy.ndarray or None
        Shape (n_pixels, 2) (or (n_pixels, 1)): the azimuth nodes each pixel mixes and their
        weights, summing to 1 per pixel [-]; the pixel's path radiance is
        Σ_a Σ_s azimuth_weight[a] · weight[s] · L[azimuth_index[a], index[s]].
    """

    observer_altitude: np.ndarray
    target_altitude: np.ndarray
    view_zenith: np.ndarray
    index: np.ndarray
    weight: np.ndarray
    relative_azimuth: np.ndarray | None = None
    azimuth_index: np.ndarray | None = None
    azimuth_weight: np.ndarray | None = None

    @property
    def size(self) -> int:
        """Number of nodes (of the geometry, without the azimuth axis)."""
        return int(np.size(self.view_zenith))

    @property
    def azimuth_size(self) -> int:
        """Number of relative-azimuth nodes (1 without the axis)."""
        return 1 if self.relative_azimuth is None else int(np.size(self.relative_azimuth))

    def azimuth_mixing(self) -> tuple[np.ndarray, np.ndarray]:
        """(index, weight) of each pixel on the azimuth nodes, shape (n_pixels, 1 or 2):
        without the axis, every pixel on the one implicit node."""
        if self.relative_azimuth is None:
            n = len(self.index)
            return np.zeros((n, 1), dtype=np.int64), np.ones((n, 1))
        return self.azimuth_index, self.azimuth_weight

    def subset(self, rows) -> PathNodes:
        """The same nodes with the mixing rows of the pixels ``rows`` only."""
        from dataclasses import replace

        if self.relative_azimuth is None:
            return replace(self, index=self.index[rows], weight=self.weight[rows])
        return replace(self, index=self.index[rows], weight=self.weight[rows],
                       azimuth_index=self.azimuth_index[rows],
                       azimuth_weight=self.azimuth_weight[rows])

    def with_azimuth(self, relative_azimuth, view_zenith) -> PathNodes:
        """These nodes with a relative-azimuth axis covering the pixels' ``relative_azimuth``
        [deg] (see :func:`radscene.atmosphere.nodes.relative_azimuth_axis`)."""
        from dataclasses import replace

        from radscene.atmosphere.nodes import relative_azimuth_axis

        az = np.ravel(np.asarray(relative_azimuth, dtype=float))
        if az.size != len(self.index):
            raise ValueError(f"relative_azimuth: one per pixel ({len(self.index)}); got "
                             f"{az.size}")
        nodes, index, weight = relative_azimuth_axis(az, view_zenith)
        return replace(self, relative_azimuth=nodes, azimuth_index=index,
                       azimuth_weight=weight)


@dataclass(frozen=True)
class SkyGeometry:
    """Where the sky is seen from and where the sun stands.

    Attributes
    ----------
    target_altitude : float
        Altitude of the surface that sees the sky [m].
    sun_zenith, sun_azimuth : float
        Sun position [deg].
    """

    target_altitude: float = 0.0
    sun_zenith: float = 0.0
    sun_azimuth: float = 0.0


#: Where an engine cannot tell its sky's scattered sunlight from its emission
#: (:meth:`Atmosphere.sky_parts`), the sky below this wavelength counts as scattered sunlight
#: and the sky at and beyond it as emission [um]: about where the two cross in a clear
#: daytime sky (the downwelled scattered sunlight falls with the solar spectrum, the emission
#: of the air at 250–300 K rises with Planck's law; near 4 µm both are a few hundredths of a
#: W m-2 sr-1 um-1 in the 3.5–4.1 µm window).
SKY_CROSSOVER_WAVELENGTH = 4.0


@dataclass(frozen=True)
class SkyParts:
    """The sky's radiance split by origin (wavelength on the last axis); ``solar + thermal``
    is :meth:`Atmosphere.sky`.

    Attributes
    ----------
    solar : numpy.ndarray
        Downwelled sunlight scattered by the air and aerosol (and the ground–air exchange of
        it) [W m-2 sr-1 um-1].
    thermal : numpy.ndarray
        Downwelled emission of the air [W m-2 sr-1 um-1].
    """

    solar: np.ndarray
    thermal: np.ndarray


class Atmosphere(abc.ABC):
    """Base class of atmosphere engines.

    Subclasses set ``name`` and ``wavelength_range`` and implement ``path``, ``sun`` and
    ``sky``; they may override ``path_nodes`` and ``sky_zenith_nodes``.
    """

    #: Registry name of the engine (the ``type`` in a scene file).
    name: str = ""
    #: Wavelength range the engine covers [um].
    wavelength_range: tuple[float, float] = (0.0, np.inf)
    #: Whether path spectra depend on the line-of-sight geometry.
    geometry_dependent: bool = False

    # -- queries -------------------------------------------------------------------------
    @abc.abstractmethod
    def path(self, observer_altitude, target_altitude, view_zenith, wavelength,
             view_azimuth=None) -> PathSpectra:
        """Line-of-sight spectra, broadcast over the geometry arrays.

        Parameters
        ----------
        observer_altitude, target_altitude : array_like
            Altitudes above sea level [m].
        view_zenith : array_like
            Zenith angle of the direction from target to observer [deg].
        wavelength : array_like
            Wavelengths, 1-D [um].
        view_azimuth : float, optional
            Azimuth of the direction from target to observer [deg, clockwise from north],
            for this call; None: the engine's own (set with :meth:`with_sun`, or the
            azimuthal mean). Engines whose path does not depend on it ignore it.

        Returns
        -------
        PathSpectra
            Arrays of shape ``geometry_shape + (n_wavelength,)``.
        """

    @abc.abstractmethod
    def sun(self, target_altitude, sun_zenith, wavelength, toa_irradiance) -> SunSpectra:
        """Sun-to-target spectra.

        Parameters
        ----------
        target_altitude : array_like
            Altitude of the target [m].
        sun_zenith : array_like
            Solar zenith angle at the target [deg].
        wavelength : array_like
            Wavelengths, 1-D [um].
        toa_irradiance : array_like
            Top-of-atmosphere solar irradiance normal to the beam at ``wavelength``
            [W m-2 um-1], already scaled to the day's Earth–Sun distance.

        Returns
        -------
        SunSpectra
        """

    @abc.abstractmethod
    def sky(self, zenith, azimuth, wavelength, geometry: SkyGeometry) -> np.ndarray:
        """Sky radiance seen from the target looking towards (zenith, azimuth).

        Parameters
        ----------
        zenith, azimuth : array_like
            Direction of view from the target towards the sky [deg].
        wavelength : array_like
            Wavelengths, 1-D [um].
        geometry : SkyGeometry
            Target altitude and sun position.

        Returns
        -------
        numpy.ndarray
            Radiance, shape ``broadcast(zenith, azimuth).shape + (n_wavelength,)``
            [W m-2 sr-1 um-1].
        """

    def sky_parts(self, zenith, azimuth, wavelength, geometry: SkyGeometry) -> SkyParts:
        """:meth:`sky` split into scattered sunlight and emission (:class:`SkyParts`).

        Parameters are those of :meth:`sky`. Engines that compute the two apart return them
        (their sum is :meth:`sky`); this default, for an engine that cannot, counts its sky
        below :data:`SKY_CROSSOVER_WAVELENGTH` as scattered sunlight and the rest as
        emission.
        """
        total = self.sky(zenith, azimuth, wavelength, geometry)
        emitted = np.asarray(wavelength, dtype=float) >= SKY_CROSSOVER_WAVELENGTH
        return SkyParts(solar=np.where(emitted, 0.0, total), thermal=np.where(emitted, total, 0.0))

    #: Whether :meth:`coupling` gives the diffuse transmittance and spherical albedo.
    couples: bool = False

    def coupling(self, observer_altitude, target_altitude, view_zenith, wavelength
                 ) -> CouplingSpectra:
        """Surface–atmosphere coupling of lines of sight (see :class:`CouplingSpectra`).

        Broadcast over the geometry arrays like :meth:`path`. The default, for engines that
        do not scatter (or cannot say), is no coupling: every array zero.
        """
        wl = self.check_wavelength(wavelength)
        shape = np.broadcast(np.asarray(observer_altitude), np.asarray(target_altitude),
                             np.asarray(view_zenith)).shape + wl.shape
        zero = np.zeros(shape)
        return CouplingSpectra(zero, zero, zero, zero, zero)

    def with_sun(self, sun_zenith, sun_azimuth, day_of_year=None, view_azimuth=None,
                 earth_sun_distance=None):
        """This engine set up for a sun position and a line-of-sight azimuth [deg].

        Engines whose spectra depend on the sun (scattered path radiance, sky) return a
        configured copy; the default, for engines that do not, returns the engine itself.
        ``earth_sun_distance`` [AU], when given, scales their solar spectrum to the day's.
        """
        return self

    # -- nodes for the spectral-spatial separation ------------------------------------------
    @property
    def azimuth_dependent(self) -> bool:
        """Whether the path radiance depends on the line of sight's azimuth relative to the
        sun (scattered sunlight: the engine scatters and its sun is up)."""
        return False

    def path_nodes(self, observer_altitude, target_altitude, view_zenith,
                   relative_azimuth=None) -> PathNodes:
        """Nodes at which path spectra are evaluated, and each pixel's weights on them.

        The default, for engines whose path does not depend on geometry, is one node at the
        mean geometry.

        Parameters
        ----------
        observer_altitude, target_altitude : array_like
            Altitudes of each pixel's observer and target [m], shape (N,).
        view_zenith : array_like
            Zenith of the direction from target to observer [deg], shape (N,).
        relative_azimuth : array_like, optional
            Azimuth of that direction minus the sun's [deg], shape (N,). Where given and
            :attr:`azimuth_dependent`, the nodes get a relative-azimuth axis
            (:meth:`PathNodes.with_azimuth`).

        Returns
        -------
        PathNodes
        """
        n = np.size(view_zenith)
        nodes = PathNodes(
            observer_altitude=np.atleast_1d(np.mean(observer_altitude) if n else 0.0),
            target_altitude=np.atleast_1d(np.mean(target_altitude) if n else 0.0),
            view_zenith=np.atleast_1d(np.mean(view_zenith) if n else 0.0),
            index=np.zeros((n, 1), dtype=np.int64),
            weight=np.ones((n, 1)),
        )
        return self.azimuth_axis(nodes, view_zenith, relative_azimuth)

    def azimuth_axis(self, nodes: PathNodes, view_zenith, relative_azimuth) -> PathNodes:
        """``nodes`` with the relative-azimuth axis where it matters: the engine is
        :attr:`azimuth_dependent` and the pixels' ``relative_azimuth`` [deg] is given."""
        if relative_azimuth is None or not self.azimuth_dependent:
            return nodes
        return nodes.with_azimuth(relative_azimuth, view_zenith)

    def sky_zenith_nodes(self) -> np.ndarray:
        """Sky zenith angles [deg] at which the sky radiance is tabulated (one: isotropic)."""
        return np.array([0.0])

    def sky_azimuth_nodes(self) -> np.ndarray:
        """Sky azimuths [deg, clockwise from north] of the table (one: no azimuth dependence).

        The renderer evaluates :meth:`sky` on the grid of zenith × azimuth nodes and
        interpolates linearly between them (periodically in azimuth).
        """
        return np.array([0.0])

    # -- helpers ---------------------------------------------------------------------------
    def check_wavelength(self, wavelength, key: str = "wavelength") -> np.ndarray:
        """Return ``wavelength`` as a float array, or raise if outside the engine's range."""
        from radscene.errors import ConfigError

        wl = np.asarray(wavelength, dtype=float)
        lo, hi = self.wavelength_range
        if wl.size and (np.nanmin(wl) < lo or np.nanmax(wl) > hi):
            raise ConfigError(
                f"the {self.name!r} atmosphere covers {lo:g}–{hi:g} µm; asked for "
                f"{np.nanmin(wl):g}–{np.nanmax(wl):g} µm",
                key=key,
            )
        return wl


class SunDependentAtmosphere(Atmosphere):
    """Base of engines whose path radiance and sky depend on the sun's position.

    They keep the sun (``sun_zenith`` None until it is set, ``sun_azimuth``) and the line of
    sight's azimuth (``view_azimuth``, None: the azimuthal mean), and the renderer sets them up
    with :meth:`with_sun`, which copies the engine and shares its tables, runs and caches.
    """

    sun_zenith: float | None = None
    sun_azimuth: float = 0.0
    view_azimuth: float | None = None

    @property
    def azimuth_dependent(self) -> bool:
        """True while the sun is up: the scattered path radiance depends on the azimuth."""
        return self.sun_zenith is not None and self.sun_zenith < 90.0

    def _set_geometry(self, surface_albedo, earth_sun_distance, sun_zenith, sun_azimuth,
                      view_azimuth) -> None:
        """Check and keep the settings every such engine takes: albedo, distance, sun, view."""
        from radscene.errors import ConfigError

        albedo = float(surface_albedo)
        if not 0.0 <= albedo <= 1.0:
            raise ConfigError(f"must lie in [0, 1]; got {surface_albedo!r}",
                              key="atmosphere.surface_albedo")
        self.surface_albedo = albedo
        d = float(earth_sun_distance)
        if not d > 0:
            raise ConfigError("must be > 0 AU", key="atmosphere.earth_sun_distance")
        self.earth_sun_distance = d
        self.view_azimuth = None if view_azimuth is None else float(view_azimuth)
        self.sun_zenith = None
        self.sun_azimuth = 0.0
        if sun_zenith is not None:
            self.set_sun(sun_zenith, sun_azimuth)

    def set_sun(self, sun_zenith, sun_azimuth=0.0) -> None:
        """Set the sun position [deg] used by :meth:`path`."""
        from radscene.errors import ConfigError

        z, a = float(sun_zenith), float(sun_azimuth)
        if not 0.0 <= z <= 180.0:
            raise ConfigError("must lie in [0, 180] deg", key="atmosphere.sun_zenith")
        if not np.isfinite(a):
            raise ConfigError("must be finite", key="atmosphere.sun_azimuth")
        self.sun_zenith, self.sun_azimuth = z, a % 360.0

    def with_sun(self, sun_zenith, sun_azimuth, day_of_year=None, view_azimuth=None,
                 earth_sun_distance=None):
        """A copy with the sun (and the line of sight's azimuth) set; tables shared.

        ``day_of_year`` is accepted for symmetry with engines that take the Earth–Sun
        distance from the date (``lowtran``); these engines take theirs from
        ``earth_sun_distance`` [AU] when it is given, else keep their own.
        """
        import copy

        from radscene.errors import ConfigError

        new = copy.copy(self)
        new.set_sun(sun_zenith, sun_azimuth)
        if earth_sun_distance is not None:
            d = float(earth_sun_distance)
            if not d > 0:
                raise ConfigError("must be > 0 AU", key="atmosphere.earth_sun_distance")
            new.earth_sun_distance = d
        if view_azimuth is not None:
            new.view_azimuth = float(view_azimuth)
        return new


def zenith_hat_weights(zenith, nodes) -> np.ndarray:
    """Linear-interpolation ("hat") weights of zenith angles on a node grid.

    Parameters
    ----------
    zenith : array_like
        Zenith angles [deg], any shape.
    nodes : array_like
        Increasing node zenith angles [deg], shape (k,). A single node gives weight 1.

    Returns
    -------
    numpy.ndarray
        Shape ``zenith.shape + (k,)``; rows sum to 1; outside the node range the end node
        takes the whole weight (the table's stated rule: constant beyond its ends).
    """
    z = np.asarray(zenith, dtype=float)
    nodes = np.asarray(nodes, dtype=float)
    k = nodes.size
    out = np.zeros(z.shape + (k,))
    if k == 1:
        out[...] = 1.0
        return out
    zc = np.clip(z, nodes[0], nodes[-1])
    i = np.clip(np.searchsorted(nodes, zc, side="right") - 1, 0, k - 2)
    frac = (zc - nodes[i]) / (nodes[i + 1] - nodes[i])
    np.put_along_axis(out, i[..., None], (1.0 - frac)[..., None], axis=-1)
    lower = np.take_along_axis(out, (i + 1)[..., None], axis=-1)
    np.put_along_axis(out, (i + 1)[..., None], lower + frac[..., None], axis=-1)
    return out


def azimuth_hat_weights(azimuth, nodes) -> np.ndarray:
    """Periodic linear-interpolation weights of azimuths on a node grid.

    Parameters
    ----------
    azimuth : array_like
        Azimuths [deg], any shape.
    nodes : array_like
        Increasing node azimuths in [0, 360) [deg], shape (l,). A single node gives weight 1.

    Returns
    -------
    numpy.ndarray
        Shape ``azimuth.shape + (l,)``; rows sum to 1; the last node wraps to the first.
    """
    a = np.asarray(azimuth, dtype=float) % 360.0
    nodes = np.asarray(nodes, dtype=float)
    n = nodes.size
    out = np.zeros(a.shape + (n,))
    if n == 1:
        out[...] = 1.0
        return out
    ext = np.concatenate([nodes, [nodes[0] + 360.0]])
    shifted = np.where(a < nodes[0], a + 360.0, a)
    i = np.clip(np.searchsorted(ext, shifted, side="right") - 1, 0, n - 1)
    frac = (shifted - ext[i]) / (ext[i + 1] - ext[i])
    j = (i + 1) % n
    np.put_along_axis(out, i[..., None], (1.0 - frac)[..., None], axis=-1)
    upper = np.take_along_axis(out, j[..., None], axis=-1)
    np.put_along_axis(out, j[..., None], upper + frac[..., None], axis=-1)
    return out


def sky_node_weights(zenith, azimuth, zenith_nodes, azimuth_nodes) -> np.ndarray:
    """Bilinear weights of directions on the zenith × azimuth sky grid.

    Returns
    -------
    numpy.ndarray
        Shape ``broadcast(zenith, azimuth).shape + (k * l,)``, node (i, j) at index
        ``i * l + j`` (zenith major), rows summing to 1.
    """
    z, a = np.broadcast_arrays(np.asarray(zenith, float), np.asarray(azimuth, float))
    wz = zenith_hat_weights(z, zenith_nodes)
    wa = azimuth_hat_weights(a, azimuth_nodes)
    return (wz[..., :, None] * wa[..., None, :]).reshape(z.shape + (-1,))
