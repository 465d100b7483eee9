"""The scene file described for people and for editors, generated from :mod:`.schema`.

:func:`scene_json_schema` is a JSON Schema (draft-07, the draft YAML editors read) of the scene
file: quantities accept a number in the canonical unit or a string with a unit of their kind
(``"25 degC"``), and every key carries its unit in its description. :func:`scene_reference`
is the Markdown page of the documentation site that lists every key of every model with its
type, unit, default, description and an example (taken from the bundled example scenes where
they use the key, else from :data:`KEY_EXAMPLES`). Both are computed from the pydantic models
each time, so they cannot drift from what :func:`radscene.load_scene` accepts.

>>> schema = scene_json_schema()
>>> schema["$schema"]
'http://json-schema.org/draft-07/schema#'
>>> "objects" in schema["properties"]
True
"""

from __future__ import annotations

import datetime as _dt
import json
import re
import typing
from collections.abc import Iterator
from importlib import resources
from typing import Any

import yaml
from pydantic import BaseModel
from pydantic.json_schema import GenerateJsonSchema

from radscene.radiometry.units import CANONICAL_UNITS, UNITS
from radscene.scene.schema import SceneSpec

__all__ = ["scene_json_schema", "scene_reference", "schema_models", "example_scenes",
           "KEY_EXAMPLES"]

DRAFT_07 = "http://json-schema.org/draft-07/schema#"
_NUMBER = r"[+-]?(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?"
_BOUNDS = {"ge": "minimum", "le": "maximum", "gt": "exclusiveMinimum", "lt": "exclusiveMaximum"}


def _regex_escape(text: str) -> str:
    """Escape regex metacharacters only (a pattern both Python and JavaScript read alike)."""
    return re.sub(r"([.^$*+?()\[\]{}|\\])", r"\\\1", text)


def quantity_pattern(kind: str) -> str:
    """Regular expression of a quantity string of ``kind``: a number and one of its units."""
    units = sorted(UNITS[kind], key=len, reverse=True)
    alternatives = "|".join(r"\s+".join(_regex_escape(p) for p in u.split()) for u in units)
    return rf"^\s*{_NUMBER}\s*(?:{alternatives})?\s*$"


class _Generator(GenerateJsonSchema):
    """pydantic's generator, marking the quantities that ``schema._quantity`` parses."""

    def function_before_schema(self, schema):
        out = super().function_before_schema(schema)
        parse = schema["function"]["function"]
        kind = getattr(parse, "quantity_kind", None)
        if kind is not None:
            out = dict(out)
            out["x-quantity"] = kind
            minimum = getattr(parse, "quantity_minimum", None)
            if minimum is not None:
                bound = "gt" if getattr(parse, "quantity_exclusive", False) else "ge"
                out.setdefault(bound, minimum)
        return out


def _walk_json(node: Any, visit) -> Any:
    """``visit`` applied bottom-up to every mapping of a JSON document."""
    if isinstance(node, dict):
        return visit({k: _walk_json(v, visit) for k, v in node.items()})
    if isinstance(node, list):
        return [_walk_json(v, visit) for v in node]
    return node


def _to_draft_07(node: dict) -> dict:
    node = dict(node)
    if "$ref" in node:
        node["$ref"] = node["$ref"].replace("#/$defs/", "#/definitions/")
    mapping = node.get("discriminator", {}).get("mapping")
    if mapping:  # OpenAPI's discriminator, which editors use to pick a tagged type
        node["discriminator"] = {**node["discriminator"], "mapping": {
            k: v.replace("#/$defs/", "#/definitions/") for k, v in mapping.items()}}
    if "prefixItems" in node:  # a tuple: draft-07 writes it as a list of item schemas
        node["items"] = node.pop("prefixItems")
        node["additionalItems"] = False
    bounds = {_BOUNDS[k]: node.pop(k) for k in list(node) if k in _BOUNDS}
    kind = node.pop("x-quantity", None)
    if kind is not None:
        unit = CANONICAL_UNITS[kind]
        number = {"type": "number", **bounds}
        string = {"type": "string", "pattern": quantity_pattern(kind)}
        keep = {k: v for k, v in node.items() if k not in ("type",)}
        return {**keep, "anyOf": [number, string], "x-unit": unit, "x-quantity": kind}
    if bounds:
        node.update(bounds)
    return node


def _describe_units(node: dict) -> dict:
    """Put the unit and the accepted units into a property's description (what editors show)."""
    if "properties" in node:
        props = {}
        for name, prop in node["properties"].items():
            kinds = sorted(set(_quantity_kinds(prop)))
            if kinds:
                units = "; ".join(f"{k} [{CANONICAL_UNITS[k]}]: a bare number in "
                                  f"{CANONICAL_UNITS[k]}, or a string with a unit, e.g. "
                                  f"{_unit_example(k)!r}" for k in kinds)
                text = prop.get("description", "")
                prop = {**prop, "description": f"{text} ({units})" if text else units}
            props[name] = prop
        node = {**node, "properties": props}
    return node


def _quantity_kinds(node: Any) -> Iterator[str]:
    if isinstance(node, dict):
        if "x-quantity" in node:
            yield node["x-quantity"]
        for key, value in node.items():
            if key not in ("properties", "definitions"):
                yield from _quantity_kinds(value)
    elif isinstance(node, list):
        for value in node:
            yield from _quantity_kinds(value)


_UNIT_EXAMPLES = {"temperature": "25 degC", "wavelength": "550 nm", "length": "2 km",
                  "angle": "30 deg", "time": "10 min", "irradiance": "50 W m-2",
                  "radiance": "5 W m-2 sr-1", "speed": "3 m/s", "pressure": "1013 hPa",
                  "power": "2 kW", "dimensionless": "50 %"}


def _unit_example(kind: str) -> str:
    return _UNIT_EXAMPLES.get(kind, f"1 {CANONICAL_UNITS[kind]}")


_ROAD = {"name": "farm_road", "points": [["0 m", "300 m"], ["1200 m", "450 m"]],
         "width": "6 m", "material": "asphalt"}
_NOISE_TEXTURE = {"type": "noise", "amplitude": 0.1, "scale": "5 m"}
_LAND_COVER = {"type": "noise", "materials": ["dry_grass", "bare_soil"], "scale": "80 m"}
_AIRCRAFT = {"position": ["0 m", "-5 km", "3 km"], "velocity": [0.0, 70.0, 0.0]}
_FLIGHT = {"times": ["0 s", "60 s"], "positions": [["0 m", "-2 km", "3 km"],
                                                  ["0 m", "2 km", "3 km"]]}
_ELEMENTS = {"epoch": "2026-06-21T10:00:00Z", "altitude": "705 km", "inclination": "98.2 deg"}
#: Examples of the keys that the bundled example scenes do not use and whose type alone gives
#: no telling example (a nested model, a length whose size depends on what it measures),
#: by (model, key); each is checked against the JSON schema (tests/system/test_docs.py).
KEY_EXAMPLES: dict[tuple[str, str], Any] = {
    ("SceneSpec", "volumes"): [{"name": "smoke", "shape": {"type": "box", "size": [
        "20 m", "20 m", "10 m"]}, "position": ["300 m", "200 m", "5 m"],
        "optical_depth": 0.8, "temperature": "320 K"}],
    ("Environment", "sun"): {"zenith": "35 deg", "azimuth": "150 deg"},
    ("FlatTerrain", "material_map"): _LAND_COVER,
    ("FlatTerrain", "roads"): [_ROAD],
    ("ProceduralTerrain", "roads"): [_ROAD],
    ("DemTerrain", "material_map"): _LAND_COVER,
    ("DemTerrain", "roads"): [_ROAD],
    ("DemTerrain", "spacing"): ["5 m", "5 m"],
    ("SeaTerrain", "fetch"): "50 km",
    ("VolumeSpec", "shape"): {"type": "ellipsoid", "radii": ["15 m", "15 m", "8 m"]},
    ("VolumeSpec", "gas"): {"co2": 0.02, "h2o": 0.05},
    ("PerspectiveSpec", "spectral"): {"min": "0.4 um", "max": "2.5 um", "step": "10 nm"},
    ("PushbroomSpec", "platform"): _AIRCRAFT,
    ("PushbroomSpec", "waypoints"): _FLIGHT,
    ("WhiskbroomSpec", "orbit"): {"elements": _ELEMENTS},
    ("WhiskbroomSpec", "platform"): _AIRCRAFT,
    ("WhiskbroomSpec", "waypoints"): _FLIGHT,
    ("WhiskbroomSpec", "gsd"): "2 m",
    ("RenderSettings", "motion_blur"): {"samples": 8, "exposure": "10 ms"},
    ("TextureSet", "reflectance"): _NOISE_TEXTURE,
    ("TextureSet", "emissivity"): {**_NOISE_TEXTURE, "amplitude": 0.02},
    ("TextureSet", "transmittance"): _NOISE_TEXTURE,
    ("RoadSpec", "points"): [["0 m", "300 m"], ["600 m", "420 m"], ["1200 m", "450 m"]],
    ("RoadSpec", "width"): "6 m",
    ("EllipsoidShape", "radii"): ["15 m", "15 m", "8 m"],
    ("DensityProfile", "scale_height"): "30 m",
    ("DensityProfile", "sigma"): "5 m",
    ("OrbitSpec", "tle"): [  # the verification set of Vallado et al. (2006), satellite 00005
        "1 00005U 58002B   00179.78495062  .00000023  00000-0  28098-4 0  4753",
        "2 00005  34.2682 348.7242 1859667 331.7664  19.3264 10.82419157413667"],
    ("OrbitSpec", "elements"): _ELEMENTS,
    ("LinearPlatformSpec", "position"): ["0 m", "-5 km", "3 km"],
    ("WaypointsSpec", "positions"): _FLIGHT["positions"],
    ("ImageTextureSpec", "size"): ["1200 m", "1200 m"],
    ("TileTextureSpec", "texel_size"): "0.5 m",
    ("TileTextureSpec", "tile_size"): ["20 m", "20 m"],
    ("NoiseTextureSpec", "scale"): "5 m",
    ("ElementsSpec", "altitude"): "705 km",
    ("ElementsSpec", "semi_major_axis"): "7083 km",
}


def scene_json_schema() -> dict:
    """JSON Schema (draft-07) of a scene file, for editors and validators.

    Returns
    -------
    dict
        The schema; ``json.dumps`` it to a file (``radscene schema -o scene.schema.json``).
        Quantities accept a number in the canonical unit or a string with a unit (its
        ``pattern`` lists the units of its kind); every model forbids unknown keys.

    Notes
    -----
    The scene loader checks more than a JSON Schema can say (cross-references between keys,
    files, material names, sizes): a file that passes this schema may still be refused by
    ``radscene check``, never the other way round for the example scenes.
    """
    raw = SceneSpec.model_json_schema(schema_generator=_Generator)
    defs = raw.pop("$defs", {})
    doc = {"$schema": DRAFT_07, **raw,
           "definitions": defs}
    doc["title"] = "radscene scene file"
    doc = _walk_json(doc, _to_draft_07)
    doc = _walk_json(doc, _describe_units)
    doc["definitions"]["Environment"]["properties"]["atmosphere"] = atmosphere_schema()
    doc["properties"]["materials"]["additionalProperties"] = material_schema()
    return doc


def material_schema() -> dict:
    """The JSON schema of one entry of ``materials``: one branch per material type, with the
    keys its builder accepts (:func:`radscene.materials.factory.material_keys`); a mapping
    without ``type`` is a custom material. Values are not typed here: the builders check
    them."""
    from radscene.materials import list_materials
    from radscene.materials.factory import material_keys

    branches = []
    for kind, keys in material_keys().items():
        props = {"type": {"const": kind}, **{k: {} for k in keys}}
        if kind == "library":
            props["name"] = {"examples": list(list_materials()),
                             "description": "a built-in material (radscene materials list)"}
        branch = {"title": f"{kind} material", "type": "object", "properties": props,
                  "additionalProperties": False}
        if kind != "custom":
            branch["required"] = ["type"]
        branches.append(branch)
    return {"title": "Material", "description": "{type: " + "|".join(material_keys())
            + ", ...}; without type a custom material", "type": "object", "oneOf": branches}


def atmosphere_schema() -> dict:
    """The JSON schema of ``environment.atmosphere``: one branch per engine (its ``type``),
    with the keys its constructor takes, their defaults and the names it knows
    (:func:`radscene.atmosphere.keys.engine_keys`). Values are not typed here: quantities
    take numbers or strings with units, and the engine checks them."""
    from radscene.atmosphere.keys import engine_keys

    branches = []
    for engine, keys in engine_keys().items():
        props = {"type": {"const": engine}}
        for key, entry in keys.items():
            prop = {}
            if "default" in entry:
                prop["default"] = entry["default"]
            if "names" in entry:
                prop["examples"] = entry["names"]
                prop["description"] = "one of: " + ", ".join(entry["names"])
            props[key] = prop
        branches.append({"title": f"{engine} engine", "type": "object", "required": ["type"],
                         "properties": props, "additionalProperties": False})
    return {"title": "Atmosphere", "description": "the atmosphere engine: {type: "
            + "|".join(engine_keys()) + ", ...}; the keys of each engine below",
            "type": "object", "required": ["type"], "oneOf": branches}


# ----------------------------------------------------------------------------- the models


def _models_in(annotation: Any) -> Iterator[type[BaseModel]]:
    if isinstance(annotation, type) and issubclass(annotation, BaseModel):
        yield annotation
        return
    for arg in typing.get_args(annotation):
        yield from _models_in(arg)


def schema_models(root: type[BaseModel] = SceneSpec) -> dict[str, type[BaseModel]]:
    """Every pydantic model reachable from ``root`` through its fields, by class name, in the
    order they are first met (breadth first)."""
    found: dict[str, type[BaseModel]] = {}
    queue = [root]
    while queue:
        model = queue.pop(0)
        if model.__name__ in found:
            continue
        found[model.__name__] = model
        for field in model.model_fields.values():
            queue.extend(m for m in _models_in(field.annotation) if m.__name__ not in found)
    return found


def example_scenes() -> dict[str, Any]:
    """The bundled example scenes as read from YAML, by name; times as ISO 8601 strings (as an
    editor sees them)."""
    out = {}
    folder = resources.files("radscene") / "examples"
    for entry in sorted(folder.iterdir(), key=lambda p: p.name):
        if entry.name.endswith(".yaml"):
            data = yaml.safe_load(entry.read_text(encoding="utf-8"))
            out[entry.name.removesuffix(".yaml")] = json.loads(json.dumps(data, default=_iso))
    return out


def _iso(value):
    if isinstance(value, _dt.datetime | _dt.date):
        return value.isoformat()
    raise TypeError(f"{type(value).__name__} is not JSON serialisable")


# ----------------------------------------------------------------------------- examples


def _resolve(node: dict, defs: dict) -> tuple[str | None, dict]:
    if "$ref" in node:
        name = node["$ref"].rsplit("/", 1)[-1]
        return name, defs[name]
    return None, node


def _flat_options(node: dict) -> Iterator[dict]:
    options = node.get("anyOf") or node.get("oneOf")
    if not options:
        yield node
        return
    for option in options:
        yield from _flat_options(option)


def _branch(node: dict, value: Any, defs: dict) -> list[dict]:
    """The alternatives of a union that ``value`` may belong to."""
    if not (node.get("anyOf") or node.get("oneOf")):
        return [node]
    picked = []
    for option in _flat_options(node):
        _, target = _resolve(option, defs)
        if isinstance(value, dict) and "properties" in target:
            tag = target["properties"].get("type", {})
            allowed = [tag["const"]] if "const" in tag else tag.get("enum")
            if allowed and "type" in value and value["type"] not in allowed:
                continue
            if not set(value) <= set(target["properties"]):
                continue
            picked.append(option)
        elif isinstance(value, list) and target.get("type") == "array":
            picked.append(option)
        elif isinstance(value, dict) and target.get("type") == "object":
            picked.append(option)
    return picked[:1]


def _collect(node: dict, value: Any, defs: dict, out: dict) -> None:
    """Record the first value met for each (model, key) while walking ``value`` by ``node``."""
    for option in _branch(node, value, defs):
        name, target = _resolve(option, defs)
        if "properties" in target and isinstance(value, dict):
            for key, item in value.items():
                if key in target["properties"]:
                    out.setdefault((name, key), item)
                    _collect(target["properties"][key], item, defs, out)
        elif target.get("type") == "array" and isinstance(value, list):
            items = target.get("items", {})
            if isinstance(items, list):
                for sub, item in zip(items, value, strict=False):
                    _collect(sub, item, defs, out)
            else:
                for item in value:
                    _collect(items, item, defs, out)
        elif target.get("type") == "object" and isinstance(value, dict):
            extra = target.get("additionalProperties")
            if isinstance(extra, dict):
                for item in value.values():
                    _collect(extra, item, defs, out)


def _examples(schema: dict) -> dict[tuple[str, str], Any]:
    defs = schema["definitions"]
    out: dict = {}
    root = {k: v for k, v in schema.items() if k != "definitions"}
    for scene in example_scenes().values():
        _collect(root, scene, defs, out)
    return {(name or "SceneSpec", key): value for (name, key), value in out.items()}


# ----------------------------------------------------------------------------- the page


def _type_text(node: dict, defs: dict) -> str:
    if "$ref" in node:
        name = node["$ref"].rsplit("/", 1)[-1]
        return f"[{name}](#{name.lower()})"
    if "x-quantity" in node:
        return node["x-quantity"]
    for union in ("anyOf", "oneOf"):
        if union in node:
            parts = [_type_text(n, defs) for n in node[union] if n.get("type") != "null"]
            text = " or ".join(dict.fromkeys(parts))
            if any(n.get("type") == "null" for n in node[union]):
                text += " or null"
            return text
    if "const" in node:
        return f"`{json.dumps(node['const'])}`"
    if "enum" in node:
        return " or ".join(f"`{json.dumps(v)}`" for v in node["enum"])
    kind = node.get("type")
    if kind == "array":
        items = node.get("items", {})
        if isinstance(items, list):
            return "[" + ", ".join(_type_text(i, defs) for i in items) + "]"
        return f"list of {_type_text(items, defs)}" if items else "list"
    if kind == "object":
        extra = node.get("additionalProperties")
        if isinstance(extra, dict) and extra:
            return f"mapping of name to {_type_text(extra, defs)}"
        return "mapping"
    if kind == "string" and node.get("format") == "date-time":
        return "date-time (ISO 8601 with a UTC offset)"
    names = {"number": "number", "integer": "integer", "string": "string", "boolean": "boolean"}
    return names.get(kind, "any")


def _bounds_text(node: dict) -> str:
    texts = []
    for sub in [node, *node.get("anyOf", []), *node.get("oneOf", [])]:
        for key, sign in (("minimum", "≥"), ("exclusiveMinimum", ">"), ("maximum", "≤"),
                          ("exclusiveMaximum", "<")):
            if key in sub and sub.get("type") in ("number", "integer"):
                texts.append(f"{sign} {sub[key]:g}")
        if "minItems" in sub and sub.get("type") == "array" and not isinstance(
                sub.get("items"), list):
            texts.append(f"at least {sub['minItems']} item(s)")
    return ", ".join(dict.fromkeys(texts))


def _yaml_value(value: Any, limit: int = 60) -> str:
    text = json.dumps(value, ensure_ascii=False)
    if len(text) > limit:
        text = text[:limit - 3] + "…"
    return "`" + text.replace("|", "\\|") + "`"


def _synthetic_example(node: dict, defs: dict) -> Any:
    """An example value from the type alone (keys the bundled scenes do not use)."""
    if "x-quantity" in node:
        return _unit_example(node["x-quantity"])
    for union in ("anyOf", "oneOf"):
        if union in node:
            options = [n for n in node[union] if n.get("type") != "null"]
            return _synthetic_example(options[0], defs) if options else None
    if "$ref" in node:  # a nested model: the row points to its section
        return {}
    if "const" in node:
        return node["const"]
    if "enum" in node:
        return node["enum"][0]
    kind = node.get("type")
    if kind == "array":
        items = node.get("items", {})
        if isinstance(items, list):
            return [_synthetic_example(i, defs) for i in items]
        return [_synthetic_example(items, defs)] if items else []
    if kind == "number":
        low = node.get("minimum", node.get("exclusiveMinimum"))
        return 1.0 if low is None or low < 1 else float(low) + 1.0
    if kind == "integer":
        return max(int(node.get("minimum", 1)), 1)
    if kind == "boolean":
        return True
    if kind == "string":
        return "2026-06-21T10:30:00+02:00" if node.get("format") == "date-time" else "…"
    if kind == "object":
        return {}
    return None


def _cell(text: str) -> str:
    return " ".join(str(text).split()).replace("|", "\\|")


def _paths(schema: dict) -> dict[str, list[str]]:
    """Where each model appears in a scene file, as key paths (``objects[*].shape``)."""
    defs = schema["definitions"]
    found: dict[str, list[str]] = {"SceneSpec": ["(the top level)"]}

    def refs(node, path):
        if isinstance(node, dict):
            if "$ref" in node:
                yield node["$ref"].rsplit("/", 1)[-1], path
            for key in ("anyOf", "oneOf"):
                for n in node.get(key, []):
                    yield from refs(n, path)
            if node.get("type") == "array":
                items = node.get("items", {})
                if isinstance(items, list):
                    for i, n in enumerate(items):
                        yield from refs(n, f"{path}[{i}]")
                else:
                    yield from refs(items, f"{path}[*]")
            extra = node.get("additionalProperties")
            if isinstance(extra, dict):
                yield from refs(extra, f"{path}.NAME")

    queue = [("SceneSpec", "")]
    while queue:
        name, prefix = queue.pop(0)
        target = schema if name == "SceneSpec" else defs[name]
        for key, prop in target.get("properties", {}).items():
            for ref, path in refs(prop, f"{prefix}{key}"):
                paths = found.setdefault(ref, [])
                if path not in paths and len(paths) < 6:
                    paths.append(path)
                    queue.append((ref, path + "."))
    return found


def scene_reference() -> str:
    """The scene-file reference as a Markdown page: every key of every model.

    Returns
    -------
    str
        Markdown: one section per model (the top level first), each a table of its keys with
        type, unit, default, description and example.
    """
    schema = scene_json_schema()
    defs = schema["definitions"]
    models = schema_models()
    examples = _examples(schema)
    paths = _paths(schema)
    lines = [
        "# Scene file reference",
        "",
        "Every key a scene file may hold, generated from the schema the loader validates with",
        "(`radscene.scene.schema`) each time the site is built. Quantities take a number in the",
        "canonical unit (the *unit* column) or a string with a unit of their kind: `\"300 K\"`,",
        "`\"25 degC\"`, `\"550 nm\"`, `\"2 km\"`, `\"30 deg\"`, `\"10 min\"`. Examples come from the",
        "bundled example scenes (`radscene examples`) where they use the key, else from a table",
        "of examples checked against the schema (`radscene.scene.reference.KEY_EXAMPLES`), the",
        "key's default, or its type. Unknown keys are refused. For completion and checking in",
        "an editor, see [the JSON schema](editor.md).",
        "",
        "Keys that take a type-tagged mapping: `environment.atmosphere` (its keys per engine",
        "are [below](#environmentatmosphere); what they mean: [atmosphere engines](api/atmosphere.md)),",
        "`materials` (its keys per type [below](#materials-by-type)), `sensors` (`radscene sensor list`).",
        "",
    ]
    for name, model in models.items():
        target = schema if name == "SceneSpec" else defs[name]
        where = ", ".join(f"`{p}`" for p in paths.get(name, []))
        lines += [f"## {name}", ""]
        if where:
            lines += [f"*Where:* {where}", ""]
        doc = (model.__doc__ or "").strip()
        if doc and name != "SceneSpec":
            lines += [" ".join(doc.split()).replace("``", "`"), ""]
        lines += ["| key | type | unit | default | description | example |",
                  "|---|---|---|---|---|---|"]
        required = set(target.get("required", []))
        for key, prop in target.get("properties", {}).items():
            field = model.model_fields[key]
            kinds = sorted(set(_quantity_kinds(prop)))
            unit = ", ".join(CANONICAL_UNITS[k] for k in kinds) or "–"
            type_text = _type_text(prop, defs)
            bounds = _bounds_text(prop)
            if bounds:
                type_text += f" ({bounds})"
            if key in required:
                default = "**required**"
            elif "default" in prop:
                default = _yaml_value(prop["default"])
            else:
                default = "–"
            description = field.description or ""
            example = examples.get((name, key))
            chosen = example is None and (name, key) in KEY_EXAMPLES
            synthetic = False
            if chosen:
                example = KEY_EXAMPLES[(name, key)]
            elif example is None:
                example = prop.get("default", None)
                if example in (None, [], {}, ""):
                    example, synthetic = _synthetic_example(prop, defs), True
            refs = [o["$ref"].rsplit("/", 1)[-1] for o in _flat_options(prop) if "$ref" in o]
            items = prop.get("items")
            if synthetic and isinstance(items, dict):  # a list of models: point to them
                refs += [o["$ref"].rsplit("/", 1)[-1] for o in _flat_options(items) if "$ref" in o]
            if chosen:
                example_text = _yaml_value(example, limit=200)
            elif isinstance(example, dict | list) and refs:
                example_text = "see " + ", ".join(f"[{r}](#{r.lower()})" for r in refs)
            else:
                example_text = _yaml_value(example)
            lines.append("| " + " | ".join([
                f"`{key}`", _cell(type_text), _cell(unit), _cell(default),
                _cell(description).replace("[", "\\[") or "–", example_text]) + " |")
        lines.append("")
    return "\n".join(lines + _atmosphere_reference() + _material_reference())


def _material_reference() -> list[str]:
    """The reference's section on the entries of ``materials``: per type, its keys."""
    from radscene.materials.factory import material_keys

    lines = ["## materials (by type)", "",
             "Each entry of `materials` is a mapping with a `type` (none: `custom`) and that "
             "type's keys; what they mean: [materials and BRDFs](api/materials.md).", "",
             "| type | keys |", "|---|---|"]
    for kind, keys in material_keys().items():
        lines.append(f"| {kind} | " + ", ".join(f"`{k}`" for k in keys) + " |")
    return lines + [""]


def _atmosphere_reference() -> list[str]:
    """The reference's section on ``environment.atmosphere``: per engine, its keys, their
    defaults and the names the engine knows."""
    from radscene.atmosphere.keys import engine_keys

    lines = ["## environment.atmosphere", "",
             "The keys each engine takes beside `type`, read from its constructor "
             "(`radscene.atmosphere.ENGINES`); units and meanings are on the engine's "
             "[API page](api/atmosphere.md). A database built with `radscene atmosphere build` "
             "may hold other profiles and aerosols than the shipped one's listed here.", ""]
    for engine, keys in engine_keys().items():
        lines += [f"### type: {engine}", ""]
        if not keys:
            lines += ["No other key.", ""]
            continue
        lines += ["| key | default | names |", "|---|---|---|"]
        for key, entry in keys.items():
            default = _yaml_value(entry["default"]) if "default" in entry else "–"
            names = ", ".join(f"`{n}`" for n in entry.get("names", [])) or "–"
            lines.append(f"| `{key}` | {_cell(default)} | {names} |")
        lines.append("")
    return lines
