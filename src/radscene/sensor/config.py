"""Building sensors from type-tagged configuration: ``make_sensor({...})``, YAML files.

The same mapping works from Python, YAML and the CLI; the scene file embeds it under
``sensors: {name: {...}}`` and refers to it from ``observers[*].sensor``.
"""

from __future__ import annotations

from collections.abc import Mapping
from importlib import resources
from pathlib import Path

from radscene.errors import ConfigError
from radscene.sensor.chain import DETECTORS, Sensor

__all__ = ["SENSOR_TYPES", "DETECTORS", "make_sensor", "load_sensor", "example_sensors",
           "example_sensor_path"]

#: Registry of sensor types (case-insensitive). Scanners register here too.
SENSOR_TYPES: dict[str, type] = {"staring": Sensor, "frame": Sensor}


def make_sensor(spec: Mapping | Sensor, key: str = "") -> Sensor:
    """Build a sensor from a type-tagged mapping.

    Parameters
    ----------
    spec : mapping or Sensor
        ``{"type": <name in SENSOR_TYPES>, ...}`` (type case-insensitive, default
        ``staring``); see :mod:`radscene.sensor.chain` for the keys. A Sensor is returned as it is.
    key : str, optional
        Key path of the mapping in a larger file (e.g. ``sensors.mwir``), for errors.

    Returns
    -------
    Sensor

    Raises
    ------
    ConfigError
        Unknown type (listing the registered ones) or any invalid parameter, naming its key.

    Examples
    --------
    >>> s = make_sensor({"optics": {"focal_length": 0.1, "f_number": 2},
    ...                  "detector": {"type": "photon", "pitch": 15e-6, "quantum_efficiency": 0.7,
    ...                               "integration_time": 0.005, "temperature": 80},
    ...                  "electronics": {"gain": 100}})
    >>> round(s.ifov * 3600, 3)   # arcsec
    30.94
    """
    if isinstance(spec, Sensor):
        return spec
    if not isinstance(spec, Mapping):
        raise ConfigError(f"a sensor is a mapping; got {type(spec).__name__} {spec!r}",
                          key=key or "sensor")
    kind = str(spec.get("type", "staring")).lower()
    if kind not in SENSOR_TYPES:
        raise ConfigError(f"unknown sensor type {spec.get('type')!r}; known: "
                          f"{', '.join(SENSOR_TYPES)}", key=f"{key}.type" if key else "type")
    return SENSOR_TYPES[kind].from_config(spec, key)


def load_sensor(path) -> Sensor:
    """Read a sensor YAML file (a bundled example's name also works, e.g. ``"mwir_cooled"``)."""
    import yaml

    p = Path(path)
    if not p.is_file() and str(path) in example_sensors():
        p = example_sensor_path(str(path))
    try:
        text = p.read_text(encoding="utf-8")
    except OSError as exc:
        raise ConfigError(f"cannot read sensor file: {exc}", key=str(path)) from None
    try:
        spec = yaml.safe_load(text)
    except yaml.YAMLError as exc:
        raise ConfigError(f"not valid YAML: {exc}", key=str(path)) from None
    if isinstance(spec, Mapping) and "sensor" in spec and len(spec) == 1:
        spec = spec["sensor"]
    return make_sensor(spec)


def _folder():
    return resources.files("radscene") / "data" / "sensors"


def example_sensors() -> list[str]:
    """Names of the bundled example sensors."""
    folder = _folder()
    if not folder.is_dir():
        return []
    return sorted(p.name.removesuffix(".yaml") for p in folder.iterdir() if p.name.endswith(".yaml"))


def example_sensor_path(name: str) -> Path:
    """Path of a bundled example sensor YAML file."""
    path = Path(str(_folder() / f"{name}.yaml"))
    if not path.is_file():
        raise ConfigError(f"unknown example sensor {name!r}; known: {', '.join(example_sensors())}",
                          key="sensor")
    return path
