"""The scene-file reference and the JSON schema cover every key of the schema models, and the
JSON schema accepts the bundled example scenes and refuses what the loader refuses."""

from __future__ import annotations

import json
import re
import subprocess
import sys

import pytest

from radscene.scene.reference import (
    example_scenes,
    quantity_pattern,
    scene_json_schema,
    scene_reference,
    schema_models,
)
from radscene.scene.schema import SceneSpec

jsonschema = pytest.importorskip("jsonschema", reason="the JSON schema checks need jsonschema "
                                 "(the dev extra)")


@pytest.fixture(scope="module")
def schema():
    return scene_json_schema()


@pytest.fixture(scope="module")
def full_reference():
    return scene_reference()


@pytest.fixture(scope="module")
def reference(full_reference):
    """The reference's model sections (the engines' keys of its last section are apart)."""
    return full_reference.split(ATMOSPHERE_SECTION, 1)[0]


ATMOSPHERE_SECTION = "\n## environment.atmosphere\n"


@pytest.fixture(scope="module")
def validator(schema):
    return jsonschema.Draft7Validator(schema)


def _sections(markdown: str) -> dict[str, set[str]]:
    """Model name -> the keys listed in its table."""
    out: dict[str, set[str]] = {}
    current = None
    for line in markdown.splitlines():
        if line.startswith("## "):
            current = out.setdefault(line[3:].strip(), set())
        elif current is not None and line.startswith("| `"):
            current.add(line.split("`")[1])
    return out


def test_schema_models_reach_every_nested_model():
    models = schema_models()
    assert next(iter(models)) == "SceneSpec"
    for expected in ("ObjectSpec", "BoxShape", "PerspectiveSpec", "PushbroomSpec", "OrbitSpec",
                     "WeatherSpec", "TimeSpan", "DensityProfile", "NoiseTextureSpec"):
        assert expected in models


def test_reference_lists_every_key_of_every_model(reference):
    sections = _sections(reference)
    for name, model in schema_models().items():
        assert name in sections, f"no section for {name}"
        assert sections[name] == set(model.model_fields), name


def test_reference_rows_have_type_unit_default_description_example(reference):
    rows = [line for line in reference.splitlines() if line.startswith("| `")]
    assert len(rows) > 200
    for row in rows:
        cells = [c.strip() for c in re.split(r"(?<!\\)\|", row)[1:-1]]
        assert len(cells) == 6, row
        assert all(cells[i] for i in (1, 2, 3, 5)), row


def test_every_key_is_described(reference):
    empty = [f"{name}.{key}" for name, model in schema_models().items()
             for key, field in model.model_fields.items() if not (field.description or "").strip()]
    assert not empty, f"keys without a description: {', '.join(empty)}"
    for row in (line for line in reference.splitlines() if line.startswith("| `")):
        description = [c.strip() for c in re.split(r"(?<!\\)\|", row)[1:-1]][4]
        assert description not in ("", "–"), row


def test_reference_units_and_defaults(reference):
    rows = {line.split("`")[1] + "@" + str(i): line
            for i, line in enumerate(reference.splitlines()) if line.startswith("| `t_min`")}
    (row,) = rows.values()
    assert "| temperature" in row and "| K |" in row and "285.15" in row
    objects = _row(reference, "ObjectSpec", "position")
    assert "[length, length, length]" in objects and "| m |" in objects


def _row(reference: str, model: str, key: str) -> str:
    section = reference.split(f"\n## {model}\n", 1)[1].split("\n## ", 1)[0]
    return next(line for line in section.splitlines() if line.startswith(f"| `{key}`"))


def test_examples_come_from_the_bundled_scenes(reference):
    from importlib import resources

    import yaml

    examples = resources.files("radscene") / "examples"
    times, sizes = set(), []
    for path in examples.iterdir():
        if path.name.endswith(".yaml"):
            data = yaml.safe_load(path.read_text())
            when = (data.get("environment") or {}).get("time")
            if when is not None:
                times.add(when.isoformat() if hasattr(when, "isoformat") else str(when))
            terrain = data.get("terrain") or {}
            if terrain.get("type") == "procedural" and "size" in terrain:
                sizes.append(terrain["size"])
    row = _row(reference, "Environment", "time")
    assert any(f'"{t}"' in row for t in times), (row, times)
    example = _row(reference, "ProceduralTerrain", "size").rstrip(" |").rsplit("|", 1)[1].strip(" `")
    assert yaml.safe_load(example) in sizes, (example, sizes)


def test_json_schema_is_valid_draft_07(schema):
    jsonschema.Draft7Validator.check_schema(schema)
    assert schema["$schema"] == "http://json-schema.org/draft-07/schema#"
    assert "$defs" not in json.dumps(schema) and "prefixItems" not in json.dumps(schema)


def test_json_schema_covers_every_key(schema):
    defs = schema["definitions"]
    for name, model in schema_models().items():
        target = schema if name == "SceneSpec" else defs[name]
        assert set(target["properties"]) == set(model.model_fields), name
        assert target.get("additionalProperties") is False, name


@pytest.mark.parametrize("name", sorted(example_scenes()))
def test_json_schema_accepts_the_example_scenes(name, validator):
    errors = [f"{list(e.absolute_path)}: {e.message}"
              for e in validator.iter_errors(example_scenes()[name])]
    assert not errors


def _demo():
    return json.loads(json.dumps(example_scenes()["demo"]))


@pytest.mark.parametrize("edit, path", [
    (lambda s: s["objects"][0].__setitem__("colour", "red"), ["objects", 0]),
    (lambda s: s["objects"][0].__setitem__("position", ["1 m", "2 m", "3 degC"]),
     ["objects", 0, "position", 2]),
    (lambda s: s["objects"][0]["shape"].__setitem__("type", "sphere"), ["objects", 0, "shape"]),
    (lambda s: s["thermal"]["weather"].__setitem__("relative_humidity", 1.5),
     ["thermal", "weather", "relative_humidity"]),
    (lambda s: s.pop("observers"), []),
    (lambda s: s["terrain"].__setitem__("temperature_map", "temps.png"), ["terrain"]),
])
def test_json_schema_refuses_what_the_loader_refuses(edit, path, validator):
    scene = _demo()
    edit(scene)
    errors = list(validator.iter_errors(scene))
    assert errors, "the schema accepted a broken scene"
    assert any(list(e.absolute_path)[:len(path)] == path for e in errors)
    with pytest.raises(ValueError):  # pydantic's ValidationError is a ValueError
        SceneSpec.model_validate(scene)


@pytest.mark.parametrize("kind, good, bad", [
    ("temperature", ["300", "300 K", "25 degC", "-3.5e1 °C", " 77 kelvin "], ["300 m", "K", "hot"]),
    ("length", ["2 km", "1.5e3 m", "12 ft", "0.5"], ["2 deg", "2 km/h"]),
    ("wavelength", ["550 nm", "10 um", "10 µm", "1 micron"], ["10 K", "nm"]),
    ("irradiance", ["50 W m-2", "50 W  m-2", "1 kW/m2"], ["50 W"]),
])
def test_quantity_pattern(kind, good, bad):
    pattern = re.compile(quantity_pattern(kind))
    assert all(pattern.match(v) for v in good)
    assert not any(pattern.match(v) for v in bad)


def test_schema_command_writes_the_schema(tmp_path, one_line_refusal):
    out = tmp_path / "scene.schema.json"
    run = subprocess.run([sys.executable, "-m", "radscene", "schema", "-o", str(out)],
                         capture_output=True, text=True, timeout=120)
    assert run.returncode == 0, run.stderr
    assert json.loads(out.read_text(encoding="utf-8")) == scene_json_schema()
    refused = subprocess.run([sys.executable, "-m", "radscene", "schema", "-o", str(tmp_path)],
                             capture_output=True, text=True, timeout=120)
    assert refused.returncode == 2 and one_line_refusal(refused.stderr, "output")


def _example_cell(row: str) -> str:
    return [c.strip() for c in re.split(r"(?<!\\)\|", row)[1:-1]][5]


def test_no_reference_row_has_a_placeholder_example(reference):
    rows = [line for line in reference.splitlines() if line.startswith("| `")]
    placeholders = [row.split("`")[1] for row in rows if "{…}" in _example_cell(row)]
    assert not placeholders, placeholders


def _strings(cell: str) -> set:
    """The strings of an example cell's JSON value (none when it is cut short or a link)."""
    try:
        value = json.loads(cell.strip("`"))
    except ValueError:
        return set()
    out, stack = set(), [value]
    while stack:
        item = stack.pop()
        if isinstance(item, str):
            out.add(item)
        elif isinstance(item, list | dict):
            stack.extend(item.values() if isinstance(item, dict) else item)
    return out


def test_length_examples_are_plausible(reference):
    """No length shows the unit's generic example ("2 km" whatever it measures): each comes
    from a bundled scene, its default or the table of examples; a road is metres wide."""
    generic = []
    for name in schema_models():
        section = reference.split(f"\n## {name}\n", 1)[1].split("\n## ", 1)[0]
        for row in (line for line in section.splitlines() if line.startswith("| `")):
            if "length" in row.split("|")[2] and _strings(_example_cell(row)) == {"2 km"}:
                generic.append(f"{name}.{row.split('`')[1]}")
    assert not generic, generic
    width = _example_cell(_row(reference, "RoadSpec", "width")).strip("`")
    from radscene.radiometry.units import parse_quantity

    assert 2.0 <= parse_quantity(json.loads(width), "length") <= 30.0


def test_table_examples_are_valid_values_of_their_keys(schema):
    """Each example of the table names a key of its model and passes both the JSON schema and
    the loader's model of that key."""
    from typing import Annotated

    from pydantic import TypeAdapter

    from radscene.scene.reference import KEY_EXAMPLES

    models = schema_models()
    defs = schema["definitions"]
    for (name, key), example in KEY_EXAMPLES.items():
        field = models[name].model_fields[key]
        target = schema if name == "SceneSpec" else defs[name]
        prop = {"definitions": defs, **target["properties"][key]}
        errors = list(jsonschema.Draft7Validator(prop).iter_errors(example))
        assert not errors, (name, key, errors[0].message)
        annotation = Annotated[(field.annotation, *field.metadata)] if field.metadata \
            else field.annotation
        TypeAdapter(annotation).validate_python(example)


def test_reference_lists_every_atmosphere_engines_keys(full_reference):
    """Per engine, the keys its constructor takes, with the names it knows."""
    from radscene.atmosphere.keys import engine_keys

    section = full_reference.split(ATMOSPHERE_SECTION, 1)[1]
    for engine, keys in engine_keys().items():
        part = section.split(f"### type: {engine}\n", 1)[1].split("\n### ", 1)[0]
        listed = {line.split("`")[1] for line in part.splitlines() if line.startswith("| `")}
        assert listed == set(keys), engine
    database = section.split("### type: database\n", 1)[1].split("\n### ", 1)[0]
    assert "`midlatitude_summer`" in database and "`maritime`" in database


@pytest.mark.parametrize("atmosphere, valid", [
    ({"type": "database", "profile": "tropical", "aerosol": "maritime", "aot550": 0.2}, True),
    ({"type": "sixs", "profile": "us_standard", "water": 2.0}, True),
    ({"type": "lowtran", "model": "tropical", "visibility": "23 km"}, True),
    ({"type": "none"}, True),
    ({"type": "database", "profle": "tropical"}, False),  # a misspelt key
    ({"type": "sixs", "transmittance": 0.9}, False),  # another engine's key
    ({"type": "uniform", "profile": "tropical"}, False),
    ({"type": "modtran"}, False),
    ({"profile": "tropical"}, False),  # no type
])
def test_json_schema_knows_each_engines_keys(validator, atmosphere, valid):
    scene = _demo()
    scene["environment"]["atmosphere"] = atmosphere
    assert validator.is_valid(scene) == valid


@pytest.mark.parametrize("material, valid", [
    ({"type": "library", "name": "asphalt"}, True),
    ({"reflectance": 0.3, "emissivity": 0.9}, True),  # no type: a custom material
    ({"type": "canopy", "lai": 3.0, "soil": "bare_soil", "chlorophyll": 40.0}, True),
    ({"type": "mixture", "parts": [{"fraction": 0.5, "material": "asphalt"},
                                   {"fraction": 0.5, "material": "concrete"}]}, True),
    ({"type": "library", "nmae": "asphalt"}, False),  # a misspelt key
    ({"type": "water", "lai": 2.0}, False),  # another type's key
    ({"reflectanse": 0.3}, False),
    ({"type": "plastic"}, False),
])
def test_json_schema_knows_each_material_types_keys(validator, material, valid):
    scene = _demo()
    scene["materials"] = {"mine": material}
    assert validator.is_valid(scene) == valid


def test_material_schema_is_the_builders_keys():
    """The schema's keys per type are those make_material accepts."""
    from radscene.materials.factory import MATERIAL_TYPES, material_keys
    from radscene.scene.reference import material_schema

    branches = {b["properties"]["type"]["const"]: b for b in material_schema()["oneOf"]}
    assert set(branches) == set(MATERIAL_TYPES)
    for kind, keys in material_keys().items():
        assert set(branches[kind]["properties"]) == {"type", *keys}
