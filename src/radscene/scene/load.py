"""Load a scene file: validate it, resolve materials, files and geometry into a :class:`Scene`.

Every problem is raised as one :class:`~radscene.errors.ConfigError` naming the key path
(``objects[2].material``) and what would be accepted.
"""

from __future__ import annotations

import copy
import datetime as _dt
import os
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
import yaml
from pydantic import ValidationError

from radscene.atmosphere import Atmosphere, make_atmosphere
from radscene.errors import ConfigError, did_you_mean, unreadable
from radscene.scene import schema

#: Surface temperature of faces without a given one when the heat balance does not run [K].
DEFAULT_TEMPERATURE = 293.15

__all__ = ["Scene", "SceneObject", "Band", "ObserverSetup", "load_scene", "read_scene_file"]


@dataclass
class SceneObject:
    """One ray-traceable object: its mesh and per-face material and temperature.

    Attributes
    ----------
    name : str
    mesh : radscene.geometry.Mesh
    face_material : numpy.ndarray
        Index into ``Scene.materials`` for each face, shape (n_faces,).
    face_temperature : numpy.ndarray
        Surface temperature of each face [K], shape (n_faces,).
    textures : dict
        ``{"reflectance"|"emissivity"|"transmittance": Texture}`` multipliers.
    is_terrain : bool
    face_fixed : numpy.ndarray or None
        Whether each face's temperature was given in the scene file (True) or is left to the
        heat balance (False), shape (n_faces,); None: every face given.
    face_corner_temperature : numpy.ndarray or None
        Temperature at each face's three corners [K], shape (n_faces, 3), in the order of the
        face's vertices: the renderer interpolates it across the face a ray hits; None: each
        face at its ``face_temperature``.
    """

    name: str
    mesh: Any
    face_material: np.ndarray
    face_temperature: np.ndarray
    textures: dict = field(default_factory=dict)
    is_terrain: bool = False
    face_fixed: np.ndarray | None = None
    face_corner_temperature: np.ndarray | None = None
    #: A semi-transparent sheet: rays pass through it with its material's transmittance.
    transmissive: bool = False


@dataclass
class Band:
    """A named spectral band and its response."""

    name: str
    response: Any


@dataclass
class ObserverSetup:
    """A camera, its supersampling, the bands it records and the sensor behind it."""

    name: str
    camera: Any
    supersample: int
    bands: list[str]
    kind: str
    sensor: Any = None
    frames: int = 1
    #: The hyperspectral grid (radscene.radiometry.ChannelGrid), None for a band observer.
    spectral: Any = None
    #: Whether a spectral observer's cube keeps its term layers (``spectral.terms``).
    spectral_terms: bool = False


@dataclass
class Scene:
    """A loaded, validated scene: everything the renderer needs, nothing computed yet."""

    name: str
    description: str
    spec: schema.SceneSpec
    objects: list[SceneObject]
    materials: list
    material_names: list[str]
    bands: list[Band]
    observers: list[ObserverSetup]
    atmosphere: Atmosphere
    location: schema.Location
    time: _dt.datetime | None
    sun: schema.SunOverride | None
    settings: schema.RenderSettings
    heightfield: Any = None
    source: Path | None = None
    #: The scene as given (the file's mapping or the dict), and the folder its relative file
    #: names resolve against: the provenance written into every output.
    document: dict | None = None
    base_dir: Path | None = None
    #: BRDF models of materials that have one, by material index (else Lambert + Phong).
    brdfs: dict = field(default_factory=dict)
    #: Participating volumes (radscene.render.volumes.Volume).
    volumes: list = field(default_factory=list)
    #: How each object (not the terrain) moves, by name (radscene.platform.motion.Motion).
    motions: dict = field(default_factory=dict)
    #: Where each object (not the terrain) stands, by name: ``(position (3,) [m], rotation
    #: (3, 3))`` of its mesh in the scene frame, at the scene's instant (its motion at t = 0 s)
    #: until a :class:`~radscene.pipeline.simulation.Simulation` moves it.
    poses: dict = field(default_factory=dict)
    #: The sea when the terrain is one (radscene.geometry.sea.TiledSea): its mesh at any time.
    sea: Any = None
    #: Objects derived from the scene by the renderer (ray tracer, face tables), built once.
    render_cache: dict = field(default_factory=dict, repr=False)
    #: What a run's memory is checked against: (bytes, where the figure comes from), from
    #: ``max_memory``, ``render.max_memory`` or the machine (radscene.scene.memory).
    memory_limit: tuple | None = None

    def band(self, name: str) -> Band:
        for band in self.bands:
            if band.name == name:
                return band
        known = [b.name for b in self.bands]
        raise ConfigError(f"unknown band {name!r}; known: {', '.join(known)}{did_you_mean(name, known)}",
                          key="band")

    def observer(self, name: str) -> ObserverSetup:
        for obs in self.observers:
            if obs.name == name:
                return obs
        known = [o.name for o in self.observers]
        raise ConfigError(
            f"unknown observer {name!r}; known: {', '.join(known)}{did_you_mean(name, known)}",
            key="observer",
        )


# ---------------------------------------------------------------------------------------------


_TAGS = ("flat", "procedural", "dem", "sea", "box", "cylinder", "plate", "mesh", "ellipsoid", "orthographic",
         "perspective", "file", "noise", "function-after", "function-before", "image", "tile")


def _key(loc: tuple, data=None) -> str:
    """The dotted key of a pydantic error location. Pydantic inserts the tag of a tagged union
    into the path; with the scene's ``data`` a part is a tag where the data at that point is a
    mapping whose ``type`` is that tag (an object or material named like a tag is a key), and
    without it wherever it is a tag's name."""
    out = ""
    node = data
    for part in loc:
        if isinstance(part, int):
            out += f"[{part}]"
            node = node[part] if isinstance(node, list) and -len(node) <= part < len(node) else None
            continue
        if part in _TAGS and (node.get("type") == part if isinstance(node, dict) else data is None):
            continue  # a discriminator tag pydantic inserted into the path
        out += f".{part}" if out else str(part)
        node = node.get(part) if isinstance(node, dict) else None
    return out


def _schema_keys() -> list[str]:
    """Every key the scene schema knows, for "did you mean" suggestions."""
    import inspect

    from pydantic import BaseModel

    keys = set()
    for _, cls in inspect.getmembers(schema, inspect.isclass):
        if issubclass(cls, BaseModel) and cls.__module__ == schema.__name__:
            keys.update(cls.model_fields)
    return sorted(keys)


def _validation_error(err: ValidationError, data=None) -> ConfigError:
    first = err.errors()[0]
    key = _key(first.get("loc", ()), data)
    msg = first.get("msg", "invalid value")
    msg = msg.removeprefix("Value error, ")
    if first.get("type") == "extra_forbidden":
        msg = "unknown key"
        loc = first.get("loc", ())
        if loc and isinstance(loc[-1], str):
            known = _schema_keys()
            msg = "not accepted here" if loc[-1] in known else msg + did_you_mean(loc[-1], known, cutoff=0.75)
    elif first.get("type") == "missing":
        msg = "required key is missing"
    elif first.get("type") == "union_tag_invalid":
        ctx = first.get("ctx", {})
        tag, expected = ctx.get("tag"), str(ctx.get("expected_tags", ""))
        known = [t.strip().strip("'\"") for t in expected.split(",") if t.strip()]
        field_name = str(ctx.get("discriminator", "type")).strip("'\"")
        msg = f"unknown {field_name} {tag!r}; known: {', '.join(known)}{did_you_mean(tag, known)}"
        key = _key((*first.get("loc", ()), field_name), data)
    elif first.get("type") == "union_tag_not_found":
        msg = f"a 'type' key is needed, one of: {first.get('ctx', {}).get('discriminator')}"
    more = len(err.errors()) - 1
    if more:
        msg += f" (and {more} more problem{'s' if more > 1 else ''})"
    return ConfigError(msg, key=key or "scene")


def read_scene_file(path: str | Path) -> dict:
    """Read a scene YAML file into a dict, with clear errors for missing, empty or odd files."""
    path = Path(path)
    if not path.is_file():
        raise ConfigError(f"no such scene file: {path}", key="scene")
    try:
        data = yaml.safe_load(path.read_text(encoding="utf-8"))
    except yaml.YAMLError as err:
        mark = getattr(err, "problem_mark", None)
        where = f" at line {mark.line + 1}, column {mark.column + 1}" if mark else ""
        problem = getattr(err, "problem", None) or str(err).splitlines()[0]
        raise ConfigError(f"malformed YAML{where}: {problem}", key=str(path)) from None
    if data is None:
        raise ConfigError("the scene file is empty; expected a mapping with environment, "
                          "bands, observers and terrain or objects", key=str(path))
    if not isinstance(data, dict):
        raise ConfigError(
            f"a scene is a mapping (key: value), not a {type(data).__name__}", key=str(path)
        )
    return data


def load_scene(source: str | Path | dict, base_dir: str | Path | None = None, *,
               max_memory=None, confine: bool = False) -> Scene:
    """Load and validate a scene.

    Parameters
    ----------
    source : str, pathlib.Path or dict
        A scene YAML file or the same content as a dict.
    base_dir : str or pathlib.Path, optional
        Folder that relative file names are resolved against; by default the scene file's
        folder (or the working directory for a dict).
    max_memory : float or str, optional
        The memory a render may need [bytes, or e.g. ``"8 GB"``]: a scene whose estimate
        (:mod:`radscene.scene.memory`) exceeds it is refused before anything is built; default
        ``render.max_memory``, else the machine's memory.
    confine : bool
        Read no file outside the scene's folder (``base_dir``): for scene files of unknown
        origin (:mod:`radscene.scene.confine`).

    Returns
    -------
    Scene

    Raises
    ------
    radscene.errors.ConfigError
        With the key path of the first problem and what would be accepted.
    """
    path = None
    if isinstance(source, dict):
        data = source
    elif isinstance(source, (str, Path)):
        path = Path(source)
        data = read_scene_file(path)
    else:
        raise ConfigError(
            f"a scene is a file path or a mapping, not a {type(source).__name__}", key="scene"
        )
    base = Path(base_dir) if base_dir is not None else (path.parent if path else Path.cwd())
    if confine and isinstance(data, dict):
        from radscene.scene.confine import check_confined

        check_confined(data, base)
    try:
        spec = schema.SceneSpec.model_validate(data)
    except ValidationError as err:
        raise _validation_error(err, data) from None
    from radscene.scene.memory import check_memory, memory_limit, parse_memory

    limit = None if max_memory is None else parse_memory(max_memory, "--max-memory")
    check_memory(spec, limit, base)
    scene = _Resolver(spec, base, path).resolve()
    scene.document = copy.deepcopy(data)
    scene.base_dir = Path(os.path.realpath(base))
    scene.memory_limit = memory_limit(spec, limit)
    return scene


class _Resolver:
    def __init__(self, spec: schema.SceneSpec, base: Path, path: Path | None):
        self.spec = spec
        self.base = base
        self.path = path
        self.materials: list = []
        self.material_names: list[str] = []
        self.brdfs: dict = {}
        self.motions: dict = {}
        self.poses: dict = {}
        self.sea_surface = None

    # -- helpers ---------------------------------------------------------------------------
    def file(self, name: str, key: str) -> Path:
        p = Path(name)
        if not p.is_absolute():
            p = self.base / p
        if not p.is_file():
            raise ConfigError(f"file not found: {p}", key=key)
        return p

    def _material_temperatures(self, objects) -> None:
        """``thermal.materials.<name>.temperature``: fix the faces of that material that have no
        temperature of their own."""
        for name, settings in self.spec.thermal.materials.items():
            if settings.temperature is None:
                continue
            if name not in self.material_names:
                raise ConfigError(f"no surface of the scene is made of {name!r}; the scene's materials: "
                                  f"{', '.join(self.material_names)}", key=f"thermal.materials.{name}.temperature")
            idx = self.material_names.index(name)
            for obj in objects:
                if obj.face_fixed is None:
                    continue
                free = (obj.face_material == idx) & ~obj.face_fixed
                obj.face_temperature[free] = settings.temperature
                obj.face_fixed[free] = True

    def material_index(self, name: str, key: str) -> int:
        from radscene.materials import get_material, list_materials

        lname = name.lower()
        if lname in self.material_names:
            return self.material_names.index(lname)
        custom = {k.lower(): v for k, v in self.spec.materials.items()}
        if lname in custom:
            from radscene.materials import make_material

            mspec = dict(custom[lname])
            brdf_spec = mspec.pop("brdf", None)
            mspec.setdefault("type", "custom")
            try:
                material = make_material(mspec, key=f"materials.{name}", base_dir=self.base)
            except ConfigError as err:
                inner = err.key or ""
                if inner.startswith("materials."):
                    raise ConfigError(err.message, key=inner) from None
                # a file:line (or other) location stays in the message
                message = f"{inner}: {err.message}" if inner else err.message
                raise ConfigError(message, key=f"materials.{name}") from None
            if material.name != lname:
                import dataclasses

                material = dataclasses.replace(material, name=lname)
        else:
            try:
                material = get_material(lname)
            except ConfigError:
                known = sorted(set(list_materials()) | set(custom))
                raise ConfigError(
                    f"unknown material {name!r}; known: {', '.join(known)}{did_you_mean(lname, known)}",
                    key=key,
                ) from None
        self.materials.append(material)
        self.material_names.append(lname)
        if lname in custom and brdf_spec is not None:
            from radscene.materials import make_brdf

            key = f"materials.{name}.brdf"
            try:
                self.brdfs[len(self.materials) - 1] = make_brdf(brdf_spec, key=key,
                                                                base_dir=self.base)
            except ConfigError as err:
                if err.key and err.key.startswith(key):
                    raise
                # a table file's error names the file (and line): the message keeps it
                raise ConfigError(f"{err.key}: {err.message}" if err.key else err.message,
                                  key=key) from None
        return len(self.materials) - 1

    def mixture_index(self, fractions: dict, key: str) -> int:
        """Index of the areal (linear) mixture of named materials with the given fractions."""
        from radscene.materials import mix_materials

        name = " + ".join(f"{f:g} {m.lower()}" for m, f in fractions.items())
        if name in self.material_names:
            return self.material_names.index(name)
        parts = [(f, self.materials[self.material_index(m, f"{key}.{m}")])
                 for m, f in fractions.items()]
        try:
            material = mix_materials(parts, name=name)
        except ConfigError as err:
            raise ConfigError(err.message, key=key) from None
        self.materials.append(material)
        self.material_names.append(name)
        return len(self.materials) - 1

    def textures(self, tset: schema.TextureSet, key: str) -> dict:
        from radscene.materials import Texture, make_texture

        out = {}
        for kind in ("reflectance", "emissivity", "transmittance"):
            tspec = getattr(tset, kind)
            if tspec is None:
                continue
            k = f"{key}.textures.{kind}"
            try:
                if tspec.type == "image":
                    out[kind] = Texture.from_image(
                        self.file(tspec.file, f"{k}.file"),
                        size=tspec.size,
                        origin=tspec.origin,
                        contrast=tspec.contrast,
                    )
                    continue
                spec = tspec.model_dump(exclude_none=True)
                if "file" in spec:
                    spec["file"] = str(self.file(spec["file"], f"{k}.file"))
                out[kind] = make_texture(spec, key=k)  # tile or noise
            except ConfigError as err:
                raise ConfigError(err.message, key=err.key if err.key and err.key.startswith(k) else k) from None
        return out

    # -- parts -----------------------------------------------------------------------------
    def terrain(self):
        from radscene.geometry import Heightfield, procedural_terrain

        tspec = self.spec.terrain
        water = None
        if isinstance(tspec, schema.SeaTerrain):
            return self.sea(tspec)
        if isinstance(tspec, schema.ProceduralTerrain):
            # the generator centres its grid on (0, 0); the scene puts its south-west corner
            # at `origin`
            spacing = tspec.spacing
            shift = tuple(o + 0.5 * round(s / spacing) * spacing
                          for o, s in zip(tspec.origin, tspec.size, strict=True))
            hf, water = procedural_terrain(
                size=tspec.size,
                spacing=spacing,
                relief=tspec.relief,
                seed=tspec.seed,
                lakes=[(lk.x - shift[0], lk.y - shift[1], lk.radius, lk.depth)
                       for lk in tspec.lakes],
            )
            hf = Heightfield(hf.elevation, origin=(hf.origin[0] + shift[0], hf.origin[1] + shift[1]),
                             spacing=hf.spacing)
        elif isinstance(tspec, schema.FlatTerrain):
            n = [round(s / tspec.spacing) + 1 for s in tspec.size]
            hf = Heightfield(np.full((n[1], n[0]), tspec.height), origin=tspec.origin,
                             spacing=(tspec.spacing, tspec.spacing))
        else:
            try:
                if tspec.file is not None:
                    fpath = self.file(tspec.file, "terrain.file")
                    if fpath.suffix.lower() == ".npy":
                        if tspec.spacing is None:
                            raise ConfigError("a .npy DEM needs 'spacing' [m, m]", key="terrain.spacing")
                        hf = Heightfield(_load_npy(fpath, "terrain.file"), origin=tspec.origin,
                                         spacing=tspec.spacing)
                    else:
                        hf = Heightfield.from_geotiff(fpath)
                else:
                    hf = Heightfield(
                        np.asarray(tspec.elevation, dtype=float),
                        origin=tspec.origin,
                        spacing=tspec.spacing,
                    )
            except ConfigError as err:
                key = "terrain.file" if tspec.file is not None else "terrain.elevation"
                raise ConfigError(err.message, key=err.key if err.key and err.key.startswith("terrain") else key) from None
        mesh = hf.to_mesh(name="terrain")
        ny, nx = hf.elevation.shape
        # sample classes per grid node, then per face by the face's first vertex cell
        classes = self._terrain_classes(tspec, hf)
        if water is not None and np.any(water):
            widx = self.material_index(tspec.water_material, "terrain.water_material")
            classes = np.where(water, widx, classes)
        face_material = self._face_values(mesh, hf, classes)
        self._paint_roads(tspec, hf, mesh, face_material)
        face_temperature = np.full(len(face_material), DEFAULT_TEMPERATURE if tspec.temperature is None
                                   else tspec.temperature)
        face_fixed = np.full(len(face_material), tspec.temperature is not None)
        for mname, temp in tspec.temperatures.items():
            idx = self.material_index(mname, f"terrain.temperatures.{mname}")
            face_temperature[face_material == idx] = temp
            face_fixed[face_material == idx] = True
        if tspec.temperature_map is not None:
            key = "terrain.temperature_map"
            image = _read_temperatures(self.file(tspec.temperature_map, key), key)
            face_temperature = self._face_values(mesh, hf, _resample_nearest(image, (ny, nx)))
            face_fixed[:] = True
        return hf, SceneObject(
            name="terrain",
            mesh=mesh,
            face_material=face_material,
            face_temperature=face_temperature,
            textures=self.textures(tspec.textures, "terrain"),
            is_terrain=True,
            face_fixed=face_fixed,
        )

    def sea(self, tspec):
        """A sea as the terrain: its waves (``self.sea_surface``, a TiledSea), the mesh at
        t = 0 and the facets' material, whose Cox-Munk BRDF carries the slope variance of the
        waves shorter than the mesh resolves (docs/sea.md). Returns the mean sea level (for
        objects on the ground) and the terrain object."""
        import dataclasses

        from radscene.geometry.sea import SeaSurface, TiledSea, wind_at_height
        from radscene.materials.brdf import CoxMunk
        from radscene.materials.brdf.coxmunk import mean_square_slope

        total = float(mean_square_slope(wind_at_height(tspec.wind_speed, 12.5)))
        surface = None
        if not tspec.far_field and tspec.wind_speed > 0.0:
            try:
                surface = SeaSurface.from_spectrum(
                    tspec.spectrum, tspec.wind_speed, tspec.wind_direction, tile=tspec.tile,
                    resolution=tspec.resolution, fetch=tspec.fetch, gamma=tspec.gamma,
                    spreading_exponent=tspec.spreading, seed=tspec.seed)
            except ConfigError as err:
                raise ConfigError(err.message, key=f"terrain.{err.key}") from None
        sea = TiledSea(surface, tspec.size, tspec.origin)
        resolved = 0.0 if surface is None else surface.mesh_slope_variance()
        if resolved >= total:
            raise ConfigError(
                f"the mesh resolves a slope variance of {resolved:.4g}, more than Cox & Munk's "
                f"{total:.4g} for the wind: nothing is left for the facets' roughness; use a "
                "coarser resolution", key="terrain.resolution")
        base = self.material_index(tspec.material, "terrain.material")
        name = f"{self.material_names[base]} (sea facets)"
        self.materials.append(dataclasses.replace(self.materials[base], name=name))
        self.material_names.append(name)
        midx = len(self.materials) - 1
        self.brdfs[midx] = CoxMunk(mean_square_slope=total - resolved, key="terrain.material")
        self.sea_surface = sea
        mesh = sea.mesh(0.0)
        n = len(mesh.faces)
        return sea.mean_level(), SceneObject(
            name="terrain",
            mesh=mesh,
            face_material=np.full(n, midx, dtype=np.int64),
            face_temperature=np.full(n, tspec.temperature),
            is_terrain=True,
            face_fixed=np.ones(n, dtype=bool),
        )

    def _paint_roads(self, tspec, hf, mesh, face_material) -> None:
        """Give the road's material to every terrain face whose centroid lies within half the
        road's width of its centre line (in x, y), road after road (a later road over an
        earlier one); changes ``face_material`` in place."""
        from radscene.geometry.terrain import polyline_distance

        if not tspec.roads:
            return
        centroid = mesh.vertices[mesh.faces].mean(axis=1)[:, :2]
        spacing = float(min(hf.spacing))
        for i, road in enumerate(tspec.roads):
            key = f"terrain.roads[{i}]"
            if road.width < spacing * (1.0 - 1e-9):
                raise ConfigError(f"{road.width:g} m is narrower than the terrain's spacing {spacing:g} m: "
                                  "the stripe would break into separate faces; give a width of at least "
                                  "the spacing, or a finer terrain", key=f"{key}.width")
            idx = self.material_index(road.material, f"{key}.material")
            on = polyline_distance(centroid, np.asarray(road.points, float)) <= 0.5 * road.width
            if not np.any(on):
                x0, x1, y0, y1 = hf.extent
                label = f"road {road.name!r}: " if road.name else ""
                raise ConfigError(f"{label}no terrain face lies within {0.5 * road.width:g} m "
                                  f"of its centre line; the terrain spans x {x0:g}..{x1:g} m, y {y0:g}..{y1:g} m",
                                  key=f"{key}.points")
            face_material[on] = idx

    def _terrain_classes(self, tspec, hf) -> np.ndarray:
        ny, nx = hf.elevation.shape
        mmap = tspec.material_map
        if mmap is None:
            return np.full((ny, nx), self.material_index(tspec.material, "terrain.material"))
        if isinstance(mmap, schema.MaterialMapNoise):
            from scipy import ndimage

            idx = np.array(
                [self.material_index(m, f"terrain.material_map.materials[{i}]") for i, m in enumerate(mmap.materials)]
            )
            rng = np.random.default_rng(mmap.seed)
            field_ = ndimage.gaussian_filter(
                rng.standard_normal((ny, nx)),
                sigma=(mmap.scale / hf.spacing[1] / 2.0, mmap.scale / hf.spacing[0] / 2.0),
                mode="wrap",
            )
            edges = np.quantile(field_, np.linspace(0, 1, len(idx) + 1)[1:-1])
            return idx[np.searchsorted(edges, field_)]
        # classified image resampled by nearest neighbour onto the grid
        fpath = self.file(mmap.file, "terrain.material_map.file")
        image = _read_image(fpath, "terrain.material_map.file")
        if image.dtype.kind == "f" and not np.all(np.isfinite(image) & (image == np.round(image))):
            raise ConfigError("class values are integers; the image holds other numbers",
                              key="terrain.material_map.file")
        image = image.astype(np.int64)
        lut = {}
        for value, mname in mmap.classes.items():
            k = f"terrain.material_map.classes.{value}"
            lut[value] = (self.material_index(mname, k) if isinstance(mname, str)
                          else self.mixture_index(mname, k))
        sampled = _resample_nearest(image, (ny, nx))
        unknown = sorted(set(np.unique(sampled).tolist()) - set(lut))
        if unknown:
            raise ConfigError(
                f"the image holds class values {unknown} that 'classes' does not map; "
                f"mapped: {sorted(lut)}",
                key="terrain.material_map.classes",
            )
        out = np.empty_like(sampled, dtype=np.int64)
        for value, idx in lut.items():
            out[sampled == value] = idx
        return out

    @staticmethod
    def _face_values(mesh, hf, grid_values) -> np.ndarray:
        centroid = mesh.vertices[mesh.faces].mean(axis=1)
        row, col = hf.cell_index(centroid[:, 0], centroid[:, 1])
        return np.asarray(grid_values)[row, col]

    def objects(self, hf) -> list:
        from radscene.geometry import Mesh, box, cylinder, load_mesh, plate
        from radscene.platform.motion import compose

        out = []
        self.motions = {o.name: self.motion(i, o, hf) for i, o in enumerate(self.spec.objects)}
        # every object where its motion puts it at the scene's instant (t = 0 s): its trajectory's
        # point, its spin's angle, its parent's pose; the scene file's position when it is still
        self.poses = compose({n: m.pose(0.0) for n, m in self.motions.items()},
                             {n: m.parent for n, m in self.motions.items()})
        rest = compose({n: m.rest_pose() for n, m in self.motions.items()},
                       {n: m.parent for n, m in self.motions.items()})
        for i, ospec in enumerate(self.spec.objects):
            key = f"objects[{i}]"
            shape = ospec.shape
            if shape.type == "box":
                mesh = box(shape.size)
            elif shape.type == "cylinder":
                mesh = cylinder(shape.radius, shape.height, shape.sections)
            elif shape.type == "plate":
                mesh = plate(shape.width, shape.length)
            else:
                try:
                    mesh = load_mesh(self.file(shape.file, f"{key}.shape.file"), name=ospec.name)
                except ConfigError as err:
                    raise ConfigError(err.message, key=f"{key}.shape.file") from None
                mesh = mesh.transformed(scale=shape.scale)
            p, rot = self.poses[ospec.name]
            if ospec.parent is None and np.array_equal(p, rest[ospec.name][0]) and np.array_equal(
                    rot, rest[ospec.name][1]):  # where the scene file places it
                mesh = mesh.transformed(translation=p, rotation=ospec.rotation)
            else:  # on its trajectory, or a part in its parent's frame
                mesh = Mesh(mesh.vertices @ rot.T + p, mesh.faces, name=mesh.name)
            mesh.name = ospec.name
            midx = self.material_index(ospec.material, f"{key}.material")
            if ospec.transmissive and not np.any(
                    np.asarray(self.materials[midx].transmittance.values) > 0.0):
                raise ConfigError(f"material {ospec.material!r} has no transmittance: give it "
                                  "one, or remove transmissive: true", key=f"{key}.transmissive")
            n = len(mesh.faces)
            out.append(
                SceneObject(
                    name=ospec.name,
                    mesh=mesh,
                    face_material=np.full(n, midx, dtype=np.int64),
                    face_temperature=np.full(n, DEFAULT_TEMPERATURE if ospec.temperature is None
                                             else ospec.temperature),
                    textures=self.textures(ospec.textures, key),
                    face_fixed=np.full(n, ospec.temperature is not None),
                    transmissive=ospec.transmissive,
                )
            )
        return out

    def motion(self, i: int, ospec, hf):
        """How ``objects[i]`` moves (radscene.platform.motion.Motion): its trajectory, from
        waypoints, a route or a track file, its attitude mode, the terrain under it, its spin
        and its parent. An object that does not move gets one too (its rest pose)."""
        from radscene.platform.motion import Motion, path_trajectory, route_times
        from radscene.platform.track_file import read_track

        key = f"objects[{i}]"
        tspec = ospec.trajectory
        on_ground = ospec.on_ground if tspec is None or tspec.on_ground is None else tspec.on_ground
        terrain = hf if on_ground and hf is not None and ospec.parent is None else None
        if terrain is not None:
            x, y = ospec.position[:2]
            xmin, xmax, ymin, ymax = hf.extent
            if not (xmin <= x <= xmax and ymin <= y <= ymax):
                raise ConfigError(f"({x:g}, {y:g}) m lies outside the terrain {hf.extent} m; "
                                  "place it inside or set on_ground: false", key=f"{key}.position")
        trajectory, attitude, source = None, "fixed", "waypoints"
        if tspec is not None:
            attitudes = quaternions = None
            if tspec.waypoints is not None:
                rows = np.array(tspec.waypoints, float)
                times, positions = rows[:, 0], rows[:, 1:4]
                attitudes = rows[:, 4:7] if rows.shape[1] == 7 else None
            elif tspec.route is not None:
                source = "route"
                positions = np.array(tspec.route, float)
                try:
                    times = route_times(positions, tspec.speed, tspec.start)
                except ConfigError as err:
                    raise ConfigError(err.message, key=f"{key}.trajectory.{err.key}") from None
            else:
                source = "track"
                fkey = f"{key}.trajectory.file"
                track = read_track(self.file(tspec.file, fkey), key=fkey)
                times, positions = track.times, track.positions
                attitudes, quaternions = track.attitudes, track.quaternions
            tabulated = attitudes is not None or quaternions is not None
            attitude = tspec.attitude or ("tabulated" if tabulated else "fixed")
            if attitude == "tabulated" and not tabulated:
                raise ConfigError(f"{tspec.file}: the track has no attitude columns (yaw, pitch, roll "
                                  "or qw, qx, qy, qz)", key=f"{key}.trajectory.attitude")
            if attitude != "tabulated" and tabulated:
                raise ConfigError(f"{tspec.file}: the track's attitudes would be ignored by attitude "
                                  f"{attitude!r}; remove the columns or the attitude",
                                  key=f"{key}.trajectory.attitude")
            trajectory = path_trajectory(times, positions, attitudes, quaternions=quaternions,
                                         interpolation=tspec.interpolation)
            if attitude == "banked" and on_ground and ospec.parent is None:
                raise ConfigError("attitude 'banked' is for airborne objects; on the ground the "
                                  "terrain sets pitch and roll (attitude 'path'), or set "
                                  "on_ground: false", key=f"{key}.trajectory.attitude")
        spin = ospec.spin
        return Motion(key, np.array(ospec.position, float), tuple(ospec.rotation), trajectory, attitude,
                      terrain, None if spin is None else np.array(spin.axis, float),
                      0.0 if spin is None else spin.rate, ospec.parent, source)

    def density_grid(self, profile, key) -> np.ndarray:
        """A volume's density grid (n_z, n_y, n_x) from a .npy file or a NetCDF variable with
        dims (z, y, x): finite, >= 0, at least two nodes along each axis."""
        path = self.file(profile.file, f"{key}.file")
        if path.suffix.lower() == ".npy":
            grid = _load_npy(path, f"{key}.file")
        else:
            import xarray as xr

            try:
                with xr.open_dataset(path) as ds:
                    if profile.variable not in ds:
                        raise ConfigError(f"{path.name} has no variable {profile.variable!r}; "
                                          f"it holds: {', '.join(map(str, ds.data_vars))}",
                                          key=f"{key}.variable")
                    var = ds[profile.variable]
                    if var.dims != ("z", "y", "x"):
                        raise ConfigError(f"{profile.variable!r} has dims {var.dims}; expected "
                                          "('z', 'y', 'x')", key=f"{key}.file")
                    if not np.issubdtype(var.dtype, np.number):
                        raise ConfigError(f"{profile.variable!r} is not numeric", key=f"{key}.file")
                    grid = var.values
            except ConfigError:
                raise
            except Exception:  # noqa: BLE001 - whatever the NetCDF libraries raise: a bad file
                raise ConfigError(f"{path.name}: not a readable NetCDF file",
                                  key=f"{key}.file") from None
        grid = np.asarray(grid, dtype=float)
        if grid.ndim != 3 or min(grid.shape) < 2:
            raise ConfigError(f"a density grid has three dimensions (z, y, x) of at least two "
                              f"nodes each; got shape {grid.shape}", key=f"{key}.file")
        if not np.all(np.isfinite(grid)) or np.any(grid < 0.0):
            raise ConfigError("a density grid must be finite and >= 0 everywhere",
                              key=f"{key}.file")
        return grid

    @staticmethod
    def gas(vspec, key):
        """A gas volume's band absorption (radscene.materials.gas.GasAbsorption); a state the
        model does not cover names ``key.temperature`` or ``key.gas.<key>``."""
        from radscene.materials.gas import GasAbsorption

        spec = vspec.gas
        fractions = (("co2", spec.co2), ("h2o", spec.h2o))
        try:
            return GasAbsorption(fractions, vspec.temperature, spec.pressure, spec.model)
        except ConfigError as err:
            where = f"{key}.temperature" if err.key == "temperature" else f"{key}.gas.{err.key}"
            raise ConfigError(err.message, key=where) from None

    def volumes(self) -> list:
        from radscene.materials.spectrum import make_spectrum
        from radscene.render.volumes import Volume, optical_path

        out = []
        for i, vspec in enumerate(self.spec.volumes):
            key = f"volumes[{i}]"
            shape = vspec.shape
            half = np.asarray(shape.size if shape.type == "box" else shape.radii, float)
            if shape.type == "box":
                half = half / 2.0
            profile = vspec.profile
            sigma = None if profile.sigma is None else np.broadcast_to(
                np.asarray(profile.sigma, float), (3,)).copy()
            given = ("gas" if vspec.gas is not None else
                     "extinction" if vspec.extinction is not None else "optical_depth")
            overlap = None
            if given == "gas":
                spectrum = self.gas(vspec, key)
                overlap = spectrum.line_overlap
            else:
                spectrum = make_spectrum(getattr(vspec, given), key=f"{key}.{given}",
                                         base_dir=self.base)
                values = np.asarray(spectrum.values, float)
                if np.any(values < 0.0) or not np.all(np.isfinite(values)):
                    raise ConfigError(f"must be finite and >= 0 everywhere; got a minimum of "
                                      f"{float(np.min(values)):g}", key=f"{key}.{given}")
            wavelengths = (np.zeros(0) if spectrum.wavelength is None
                           else np.asarray(spectrum.wavelength, float))
            volume = Volume(vspec.name, shape.type, np.asarray(vspec.position, float), half,
                            spectrum, profile.type,
                            np.inf if profile.scale_height is None else profile.scale_height,
                            sigma, vspec.density, vspec.single_scattering_albedo,
                            vspec.temperature, wavelengths, vspec.asymmetry,
                            None if profile.type != "grid" else self.density_grid(
                                profile, f"{key}.profile"), overlap)
            if given == "optical_depth":
                # k = τ / X along the vertical through the centre, from below
                below = volume.center - np.array([0.0, 0.0, 2.0 * half[2] + 1.0])
                vertical = float(optical_path(volume, below[None], np.array([[0.0, 0.0, 1.0]]))[0])
                if not vertical > 0.0:
                    raise ConfigError("an optical depth needs a density above 0 along the "
                                      "vertical through the centre", key=f"{key}.density")
                volume = Volume(*(getattr(volume, f) for f in (
                    "name", "shape", "center", "half_size")),
                    _Scaled(spectrum, 1.0 / vertical), *(getattr(volume, f) for f in (
                        "profile", "scale_height", "sigma", "density", "albedo",
                        "temperature", "wavelengths", "asymmetry", "grid")))
            out.append(volume)
        return out

    def bands(self) -> list[Band]:
        from radscene.radiometry import GaussianResponse, RectangularResponse, TabulatedResponse

        out = []
        for i, b in enumerate(self.spec.bands):
            try:
                if b.type == "rectangular":
                    resp = RectangularResponse(b.min, b.max, name=b.name)
                elif b.type == "gaussian":
                    resp = GaussianResponse(b.center, b.fwhm, name=b.name)
                elif b.type == "library":
                    from radscene.sensor.srf_library import get_band

                    resp = get_band(b.sensor, b.band)
                else:
                    resp = TabulatedResponse.from_file(self.file(b.file, f"bands[{i}].file"), name=b.name)
            except ConfigError as err:
                raise ConfigError(err.message, key=f"bands[{i}]") from None
            out.append(Band(b.name, resp))
        return out

    def sensors(self) -> dict:
        """Sensor models by name: inline, ``{file: path}`` or ``{example: name}``, the last two
        with optional overrides deep-merged into the file's mapping (e.g. a smaller array)."""
        from radscene.sensor import example_sensor_path, example_sensors, make_sensor
        from radscene.sensor.config import read_sensor_file

        out = {}
        for name, spec in self.spec.sensors.items():
            key = f"sensors.{name}"
            if not isinstance(spec, dict):
                raise ConfigError("a sensor is a mapping, {file: path} or {example: name}", key=key)
            spec = dict(spec)
            if "file" in spec or "example" in spec:
                if "file" in spec and "example" in spec:
                    raise ConfigError("give 'file' or 'example', not both", key=key)
                if "file" in spec:
                    path = self.file(spec.pop("file"), f"{key}.file")
                else:
                    example = spec.pop("example")
                    if example not in example_sensors():
                        raise ConfigError(f"unknown example sensor {example!r}; known: "
                                          f"{', '.join(example_sensors())}"
                                          f"{did_you_mean(example, example_sensors())}", key=f"{key}.example")
                    path = example_sensor_path(example)
                try:
                    base = read_sensor_file(path)["sensor"]  # the mapping, or a file's parts
                except ConfigError as err:
                    raise ConfigError(f"{path}: {err.message}", key=f"{key}.file") from None
                spec = _deep_merge(base, spec)
            out[name] = make_sensor(spec, key=key)
        return out

    def observers(self, band_names: list[str]) -> list[ObserverSetup]:
        from radscene.platform import OrthographicCamera, PerspectiveCamera

        sensors = self.sensors()
        out = []
        for i, o in enumerate(self.spec.observers):
            key = f"observers[{i}]"
            sensor = sensors.get(o.sensor) if getattr(o, "sensor", None) else None
            scanner = o.type in ("pushbroom", "whiskbroom")  # its shape and gsd/ifov set the grid
            geometry = sensor.observer_geometry() if sensor and not scanner else {}
            if geometry and o.shape is not None and tuple(o.shape) != geometry["shape"]:
                raise ConfigError(
                    f"sensor {o.sensor!r} records {geometry['shape'][0] // sensor.oversample} x "
                    f"{geometry['shape'][1] // sensor.oversample} detectors at {sensor.oversample} "
                    f"samples per pitch, so the render is {geometry['shape'][0]} x "
                    f"{geometry['shape'][1]} samples: omit shape or give that",
                    key=f"{key}.shape")
            shape = o.shape or geometry.get("shape")
            bands = o.bands if o.bands is not None else list(band_names)
            for j, bname in enumerate(bands):
                if bname not in band_names:
                    raise ConfigError(
                        f"unknown band {bname!r}; known: {', '.join(band_names)}"
                        f"{did_you_mean(bname, band_names)}",
                        key=f"{key}.bands[{j}]",
                    )
            if o.type in ("pushbroom", "whiskbroom"):
                from radscene.platform.config import build_observer, check_sensor_sampling
                from radscene.platform.geolocation import LocalFrame

                loc = self.spec.environment.location
                frame = LocalFrame(loc.latitude, loc.longitude, loc.altitude)
                cam = build_observer(o, frame, self.spec.environment.time, key=key)
                if sensor is not None:
                    check_sensor_sampling(cam, sensor, key, gsd=o.gsd)
                out.append(ObserverSetup(o.name, cam, o.supersample, bands, o.type, sensor,
                                         getattr(o, "frames", 1)))
                continue
            try:
                if o.type == "orthographic":
                    gsd = o.gsd or geometry["gsd_per_distance"] * o.altitude
                    cam = OrthographicCamera(
                        center=o.center, shape=shape, gsd=gsd, altitude=o.altitude,
                        zenith=o.zenith, azimuth=o.azimuth,
                    )
                else:
                    cam = PerspectiveCamera(
                        position=o.position, shape=shape, fov=o.fov or geometry.get("fov", 45.0),
                        look_at=o.look_at, attitude=o.attitude,
                    )
            except ConfigError as err:
                raise ConfigError(err.message, key=f"{key}.{err.key}" if err.key else key) from None
            grid = None
            if o.spectral is not None:
                from radscene.radiometry import channel_grid

                g = o.spectral
                grid = channel_grid(g.min, g.max, g.step, key=f"{key}.spectral")
                bands = []
            out.append(ObserverSetup(o.name, cam, o.supersample, bands, o.type, sensor, o.frames,
                                     grid, bool(o.spectral is not None and o.spectral.terms)))
        return out

    def _check_resolving_grid(self, observers, bands):
        """``render.spectral_grid``, where given: a valid grid that holds every band of the band
        observers (their non-linear layers are resolved on it)."""
        spec = self.spec.render.spectral_grid
        if spec is None:
            return
        from radscene.radiometry import channel_grid
        from radscene.render.resolved import KEY, grid_weights

        grid = channel_grid(spec.min, spec.max, spec.step, key=KEY)
        by_name = {b.name: b for b in bands}
        for o in observers:
            if o.spectral is None:
                grid_weights(grid, [by_name[n] for n in o.bands])

    def _atmosphere_spec(self) -> dict:
        """The atmosphere's settings with its files (a database, an engine executable) named
        relative to the scene file's folder made absolute, as every other file of a scene is
        (a shipped database's name stays a name)."""
        out = dict(self.spec.environment.atmosphere or {})
        for name in ("file", "executable"):
            value = out.get(name)
            if isinstance(value, str) and value and not Path(os.path.expanduser(value)).is_absolute():
                candidate = self.base / value
                if candidate.exists():
                    out[name] = str(candidate)
        return out

    def resolve(self) -> Scene:
        spec = self.spec
        try:
            atmosphere = make_atmosphere(self._atmosphere_spec())
        except ConfigError as err:
            key = err.key or ""
            if key.startswith("atmosphere"):
                key = "environment." + key
            raise ConfigError(err.message, key=key or "environment.atmosphere") from None
        if spec.render.coupling and atmosphere.couples and float(
                getattr(atmosphere, "surface_albedo", 0.0) or 0.0) > 0.0:
            raise ConfigError(
                "the render takes the surroundings' albedo from the scene itself (multiple "
                "reflection, render.coupling: true); remove it, or set "
                "render: {coupling: false} to use a fixed albedo instead",
                key="environment.atmosphere."
                + getattr(atmosphere, "surface_albedo_key", "surface_albedo"))
        hf, objects = None, []
        if spec.terrain is not None:
            hf, terrain_obj = self.terrain()
            objects.append(terrain_obj)
        objects.extend(self.objects(hf))
        self._material_temperatures(objects)
        volumes = self.volumes()
        bands = self.bands()
        observers = self.observers([b.name for b in bands])
        self._check_resolving_grid(observers, bands)
        if hf is not None:
            _check_above_terrain(spec.observers, hf)
        spans = [b.response.support for b in bands]
        for b in bands:  # the render checks each band's nodes; refused here, before it starts
            atmosphere.check_wavelength(np.asarray(b.response.support, dtype=float),
                                        key=f"bands[{b.name}]")
        for i, obs in enumerate(observers):
            if obs.spectral is not None:
                wl = obs.spectral.wavelength
                key = f"observers[{i}].spectral"
                atmosphere.check_wavelength(wl[[0, -1]], key=key)
                from radscene.sun.spectrum import SOLAR_WAVELENGTH_RANGE

                slo, shi = SOLAR_WAVELENGTH_RANGE
                if wl[0] < slo or wl[-1] > shi:
                    raise ConfigError(f"the grid spans {wl[0]:g}–{wl[-1]:g} µm; the renderer's "
                                      f"solar spectrum covers {slo:g}–{shi:g} µm", key=key)
                spans.append((float(wl[0]), float(wl[-1])))
        if spec.render.spectral_grid is not None:  # the grid band renders resolve on
            from radscene.radiometry import channel_grid
            from radscene.sun.spectrum import SOLAR_WAVELENGTH_RANGE

            g = spec.render.spectral_grid
            wl = channel_grid(g.min, g.max, g.step, key="render.spectral_grid").wavelength
            atmosphere.check_wavelength(wl[[0, -1]], key="render.spectral_grid")
            slo, shi = SOLAR_WAVELENGTH_RANGE
            if wl[0] < slo or wl[-1] > shi:
                raise ConfigError(f"the grid spans {wl[0]:g}–{wl[-1]:g} µm; the renderer's "
                                  f"solar spectrum covers {slo:g}–{shi:g} µm",
                                  key="render.spectral_grid")
            spans.append((float(wl[0]), float(wl[-1])))
        lo, hi = min(s[0] for s in spans), max(s[1] for s in spans)
        for m_name, material in zip(self.material_names, self.materials, strict=True):
            mlo, mhi = _material_range(material)
            if lo < mlo or hi > mhi:
                raise ConfigError(
                    f"material {m_name!r} is defined over {mlo:g}–{mhi:g} µm but the bands "
                    f"and spectral grids span {lo:g}–{hi:g} µm",
                    key=f"materials.{m_name}",
                )
        return Scene(
            name=spec.name,
            description=spec.description,
            spec=spec,
            objects=objects,
            materials=self.materials,
            material_names=self.material_names,
            bands=bands,
            observers=observers,
            atmosphere=atmosphere,
            location=spec.environment.location,
            time=spec.environment.time,
            sun=spec.environment.sun,
            settings=spec.render,
            heightfield=hf,
            source=self.path,
            brdfs=self.brdfs,
            volumes=volumes,
            motions=self.motions,
            poses=self.poses,
            sea=self.sea_surface,
        )


@dataclass(frozen=True)
class _Scaled:
    """A spectrum times a factor: a volume's extinction [m-1] from its optical depth."""

    spectrum: Any
    factor: float

    def __call__(self, wavelength):
        return self.spectrum(wavelength) * self.factor


def _check_above_terrain(observers, hf) -> None:
    """Refuse a frame camera below the terrain under it, or a map camera below its highest point."""
    top = float(np.max(hf.elevation))
    x0, x1, y0, y1 = hf.extent
    for i, o in enumerate(observers):
        if o.type == "perspective":
            x, y, z = o.position
            if x0 <= x <= x1 and y0 <= y <= y1:
                ground = float(hf.height_at(x, y))
                if z <= ground:
                    raise ConfigError(
                        f"the camera at z = {z:g} m is {ground - z:.3g} m below the terrain there "
                        f"(height {ground:g} m): it would see nothing but the inside of the ground; "
                        "raise it", key=f"observers[{i}].position")
        elif o.type == "orthographic" and o.altitude <= top:
            raise ConfigError(f"{o.altitude:g} m is not above the terrain's highest point ({top:g} m)",
                              key=f"observers[{i}].altitude")


def _material_range(material) -> tuple[float, float]:
    lo, hi = 0.0, np.inf
    for spec in (
        material.diffuse_reflectance,
        material.specular_reflectance,
        material.transmittance,
    ):
        slo, shi = spec.range
        if spec.extend == "error":
            lo, hi = max(lo, slo), min(hi, shi)
    return lo, hi


def _deep_merge(base: dict, override: dict) -> dict:
    """``base`` with ``override``'s keys replacing its own, recursively into mappings."""
    out = dict(base)
    for k, v in override.items():
        out[k] = _deep_merge(out[k], v) if isinstance(v, dict) and isinstance(out.get(k), dict) else v
    return out


def _resample_nearest(image: np.ndarray, shape: tuple[int, int]) -> np.ndarray:
    """Nearest-neighbour resampling of an image covering the terrain extent onto its grid."""
    ny, nx = shape
    rows = np.minimum(((np.arange(ny) + 0.5) * image.shape[0] / ny).astype(int), image.shape[0] - 1)
    cols = np.minimum(((np.arange(nx) + 0.5) * image.shape[1] / nx).astype(int), image.shape[1] - 1)
    return image[np.ix_(rows, cols)]


def _load_npy(path: Path, key: str) -> np.ndarray:
    """A numeric .npy array, or one line naming ``key`` (pickled objects are never loaded)."""
    try:
        array = np.load(path, allow_pickle=False)
    except (ValueError, OSError, EOFError) as err:
        reason = ("not a .npy array (reading it would need unpickling, which is never done)"
                  if "pickle" in str(err) else "not a readable .npy array")
        raise ConfigError(f"{path.name}: {reason}", key=key) from None
    if not isinstance(array, np.ndarray) or not np.issubdtype(array.dtype, np.number):
        raise ConfigError(f"{path.name}: not a numeric array", key=key)
    return array


def _read_image(path: Path, key: str) -> np.ndarray:
    """Read a single-band image as the numbers it stores, sized beforehand against the memory
    limit (radscene.scene.memory.image_header).

    Parameters
    ----------
    path : pathlib.Path
        A .npy array, a GeoTIFF (``.tif``, ``.tiff``: its first band) or an image Pillow
        opens (PNG, JPEG, ...: its levels, 8- or 16-bit, a palette's indices, the first
        channel of a colour image), read with Pillow's pixel-count limit lifted.
    key : str
        The scene key that names the file, for errors.

    Returns
    -------
    numpy.ndarray
        The 2-D image, in the file's own dtype: levels are never rescaled.

    Raises
    ------
    radscene.errors.ConfigError
        Naming ``key``: an unreadable file, or not one band of two dimensions.
    """
    suffix = path.suffix.lower()
    try:
        if suffix == ".npy":
            image = _load_npy(path, key)
        elif suffix in (".tif", ".tiff"):
            import rioxarray

            image = rioxarray.open_rasterio(path).values[0]
        else:
            from PIL import Image

            from radscene.materials.imagefile import pil_unlimited

            with pil_unlimited(), Image.open(path) as opened:
                image = np.asarray(opened)
            if image.ndim == 3:
                image = image[..., 0]
    except Exception as err:  # noqa: BLE001 - any reader failure is a bad file
        why = err.message if isinstance(err, ConfigError) else unreadable(err)
        raise ConfigError(f"cannot read image {path}: {why}", key=key) from None
    if image.ndim != 2:
        raise ConfigError(f"a 2-D single-band image is needed, got shape {image.shape}", key=key)
    return np.asarray(image)


#: A temperature map none of whose values exceeds this [K] holds image levels scaled to 0-1.
LEVELS_KELVIN = 1.0


def _read_temperatures(path: Path, key: str) -> np.ndarray:
    """A temperature map [K] (a .npy array or a GeoTIFF, integer or floating-point kelvin;
    the scene schema refuses the other formats) as float64.

    Raises
    ------
    radscene.errors.ConfigError
        Naming ``key``: a value not finite or not above 0 K, or every value at most
        :data:`LEVELS_KELVIN` (image levels scaled to 0-1, not temperatures).
    """
    image = _read_image(path, key).astype(float)
    if not np.all(np.isfinite(image)):
        raise ConfigError("temperatures must be finite and > 0 K everywhere; the map holds "
                          "values that are not finite", key=key)
    if np.any(image <= 0.0):
        raise ConfigError("temperatures must be finite and > 0 K everywhere; the map holds "
                          f"{image.min():g} K", key=key)
    if image.max() <= LEVELS_KELVIN:
        raise ConfigError(f"every value is at most {LEVELS_KELVIN:g} K (the largest "
                          f"{image.max():g}): these are image levels scaled to 0-1, not "
                          "temperatures; give the temperatures [K]", key=key)
    return image
