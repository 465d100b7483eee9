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
from pathlib import Path
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
#: The formats of a temperature map: numbers as they are (kelvin), never image levels.
TEMPERATURE_MAP_SUFFIXES = (".npy", ".tif", ".tiff")
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

    type: Literal["image"] = Field(
        "image", description="`image` (the default when `type` is omitted)")
    file: str = Field(
        description="PNG/JPEG (colour taken as luminance, integers scaled to [0, 1]) or .npy "
        "array of multipliers, row 0 north")
    size: tuple[PositiveLength, PositiveLength] = Field(
        description="(width, height) the image covers on the ground [m]; tiled beyond it")
    origin: tuple[Length, Length] = Field(
        (0.0, 0.0), description="(x, y) of the image's south-west corner [m]")
    contrast: Annotated[float, Field(ge=0)] | None = Field(
        None, description="none: the pixel values are the multipliers (>= 0); a number c: the "
        "multiplier is 1 + c (v - mean) / (max - min), of mean 1 and peak-to-peak range c")


class TileTextureSpec(_Model):
    """A small multiplier pattern repeated over the whole ground plane at a stated scale: each
    texel covers ``texel_size`` (e.g. ``"2 m"``), or the whole pattern ``tile_size``."""

    type: Literal["tile"] = Field(
        description="`tile`: a pattern repeated over the whole ground plane")
    values: list[list[Annotated[float, Field(ge=0)]]] | None = Field(
        None, description="the pattern's multipliers as rows of numbers (row 0 north); exactly "
        "one of values and file")
    file: str | None = Field(
        None, description="an image (PNG/JPEG/.npy) of the pattern's multipliers")
    texel_size: PositiveLength | tuple[PositiveLength, PositiveLength] | None = Field(
        None, description="ground size of one pattern pixel [m]: one number, or (dx, dy); exactly "
        "one of texel_size and tile_size")
    tile_size: tuple[PositiveLength, PositiveLength] | None = Field(
        None, description="(width, height) of the whole pattern on the ground [m]")
    origin: tuple[Length, Length] = Field(
        (0.0, 0.0), description="(x, y) of a tile's south-west corner [m]")

    @model_validator(mode="after")
    def _one_each(self):
        if (self.values is None) == (self.file is None):
            raise ValueError("give exactly one of 'values' (a 2-D list) or 'file'")
        if (self.texel_size is None) == (self.tile_size is None):
            raise ValueError("give exactly one of 'texel_size' [m] or 'tile_size' [m, m]")
        return self


class NoiseTextureSpec(_Model):
    """Procedural fractal-noise multiplier ``1 + amplitude * noise`` (terrain detail)."""

    type: Literal["noise"] = Field(description="`noise`: fractal gradient (Perlin) noise")
    amplitude: Annotated[float, Field(ge=0, le=1)] = Field(
        description="swing of the multiplier 1 + amplitude * noise, the noise lying in [-1, 1] "
        "[-]")
    scale: PositiveLength = Field(
        description="wavelength of the first octave, the size of the largest features [m]")
    octaves: Annotated[int, Field(ge=1, le=16)] = Field(4, description="number of octaves summed")
    persistence: Annotated[float, Field(gt=0, le=1)] = Field(
        0.5, description="amplitude ratio of successive octaves")
    lacunarity: Annotated[float, Field(gt=1)] = Field(
        2.0, description="frequency ratio of successive octaves")
    seed: Annotated[int, Field(ge=0)] = Field(
        0, description="seed of the noise lattice: the same seed gives the same pattern")


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
    reflectance: TextureSpec | None = Field(
        None, description="multiplier of the reflectance (Δρ) over the surface; default none (1)")
    emissivity: TextureSpec | None = Field(
        None, description="multiplier of the emissivity (Δε) over the surface; default none (1)")
    transmittance: TextureSpec | None = Field(
        None, description="multiplier of the transmittance (Δτ) of a transmissive object; default "
        "none (1)")


# ---------------------------------------------------------------------------------------------
# terrain


class Lake(_Model):
    x: Length = Field(description="east coordinate of the lake's centre [m]")
    y: Length = Field(description="north coordinate of the lake's centre [m]")
    radius: PositiveLength = Field(description="radius of the lake's disc [m]")
    depth: PositiveLength = Field(
        3.0, description="depth of the water surface below the lowest ground within the disc and "
        "its shore band [m]")


class MaterialMapFile(_Model):
    """A classified image over the terrain extent: pixel value → a material name, or the
    fractions of several materials in that class, ``{grass: 0.6, bare_soil: 0.4}`` (sub-pixel
    areal mixture: the spectra are mixed linearly)."""

    type: Literal["file"] = Field("file", description="`file`: a classified image")
    file: str = Field(
        description="classified image over the terrain extent, resampled by nearest neighbour "
        "onto the terrain grid: a .npy array or a GeoTIFF (first band) of integer class values, "
        "or a PNG/JPEG whose 8- or 16-bit levels are the class values (a palette image's "
        "indices, a colour image's first channel)")
    classes: dict[int, str | dict[str, float]] = Field(
        description="pixel value -> a material name, or the fractions of several materials that "
        "sum to 1 (a linear areal mixture); every value in the image must be mapped")

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

    type: Literal["noise"] = Field("noise", description="`noise`: smooth random patches")
    materials: list[str] = Field(
        min_length=1, description="the materials of the patches, each taking an equal share of "
        "the area (list a material twice for a double share)")
    scale: PositiveLength = Field(
        100.0, description="size of the patches [m] (the smoothing of the random field is scale / "
        "2)")
    seed: int = Field(
        0, description="seed of the random field: the same seed gives the same patches")


class RoadSpec(_Model):
    """A road: a polyline on the ground with a width, painted onto the terrain's faces as its
    own material (a stripe of the terrain mesh, not a mesh of its own)."""

    points: list[tuple[Length, Length]] = Field(
        min_length=2, description="[x, y] of the centre line's vertices in the scene frame [m], "
        "in order")
    width: PositiveLength = Field(
        description="width of the road [m]: every terrain face whose centroid lies within "
        "width / 2 of the centre line takes the road's material; at least the terrain's spacing")
    material: str = Field(
        "asphalt", description="the road's material (a built-in or a key of `materials`); the "
        "heat balance solves its faces as that material")
    name: str | None = Field(None, description="a label for messages; default roads[i]")

    @field_validator("points")
    @classmethod
    def _distinct(cls, value):
        for i in range(1, len(value)):
            if value[i] == value[i - 1]:
                raise ValueError(f"points {i - 1} and {i} are the same point {list(value[i])}")
        return value


class _TerrainCommon(_Model):
    origin: tuple[Length, Length] = Field(
        (0.0, 0.0), description="(x, y) of the grid's south-west sample in the scene frame [m]; "
        "ignored for a GeoTIFF DEM, which carries its own coordinates")
    material: str = Field(
        "dry_grass", description="the material of the whole terrain when there is no "
        "material_map: a built-in material or a key of `materials`")
    material_map: Annotated[MaterialMapFile | MaterialMapNoise, Field(discriminator="type")] | None = Field(
        None, description="land cover: a classified image (type file) or random patches of "
        "several materials (type noise); default the one `material` everywhere")
    water_material: str = Field(
        "water", description="the material of the lakes' water surface (procedural terrain with "
        "lakes)")
    temperature: Temperature | None = Field(
        None, description="a fixed surface temperature [K]; default: solved by the heat balance "
        "(293.15 K with thermal off)")
    temperatures: dict[str, Temperature] = Field(
        default_factory=dict, description="fixed surface temperatures [K] by material name: the "
        "terrain faces of that material keep it instead of being solved; default none")
    temperature_map: str | None = Field(
        None, description="surface temperatures [K] over the terrain extent: a .npy array or a "
        "GeoTIFF (first band) of kelvin, every value finite and > 0 K, resampled by nearest "
        "neighbour onto the terrain grid; its faces keep them instead of being solved. A PNG "
        "or JPEG is refused: it holds 8- or 16-bit levels, not temperatures",
        # the same rule for editors that read the JSON schema (a string's suffix)
        json_schema_extra={"pattern": r"\.([nN][pP][yY]|[tT][iI][fF][fF]?)$"})
    textures: TextureSet = Field(
        TextureSet(), description="multipliers of the terrain's reflectance, emissivity and "
        "transmittance laid on the ground plane; default none (every multiplier 1)")
    roads: list[RoadSpec] = Field(
        default_factory=list, description="roads painted onto the terrain over its land cover "
        "and lakes, each a polyline with a width and its own material; default none")

    @field_validator("temperature_map")
    @classmethod
    def _kelvin_file(cls, value):
        if value is not None and Path(value).suffix.lower() not in TEMPERATURE_MAP_SUFFIXES:
            raise ValueError(
                "a temperature map holds kelvin: give a .npy array or a GeoTIFF (.tif, .tiff) "
                f"of temperatures; {Path(value).name!r} is neither (a PNG or JPEG holds 8- or "
                "16-bit levels, not temperatures)")
        return value


class FlatTerrain(_TerrainCommon):
    """A level ground plane of one material (or a material map), without relief or noise."""

    type: Literal["flat"] = Field(description="`flat`: a level plane")
    size: tuple[PositiveLength, PositiveLength] = Field(
        (1000.0, 1000.0), description="(east, north) extent [m], from `origin` (the south-west "
        "corner); the grid has round(size / spacing) + 1 samples a side")
    spacing: PositiveLength = Field(
        5.0, description="distance between grid samples, both axes [m]: the resolution of the "
        "material map, the roads and the heat balance's terrain grid")
    height: Length = Field(0.0, description="height of the plane above the scene origin [m]")


class ProceduralTerrain(_TerrainCommon):
    """Fractal hills with optional lakes, generated from a seed."""

    type: Literal["procedural"] = Field(
        description="`procedural`: fractal hills generated from `seed`")
    size: tuple[PositiveLength, PositiveLength] = Field(
        (1000.0, 1000.0), description="(east, north) extent of the grid [m]; it has round(size / "
        "spacing) + 1 samples a side")
    spacing: PositiveLength = Field(5.0, description="distance between grid samples, both axes [m]")
    relief: Annotated[Length, Field(ge=0)] = Field(
        40.0, description="peak-to-trough height of the hills before lakes are carved [m]; 0: "
        "flat")
    seed: int = Field(
        0, description="seed of the hills' random generator: the same seed gives the same terrain")
    lakes: list[Lake] = Field(
        default_factory=list, description="flat lakes carved into the hills, each filled with "
        "`water_material`; default none")


class DemTerrain(_TerrainCommon):
    """A digital elevation model from a GeoTIFF/.npy file or an inline array."""

    type: Literal["dem"] = Field(description="`dem`: a digital elevation model")
    file: str | None = Field(
        None, description="GeoTIFF (its own coordinates) or .npy array of heights [m], row 0 "
        "north, column 0 west; relative paths from the scene file's folder; exactly one of file "
        "and elevation")
    elevation: list[list[float]] | None = Field(
        None, description="inline heights [m] as rows of numbers, row 0 north, column 0 west; "
        "needs `spacing`")
    spacing: tuple[PositiveLength, PositiveLength] | None = Field(
        None, description="(east, north) distance between samples [m] of an inline elevation or a "
        ".npy file (a GeoTIFF carries its own)")

    @model_validator(mode="after")
    def _one_source(self):
        if (self.file is None) == (self.elevation is None):
            raise ValueError("give exactly one of 'file' or 'elevation'")
        if self.elevation is not None and self.spacing is None:
            raise ValueError("an inline 'elevation' needs 'spacing' [m, m]")
        return self

    @field_validator("elevation")
    @classmethod
    def _rectangular(cls, value):
        if value:
            lengths = [len(row) for row in value]
            odd = next((k for k, n in enumerate(lengths) if n != lengths[0]), None)
            if odd is not None:
                raise ValueError(f"rows must all have the same length: row 0 has {lengths[0]} "
                                 f"samples, row {odd} has {lengths[odd]}")
        return value


class SeaTerrain(_Model):
    """A wind-driven sea surface (docs/sea.md): waves drawn from a named spectrum by FFT on a
    periodic tile, repeated over ``size``, moving with the clock in sequences and
    radscene.Simulation; the waves shorter than ``resolution`` are the facets' Cox-Munk
    roughness. Deterministic for a seed."""

    type: Literal["sea"] = Field(description="`sea`: a wind-driven sea surface")
    wind_speed: Speed = Field(description="U10, 10 m above the sea, e.g. '8 m/s'; 0: a calm sea "
                              "(flat, with Cox & Munk's clean-surface roughness)")
    wind_direction: Angle = Field(0.0, description="where the wind comes from, clockwise from "
                                  "north [deg]; the waves travel downwind")
    spectrum: Literal["pierson_moskowitz", "jonswap"] = Field(
        "pierson_moskowitz", description="pierson_moskowitz (fully developed, 1964) or jonswap "
        "(fetch-limited, Hasselmann et al. 1973, needs fetch)")
    fetch: PositiveLength | None = Field(None, description="jonswap: the distance the wind has "
                                         "blown over the water, e.g. '50 km'")
    gamma: Annotated[float, Field(ge=1.0, le=10.0)] = Field(3.3, description="jonswap: peak "
                                                            "enhancement factor")
    spreading: Annotated[float, Field(ge=0.0, le=100.0)] = Field(
        10.0, description="s of the cos-2s directional spreading (Longuet-Higgins et al. 1963); "
        "larger is narrower, 0 isotropic")
    tile: PositiveLength = Field(64.0, description="side of the periodic tile of waves [m]")
    resolution: PositiveLength = Field(0.25, description="sample spacing of the tile and the "
                                       "mesh [m]; the tile must hold a whole number of samples")
    size: tuple[PositiveLength, PositiveLength] = Field(
        (64.0, 64.0), description="extent east and north [m], the tile repeated over it")
    origin: tuple[Length, Length] = Field((0.0, 0.0), description="south-west corner [m]")
    seed: int = Field(0, description="the waves' random phases and amplitudes")
    far_field: bool = Field(False, description="no waves in the geometry: a flat surface with "
                            "the Cox-Munk BRDF of the whole wind (for seas seen from far away)")
    material: str = Field("water", description="the name the faces carry in material_id; their "
                          "optics are the Cox-Munk facets of liquid water (Hale & Querry 1973)")
    temperature: Temperature = Field(description="the sea's surface temperature [K], e.g. '288 K'")

    @model_validator(mode="after")
    def _fetch(self):
        if self.spectrum == "jonswap" and self.fetch is None:
            raise ValueError("the jonswap spectrum needs a 'fetch', e.g. '50 km'")
        if self.spectrum != "jonswap" and self.fetch is not None:
            raise ValueError("'fetch' belongs to the jonswap spectrum (pierson_moskowitz is "
                             "fully developed)")
        return self


Terrain = Annotated[FlatTerrain | ProceduralTerrain | DemTerrain | SeaTerrain, Field(discriminator="type")]


# ---------------------------------------------------------------------------------------------
# objects


class BoxShape(_Model):
    type: Literal["box"] = Field(description="`box`")
    size: tuple[PositiveLength, PositiveLength, PositiveLength] = Field(
        description="edge lengths (east, north, up) before rotation [m]; the base is centred on "
        "the object's position")


class CylinderShape(_Model):
    type: Literal["cylinder"] = Field(description="`cylinder`: upright, capped")
    radius: PositiveLength = Field(
        description="radius of the circle through the polygon's vertices [m]")
    height: PositiveLength = Field(description="height [m], from the base at the object's position")
    sections: Annotated[int, Field(ge=3)] = Field(
        32, description="vertices of the polygon that approximates the circle")


class PlateShape(_Model):
    type: Literal["plate"] = Field(
        description="`plate`: a flat rectangle facing up before rotation")
    width: PositiveLength = Field(description="extent east before rotation [m]")
    length: PositiveLength = Field(description="extent north before rotation [m]")


class MeshShape(_Model):
    type: Literal["mesh"] = Field(description="`mesh`: a triangle mesh from a file")
    file: str = Field(
        description="OBJ, PLY, STL (z up) or glTF/GLB (y up, turned to z up) file, coordinates in "
        "metres; relative paths from the scene file's folder")
    scale: Annotated[float, Field(gt=0)] = Field(
        1.0, description="factor applied to the mesh's coordinates [-]")


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
    attitude: Literal["fixed", "path", "banked", "tabulated"] | None = Field(
        None, description="fixed: the object's rotation; path: forward along the velocity (heading "
        "and climb; on the ground pitch and roll from the terrain's slope), rotation on top; "
        "banked: as path, rolled into turns as in coordinated flight (airborne; spline paths); "
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
        if tabulated and self.attitude in ("fixed", "path", "banked"):
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
    type: Literal["ellipsoid"] = Field(description="`ellipsoid`")
    radii: tuple[PositiveLength, PositiveLength, PositiveLength] = Field(
        description="semi-axes along east, north and up [m]")


class DensityProfile(_Model):
    """How a volume's relative density varies: ``uniform``; ``exponential`` in height above
    the volume's base, e-folding over ``scale_height``; ``gaussian`` about its centre with
    standard deviations ``sigma`` (one, or one per axis) [m]; ``grid``: a 3-D array from
    ``file``, trilinear between its nodes, which span the volume's bounding box."""

    type: Literal["uniform", "exponential", "gaussian", "grid"] = Field(
        "uniform", description="uniform, exponential (in height above the volume's base), "
        "gaussian (about its centre) or grid (a 3-D array)")
    scale_height: PositiveLength | None = Field(
        None, description="exponential: height over which the density falls by a factor e [m]")
    sigma: PositiveLength | tuple[PositiveLength, PositiveLength, PositiveLength] | None = Field(
        None, description="gaussian: standard deviation about the centre [m], one or one per axis "
        "(east, north, up)")
    file: str | None = Field(None, description="grid: a .npy array or a NetCDF variable of "
                             "relative density, dims (z, y, x), nodes spanning the volume's box; "
                             "sized from its header against the memory limit before it is read")
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
        if self.co2 + self.h2o <= 0.0:
            raise ValueError("a gas plume needs its composition: a mole fraction co2 or h2o > 0 "
                             "(neither given, it would neither emit nor absorb)")
        return self


class VolumeSpec(_Model):
    """A participating volume (smoke, dust, cloud, gas): an axis-aligned box or ellipsoid
    centred at ``position`` (z above the scene origin) filled with a medium of extinction
    coefficient ``extinction`` [m-1] at density 1 (a number or a spectrum), or of vertical
    optical depth ``optical_depth`` through its centre, or a ``gas`` mixture of CO2 and H2O
    absorbing and emitting in their bands at the volume's temperature (a band model; albedo
    0); ``density`` scales the ``profile``."""

    name: str = Field(description="unique name of the volume")
    shape: Annotated[BoxShape | EllipsoidShape, Field(discriminator="type")] = Field(
        description="an axis-aligned box (size: full edge lengths) or ellipsoid (radii)")
    position: tuple[Length, Length, Length] = Field(
        (0.0, 0.0, 0.0), description="(x, y, z) of the volume's centre [m]; z above the scene "
        "origin, not the terrain")
    density: Annotated[float, Field(ge=0.0)] = Field(
        1.0, description="relative density at the profile's reference (base or centre), "
        "multiplying the extinction [-]")
    profile: DensityProfile = Field(
        DensityProfile(), description="how the relative density varies within the volume; default "
        "uniform")
    extinction: float | dict[str, Any] | None = Field(
        None, description="extinction coefficient at density 1 [m-1]: a number, or a spectrum "
        "{wavelength [µm], values} or {file}; exactly one of extinction and optical_depth")
    optical_depth: float | dict[str, Any] | None = Field(
        None, description="vertical optical depth through the centre, from below [-]: a number or "
        "a spectrum; the extinction follows from it")
    single_scattering_albedo: Fraction = Field(
        0.0, description="share of the extinction that scatters (ω) [-]: 0 a purely absorbing "
        "medium; the absorbed share (1 - ω) emits")
    asymmetry: Annotated[float, Field(gt=-1.0, lt=1.0)] = Field(
        0.0, description="Henyey-Greenstein asymmetry parameter of the scattering (0: isotropic)")
    temperature: Temperature = Field(
        description="temperature of the medium [K], for its thermal emission")
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

    name: str = Field(
        description="unique name of the band, used by observers' `bands` and in the outputs")
    type: Literal["rectangular", "gaussian", "tabulated", "library"] | None = Field(
        None, description="the kind of response; default inferred from the keys given (min/max "
        "rectangular, center/fwhm gaussian, file tabulated, sensor/band library)")
    min: Wavelength | None = Field(None, description="rectangular: short-wave edge [µm]")
    max: Wavelength | None = Field(None, description="rectangular: long-wave edge [µm], above min")
    center: Wavelength | None = Field(None, description="gaussian: centre wavelength [µm]")
    fwhm: Wavelength | None = Field(None, description="gaussian: full width at half maximum [µm]")
    file: str | None = Field(
        None, description="tabulated: a two-column text/CSV file of wavelength [µm] and relative "
        "response")
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
            raise ValueError(f"max ({self.max:g} µm) must exceed min ({self.min:g} µm)")
        object.__setattr__(self, "type", kind)
        return self


class ChannelGridSpec(_Model):
    """A grid of channels: centres from ``min`` to ``max`` every ``step``, each with a
    triangular response (FWHM = step) reaching zero at its neighbours' centres
    (:mod:`radscene.radiometry.channels`)."""

    min: Wavelength = Field(description="centre of the first channel [µm]")
    max: Wavelength = Field(
        description="centre of the last channel [µm], or the last centre below it when the steps "
        "do not land on it")
    step: float = Field(description="spacing of the channel centres, e.g. '10 nm'",
                        json_schema_extra={"x-quantity": "wavelength", "gt": 0.0})

    @field_validator("step", mode="before")
    @classmethod
    def _step(cls, value):
        if isinstance(value, bool):
            raise ValueError(f"expected a wavelength, got {value!r}")
        number = float(parse_quantity(value, "wavelength"))
        if not number > 0:
            raise ValueError(f"must be > 0 µm; got {value!r}")
        return number


class SpectralGridSpec(ChannelGridSpec):
    """A hyperspectral grid: channel centres from ``min`` to ``max`` every ``step``, each with a
    triangular response (FWHM = step) reaching zero at its neighbours' centres
    (:mod:`radscene.radiometry.channels`)."""

    terms: bool = Field(
        False, description="also keep every layer that sums to the radiance (sun_diffuse, "
        "sky_reflected, thermal_emission, path_radiance, ...) and the parts of the reflected "
        "sky and background by the light's origin (sky_reflected_solar, ...) as a spectral "
        "variable of its own, <term>(wavelength, y, x) [W m-2 sr-1 µm-1], in memory and in the "
        "NetCDF or Zarr cube (the ENVI image stays radiance only); multiplies the cube's size "
        "by up to 17 "
        "and shrinks the render's passes")


class _ObserverCommon(_Model):
    name: str = Field(
        description="unique name of the observer; its output files are named after it")
    shape: tuple[Annotated[int, Field(ge=1)], Annotated[int, Field(ge=1)]] | None = Field(
        None, description="rendered samples (rows, columns); from the sensor when omitted")
    supersample: Annotated[int, Field(ge=1, le=16)] = Field(
        1, description="rays per pixel along each axis: supersample² samples averaged into each "
        "pixel")
    bands: list[str] | None = Field(
        None, description="names of the scene's bands this observer renders; default all of them")
    spectral: SpectralGridSpec | None = Field(
        None, description="hyperspectral mode: spectral radiance on this grid instead of bands")
    sensor: str | None = Field(None, description="name of an entry of `sensors`")
    frames: Annotated[int, Field(ge=1, le=1000)] = Field(
        1, description="frames the observer's sensor records from one render, each with its own "
        "temporal noise; unused without a sensor")


class OrthographicSpec(_ObserverCommon):
    """A map camera looking down (or along zenith/azimuth) with parallel rays."""

    type: Literal["orthographic"] = Field(
        description="`orthographic`: a map camera with parallel rays")
    center: tuple[Length, Length] = Field(
        description="(x, y) where the image centre's ray meets z = 0 [m]")
    gsd: PositiveLength | None = Field(None, description="from the sensor when omitted")
    altitude: PositiveLength = Field(
        10000.0, description="height of the image plane's centre above z = 0, where the rays "
        "start [m]; must exceed the terrain")
    zenith: Annotated[Angle, Field(ge=0, lt=90)] = Field(
        0.0, description="zenith angle of the direction from the ground to the camera [deg]; 0: "
        "looking straight down (a north-up map)")
    azimuth: Angle = Field(0.0, description="azimuth of that direction, clockwise from north [deg]")


class PerspectiveSpec(_ObserverCommon):
    """A pinhole frame camera."""

    type: Literal["perspective"] = Field(description="`perspective`: a pinhole frame camera")
    position: tuple[Length, Length, Length] = Field(
        description="(x, y, z) of the pinhole [m]; z above the scene origin, not the terrain")
    look_at: tuple[Length, Length, Length] | None = Field(
        None, description="a point (x, y, z) on the optical axis [m], with the horizon level "
        "(roll 0); exactly one of look_at and attitude")
    attitude: tuple[Angle, Angle, Angle] | None = Field(
        None, description="(yaw, pitch, roll) [deg]: yaw the azimuth of the optical axis "
        "clockwise from north, pitch its elevation (negative looking down), roll positive turning "
        "the image's right side down")
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
    sky_samples: Annotated[int, Field(ge=1, le=4096)] = Field(
        16, description="cosine-weighted hemisphere rays per surface hit that estimate the "
        "visible sky (sky view and reflected sky radiance)")
    specular_samples: Annotated[int, Field(ge=1, le=4096)] = Field(
        16, description="rays per hit in the specular lobe of a glossy material, for the sky "
        "reflected in it")
    shadows: bool = Field(
        True, description="trace rays towards the sun; false: every surface facing the sun is lit")
    seed: int = Field(
        0, description="seed of the random sampling (renders, the heat balance's rays, sensor "
        "noise): the same seed gives the same outputs")
    video: Literal["auto", "gif", "mp4", "both", "none"] = Field(
        "auto", description="a sequence's animations per band: auto writes a GIF, and an MP4 too "
        "when imageio and imageio-ffmpeg are installed (pip install imageio imageio-ffmpeg); mp4 and both "
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
        "one each); the first sky_samples of a supersample take their diffuse first direction "
        "from its stratified sky rays, the others draw their own; the term's noise falls as "
        "1/sqrt(samples) or faster")
    max_memory: float | str | None = Field(
        None, description="the memory a render may need, e.g. '8 GB': a scene estimated above "
        "it is refused before work; default the machine's memory")
    key_frames: bool = Field(
        False, description="frame sequences and radscene.Simulation: frames between key frames "
        "shade only the pixels something moved through and take the others' radiance in time "
        "from two key frames — interpolated between the key frame behind and one rendered "
        "ahead in a sequence, extrapolated from the last two in radscene.Simulation.step — about "
        "4 times faster and within about 2e-4 of the frame's own radiance (docs/simulation.md, "
        "'Key frames'); default false: every frame shades every pixel at its own instant, exactly")
    key_frame_interval: Duration = Field(
        1.0, description="the time between key frames, e.g. '1 s'; the sun turning by 0.05 deg, "
        "a time step of the heat balance or a change of what the atmosphere's nodes cover makes "
        "a key frame sooner")
    spectral_grid: ChannelGridSpec | None = Field(
        None, description="band renders resolve their non-linear layers (the coupling, the "
        "reflected background, and with volumes or sheets every layer) on this channel grid "
        "{min, max, step} and integrate them with each band's response, as a hyperspectral cube "
        "on the grid integrated with it would (docs/hyperspectral.md, 'Resolved band renders'); "
        "renders the channels inside the bands besides the bands; default off: band means")
    motion_blur: MotionBlurSpec | None = Field(
        None, description="motion blur in frame sequences and radscene.Simulation: {samples, "
        "exposure}; objects on trajectories, spinning parts and scanners are placed at each "
        "sub-frame instant, the sun and the atmosphere stay those of the frame. A single render "
        "is the instant itself (what moves where it is at t = 0), not blurred; default off")


# ---------------------------------------------------------------------------------------------
# heat balance


class WeatherSpec(_Model):
    """The weather of the heat balance: a file, or a diurnal cycle from these figures."""

    file: str | None = Field(None, description="CSV, NetCDF or THERM .wth weather file")
    start: _dt.datetime | None = Field(None, description="when a .wth file's first row is (it has no date)")
    fields: dict[int, str] | None = Field(
        None, description="a .wth file's fields after the sixth, which its format leaves undocumented: "
        "field number -> 'name [unit]', e.g. {7: 'global_shortwave [W m-2]', 8: 'diffuse_shortwave [W m-2]'}")
    t_min: Temperature = Field(
        285.15, description="daily minimum air temperature [K], shortly before sunrise (diurnal "
        "cycle without a file)")
    t_max: Temperature = Field(
        298.15, description="daily maximum air temperature [K], in the early afternoon (local "
        "solar time)")
    relative_humidity: Fraction = Field(
        0.5, description="relative humidity at the mean of t_min and t_max [0-1]; the dew point "
        "it gives is kept through the day")
    wind_speed: Speed = Field(
        2.0, description="wind speed near the surface, constant [m/s]; drives convection")
    cloud_cover: Fraction = Field(
        0.0, description="cloud cover, constant [0-1]; with a .wth file, given only to override "
        "the file")
    pressure: Pressure | None = Field(None, description="default: the standard atmosphere's at the scene's altitude")
    max_gap: Duration | None = Field(
        None, description="longest step between a file's rows that is bridged [s]; default three "
        "times the file's most frequent step")
    place_tolerance: Annotated[float, _quantity("angle", 0.0, exclusive=True)] = Field(
        1.0, description="largest difference in latitude and in longitude between the file's stated "
        "place and the scene's [deg]")

    @model_validator(mode="after")
    def _order(self):
        if self.t_min > self.t_max:
            raise ValueError(f"t_min {self.t_min:g} K is above t_max {self.t_max:g} K")
        return self

    @model_validator(mode="after")
    def _with_a_file(self):
        # a key counts as given where it differs from its default (a resolved scene, which
        # writes every key, loads again)
        given = {k for k in self.model_fields_set if getattr(self, k) != type(self).model_fields[k].default}
        if self.file is None:
            extra = [k for k in ("start", "fields", "max_gap", "place_tolerance") if k in given]
            if extra:
                raise ValueError(f"{', '.join(extra)} apply to a weather file; no file is given")
            return self
        thermal_file = self.file.lower().endswith(".wth")
        # a CSV or NetCDF file carries its own weather, dates and place; a .wth file its own
        # weather, less the date, the place and (in its short form) the cloud
        ignored = ["t_min", "t_max", "relative_humidity", "wind_speed", "pressure"]
        if thermal_file:
            ignored += ["place_tolerance"]
        else:
            ignored += ["cloud_cover", "start", "fields"]
        extra = [k for k in ignored if k in given]
        if extra:
            raise ValueError(f"{', '.join(extra)} would be ignored: the weather file {self.file} gives "
                             f"{'them' if len(extra) > 1 else 'it'}; remove {'them' if len(extra) > 1 else 'it'} "
                             f"or the file")
        return self


class ThermalMaterialSpec(_Model):
    """Overrides of a material's thermal description."""

    layers: list[dict[str, Any]] | None = Field(None, description="top first: thickness, conductivity, density, specific_heat")
    bottom: str | dict[str, Any] | None = Field(
        None, description="below the last layer: semi-infinite, insulated, or {interior_air: T "
        "[K], h [W m-2 K-1]}; default the material's")
    solar_absorptance: Fraction | None = Field(
        None, description="absorptance of sunlight [0-1]; default computed from the material's "
        "reflectance against the sun's spectrum at the ground")
    longwave_emissivity: Fraction | None = Field(
        None, description="long-wave emissivity [0-1]; default the material's thermal data or its "
        "spectral emissivity")
    moisture_availability: Fraction | None = Field(
        None, description="β of the evaporation flux [0-1]: 1 open water, 0 a dry surface; "
        "default the material's (0 when it has none)")
    internal_flux: Irradiance = Field(
        0.0, description="heat flux from within into the surface [W m-2]; 0: none")
    temperature: Temperature | None = Field(
        None, description="a fixed temperature [K] for every surface of this material that has no "
        "temperature of its own (an object's, or the terrain's); such surfaces are not solved")


class ThermalObjectSpec(_Model):
    """An object's own thermal description and heat sources (over its material's)."""

    layers: list[dict[str, Any]] | None = Field(
        None, description="the object's own stack, top first: thickness, conductivity, density, "
        "specific_heat; default its material's")
    bottom: str | dict[str, Any] | None = Field(
        None, description="below the object's last layer: semi-infinite, insulated, or "
        "{interior_air: T [K], h [W m-2 K-1]}; default its material's")
    solar_absorptance: Fraction | None = Field(None, description="the object's own [0-1]; default its material's")
    longwave_emissivity: Fraction | None = Field(None, description="the object's own [0-1]; default its material's")
    moisture_availability: Fraction | None = Field(
        None, description="β of the object's evaporation [0-1]; default its material's")
    internal_flux: Irradiance = Field(0.0, description="W m-2 over the object's faces (internal_faces)")
    internal_power: Power = Field(0.0, description="W spread over the object's faces (internal_faces)")
    internal_faces: Literal["all", "top", "bottom", "sides"] = Field(
        "all", description="which faces carry internal_flux and internal_power: all, top (outward "
        "normal within 60 deg of up), bottom (within 60 deg of down) or sides (the rest)")
    air_speed: Speed = Field(0.0, description="speed through the air, for aerodynamic heating")
    length: PositiveLength = Field(1.0, description="length along the airflow, for the airspeed's convection")

    @model_validator(mode="after")
    def _faces_carry_something(self):
        if self.internal_faces != "all" and not (self.internal_flux or self.internal_power):
            raise ValueError(f"internal_faces: {self.internal_faces} would carry nothing: give internal_flux "
                             "or internal_power")
        return self


class ThermalSpec(_Model):
    """The heat balance that sets the temperatures of surfaces without a fixed one."""

    enabled: Literal["auto"] | bool = Field(
        "auto", description="auto: when a band lies beyond 2.5 µm and a surface has no fixed temperature")
    start: _dt.datetime | None = Field(None, description="default: one day before the scene's time")
    end: _dt.datetime | None = Field(None, description="default: the scene's time")
    step: Duration = Field(600.0, description="time step of the heat balance [s]")
    shadow_interval: Duration | None = Field(
        None, description="time between shadow traces [s]; default every step")
    spin_up: bool | None = Field(
        None, description="repeat the first day until it repeats itself, so the start's guess is "
        "forgotten (a run shorter than a day spins up on the day that begins at its start); "
        "default: on, off where initial_temperature is given")
    spin_up_tolerance: Annotated[float, _quantity("temperature", 0.0, exclusive=True)] = Field(
        0.05, description="largest day-to-day change of a surface temperature at which the "
        "spin-up stops [K]")
    initial_temperature: Temperature | dict[str, Temperature] | None = Field(
        None, description="start every conduction node at this temperature [K], or per material "
        "name (the others at the first day's mean air temperature), in place of the spin-up; "
        "default: the spin-up, or the first day's mean air temperature without it")
    profiles: bool = Field(
        False, description="also write the temperature of every conduction node at every time "
        "(node_temperature, node_depth); the layers' temperatures are always written")
    resolution: PositiveLength | None = Field(None, description="terrain thermal grid; default the terrain's spacing")
    hemisphere_samples: Annotated[int, Field(ge=1, le=4096)] = Field(
        64, description="hemisphere rays per element for its sky view and its view factors to the "
        "other elements")
    nodes: Annotated[int, Field(ge=3, le=200)] = Field(
        20, description="conduction nodes through the depth of each element")
    convection: str = Field(
        "mcadams", description="correlation of the convection coefficient: mcadams (h = 5.7 + 3.8 u), "
        "watmuff (2.8 + 3.0 u), mixed (free convection by the surface-to-air difference and the "
        "orientation, Walton 1983, plus 3.0 u) or none")
    lateral: bool = Field(False, description="lateral conduction between neighbouring elements")

    @field_validator("convection")
    @classmethod
    def _convection(cls, value):
        known = ("mcadams", "watmuff", "mixed", "none")
        if str(value).strip().lower() not in known:
            raise ValueError(f"unknown convection {value!r}; known: {', '.join(known)}")
        return str(value).strip().lower()
    interpolate: bool = Field(True, description="render the terrain's temperature as a limited linear "
                              "reconstruction across its thermal cells (each cell's mean kept); false: "
                              "one temperature per cell")
    exchange_reflections: Annotated[int, Field(ge=0, le=100)] = Field(
        1, description="reflections followed in the exchange between elements: 0 the neighbours' "
        "emission only, 1 also what they reflect once")
    weather: WeatherSpec = Field(
        WeatherSpec(), description="air temperature, humidity, wind and cloud: a file or a "
        "diurnal cycle")
    materials: dict[str, ThermalMaterialSpec] = Field(
        default_factory=dict, description="overrides of materials' thermal descriptions, by "
        "material name")
    objects: dict[str, ThermalObjectSpec] = Field(
        default_factory=dict, description="objects' own stacks, optics, wetness and heat sources, by "
        "object name")

    @field_validator("start", "end")
    @classmethod
    def _aware(cls, value):
        if value is not None and value.tzinfo is None:
            raise ValueError("a time with a UTC offset, e.g. '2026-06-21T10:30:00+02:00' or '...Z'")
        return value

    @property
    def spins_up(self) -> bool:
        """Whether the spin-up runs: as given, else unless initial temperatures are given."""
        return self.initial_temperature is None if self.spin_up is None else self.spin_up

    @model_validator(mode="after")
    def _start_state(self):
        if self.initial_temperature is not None:
            if self.spin_up:
                raise ValueError("initial_temperature and spin_up: true exclude each other: the spin-up "
                                 "forgets the start's temperatures; set spin_up: false or drop "
                                 "initial_temperature")
        return self


class TimeSpan(_Model):
    """A sequence of frames: every ``step`` from ``start`` to ``end`` (both included when the
    steps land on it)."""

    start: _dt.datetime = Field(description="the first frame's instant, with its UTC offset")
    end: _dt.datetime = Field(description="the last instant a frame may have, with its UTC offset")
    step: Duration = Field(description="time between frames [s]")

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
    terrain: Terrain | None = Field(None, description="the ground: procedural hills, a DEM or a "
                                    "wind-driven sea")
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
