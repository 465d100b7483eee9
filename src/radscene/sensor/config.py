"""Building sensors from type-tagged configuration: ``make_sensor({...})``, YAML files.

The same mapping works from Python, YAML and the CLI; the scene file embeds it under
``sensors: {name: {...}}`` and refers to it from ``observers[*].sensor``.
"""

from __future__ import annotations

from collections.abc import Mapping
from importlib import resources
from pathlib import Path

from radscene.errors import ConfigError, did_you_mean
from radscene.sensor.chain import DETECTORS, Sensor

__all__ = ["SENSOR_TYPES", "DETECTORS", "make_sensor", "load_sensor", "read_sensor_file",
           "example_sensors", "example_sensor_path"]

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
                          f"{', '.join(SENSOR_TYPES)}"
                          f"{did_you_mean(spec.get('type'), SENSOR_TYPES)}", key=f"{key}.type" if key else "type")
    return SENSOR_TYPES[kind].from_config(spec, key)


#: Top-level keys of a sensor file that holds more than the sensor (see :func:`read_sensor_file`).
FILE_PARTS = ("sensor", "observer")


def read_sensor_file(path) -> dict:
    """Read a sensor YAML file into its parts: ``{"sensor": {...}, "observer": {...} or None}``.

    A sensor file is either the sensor mapping itself (``optics``, ``detector``, ...) or a
    mapping of parts: ``sensor`` (required) and ``observer`` (optional: a scene-file observer,
    e.g. a pushbroom on its orbit, :mod:`radscene.platform.config`). A bundled example's name
    (:func:`example_sensors`) works as well as a path.

    Parameters
    ----------
    path : str or path-like

    Returns
    -------
    dict
        ``sensor`` (mapping) and ``observer`` (mapping or None).

    Raises
    ------
    ConfigError
        Unreadable file, malformed YAML, or unknown parts (naming the file).
    """
    import yaml

    p = Path(path)
    if not p.is_file() and str(path) in example_sensors():
        p = example_sensor_path(str(path))
    try:
        text = p.read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError) as exc:
        what = "not a text (UTF-8) file" if isinstance(exc, UnicodeDecodeError) else str(exc)
        raise ConfigError(f"cannot read sensor file: {what}", key=str(path)) from None
    try:
        spec = yaml.safe_load(text)
    except yaml.YAMLError as exc:
        mark = getattr(exc, "problem_mark", None)
        where = f" at line {mark.line + 1}, column {mark.column + 1}" if mark else ""
        problem = getattr(exc, "problem", None) or str(exc).splitlines()[0]
        raise ConfigError(f"not valid YAML{where}: {problem}", key=str(path)) from None
    if not isinstance(spec, Mapping):
        got = "an empty file" if spec is None else f"a {type(spec).__name__}"
        raise ConfigError(f"a sensor file holds a mapping (optics, detector, ...); got {got}",
                          key=str(path))
    if "sensor" not in spec:
        return {"sensor": dict(spec), "observer": None}
    unknown = sorted(str(k) for k in set(spec) - set(FILE_PARTS))
    if unknown:
        raise ConfigError(f"unknown part(s) {', '.join(unknown)} beside 'sensor'; accepted: "
                          f"{', '.join(FILE_PARTS)}", key=str(path))
    if not isinstance(spec["sensor"], Mapping):
        raise ConfigError(f"'sensor' must be a mapping; got a {type(spec['sensor']).__name__}",
                          key=f"{path}: sensor")
    observer = spec.get("observer")
    if observer is not None and not isinstance(observer, Mapping):
        raise ConfigError(f"'observer' must be a mapping; got a {type(observer).__name__}",
                          key=f"{path}: observer")
    return {"sensor": dict(spec["sensor"]),
            "observer": None if observer is None else dict(observer)}


def load_sensor(path) -> Sensor:
    """Read a sensor YAML file (a bundled example's name also works, e.g. ``"landsat_like"``).

    The file is the sensor mapping of :func:`make_sensor`, or parts as described by
    :func:`read_sensor_file` (only ``sensor`` is used here). Band responses may name the
    bundled SRF library: ``{type: library, sensor: landsat8_oli, band: B4}``.

    Examples
    --------
    >>> s = load_sensor("landsat_like")
    >>> s.channel("tir1").response.name
    'landsat8_tirs B10'
    """
    spec = read_sensor_file(path)["sensor"]
    try:
        return make_sensor(spec)
    except ConfigError as err:
        raise ConfigError(f"{err.message} (sensor file {path})", key=err.key) from None


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
        raise ConfigError(f"unknown example sensor {name!r}; known: {', '.join(example_sensors())}"
                          f"{did_you_mean(name, example_sensors())}",
                          key="sensor")
    return path
