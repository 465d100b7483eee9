"""The whole run: the heat balance of a scene, the render of an observer, then the sensor."""

from __future__ import annotations

import datetime as _dt
from typing import TYPE_CHECKING

import numpy as np

from radscene.errors import ConfigError
from radscene.pipeline.progress import progress_callback
from radscene.pipeline.provenance import stamp

#: One day [s].
DAY = 86400.0

if TYPE_CHECKING:  # the renderer, and xarray with it, are imported by the functions that use them
    import xarray as xr

__all__ = ["as_scene", "render", "render_all", "render_hyperspectral", "spectral_passes", "simulate",
           "solve_thermal", "thermal_active", "apply_thermal", "record_signal", "check_thermal_inputs",
           "check_thermal_size"]

#: Bands whose response reaches beyond this wavelength make the heat balance run by default [um].
THERMAL_FROM = 2.5


def as_scene(scene):
    """A loaded scene from a :class:`~radscene.scene.Scene`, a scene file path or a dict.

    The public functions below take any of the three, so ``radscene.render("scene.yaml")`` and
    ``radscene.render({...})`` give the same errors as ``radscene render`` on the command line
    (:class:`~radscene.errors.ConfigError` naming the key).
    """
    from pathlib import Path

    from radscene.scene import Scene, load_scene

    if isinstance(scene, Scene):
        return scene
    if isinstance(scene, (dict, str, Path)):
        return load_scene(scene)
    raise TypeError(f"a scene is a radscene Scene, a scene file path or a dict, not "
                    f"{type(scene).__name__}")


def thermal_active(scene) -> bool:
    """Whether the scene's surface temperatures come from the heat balance: ``thermal.enabled``
    true, or ``auto`` with a band reaching beyond 2.5 µm and a surface without a fixed
    temperature."""
    scene = as_scene(scene)
    enabled = scene.spec.thermal.enabled
    if enabled is not True and enabled != "auto":
        return False
    free = any(obj.face_fixed is not None and not np.all(obj.face_fixed) for obj in scene.objects)
    if enabled is True:
        return free
    return free and (any(b.response.support[1] > THERMAL_FROM for b in scene.bands) or any(
        o.spectral is not None and o.spectral.wavelength[-1] > THERMAL_FROM
        for o in scene.observers))


def _span(scene, start=None, end=None):
    spec = scene.spec.thermal
    start = start or spec.start
    end = end or spec.end
    if end is None:
        end = scene.time
    if start is None and end is not None:
        start = end - _dt.timedelta(days=1)
    if start is None or end is None:
        raise ConfigError("the heat balance needs a time: give environment.time, or thermal.start and "
                          "thermal.end", key="thermal.start")
    for value, key in ((start, "thermal.start"), (end, "thermal.end")):
        if value.tzinfo is None:
            raise ConfigError("a time with a UTC offset, e.g. '2026-06-21T10:30:00+02:00'", key=key)
    return start, end


def check_thermal_description(scene, elements=None) -> None:
    """Refuse, naming the scene file's key, what the heat balance would refuse only when it
    builds its stacks: an unknown object under ``thermal.objects``, a material without a thermal
    description, a bad layer or bottom (of a material's or an object's own stack), too few
    nodes for the layers."""
    from radscene.thermal.conduction import build_grid

    spec = scene.spec.thermal
    names = [o.name for o in scene.objects]
    for name in spec.objects:
        if name not in names:
            raise ConfigError(f"unknown object {name!r}; the scene's: {', '.join(names)}", key=f"thermal.objects.{name}")
    if elements is None:
        elements = _thermal_elements(scene)
    if elements.size == 0:
        return
    used, stack_index = np.unique(elements.material, return_inverse=True)
    stacks = _stacks(scene, used, _object_layered(scene, elements, used))
    zeros = np.zeros(len(stacks))
    stacks, _, _, _, material, owner = _object_stacks(scene, elements, used, stack_index, stacks, zeros, zeros)
    try:
        build_grid(stacks, n_nodes=spec.nodes)
    except ConfigError as err:
        import re

        key = err.key or ""
        found = re.match(r"stacks\[(\d+)\](.*)", key)
        if found:
            j, rest = int(found.group(1)), found.group(2)
            where = (f"thermal.objects.{scene.objects[owner[j]].name}" if owner[j] >= 0
                     else f"thermal.materials.{scene.material_names[material[j]]}")
            raise ConfigError(err.message, key=where + rest) from None
        if key == "n_nodes":
            raise ConfigError(err.message, key="thermal.nodes") from None
        raise


def check_thermal_inputs(scene) -> None:
    """Read what the heat balance will read — its span and its weather file — and size it
    against the scene's memory limit (:func:`check_thermal_size`) when it runs
    (:func:`thermal_active`), so that ``radscene check`` and ``radscene render`` refuse a bad
    weather file or an oversized balance before any render; raises
    :class:`~radscene.errors.ConfigError` naming the key."""
    if thermal_active(scene):
        start = end = None
        span = scene.spec.time
        if span is not None and scene.time is None:
            # a sequence without an instant of its own: the balance runs from a day before its
            # first frame (or thermal.start) to its last (or thermal.end), as the frames ask
            start = scene.spec.thermal.start or (span.start - _dt.timedelta(days=1))
            end = max(span.end, scene.spec.thermal.end or span.end)
        check_thermal_size(scene, start, end)
        first, last = _span(scene, start, end)
        if span is None and scene.time is not None and not first <= scene.time <= last:
            raise ConfigError(f"the heat balance runs {first.isoformat()} to {last.isoformat()}, which does not hold "
                              f"the scene's time {scene.time.isoformat()}",
                              key="thermal.end" if scene.time > last else "thermal.start")
        _weather(scene, first, last)
        check_thermal_description(scene)


def _thermal_elements(scene):
    """The surface elements of the heat balance (radscene.thermal.elements)."""
    from radscene.thermal.elements import build_elements

    solved = [~o.face_fixed if o.face_fixed is not None else np.zeros(len(o.face_material), bool)
              for o in scene.objects]
    terrain = next((k for k, o in enumerate(scene.objects) if o.is_terrain), None)
    return build_elements([o.mesh for o in scene.objects], [o.face_material for o in scene.objects],
                          solved, terrain=terrain, heightfield=scene.heightfield,
                          resolution=scene.spec.thermal.resolution)


def check_thermal_size(scene, start=None, end=None, step=None, elements=None) -> float:
    """Refuse a heat balance from ``start`` to ``end`` every ``step`` [s] (defaults as for
    :func:`solve_thermal`) whose arrays would exceed the scene's memory limit
    (:func:`radscene.scene.memory.check_thermal_memory`), before a step of it is taken;
    returns the bytes estimated.

    Raises
    ------
    radscene.errors.ConfigError
        Naming ``thermal.step``, with the elements, steps and figures.
    """
    from radscene.scene.memory import check_thermal_memory, memory_limit
    from radscene.thermal.solve import time_steps

    spec = scene.spec.thermal
    start, end = _span(scene, start, end)
    step = spec.step if step is None else float(step)
    steps = time_steps(np.datetime64(start.astimezone(_dt.UTC).replace(tzinfo=None), "ns"),
                       np.datetime64(end.astimezone(_dt.UTC).replace(tzinfo=None), "ns"), step)
    if _own_spin_up_day(spec, start, end, step):
        steps += max(1, int(round(DAY / step))) + 1  # the forcing of the spin-up's own day
    if elements is None:
        elements = _thermal_elements(scene)
    return check_thermal_memory(elements.size, steps, spec.nodes, spec.hemisphere_samples,
                                scene.memory_limit or memory_limit(scene.spec), profiles=spec.profiles)


def _own_spin_up_day(spec, start, end, step) -> bool:
    """Whether the spin-up repeats a day of its own (the run has no time a day after its start:
    shorter than a day, or a step that misses that instant)."""
    if not spec.spins_up:
        return False
    span = (end - start).total_seconds()
    whole = DAY / step
    return span < DAY - 1e-6 or abs(whole - round(whole)) > 1e-9


def _read_weather_file(scene, spec, path, start, end):
    from radscene.thermal import weather as wx

    loc = scene.location
    if path.suffix.lower() == ".wth":
        if spec.start is None:
            raise ConfigError("a THERM .wth file has no date: give thermal.weather.start, the instant of its "
                              "hour 0 with its UTC offset", key="thermal.weather.start")
        cloud = spec.cloud_cover if "cloud_cover" in spec.model_fields_set else None
        weather = wx.read_weather(path, latitude=loc.latitude, longitude=loc.longitude, start=spec.start,
                                  cloud_cover=cloud, fields=spec.fields, max_gap=spec.max_gap,
                                  tolerance_deg=spec.place_tolerance)
        if not weather.covers(start, end):
            raise ConfigError(f"{path} covers {weather.span_text()}, not the heat balance's {start} – {end}",
                              key="thermal.weather.file")
        return weather
    return wx.read_weather(path, latitude=loc.latitude, longitude=loc.longitude, start=start, end=end,
                           max_gap=spec.max_gap, tolerance_deg=spec.place_tolerance)


def _weather(scene, start, end):
    from radscene.thermal import weather as wx

    spec = scene.spec.thermal.weather
    loc = scene.location
    if spec.file is not None:
        from pathlib import Path

        path = Path(spec.file)
        base = scene.base_dir or (Path(scene.source).parent if scene.source is not None else None)
        if not path.is_absolute() and base is not None:
            path = Path(base) / path
        if not path.is_file():
            raise ConfigError(f"no such weather file: {path}", key="thermal.weather.file")
        try:
            weather = _read_weather_file(scene, spec, path, start, end)
        except ConfigError as err:
            if err.key and err.key.startswith("thermal."):
                raise
            first = str(err.message).strip().splitlines()[0] if str(err.message).strip() else "unreadable"
            raise ConfigError(first if str(path) in first else f"{path}: {first}",
                              key="thermal.weather.file") from None
        except (OSError, UnicodeDecodeError, ValueError) as err:
            what = ("not a text file" if isinstance(err, UnicodeDecodeError)
                    else str(err).strip().splitlines()[0] if str(err).strip() else type(err).__name__)
            raise ConfigError(f"cannot read weather file {path.name}: {what}",
                              key="thermal.weather.file") from None
        thermal = scene.spec.thermal
        day_end = start + _dt.timedelta(days=1)
        if (thermal.spins_up and end < day_end
                and not weather.covers(start, day_end)):
            raise ConfigError(
                f"the spin-up repeats the day from the start, {start.isoformat()} to {day_end.isoformat()}, "
                f"which {path.name} ({weather.span_text()}) does not cover; extend the file, or set "
                "thermal.spin_up: false (with thermal.initial_temperature)", key="thermal.spin_up")
        return weather
    pressure = spec.pressure
    if pressure is None:
        import pvlib

        pressure = float(pvlib.atmosphere.alt2pres(loc.altitude))
    # local mean-solar dates, from the day before the start to the day after the end
    solar = _dt.timedelta(hours=loc.longitude / 15.0)
    first = (start.astimezone(_dt.UTC) + solar).date() - _dt.timedelta(days=1)
    last = (end.astimezone(_dt.UTC) + solar).date() + _dt.timedelta(days=1)
    return wx.diurnal_weather(loc.latitude, loc.longitude, first, t_min=spec.t_min, t_max=spec.t_max,
                              relative_humidity=spec.relative_humidity, wind_speed=spec.wind_speed,
                              cloud_cover=spec.cloud_cover, pressure=pressure, days=(last - first).days + 1)


def _initial_temperature(scene, used):
    """``thermal.initial_temperature`` as the solver takes it: a temperature [K], one per stack
    from its material (``used``: each stack's material index; NaN: not given), or None."""
    given = scene.spec.thermal.initial_temperature
    if given is None or not isinstance(given, dict):
        return given
    names = [scene.material_names[i] for i in used]
    for name in given:
        if name not in names:
            raise ConfigError(f"no solved surface is made of {name!r}; the solved materials: "
                              f"{', '.join(sorted(set(names)))}", key=f"thermal.initial_temperature.{name}")
    return np.array([given.get(name, np.nan) for name in names], float)


def _object_layered(scene, elements, used):
    """The materials (indices in ``used``) whose every solved element belongs to an object that
    gives its own ``layers``: they need no thermal description of their own."""
    spec = scene.spec.thermal
    layered = np.array([spec.objects.get(o.name) is not None and spec.objects[o.name].layers is not None
                        for o in scene.objects] + [False])
    owner = np.where(elements.object >= 0, elements.object, len(scene.objects))
    return {int(m) for m in used if np.all(layered[owner[elements.material == m]])}


def _stacks(scene, used, layered_by_objects=frozenset()):
    """The thermal stack and optical figures of each material in ``used`` (material indices);
    a material in ``layered_by_objects`` without a description gets an empty placeholder, which
    :func:`_object_stacks` replaces."""
    from dataclasses import replace

    from radscene.materials import get_thermal_properties
    from radscene.materials.thermal import make_layers

    spec = scene.spec.thermal
    for name in spec.materials:
        if name not in scene.material_names:
            raise ConfigError(f"unknown material {name!r}; the scene's: {', '.join(scene.material_names)}",
                              key=f"thermal.materials.{name}")
    stacks = []
    for m in used:
        name = scene.material_names[m]
        override = spec.materials.get(name)
        key = f"thermal.materials.{name}"
        try:
            stack = get_thermal_properties(name)
        except ConfigError:
            if (override is None or override.layers is None) and m not in layered_by_objects:
                raise ConfigError(
                    f"material {name!r} has no thermal description: give its layers under {key}.layers "
                    "(thickness, conductivity, density, specific_heat), or fixed temperatures to the "
                    "surfaces made of it", key=key) from None
            from radscene.materials.thermal import ThermalProperties

            stack = ThermalProperties(material=name, layers=(), bottom="semi-infinite",
                                      solar_absorptance=float("nan"), longwave_emissivity=float("nan"))
        if override is not None:
            changes = {}
            if override.layers is not None:
                changes["layers"] = make_layers(override.layers, key=f"{key}.layers")
            if override.bottom is not None:
                changes["bottom"] = override.bottom
            stack = replace(stack, **changes) if changes else stack
        stacks.append(stack)
    return stacks


def _optics(scene, used, stacks, table):
    """Solar absorptance (against the engine's ground spectrum over the run) and long-wave
    emissivity of each used material, unless the scene file gives them."""
    from radscene.materials.thermal import longwave_emissivity, solar_absorptance

    spec = scene.spec.thermal
    alpha, eps = [], []
    for m, stack in zip(used, stacks, strict=True):
        name = scene.material_names[m]
        override = spec.materials.get(name)
        material = scene.materials[m]
        a = override.solar_absorptance if override is not None else None
        e = override.longwave_emissivity if override is not None else None
        alpha.append(a if a is not None else solar_absorptance(material, irradiance=table))
        eps.append(e if e is not None else (stack.longwave_emissivity if np.isfinite(stack.longwave_emissivity)
                                            else longwave_emissivity(material)))
    return np.array(alpha), np.array(eps)


def _object_stacks(scene, elements, used, stack_index, stacks, alpha, eps):
    """Split off a stack of its own for each object whose ``thermal.objects`` entry gives a stack,
    optics or wetness of its own (per material of the object's elements).

    Returns the stacks, their absorptance and emissivity, each element's stack, and each stack's
    material (index) and object (index, −1: the material's own)."""
    from dataclasses import replace

    from radscene.materials.thermal import make_layers

    spec = scene.spec.thermal
    stacks, alpha, eps = list(stacks), list(alpha), list(eps)
    material, owner = list(used), [-1] * len(stacks)
    index = np.asarray(stack_index).ravel().copy()
    own = ("layers", "bottom", "solar_absorptance", "longwave_emissivity", "moisture_availability")
    for k, obj in enumerate(scene.objects):
        settings = spec.objects.get(obj.name)
        if settings is None or all(getattr(settings, name) is None for name in own):
            continue
        key = f"thermal.objects.{obj.name}"
        mine = elements.object == k
        if not np.any(mine):
            raise ConfigError(f"object {obj.name!r} has no solved surface (it keeps a fixed temperature)", key=key)
        for s in np.unique(index[mine]):
            changes = {}
            if settings.layers is not None:
                changes["layers"] = make_layers(settings.layers, key=f"{key}.layers")
            if settings.bottom is not None:
                changes["bottom"] = settings.bottom
            stacks.append(replace(stacks[s], **changes) if changes else stacks[s])
            alpha.append(alpha[s] if settings.solar_absorptance is None else settings.solar_absorptance)
            eps.append(eps[s] if settings.longwave_emissivity is None else settings.longwave_emissivity)
            material.append(material[s])
            owner.append(k)
            index[mine & (index == s)] = len(stacks) - 1
    kept, index = np.unique(index, return_inverse=True)  # drop the stacks no element has left
    return ([stacks[j] for j in kept], np.array(alpha)[kept], np.array(eps)[kept], index.ravel(),
            np.array(material)[kept], np.array(owner)[kept])


def _spectral_absorptance(scene, stack_material, stack_object, alpha, table):
    """Each stack's solar absorptance of the beam and of the diffuse sky at every sun-zenith node
    of ``table`` (n_nodes, n_stacks), from its material's spectrum against each one's spectrum
    at the ground; the given (or daily) ``alpha`` where the scene file sets it or a node has no
    light."""
    from radscene.materials.thermal import solar_absorptance

    spec = scene.spec.thermal
    n = table.zenith.size
    direct, diffuse = np.tile(alpha, (n, 1)), np.tile(alpha, (n, 1))
    if table.direct_spectrum is None:
        return direct, diffuse
    wl = table.wavelength
    done = {}
    for s, (m, k) in enumerate(zip(stack_material, stack_object, strict=True)):
        name = scene.material_names[m]
        material_given = spec.materials.get(name) is not None and spec.materials[name].solar_absorptance is not None
        object_given = k >= 0 and spec.objects[scene.objects[k].name].solar_absorptance is not None
        if material_given or object_given:
            continue
        if m not in done:
            values = np.full((2, n), np.nan)
            for j in range(n):
                for row, spectra in enumerate((table.direct_spectrum, table.diffuse_spectrum)):
                    if np.trapezoid(spectra[j], wl) > 1e-6:
                        values[row, j] = solar_absorptance(scene.materials[m], irradiance=(wl, spectra[j]))
            done[m] = values
        direct[:, s] = np.where(np.isfinite(done[m][0]), done[m][0], alpha[s])
        diffuse[:, s] = np.where(np.isfinite(done[m][1]), done[m][1], alpha[s])
    return direct, diffuse


#: ``internal_faces``: the faces by their outward normal's vertical component (60 deg from up
#: or down).
_FACES = {"all": lambda nz: np.ones(nz.shape, bool), "top": lambda nz: nz > 0.5,
          "bottom": lambda nz: nz < -0.5, "sides": lambda nz: np.abs(nz) <= 0.5}


def _sources(scene, elements, stack_material, stack_object, stacks, index, times):
    """Moisture availability, internal flux, airspeed and length per element from the stacks, the
    scene file's ``thermal.materials`` and ``thermal.objects``, and the objects' trajectories
    (their speed over the ground at ``times``, where no ``air_speed`` is given)."""
    spec = scene.spec.thermal
    beta, flux = [], []
    for m, k, stack in zip(stack_material, stack_object, stacks, strict=True):
        override = spec.materials.get(scene.material_names[m])
        given = None if override is None else override.moisture_availability
        if k >= 0 and spec.objects[scene.objects[k].name].moisture_availability is not None:
            given = spec.objects[scene.objects[k].name].moisture_availability
        beta.append(given if given is not None else float(getattr(stack, "moisture_availability", 0.0) or 0.0))
        flux.append(0.0 if override is None else override.internal_flux)
    internal = np.array(flux)[index]
    speed = np.full(elements.size, np.nan)
    length = np.ones(elements.size)
    for k, obj in enumerate(scene.objects):
        settings = spec.objects.get(obj.name)
        if settings is None:
            continue
        mine = elements.object == k
        if settings.internal_flux or settings.internal_power:
            heated = mine & _FACES[settings.internal_faces](elements.normal[:, 2])
            area = float(elements.area[heated].sum())
            if area <= 0:
                raise ConfigError(f"object {obj.name!r} has no solved {settings.internal_faces} faces to carry "
                                  "its internal sources", key=f"thermal.objects.{obj.name}.internal_faces")
            internal[heated] += settings.internal_flux + settings.internal_power / area
        if settings.air_speed > 0:
            speed[mine] = settings.air_speed
            length[mine] = settings.length
    moving = _trajectory_speeds(scene, elements, times)
    if moving:
        speed = np.broadcast_to(speed, (len(times), elements.size)).copy()
        for k, value in moving.items():
            settings = spec.objects.get(scene.objects[k].name)
            if settings is not None and "air_speed" in settings.model_fields_set:
                continue  # a speed through the air given: it holds (e.g. against a head wind)
            mine = elements.object == k
            speed[:, mine] = np.where(value > 0, value, np.nan)[:, None]
            length[mine] = 1.0 if settings is None else settings.length
    return {"moisture_availability": np.array(beta)[index], "internal_flux": internal, "air_speed": speed,
            "characteristic_length": length}


def _motion_epoch(scene):
    """The instant of the trajectories' t = 0: a simulation's start, else the scene file's
    instant (``environment.time``, or a sequence's ``time.start``), not the clock a simulation
    moves."""
    epoch = getattr(scene, "render_cache", {}).get("motion_epoch")
    if epoch is not None:
        return epoch
    spec = scene.spec
    if spec.environment.time is not None:
        return spec.environment.time
    return spec.time.start if spec.time is not None else None


def _trajectory_speeds(scene, elements, times):
    """Speed over the ground [m s-1] at ``times`` of each object (index) with solved elements
    that moves on a trajectory (its own or a parent's): the trajectory's velocity at each time
    from the scene's instant (t = 0), 0 outside the trajectory's samples (held at its ends)."""
    epoch = _motion_epoch(scene)
    if not getattr(scene, "motions", None) or epoch is None:
        return {}
    t = (np.asarray(times, "datetime64[ns]") - np.datetime64(
        epoch.astimezone(_dt.UTC).replace(tzinfo=None), "ns")) / np.timedelta64(1, "s")
    out = {}
    for k, obj in enumerate(scene.objects):
        motion = scene.motions.get(obj.name)
        while motion is not None and motion.trajectory is None and motion.parent is not None:
            motion = scene.motions.get(motion.parent)
        if motion is None or motion.trajectory is None or not np.any(elements.object == k):
            continue
        traj = motion.trajectory
        lo, hi = traj.span
        inside = (t >= lo) & (t <= hi)
        value = np.zeros(t.size)
        if np.any(inside):
            value[inside] = np.linalg.norm(traj.velocity(t[inside]), axis=-1)
        if np.any(value > 0):
            out[k] = value
    return out


def _fixed_exitance(scene, elements):
    """ε σ T⁴ of every face that keeps a fixed temperature (0 on solved faces) [W m-2]."""
    from radscene.materials.thermal import longwave_emissivity
    from radscene.thermal.radiation import SIGMA

    temperature = np.concatenate([o.face_temperature for o in scene.objects])
    material = np.concatenate([o.face_material for o in scene.objects])
    fixed = elements.face_element < 0
    out = np.zeros(temperature.size)
    for m in np.unique(material[fixed]):
        sel = fixed & (material == m)
        out[sel] = longwave_emissivity(scene.materials[m]) * SIGMA * temperature[sel] ** 4
    return out


def solve_thermal(scene, *, start=None, end=None, step=None, progress=None) -> xr.Dataset:
    """The heat balance of every surface of a scene without a fixed temperature.

    Parameters
    ----------
    scene : radscene.scene.Scene, dict or path
        A loaded scene, or what :func:`radscene.load_scene` loads.
    start, end : datetime, optional
        Timezone-aware; default ``thermal.start``/``thermal.end`` of the scene file, else one
        day up to the scene's time.
    step : float, optional
        [s]; default ``thermal.step``.
    progress : callable(stage, done, total), bool, optional
        A callable is called with each stage's progress; True shows a bar, False none; the
        default shows one when Python runs interactively (:mod:`radscene.pipeline.progress`).

    Returns
    -------
    xarray.Dataset
        ``surface_temperature(time, element)`` [K], the flux terms ``q_*(time, element)``
        [W m-2], element coordinates (position, normal, area, material, object), the forcing
        per time; see :func:`radscene.thermal.solve.solve_elements`.
    """
    from radscene.geometry import RayTracer
    from radscene.thermal.irradiance import shortwave_table
    from radscene.thermal.solve import ThermalOptions, solve_elements, time_axis

    scene = as_scene(scene)
    spec = scene.spec.thermal
    start, end = _span(scene, start, end)
    step = spec.step if step is None else float(step)
    names = [o.name for o in scene.objects]
    meshes = [o.mesh for o in scene.objects]
    elements = _thermal_elements(scene)
    check_thermal_description(scene, elements)
    check_thermal_size(scene, start, end, step, elements)
    times = time_axis(np.datetime64(start.astimezone(_dt.UTC).replace(tzinfo=None), "ns"),
                      np.datetime64(end.astimezone(_dt.UTC).replace(tzinfo=None), "ns"), step)
    used, stack_index = np.unique(elements.material, return_inverse=True)
    stacks = _stacks(scene, used, _object_layered(scene, elements, used))
    loc = scene.location
    weather = _weather(scene, start, end)
    first = times[0].astype("datetime64[D]")
    day = int((first - first.astype("datetime64[Y]")).astype(int)) + 1
    from radscene.sun import earth_sun_distance

    distance = float(earth_sun_distance(start)) if scene.sun is None else scene.sun.distance
    override = None if scene.sun is None else (scene.sun.zenith, scene.sun.azimuth, scene.sun.distance)
    table = shortwave_table(scene.atmosphere, loc.altitude, day, distance)
    if scene.sun is None:
        import pandas as pd

        from radscene.sun import sun_position

        zenith = sun_position(pd.DatetimeIndex(times).tz_localize("UTC"), loc.latitude, loc.longitude,
                              loc.altitude).zenith
    else:
        zenith = np.full(times.size, scene.sun.zenith)
    # solar absorptance against the ground's global spectrum summed over the run's sun positions
    alpha, eps = _optics(scene, used, stacks, (table.wavelength, table.daily_spectrum(zenith)))
    stacks, alpha, eps, index, stack_material, stack_object = _object_stacks(
        scene, elements, used, stack_index, stacks, alpha, eps)
    options = ThermalOptions(step=step, shadow_interval=spec.shadow_interval,
                             spin_up=spec.spins_up,
                             spin_up_tolerance=spec.spin_up_tolerance, hemisphere_samples=spec.hemisphere_samples,
                             nodes=spec.nodes, convection=spec.convection, seed=scene.settings.seed,
                             lateral=spec.lateral, exchange_reflections=spec.exchange_reflections,
                             initial_temperature=_initial_temperature(scene, stack_material),
                             profiles=spec.profiles)
    tracer = RayTracer(meshes)
    shadow_tracer, sun_transmittance = _media_sun_transmittance(
        scene, tracer, table.wavelength, table.daily_spectrum(zenith))
    see_through = _sheet_see_through(scene, table.wavelength, table.daily_spectrum(zenith))
    sources = _sources(scene, elements, stack_material, stack_object, stacks, index, times)
    spectral = _spectral_absorptance(scene, stack_material, stack_object, alpha, table)
    with progress_callback(progress, "heat balance", stages=True) as report:
        ds = solve_elements(tracer, elements, stacks, index, times,
                            (loc.latitude, loc.longitude, loc.altitude), scene.atmosphere, weather,
                            absorptance=alpha[index], emissivity=eps[index],
                            fixed_face_exitance=_fixed_exitance(scene, elements), meshes=meshes, options=options,
                            **sources, names={"material": scene.material_names, "object": names},
                            sun_override=override, progress=report,
                            sun_transmittance=sun_transmittance, shadow_tracer=shadow_tracer,
                            see_through=see_through, node_absorptance=spectral)
    ds.attrs.update({"scene": scene.name, "weather": getattr(weather, "source", "")})
    stamp(ds, scene)
    scene.render_cache["thermal_elements"] = elements
    return ds


def apply_thermal(scene, solution=None, time=None, *, progress=None):
    """Set the scene's free surface temperatures from the heat balance at an instant.

    Parameters
    ----------
    scene : radscene.scene.Scene
        Changed in place: ``face_temperature`` of every face without a fixed temperature, and
        the terrain's ``face_corner_temperature`` (the reconstruction of
        :mod:`radscene.thermal.reconstruction`) unless ``thermal.interpolate`` is false.
    solution : xarray.Dataset, optional
        From :func:`solve_thermal`; solved (and kept with the scene) when not given.
    time : datetime, optional
        Default the scene's time; linear between the solution's steps.
    progress : callable(stage, done, total), bool, optional
        Of the heat balance, when it is solved here; as for :func:`solve_thermal`.

    Returns
    -------
    xarray.Dataset
        The solution used.
    """
    if solution is None:
        solution = scene.render_cache.get("thermal")
        if solution is None:
            solution = solve_thermal(scene, progress=progress)
    scene.render_cache["thermal"] = solution
    elements = scene.render_cache.get("thermal_elements")
    if elements is None:
        raise ConfigError("the solution's elements are not known: solve it with solve_thermal(scene)", key="thermal")
    when = scene.time if time is None else time
    t = np.datetime64(when.astimezone(_dt.UTC).replace(tzinfo=None), "ns") if when is not None else solution.time.values[-1]
    times = solution.time.values
    if t < times[0] or t > times[-1]:
        raise ConfigError(f"{when} lies outside the heat balance's span {times[0]} – {times[-1]} (UTC)", key="thermal.end")
    surface = solution.surface_temperature.interp(time=t).values.astype(float)
    fixed = np.concatenate([o.face_temperature for o in scene.objects])
    faces = elements.face_values(surface, fixed)
    corners = None
    if scene.spec.thermal.interpolate and elements.grid_shape is not None:
        from radscene.thermal.reconstruction import corner_temperature, terrain_neighbours

        cached = scene.render_cache.get("thermal_neighbours")
        if cached is None or cached[0] is not elements:
            cached = scene.render_cache["thermal_neighbours"] = (elements, terrain_neighbours(elements))
        neighbours = cached[1]
        corners = corner_temperature(elements, surface, fixed, neighbours)
    offset = 0
    for obj in scene.objects:
        n = len(obj.face_temperature)
        obj.face_temperature = faces[offset:offset + n].copy()
        obj.face_corner_temperature = None if corners is None or not obj.is_terrain else corners[offset:offset + n].copy()
        offset += n
    scene.render_cache.pop("tables", None)
    return solution


def _weighting_band(wavelength, weights, name):
    """A band object whose response is ``weights`` over ``wavelength`` [um] (zeros left out):
    the weighting of a broadband transmittance (:func:`radscene.render.sheets.band_transmittance`,
    :func:`radscene.render.volumes.sun_transmittance`)."""
    from types import SimpleNamespace

    from radscene.radiometry import TabulatedResponse

    keep = np.asarray(weights, float) > 0.0
    return SimpleNamespace(response=TabulatedResponse(np.asarray(wavelength, float)[keep],
                                                      np.asarray(weights, float)[keep],
                                                      name=name))


def _face_tables(scene):
    """(first face of each object in the scene's face order, material of every face)."""
    counts = [len(o.face_material) for o in scene.objects]
    return (np.concatenate([[0], np.cumsum(counts)[:-1]]).astype(int),
            np.concatenate([o.face_material for o in scene.objects]))


def _media_sun_transmittance(scene, tracer, wavelength, spectrum):
    """The heat balance's partial shadows: (the tracer of its shadow rays, which do not see the
    sheets; ``transmittance(points, sun)``, the share of the direct sun passing the scene's
    volumes and sheets, or None without either).

    A sheet's share is Δτ τ (its texture's multiplier times its material's transmittance),
    weighted by the ground's global spectrum like the volumes' (:func:`_volume_sun_transmittance`);
    sheets in series multiply, as in the render (:func:`radscene.render.sheets.sun_transmittance`).
    """
    through_volumes = _volume_sun_transmittance(scene, wavelength, spectrum)
    from radscene.render import sheets

    is_sheet, shadow_tracer, sheet_tracer = sheets.tracers(scene.objects, tracer)
    if not is_sheet.any():
        return tracer, through_volumes
    from types import SimpleNamespace

    band = _weighting_band(wavelength, spectrum, "shortwave")
    tau = sheets.band_transmittance(scene.materials, [band], hold=True)
    offset, material = _face_tables(scene)
    lo, hi = tracer.bounds
    geometry = SimpleNamespace(epsilon=1e-4 + 2e-6 * float(np.linalg.norm(hi - lo)), sheet_tracer=sheet_tracer,
                               face_offset=offset, face_material=material)

    multiplier = _textured_sheet_multiplier(scene)

    def transmittance(points, sun):
        points = np.asarray(points, float)
        # the shadow points lie on faces facing the sun, just off them: any normal towards the
        # sun keeps the sheet rays' origins on the lit side
        normals = np.broadcast_to(np.asarray(sun, float), points.shape)
        out = sheets.sun_transmittance(geometry, tau, points, normals, sun, multiplier)[:, 0]
        return out if through_volumes is None else out * through_volumes(points, sun)
    return shadow_tracer, transmittance


#: The long-wave weighting of a sheet's transmittance in the heat balance's hemisphere: a
#: blackbody at this temperature [K] over :data:`_LONGWAVE_UM` [um].
_LONGWAVE_TEMPERATURE = 300.0
_LONGWAVE_UM = (4.0, 50.0)


def _textured_sheet_multiplier(scene):
    """``multiplier(object, position)``: Δτ of textured sheets at hit points (1 elsewhere)."""
    def multiplier(obj, pos):
        out = np.ones(len(obj))
        for k, o in enumerate(scene.objects):
            texture = o.textures.get("transmittance") if o.textures else None
            if texture is not None and np.any(obj == k):
                out[obj == k] = texture.sample(pos[obj == k, 0], pos[obj == k, 1])
        return out
    return multiplier


def _sheet_see_through(scene, wavelength, spectrum):
    """``see_through(object, primitive, position)``: the shares of the heat balance's
    hemisphere a sheet passes, (N, 2): Δτ τ with τ its material's transmittance weighted by a
    300 K blackbody over 4–50 um (the sky's and the scene's long-wave exchange), and by the
    ground's global short-wave spectrum (``wavelength`` [um], ``spectrum``; the diffuse sky's
    light); 0 for other faces. None without sheets (every face opaque)."""
    from radscene.render import sheets

    is_sheet = np.array([bool(getattr(o, "transmissive", False)) for o in scene.objects])
    if not is_sheet.any():
        return None
    from radscene.radiometry import spectral_radiance

    wl = np.linspace(*_LONGWAVE_UM, 941)
    bands = [_weighting_band(wl, spectral_radiance(wl, _LONGWAVE_TEMPERATURE), "longwave"),
             _weighting_band(wavelength, spectrum, "shortwave")]
    tau = sheets.band_transmittance(scene.materials, bands, hold=True)  # (n_m, 2)
    offset, material = _face_tables(scene)
    multiplier = _textured_sheet_multiplier(scene)

    def see_through(obj, primitive, position):
        obj = np.asarray(obj, int)
        out = np.zeros((obj.size, 2))
        on = is_sheet[obj]
        if on.any():
            out[on] = (tau[material[offset[obj[on]] + np.asarray(primitive)[on]]]
                       * multiplier(obj[on], np.asarray(position)[on])[:, None])
        return out
    return see_through


def _volume_sun_transmittance(scene, wavelength, spectrum):
    """``transmittance(points, sun)``: the share of the direct sun passing the scene's volumes,
    their transmittance weighted by the ground's global spectrum (the heat balance's solar
    weighting) [-]; None without volumes."""
    if not scene.volumes:
        return None
    from radscene.render import volumes

    band = _weighting_band(wavelength, spectrum, "shortwave")

    def transmittance(points, sun):
        return volumes.sun_transmittance(scene.volumes, [band], points, sun)[:, 0]
    return transmittance


def render(scene, observer=None, *, progress=None, **kwargs):
    """:func:`radscene.render.integrator.render` with the scene's heat balance applied first
    (when it runs; :func:`thermal_active`); an observer with a spectral grid (and no ``bands``
    given) through :func:`render_hyperspectral`.

    ``progress``: a callable, called as ``progress(samples_done, samples_total)`` after each
    tile; True for a progress bar (the heat balance's, then the render's); False for none; by
    default a bar when Python runs interactively — IPython, Jupyter, the ``python`` prompt
    (:mod:`radscene.pipeline.progress`).
    """
    from radscene.render.integrator import render as render_observer

    scene = as_scene(scene)
    setup = scene.observers[0] if observer is None else scene.observer(observer)
    if setup.spectral is not None and kwargs.get("bands") is None:
        return render_hyperspectral(scene, setup.name, progress=progress)
    if thermal_active(scene):
        apply_thermal(scene, progress=None if callable(progress) else progress)
    with progress_callback(progress, f"render {setup.name}") as report:
        if _blurs_motion(scene, setup) and not kwargs:
            images = _through_simulation(scene, setup, report, blur=True)
        elif _scans_motion(scene, setup) and not kwargs:
            images = _through_simulation(scene, setup, report)
        else:
            images = render_observer(scene, observer, progress=report, **kwargs)
    return stamp(images, scene, setup.name)


def _moves(scene) -> bool:
    """Whether anything in the scene moves (objects on trajectories, a wavy sea)."""
    return any(m.moves for m in scene.motions.values()) or (
        scene.sea is not None and scene.sea.moves)


def _blurs_motion(scene, setup) -> bool:
    """Whether a band observer's image is blurred by what moves during its exposure
    (``render.motion_blur``)."""
    return (scene.settings.motion_blur is not None and setup.spectral is None
            and _moves(scene))


def _scans_motion(scene, setup) -> bool:
    """Whether a band observer is a scanner over something that moves during its scan."""
    return setup.kind in ("pushbroom", "whiskbroom") and setup.spectral is None and _moves(scene)


def _through_simulation(scene, setup, progress=None, blur=False):
    """The image of an observer over a moving scene through a :class:`Simulation` at the
    scene's instant, as frame 0 of a sequence renders it: a scanner's pixels each at its time
    (:mod:`radscene.pipeline.scan_motion`), and with ``blur`` the mean over the exposure's
    sub-instants (:mod:`radscene.pipeline.motion_blur`). The scene's meshes, poses and tables
    are left as they were."""
    from radscene.pipeline.simulation import Simulation
    from radscene.render.integrator import render as render_observer

    meshes = [obj.mesh for obj in scene.objects]
    poses = dict(scene.poses)
    cached = scene.render_cache.get("tables")
    try:
        sim = Simulation(scene, incremental=False)
        tables = scene.render_cache["tables"]

        def once(tables=tables):
            if sim._scans_motion(setup):
                return sim._scan(setup, tables, progress)
            return render_observer(scene, setup.name, progress=progress, tables=tables)

        return sim._expose(setup, once, tables) if blur else sim._scan(setup, tables, progress)
    finally:
        for obj, mesh in zip(scene.objects, meshes, strict=True):
            obj.mesh = mesh
        scene.poses.clear()
        scene.poses.update(poses)
        if cached is None:
            scene.render_cache.pop("tables", None)
        else:
            scene.render_cache["tables"] = cached


def render_all(scene, *, progress=None, **kwargs):
    """:func:`radscene.render.integrator.render_all` with the scene's heat balance applied first;
    observers with a spectral grid through :func:`render_hyperspectral`. ``progress`` as for
    :func:`render`, one bar over each observer in turn."""
    from radscene.render.integrator import render_all as render_observers

    scene = as_scene(scene)
    if any(o.spectral is not None or _scans_motion(scene, o) or _blurs_motion(scene, o)
           for o in scene.observers):
        return {o.name: render(scene, o.name, progress=progress, **kwargs) for o in scene.observers}
    if thermal_active(scene):
        apply_thermal(scene, progress=None if callable(progress) else progress)
    with progress_callback(progress, "render") as report:
        images = render_observers(scene, progress=report, **kwargs)
    return {name: stamp(ds, scene, name) for name, ds in images.items()}


def render_hyperspectral(scene, observer=None, *, progress=None, **kwargs):
    """:func:`radscene.render.hyperspectral.render_hyperspectral` (the observer's spectral grid
    into one Dataset, ``radiance(wavelength, y, x)`` [W m-2 sr-1 um-1]) with the scene's heat
    balance applied first; ``progress`` as for :func:`render`."""
    from radscene.render.hyperspectral import render_hyperspectral as _render_cube
    from radscene.scene.memory import check_cube_memory, memory_limit

    scene = as_scene(scene)
    setup = scene.observers[0] if observer is None else scene.observer(observer)
    grid = kwargs.get("grid", setup.spectral)
    if grid is not None:  # the cube is gathered in memory: sized before the heat balance
        index = scene.observers.index(setup)
        rows, columns = setup.camera.shape
        check_cube_memory(len(grid), rows * columns, scene.memory_limit or memory_limit(scene.spec),
                          f"observers[{index}].spectral.step",
                          np.dtype(kwargs.get("dtype", np.float32)).itemsize)
    if thermal_active(scene):
        apply_thermal(scene, progress=None if callable(progress) else progress)
    name = scene.observers[0].name if observer is None else observer
    with progress_callback(progress, f"render {name}") as report:
        cube = _render_cube(scene, observer, progress=report, **kwargs)
    return stamp(cube, scene, name)


def spectral_passes(scene, observer=None, *, progress=None, **kwargs):
    """:func:`radscene.render.hyperspectral.render_passes` (the observer's spectral grid a group
    of channels at a time) with the scene's heat balance applied first; ``progress`` as for
    :func:`render`."""
    from radscene.render.hyperspectral import render_passes

    scene = as_scene(scene)
    if thermal_active(scene):
        apply_thermal(scene, progress=None if callable(progress) else progress)
    name = scene.observers[0].name if observer is None else observer

    def passes():
        with progress_callback(progress, f"render {name}") as report:
            for part in render_passes(scene, observer, progress=report, **kwargs):
                yield stamp(part, scene, name)
    return passes()


def simulate(scene, observer: str | None = None, *, progress=None
             ) -> tuple[xr.Dataset, xr.Dataset | None]:
    """Render an observer and, when it has a sensor, record the signal.

    Surfaces without a fixed temperature take the heat balance's at the scene's time
    (:func:`thermal_active`, :func:`apply_thermal`).

    Parameters
    ----------
    scene : radscene.scene.Scene, dict or path
        A loaded scene, or what :func:`radscene.load_scene` loads.
    observer : str, optional
        Observer name; the first by default.
    progress : callable, bool, optional
        As for :func:`radscene.render`.

    Returns
    -------
    radiance : xarray.Dataset
        The render (``radiance(band, y, x)`` [W m-2 sr-1], terms, truth); for an observer
        with a spectral grid the cube, ``radiance(wavelength, y, x)`` [W m-2 sr-1 um-1].
    signal : xarray.Dataset or None
        The sensor's output (``dn(frame, band, y, x)`` [DN] and its truth), or None when the
        observer has no sensor.
    """
    scene = as_scene(scene)
    setup = scene.observers[0] if observer is None else scene.observer(observer)
    images = render(scene, setup.name, progress=progress)
    if setup.sensor is None or setup.spectral is not None:
        return images, None
    return images, record_signal(scene, setup, images)


def record_signal(scene, setup, images, seed=None) -> xr.Dataset:
    """The signal of an observer's sensor (``setup.sensor``) recording a render ``images``,
    with the scene's seed unless ``seed`` is given."""
    responses = {b.name: b.response for b in scene.bands if b.name in setup.bands}
    signal = setup.sensor.apply(images, frames=setup.frames,
                                seed=scene.settings.seed if seed is None else seed, responses=responses)
    signal.attrs.update({"scene": scene.name, "observer": setup.name})
    return stamp(signal, scene, setup.name)
