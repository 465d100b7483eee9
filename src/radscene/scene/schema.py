"""The scene file schema (pydantic).

A scene file is YAML; this module says what it may hold. Quantities take unit strings
(``"300 K"``, ``"25 degC"``, ``"10 um"``, ``"500 m"``, ``"30 deg"``) or bare numbers in the
canonical unit (K, um, m, deg). Swappable parts are type-tagged (``{type: box, ...}``).
Nothing is computed here: :mod:`radscene.scene.load` validates with these models, then
resolves materials, files and meshes.
"""

from __future__ import annotations

import datetime as _dt
import math
from typing import Annotated, Any, Literal

from pydantic import BaseModel, BeforeValidator, ConfigDict, Field, field_validator, model_validator

from radscene.radiometry.units import parse_quantity

__all__ = ["SceneSpec"]


def _quantity(kind: str, minimum: float | None = None, exclusive: bool = False):
    def parse(value: Any) -> float:
        if isinstance(value, bool):
            raise ValueError(f"expected a {kind}, got {value!r}")
        number = float(parse_quantity(value, kind))
        if minimum is not None and (number <= minimum if exclusive else number < minimum):
            op = ">" if exclusive else ">="
            raise ValueError(f"must be {op} {minimum:g} (canonical unit), got {value!r}")
        return number

    # read by the scene-file reference and the JSON schema (radscene.scene.reference)
    parse.quantity_kind, parse.quantity_minimum, parse.quantity_exclusive = kind, minimum, exclusive
    return BeforeValidator(parse)


Temperature = Annotated[float, _quantity("temperature", 0.0, exclusive=True)]
Length = Annotated[float, _quantity("length")]
PositiveLength = Annotated[float, _quantity("length", 0.0, exclusive=True)]
Angle = Annotated[float, _quantity("angle")]
Wavelength = Annotated[float, _quantity("wavelength", 0.0, exclusive=True)]
Duration = Annotated[float, _quantity("time", 0.0, exclusive=True)]
Speed = Annotated[float, _quantity("speed", 0.0)]
Pressure = Annotated[float, _quantity("pressure", 0.0, exclusive=True)]
Fraction = Annotated[float, _quantity("dimensionless"), Field(ge=0.0, le=1.0)]
Irradiance = Annotated[float, _quantity("irradiance")]
Power = Annotated[float, _quantity("power")]


class _Model(BaseModel):
    model_config = ConfigDict(extra="forbid", frozen=True)


# ---------------------------------------------------------------------------------------------
# environment


class Location(_Model):
    """A place on the Earth: WGS84 latitude and longitude [deg], altitude of the scene origin [m]."""

    latitude: Annotated[float, Field(ge=-90, le=90, description="WGS84 latitude of the scene origin [deg], north positive")]
    longitude: Annotated[float, Field(ge=-180, le=360, description="WGS84 longitude of the scene origin [deg], east positive")]
    altitude: Length = Field(0.0, description="altitude of the scene origin (z = 0) above sea level [m]")


class SunOverride(_Model):
    """A sun placed by hand instead of by ephemeris."""

    zenith: Annotated[Angle, Field(ge=0, le=180, description="solar zenith angle at the scene [deg]")]
    azimuth: Angle = Field(180.0, description="solar azimuth, clockwise from north [deg]")
    distance: Annotated[float, Field(gt=0.9, lt=1.1, description="Earth–Sun distance [AU]")] = 1.0


class Environment(_Model):
    location: Location = Field(Location(latitude=0.0, longitude=0.0), description="where the scene origin is on the Earth")
    time: _dt.datetime | None = Field(None, description="the instant of the scene, with its UTC offset; the sun follows from it and the place")
    sun: SunOverride | None = Field(None, description="a sun placed by hand instead of by ephemeris")
    atmosphere: dict[str, Any] = Field(default_factory=lambda: {"type": "none"}, description="the atmosphere engine: {type: none|uniform|database|sixs|lowtran, ...}")

    @field_validator("time")
    @classmethod
    def _aware(cls, value):
        if value is not None and value.tzinfo is None:
            raise ValueError(
                "a time with a UTC offset, e.g. '2026-06-21T10:30:00+02:00' or '...Z'"
            )
        return value

    @model_validator(mode="after")
    def _sun_or_time(self):
        if self.time is None and self.sun is None:
            raise ValueError("give 'time' (the sun follows from place and time) or 'sun'")
        return self


# ---------------------------------------------------------------------------------------------
# materials and textures




class ImageTextureSpec(_Model):
    """A multiplier image (Δρ, Δε or Δτ) laid on a ``size`` rectangle of the ground plane, tiled
    beyond it. The default type: a texture without ``type`` is an image."""

    type: Literal["image"] = "image"
    file: str
    size: tuple[PositiveLength, PositiveLength]
    origin: tuple[Length, Length] = (0.0, 0.0)
    contrast: Annotated[float, Field(ge=0)] | None = None


class TileTextureSpec(_Model):
    """A small multiplier pattern repeated over the whole ground plane at a stated scale: each
    texel covers ``texel_size`` (e.g. ``"2 m"``), or the whole pattern ``tile_size``."""

    type: Literal["tile"]
    values: list[list[Annotated[float, Field(ge=0)]]] | None = None
    file: str | None = None
    texel_size: PositiveLength | tuple[PositiveLength, PositiveLength] | None = None
    tile_size: tuple[PositiveLength, PositiveLength] | None = None
    origin: tuple[Length, Length] = (0.0, 0.0)

    @model_validator(mode="after")
    def _one_each(self):
        if (self.values is None) == (self.file is None):
            raise ValueError("give exactly one of 'values' (a 2-D list) or 'file'")
        if (self.texel_size is None) == (self.tile_size is None):
            raise ValueError("give exactly one of 'texel_size' [m] or 'tile_size' [m, m]")
        return self


class NoiseTextureSpec(_Model):
    """Procedural fractal-noise multiplier ``1 + amplitude * noise`` (terrain detail)."""

    type: Literal["noise"]
    amplitude: Annotated[float, Field(ge=0, le=1)]
    scale: PositiveLength
    octaves: Annotated[int, Field(ge=1, le=16)] = 4
    persistence: Annotated[float, Field(gt=0, le=1)] = 0.5
    lacunarity: Annotated[float, Field(gt=1)] = 2.0
    seed: Annotated[int, Field(ge=0)] = 0


def _image_by_default(value: Any) -> Any:
    if isinstance(value, dict) and "type" not in value:
        return {**value, "type": "image"}
    return value


TextureSpec = Annotated[
    ImageTextureSpec | TileTextureSpec | NoiseTextureSpec,
    Field(discriminator="type"),
    BeforeValidator(_image_by_default),
]


class TextureSet(_Model):
    reflectance: TextureSpec | None = None
    emissivity: TextureSpec | None = None
    transmittance: TextureSpec | None = None


# ---------------------------------------------------------------------------------------------
# terrain


class Lake(_Model):
    x: Length
    y: Length
    radius: PositiveLength
    depth: PositiveLength = 3.0


class MaterialMapFile(_Model):
    """A classified image over the terrain extent: pixel value → a material name, or the
    fractions of several materials in that class, ``{grass: 0.6, bare_soil: 0.4}`` (sub-pixel
    areal mixture: the spectra are mixed linearly)."""

    type: Literal["file"] = "file"
    file: str
    classes: dict[int, str | dict[str, float]]

    @field_validator("classes")
    @classmethod
    def _fractions(cls, value):
        for cls_value, entry in value.items():
            if isinstance(entry, str):
                continue
            if not entry:
                raise ValueError(f"class {cls_value}: give at least one material and its fraction")
            bad = {m: f for m, f in entry.items() if not 0.0 <= f <= 1.0}
            if bad:
                raise ValueError(f"class {cls_value}: fractions must lie in [0, 1]; got {bad}")
            total = sum(entry.values())
            if abs(total - 1.0) > 1e-6:
                raise ValueError(
                    f"class {cls_value}: the fractions of {sorted(entry)} sum to {total:g}, not 1"
                )
        return value


class MaterialMapNoise(_Model):
    """Smooth random patches of the listed materials (procedural land cover)."""

    type: Literal["noise"] = "noise"
    materials: list[str] = Field(min_length=1)
    scale: PositiveLength = 100.0
    seed: int = 0


class _TerrainCommon(_Model):
    origin: tuple[Length, Length] = (0.0, 0.0)
    material: str = "dry_grass"
    material_map: Annotated[MaterialMapFile | MaterialMapNoise, Field(discriminator="type")] | None = None
    water_material: str = "water"
    temperature: Temperature | None = Field(
        None, description="a fixed surface temperature [K]; default: solved by the heat balance "
        "(293.15 K with thermal off)")
    temperatures: dict[str, Temperature] = Field(default_factory=dict)
    temperature_map: str | None = Field(
        None, description="image of surface temperature [K] over the terrain extent"
    )
    textures: TextureSet = TextureSet()


class ProceduralTerrain(_TerrainCommon):
    """Fractal hills with optional lakes, generated from a seed."""

    type: Literal["procedural"]
    size: tuple[PositiveLength, PositiveLength] = (1000.0, 1000.0)
    spacing: PositiveLength = 5.0
    relief: Annotated[Length, Field(ge=0)] = 40.0
    seed: int = 0
    lakes: list[Lake] = Field(default_factory=list)


class DemTerrain(_TerrainCommon):
    """A digital elevation model from a GeoTIFF/.npy file or an inline array."""

    type: Literal["dem"]
    file: str | None = None
    elevation: list[list[float]] | None = None
    spacing: tuple[PositiveLength, PositiveLength] | None = None

    @model_validator(mode="after")
    def _one_source(self):
        if (self.file is None) == (self.elevation is None):
            raise ValueError("give exactly one of 'file' or 'elevation'")
        if self.elevation is not None and self.spacing is None:
            raise ValueError("an inline 'elevation' needs 'spacing' [m, m]")
        return self


Terrain = Annotated[ProceduralTerrain | DemTerrain, Field(discriminator="type")]


# ---------------------------------------------------------------------------------------------
# objects


class BoxShape(_Model):
    type: Literal["box"]
    size: tuple[PositiveLength, PositiveLength, PositiveLength]


class CylinderShape(_Model):
    type: Literal["cylinder"]
    radius: PositiveLength
    height: PositiveLength
    sections: Annotated[int, Field(ge=3)] = 32


class PlateShape(_Model):
    type: Literal["plate"]
    width: PositiveLength
    length: PositiveLength


class MeshShape(_Model):
    type: Literal["mesh"]
    file: str
    scale: Annotated[float, Field(gt=0)] = 1.0


Shape = Annotated[BoxShape | CylinderShape | PlateShape | MeshShape, Field(discriminator="type")]


class TrajectorySpec(_Model):
    """How an object moves: exactly one of ``waypoints`` (``[t, x, y, z]`` or ``[t, x, y, z, yaw,
    pitch, roll]``; t [s] from the start of the simulation or sequence), ``route`` (``[x, y]``
    or ``[x, y, z]`` driven at ``speed`` from ``start``) or ``file`` (a tabulated 6-DOF track,
    CSV or NetCDF: ``time [s], x [m], y [m], z [m]`` and optionally ``yaw, pitch, roll [deg]``
    or ``qw, qx, qy, qz``). z is a height above the terrain when the object is on the ground."""

    waypoints: list[list[Any]] | None = Field(
        None, description="[t, x, y, z] or [t, x, y, z, yaw, pitch, roll] rows, t increasing")
    route: list[list[Any]] | None = Field(
        None, description="[x, y] or [x, y, z] points driven at 'speed' (over the map, x and y)")
    speed: Annotated[Speed, Field(gt=0)] | None = Field(None, description="a route's speed, e.g. '36 km/h'")
    start: Annotated[float, _quantity("time")] = Field(0.0, description="when a route begins [s]")
    file: str | None = Field(None, description="a track file (.csv or .nc), see docs/simulation.md")
    interpolation: Literal["linear", "spline"] = Field(
        "linear", description="positions between samples: straight lines, or the C2 cubic spline "
        "through them (not-a-knot ends); attitudes are always slerped")
    attitude: Literal["fixed", "path", "tabulated"] | None = Field(
        None, description="fixed: the object's rotation; path: forward along the velocity (heading "
        "and climb; on the ground pitch and roll from the terrain's slope), rotation on top; "
        "tabulated: the waypoints' or file's attitudes, rotation on top. Default: tabulated when "
        "the samples have attitudes, else fixed")
    on_ground: bool | None = Field(
        None, description="z is a height above the terrain under the object; default the object's on_ground")

    @field_validator("waypoints")
    @classmethod
    def _waypoints(cls, value):
        if value is None:
            return value
        if len(value) < 2:
            raise ValueError(f"give at least two waypoints; got {len(value)}")
        width = len(value[0])
        kinds = ("time", "length", "length", "length", "angle", "angle", "angle")
        rows = []
        for k, row in enumerate(value):
            if len(row) not in (4, 7) or len(row) != width:
                raise ValueError(f"waypoints[{k}]: every waypoint is [t, x, y, z] or every one "
                                 f"[t, x, y, z, yaw, pitch, roll]; got {len(row)} values")
            rows.append([float(parse_quantity(v, kind, key=f"waypoints[{k}][{c}]"))
                         for c, (v, kind) in enumerate(zip(row, kinds, strict=False))])
        return rows

    @field_validator("route")
    @classmethod
    def _route(cls, value):
        if value is None:
            return value
        if len(value) < 2:
            raise ValueError(f"give at least two route points; got {len(value)}")
        rows = []
        for k, row in enumerate(value):
            if len(row) not in (2, 3):
                raise ValueError(f"route[{k}]: [x, y] or [x, y, z]; got {len(row)} values")
            rows.append([float(parse_quantity(v, "length", key=f"route[{k}][{c}]")) for c, v in enumerate(row)]
                        + [0.0] * (3 - len(row)))
        return rows

    @model_validator(mode="after")
    def _one_source(self):
        given = [k for k in ("waypoints", "route", "file") if getattr(self, k) is not None]
        if len(given) != 1:
            raise ValueError("give exactly one of 'waypoints', 'route' (with 'speed') or 'file'"
                             + (f"; got {', '.join(given)}" if given else ""))
        rows = self.waypoints or []
        for k in range(1, len(rows)):
            if not rows[k][0] > rows[k - 1][0]:
                raise ValueError(f"waypoints[{k}]: t = {rows[k][0]:g} s does not follow t = {rows[k - 1][0]:g} s "
                                 "of the waypoint before; times must increase")
        if (self.route is None) != (self.speed is None):
            raise ValueError("'speed' goes with a 'route', and a route needs a 'speed'")
        if "start" in self.model_fields_set and self.route is None:
            raise ValueError("'start' belongs to a 'route' (waypoints and files carry their times)")
        tabulated = self.waypoints is not None and len(self.waypoints[0]) == 7
        if self.attitude == "tabulated" and (self.route is not None or (self.waypoints is not None
                                                                         and not tabulated)):
            raise ValueError("attitude 'tabulated' needs attitudes in the samples: waypoints "
                             "[t, x, y, z, yaw, pitch, roll] or a file with them")
        if tabulated and self.attitude in ("fixed", "path"):
            raise ValueError(f"the waypoints carry attitudes, which attitude {self.attitude!r} would "
                             "ignore; drop them or the attitude")
        return self


class SpinSpec(_Model):
    """A part turning at a constant rate about an axis through its origin (a rotor, a radar)."""

    axis: tuple[float, float, float] = Field(description="in the object's own (model) frame")
    rate: Annotated[float, _quantity("angular_speed")] = Field(
        description="e.g. '300 rpm', '30 deg/s', '2 rad/s'; right-handed about the axis")

    @field_validator("axis")
    @classmethod
    def _nonzero(cls, value):
        if not any(value) or not all(math.isfinite(v) for v in value):
            raise ValueError(f"must be a finite, non-zero vector; got {list(value)}")
        return value


class ObjectSpec(_Model):
    """An object placed in the scene."""

    name: str = Field(description="unique name; the object_id truth map lists it")
    shape: Shape = Field(description="the geometry: a box, cylinder, plate or mesh file")
    position: tuple[Length, Length, Length] = Field(
        (0.0, 0.0, 0.0), description="x east, y north [m] of the shape's base centre, z [m] (see "
        "on_ground); relative to the parent's body frame for a part (parent)")
    on_ground: bool = Field(
        True, description="z of position is height above the terrain at (x, y), not altitude"
    )
    rotation: tuple[Angle, Angle, Angle] = Field(
        (0.0, 0.0, 0.0), description="attitude (yaw, pitch, roll) [deg]: yaw clockwise from north, "
        "then pitch nose up, then roll right side down; relative to the parent for a part, on top "
        "of the path's or track's attitude with trajectory.attitude path or tabulated")
    trajectory: TrajectorySpec | None = Field(None, description="how the object moves in time")
    parent: str | None = Field(None, description="another object that carries this one: position and "
                               "rotation are in its body frame, and the part moves with it")
    spin: SpinSpec | None = Field(None, description="turn at a constant rate about an axis")
    material: str = Field(description="a built-in material (radscene materials list) or a key of `materials`")
    temperature: Temperature | None = Field(
        None, description="a fixed surface temperature [K]; default: solved by the heat balance "
        "(293.15 K with thermal off)")
    textures: TextureSet = Field(TextureSet(), description="multipliers of reflectance, emissivity and transmittance over the surface")
    transmissive: bool = Field(
        False, description="a semi-transparent sheet (camouflage net, foliage layer): rays "
        "and sun rays pass through it with its material's transmittance (times the Δτ texture)")


class EllipsoidShape(_Model):
    type: Literal["ellipsoid"]
    radii: tuple[PositiveLength, PositiveLength, PositiveLength]


class DensityProfile(_Model):
    """How a volume's relative density varies: ``uniform``; ``exponential`` in height above
    the volume's base, e-folding over ``scale_height``; ``gaussian`` about its centre with
    standard deviations ``sigma`` (one, or one per axis) [m]; ``grid``: a 3-D array from
    ``file``, trilinear between its nodes, which span the volume's bounding box."""

    type: Literal["uniform", "exponential", "gaussian", "grid"] = "uniform"
    scale_height: PositiveLength | None = None
    sigma: PositiveLength | tuple[PositiveLength, PositiveLength, PositiveLength] | None = None
    file: str | None = Field(None, description="grid: a .npy array or a NetCDF variable of "
                             "relative density, dims (z, y, x), nodes spanning the volume's box")
    variable: str = Field("density", description="grid: the NetCDF variable")

    @model_validator(mode="after")
    def _parameters(self):
        need = {"exponential": "scale_height", "gaussian": "sigma", "grid": "file"}.get(self.type)
        if need is not None and getattr(self, need) is None:
            raise ValueError(f"a {self.type} profile needs '{need}'")
        for other in ("scale_height", "sigma", "file"):
            if other != need and getattr(self, other) is not None:
                raise ValueError(f"'{other}' does not belong to a {self.type} profile")
        return self


class GasSpec(_Model):
    """A gas plume's composition: mole fractions of CO2 and H2O at a total ``pressure``, at the
    volume's temperature; its absorption and emission in their bands come from a band model
    (``model``: ``edwards``, the exponential wide-band model of Edwards 1976 with the parameters
    tabulated by Modest, Radiative Heat Transfer, 3rd ed. 2013, Table 11.3; 300-2500 K,
    0.1-10 atm; a band model, not line-by-line: meaningful over spectral intervals of
    ~20-200 cm-1). The profile's density scales the amount of gas at the same pressure."""

    model: str = Field("edwards", description="the band model (radscene.materials.gas.GAS_MODELS)")
    co2: Fraction = Field(0.0, description="mole fraction of CO2 [-]")
    h2o: Fraction = Field(0.0, description="mole fraction of H2O [-]")
    pressure: Pressure = Field(101325.0, description="total pressure [Pa]; e.g. '1 atm'")

    @model_validator(mode="before")
    @classmethod
    def _known_gases(cls, data):
        if isinstance(data, dict):
            for key in data:
                if key not in cls.model_fields:
                    raise ValueError(f"unknown gas or key {key!r}; known gases: co2, h2o "
                                     "(mole fractions), and model, pressure")
        return data

    @model_validator(mode="after")
    def _fractions(self):
        if self.co2 + self.h2o > 1.0:
            raise ValueError(f"the mole fractions sum to {self.co2 + self.h2o:g} > 1")
        return self


class VolumeSpec(_Model):
    """A participating volume (smoke, dust, cloud, gas): an axis-aligned box or ellipsoid
    centred at ``position`` (z above the scene origin) filled with a medium of extinction
    coefficient ``extinction`` [m-1] at density 1 (a number or a spectrum), or of vertical
    optical depth ``optical_depth`` through its centre, or a ``gas`` mixture of CO2 and H2O
    absorbing and emitting in their bands at the volume's temperature (a band model; albedo
    0); ``density`` scales the ``profile``."""

    name: str
    shape: Annotated[BoxShape | EllipsoidShape, Field(discriminator="type")]
    position: tuple[Length, Length, Length] = (0.0, 0.0, 0.0)
    density: Annotated[float, Field(ge=0.0)] = 1.0
    profile: DensityProfile = DensityProfile()
    extinction: float | dict[str, Any] | None = None
    optical_depth: float | dict[str, Any] | None = None
    single_scattering_albedo: Fraction = 0.0
    asymmetry: Annotated[float, Field(gt=-1.0, lt=1.0)] = Field(
        0.0, description="Henyey-Greenstein asymmetry parameter of the scattering (0: isotropic)")
    temperature: Temperature
    gas: GasSpec | None = Field(None, description="CO2/H2O mole fractions and pressure: a gas "
                                "plume from a band model instead of extinction")

    @model_validator(mode="after")
    def _one_medium(self):
        given = [k for k in ("extinction", "optical_depth", "gas") if getattr(self, k) is not None]
        if len(given) != 1:
            raise ValueError("give exactly one of 'extinction' [m-1], 'optical_depth' or 'gas'")
        if self.gas is not None and self.single_scattering_albedo != 0.0:
            raise ValueError("a gas absorbs and emits only: remove single_scattering_albedo")
        return self


# ---------------------------------------------------------------------------------------------
# bands and observers


class BandSpec(_Model):
    """A spectral band: a rectangular, Gaussian or tabulated response.

    Shorthands: ``{name, min, max}`` is rectangular, ``{name, center, fwhm}`` Gaussian,
    ``{name, file}`` tabulated, ``{name, sensor, band}`` a bundled real sensor's response
    (``radscene.sensor.srf_library.list_sensors()``).
    """

    name: str
    type: Literal["rectangular", "gaussian", "tabulated", "library"] | None = None
    min: Wavelength | None = None
    max: Wavelength | None = None
    center: Wavelength | None = None
    fwhm: Wavelength | None = None
    file: str | None = None
    sensor: str | None = Field(None, description="a bundled sensor, e.g. landsat8_oli")
    band: str | None = Field(None, description="that sensor's band, e.g. B4")

    @model_validator(mode="after")
    def _complete(self):
        if self.sensor is not None or self.band is not None:
            if self.sensor is None or self.band is None or self.type is not None or any(
                    getattr(self, k) is not None for k in ("min", "max", "center", "fwhm", "file")):
                raise ValueError("a library band takes exactly 'sensor' and 'band' (and 'name')")
            object.__setattr__(self, "type", "library")
            return self
        kind = self.type or (
            "rectangular"
            if self.min is not None or self.max is not None
            else "gaussian"
            if self.center is not None or self.fwhm is not None
            else "tabulated"
            if self.file is not None
            else None
        )
        need = {"rectangular": ("min", "max"), "gaussian": ("center", "fwhm"), "tabulated": ("file",)}
        if kind is None:
            raise ValueError("give min and max (rectangular), center and fwhm (gaussian) or file")
        missing = [k for k in need[kind] if getattr(self, k) is None]
        if missing:
            raise ValueError(f"a {kind} band needs {', '.join(need[kind])}; missing {', '.join(missing)}")
        if kind == "rectangular" and self.max <= self.min:
            raise ValueError(f"max ({self.max:g} um) must exceed min ({self.min:g} um)")
        object.__setattr__(self, "type", kind)
        return self


class SpectralGridSpec(_Model):
    """A hyperspectral grid: channel centres from ``min`` to ``max`` every ``step``, each with a
    triangular response (FWHM = step) reaching zero at its neighbours' centres
    (:mod:`radscene.radiometry.channels`)."""

    min: Wavelength
    max: Wavelength
    step: float = Field(description="spacing of the channel centres, e.g. '10 nm'",
                        json_schema_extra={"x-quantity": "wavelength", "gt": 0.0})

    @field_validator("step", mode="before")
    @classmethod
    def _step(cls, value):
        if isinstance(value, bool):
            raise ValueError(f"expected a wavelength, got {value!r}")
        number = float(parse_quantity(value, "wavelength"))
        if not number > 0:
            raise ValueError(f"must be > 0 um; got {value!r}")
        return number


class _ObserverCommon(_Model):
    name: str
    shape: tuple[Annotated[int, Field(ge=1)], Annotated[int, Field(ge=1)]] | None = Field(
        None, description="rendered samples (rows, columns); from the sensor when omitted")
    supersample: Annotated[int, Field(ge=1, le=16)] = 1
    bands: list[str] | None = None
    spectral: SpectralGridSpec | None = Field(
        None, description="hyperspectral mode: spectral radiance on this grid instead of bands")
    sensor: str | None = Field(None, description="name of an entry of `sensors`")
    frames: Annotated[int, Field(ge=1, le=1000)] = 1


class OrthographicSpec(_ObserverCommon):
    """A map camera looking down (or along zenith/azimuth) with parallel rays."""

    type: Literal["orthographic"]
    center: tuple[Length, Length]
    gsd: PositiveLength | None = Field(None, description="from the sensor when omitted")
    altitude: PositiveLength = 10000.0
    zenith: Annotated[Angle, Field(ge=0, lt=90)] = 0.0
    azimuth: Angle = 0.0


class PerspectiveSpec(_ObserverCommon):
    """A pinhole frame camera."""

    type: Literal["perspective"]
    position: tuple[Length, Length, Length]
    look_at: tuple[Length, Length, Length] | None = None
    attitude: tuple[Angle, Angle, Angle] | None = None
    fov: Annotated[Angle, Field(gt=0, lt=180)] | None = Field(
        None, description="horizontal field of view; 45 deg, or from the sensor, when omitted")

    @model_validator(mode="after")
    def _pointing(self):
        if (self.look_at is None) == (self.attitude is None):
            raise ValueError("give exactly one of 'look_at' [x, y, z] or 'attitude' [yaw, pitch, roll]")
        return self


from radscene.platform.config import PushbroomSpec, WhiskbroomSpec  # noqa: E402

Observer = Annotated[OrthographicSpec | PerspectiveSpec | PushbroomSpec | WhiskbroomSpec,
                     Field(discriminator="type")]


class MotionBlurSpec(_Model):
    """Motion within a frame: the image is the mean of renders at sub-frame instants."""

    samples: Annotated[int, Field(ge=1, le=1024)] = Field(
        8, description="renders per frame, at the centres of equal parts of the exposure (centred "
        "on the frame's instant); 1: the unblurred frame. Moving features are spread into "
        "samples copies over speed x exposure: a smooth streak when speed x exposure / samples "
        "is at most a pixel")
    exposure: Duration | None = Field(
        None, description="the time the frame integrates, e.g. '10 ms'; default each observer's "
        "sensor integration time (required for observers without a sensor)")


class RenderSettings(_Model):
    sky_samples: Annotated[int, Field(ge=1, le=4096)] = 16
    specular_samples: Annotated[int, Field(ge=1, le=4096)] = 16
    shadows: bool = True
    seed: int = 0
    video: Literal["auto", "gif", "mp4", "both", "none"] = Field(
        "auto", description="a sequence's animations per band: auto writes a GIF, and an MP4 too "
        "when imageio and imageio-ffmpeg are installed (pip install radscene[video]); mp4 and both "
        "need them")
    coupling: bool = Field(True, description="surface-atmosphere coupling: multiple reflection "
                           "and the diffusely transmitted surface radiance")
    adjacency: Literal["auto"] | bool = Field(
        "auto", description="the atmospheric point-spread function over the scene's surface "
        "radiance; auto: for observers more than 2 km above the ground")
    background_bounces: Annotated[int, Field(ge=0, le=64)] = Field(
        1, description="surface vertices beyond the hit whose radiance the reflected "
        "background term follows: 1 the neighbours' own emission, sun and sky, N a path "
        "tracer of N bounces, 0 off")
    background_samples: Annotated[int, Field(ge=1, le=65536)] = Field(
        16, description="background paths per pixel, shared among its supersamples (at least "
        "one each); the term's noise falls as 1/sqrt(samples)")
    max_memory: float | str | None = Field(
        None, description="the memory a render may need, e.g. '8 GB': a scene estimated above "
        "it is refused before work; default the machine's memory")
    motion_blur: MotionBlurSpec | None = Field(
        None, description="motion blur in frame sequences and radscene.Simulation: {samples, "
        "exposure}; objects on trajectories, spinning parts and scanners are placed at each "
        "sub-frame instant, the sun and the atmosphere stay those of the frame. A single render "
        "moves nothing, so it is unchanged; default off")


# ---------------------------------------------------------------------------------------------
# heat balance


class WeatherSpec(_Model):
    """The weather of the heat balance: a file, or a diurnal cycle from these figures."""

    file: str | None = Field(None, description="CSV, NetCDF or THERM .wth weather file")
    start: _dt.datetime | None = Field(None, description="when a .wth file's first row is (it has no date)")
    fields: dict[int, str] | None = Field(
        None, description="a .wth file's fields after the sixth, which its format leaves undocumented: "
        "field number -> 'name [unit]', e.g. {7: 'global_shortwave [W m-2]', 8: 'diffuse_shortwave [W m-2]'}")
    t_min: Temperature = 285.15
    t_max: Temperature = 298.15
    relative_humidity: Fraction = 0.5
    wind_speed: Speed = 2.0
    cloud_cover: Fraction = 0.0
    pressure: Pressure | None = Field(None, description="default: the standard atmosphere's at the scene's altitude")

    @model_validator(mode="after")
    def _order(self):
        if self.t_min > self.t_max:
            raise ValueError(f"t_min {self.t_min:g} K is above t_max {self.t_max:g} K")
        return self


class ThermalMaterialSpec(_Model):
    """Overrides of a material's thermal description."""

    layers: list[dict[str, Any]] | None = Field(None, description="top first: thickness, conductivity, density, specific_heat")
    bottom: str | dict[str, Any] | None = None
    solar_absorptance: Fraction | None = None
    longwave_emissivity: Fraction | None = None
    moisture_availability: Fraction | None = None
    internal_flux: Irradiance = 0.0


class ThermalObjectSpec(_Model):
    """Heat sources of an object."""

    internal_flux: Irradiance = Field(0.0, description="W m-2 over the object's surface")
    internal_power: Power = Field(0.0, description="W spread over the object's surface")
    air_speed: Speed = Field(0.0, description="speed through the air, for aerodynamic heating")
    length: PositiveLength = Field(1.0, description="length along the airflow, for the airspeed's convection")


class ThermalSpec(_Model):
    """The heat balance that sets the temperatures of surfaces without a fixed one."""

    enabled: Literal["auto"] | bool = Field(
        "auto", description="auto: when a band lies beyond 2.5 um and a surface has no fixed temperature")
    start: _dt.datetime | None = Field(None, description="default: one day before the scene's time")
    end: _dt.datetime | None = Field(None, description="default: the scene's time")
    step: Duration = 600.0
    shadow_interval: Duration | None = None
    spin_up: bool = True
    spin_up_tolerance: Annotated[float, _quantity("temperature", 0.0, exclusive=True)] = 0.05
    resolution: PositiveLength | None = Field(None, description="terrain thermal grid; default the terrain's spacing")
    hemisphere_samples: Annotated[int, Field(ge=1, le=4096)] = 64
    nodes: Annotated[int, Field(ge=3, le=200)] = 20
    convection: str = "mcadams"
    lateral: bool = Field(False, description="lateral conduction between neighbouring elements")
    interpolate: bool = Field(True, description="render the terrain's temperature as a limited linear "
                              "reconstruction across its thermal cells (each cell's mean kept); false: "
                              "one temperature per cell")
    exchange_reflections: Annotated[int, Field(ge=0, le=100)] = 1
    weather: WeatherSpec = WeatherSpec()
    materials: dict[str, ThermalMaterialSpec] = Field(default_factory=dict)
    objects: dict[str, ThermalObjectSpec] = Field(default_factory=dict)

    @field_validator("start", "end")
    @classmethod
    def _aware(cls, value):
        if value is not None and value.tzinfo is None:
            raise ValueError("a time with a UTC offset, e.g. '2026-06-21T10:30:00+02:00' or '...Z'")
        return value


class TimeSpan(_Model):
    """A sequence of frames: every ``step`` from ``start`` to ``end`` (both included when the
    steps land on it)."""

    start: _dt.datetime
    end: _dt.datetime
    step: Duration

    @field_validator("start", "end")
    @classmethod
    def _aware(cls, value):
        if value.tzinfo is None:
            raise ValueError("a time with a UTC offset, e.g. '2026-06-21T10:30:00+02:00' or '...Z'")
        return value

    @model_validator(mode="after")
    def _ordered(self):
        if self.end < self.start:
            raise ValueError(f"end {self.end.isoformat()} lies before start {self.start.isoformat()}")
        return self


class SceneSpec(_Model):
    """The whole scene file."""

    name: str = Field("scene", description="the scene's name, recorded in the outputs")
    description: str = Field("", description="free text")
    environment: Environment = Field(description="place, time, sun and atmosphere")
    materials: dict[str, dict[str, Any]] = Field(
        default_factory=dict,
        description="user materials: {type: custom|library|file|earthlib|leaf|canopy|water|"
                    "mixture, ...}; without 'type' a custom material (reflectance, emissivity, ...)")
    terrain: Terrain | None = Field(None, description="the ground: procedural hills or a DEM")
    objects: list[ObjectSpec] = Field(default_factory=list, description="buildings, vehicles, panels placed in the scene")
    volumes: list[VolumeSpec] = Field(default_factory=list,
                                      description="participating media (smoke, dust, cloud, gas)")
    bands: list[BandSpec] = Field(default_factory=list,
                                  description="at least one, unless every observer is spectral")
    sensors: dict[str, Any] = Field(
        default_factory=dict,
        description="sensor models by name: a mapping (radscene.sensor.make_sensor), "
                    "{file: path} or {example: name}")
    observers: list[Observer] = Field(min_length=1, description="the cameras and scanners that record the scene")
    render: RenderSettings = Field(RenderSettings(), description="sampling and the terms of the renderer")
    thermal: ThermalSpec = Field(ThermalSpec(), description="the heat balance of surfaces without a fixed temperature")
    time: TimeSpan | None = Field(None, description="a frame sequence: {start, end, step}")

    @model_validator(mode="after")
    def _unique_names(self):
        for label, items in (("bands", self.bands), ("observers", self.observers), ("objects", self.objects),
                             ("volumes", self.volumes)):
            seen = set()
            for item in items:
                if item.name in seen:
                    raise ValueError(f"{label}: the name {item.name!r} is used twice")
                seen.add(item.name)
        names = [o.name for o in self.objects]
        for i, obj in enumerate(self.objects):
            if obj.parent is None:
                continue
            if obj.parent not in names:
                raise ValueError(f"objects[{i}].parent: unknown object {obj.parent!r}; known: {', '.join(names)}")
            if obj.trajectory is not None:
                raise ValueError(f"objects[{i}].trajectory: a part moves with its parent {obj.parent!r}; "
                                 "give the trajectory to the parent")
            if "on_ground" in obj.model_fields_set and obj.on_ground:
                raise ValueError(f"objects[{i}].on_ground: a part's position is in its parent's frame, "
                                 "not above the terrain; remove on_ground")
            chain, name = [obj.name], obj.parent
            while name is not None:
                if name in chain:
                    raise ValueError(f"objects[{i}].parent: {' -> '.join([*chain, name])} is a loop")
                chain.append(name)
                name = self.objects[names.index(name)].parent
        if self.terrain is None and not self.objects:
            raise ValueError("the scene has neither terrain nor objects")
        for i, obs in enumerate(self.observers):
            if getattr(obs, "spectral", None) is not None:
                for other in ("bands", "sensor"):
                    if getattr(obs, other) is not None:
                        raise ValueError(f"observers[{i}].{other}: a spectral observer renders "
                                         f"its grid, not {other}; remove one of them")
            elif not self.bands:
                raise ValueError(f"bands: give at least one band (observers[{i}] has no "
                                 "spectral grid)")
            sensor = getattr(obs, "sensor", None)
            if sensor is not None and sensor not in self.sensors:
                known = ", ".join(self.sensors) or "none defined"
                raise ValueError(f"observers[{i}].sensor: unknown sensor {sensor!r}; known: {known}")
            if sensor is None and obs.shape is None:
                raise ValueError(f"observers[{i}].shape: required when the observer has no sensor")
            if sensor is None and getattr(obs, "type", "") == "orthographic" and obs.gsd is None:
                raise ValueError(f"observers[{i}].gsd: required when the observer has no sensor")
        return self
