"""The heat balance of a scene's surface elements over a span of time.

:func:`solve_elements` joins the parts: the sun's position at every step
(:mod:`radscene.sun`), the short- and long-wave irradiance at the ground from the scene's
atmosphere engine (:mod:`radscene.thermal.irradiance`), the weather
(:mod:`radscene.thermal.weather`), shadows and the hemisphere of every element from the ray
engine (:mod:`radscene.thermal.exposure`), and the time stepper
(:class:`radscene.thermal.balance.HeatBalance`). It returns an xarray Dataset with the surface
temperature and every flux term of every element at every step.

Shadows are traced every ``shadow_interval`` (default: every step) and the sunlit fraction is
interpolated linearly in time between traces. The spin-up repeats the run's first day, or,
when the run has no time one day after its start, a day of its own from the start, until the
surface temperatures repeat from one day to the next.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import xarray as xr

from radscene.errors import ConfigError
from radscene.thermal.balance import HeatBalance, ThermalForcing
from radscene.thermal.conduction import DAY
from radscene.thermal.exposure import hemisphere_exposure, sunlit_fraction
from radscene.thermal.irradiance import shortwave_table, sky_longwave_irradiance

__all__ = ["ThermalOptions", "layer_probes", "solve_elements", "sun_vectors", "time_axis", "time_steps"]


@dataclass(frozen=True)
class ThermalOptions:
    """How the heat balance of a scene is run.

    Attributes
    ----------
    step : float
        Time step [s].
    shadow_interval : float or None
        Time between shadow traces [s]; None: every step.
    spin_up : bool
        Repeat the first day until it repeats itself (the run's own first day, or, when it has
        no time one day after its start, a day of its own from the start).
    spin_up_tolerance : float
        [K].
    max_spin_up_days : int
    hemisphere_samples : int
        Hemisphere rays per face for the sky view and view factors.
    nodes : int
        Conduction nodes per element.
    convection : str
        Wind correlation (``thermal.convection.CONVECTION_MODELS``).
    seed : int
    lateral : bool
        Lateral conduction between neighbouring elements (``thermal.lateral``).
    exchange_reflections : int
        Reflections followed in Q_env.
    initial_temperature : float or ndarray of float, or None
        Start every node at this temperature [K], or per stack (NaN: the first day's mean air
        temperature); None: that mean everywhere.
    profiles : bool
        Also write the temperature of every conduction node at every time
        (``node_temperature``); the layers' temperatures are always written.
    """

    step: float = 600.0
    shadow_interval: float | None = None
    spin_up: bool = True
    spin_up_tolerance: float = 0.05
    max_spin_up_days: int = 20
    hemisphere_samples: int = 64
    nodes: int = 20
    convection: str = "mcadams"
    seed: int = 0
    lateral: bool = False
    exchange_reflections: int = 1
    initial_temperature: float | np.ndarray | None = None
    profiles: bool = False


def time_axis(start, end, step):
    """UTC times from ``start`` to ``end`` inclusive every ``step`` [s] (datetime64[ns]).

    Raises
    ------
    ConfigError
        A start after the end, a step ≤ 0 or longer than the span.
    """
    t0, t1 = np.datetime64(start, "ns"), np.datetime64(end, "ns")
    n = _whole_steps(start, end, step)
    times = t0 + (np.arange(n + 1) * step * 1e9).astype("timedelta64[ns]")
    if times[-1] < t1:
        times = np.append(times, t1)
    return times


def _whole_steps(start, end, step) -> int:
    """The whole steps of [s] that fit from ``start`` to ``end``, checked as :func:`time_axis`
    says."""
    t0, t1 = np.datetime64(start, "ns"), np.datetime64(end, "ns")
    span = (t1 - t0) / np.timedelta64(1, "s")
    if span <= 0:
        raise ConfigError(f"the start {start} is not before the end {end}", key="thermal.start")
    if not (np.isfinite(step) and step > 0):
        raise ConfigError(f"must be > 0 s; got {step!r}", key="thermal.step")
    if step > span:
        raise ConfigError(f"{step:g} s is longer than the span {span:g} s", key="thermal.step")
    return int(np.floor(span / step + 1e-9))


def time_steps(start, end, step) -> int:
    """How many times :func:`time_axis` gives (without building them; the same errors): the
    whole steps and the start, and the end when the last step falls short of it."""
    n = _whole_steps(start, end, step)
    last = np.datetime64(start, "ns") + np.timedelta64(int(n * step * 1e9), "ns")
    return n + 1 + int(last < np.datetime64(end, "ns"))


def sun_vectors(zenith, azimuth):
    """Unit vectors towards the sun, east-north-up, from zenith and azimuth (clockwise from
    north) [deg]; shape (..., 3)."""
    z, a = np.radians(zenith), np.radians(azimuth)
    return np.stack([np.sin(z) * np.sin(a), np.sin(z) * np.cos(a), np.cos(z)], axis=-1)


def _seconds(times):
    return _seconds_from(times, times[0])


def _at_times(value, times, at):
    """A per-element value, or a (n_times, n_elements) series over ``times``, at the times
    ``at`` (linear in time, held beyond the ends)."""
    if value is None or np.ndim(value) < 2 or at is times:
        return value
    x, xp = np.clip(_seconds_from(at, times[0]), 0.0, None), _seconds(times)
    x = np.minimum(x, xp[-1])
    i = np.clip(np.searchsorted(xp, x, side="right") - 1, 0, xp.size - 2)
    w = ((x - xp[i]) / (xp[i + 1] - xp[i]))[:, None]
    value = np.asarray(value, float)
    return (1.0 - w) * value[i] + w * value[i + 1]


def _seconds_from(times, origin):
    return (np.asarray(times, "datetime64[ns]") - origin) / np.timedelta64(1, "s")


def _utc_index(times):
    import pandas as pd

    return pd.DatetimeIndex(times).tz_localize("UTC")


def _sun(times, lat, lon, alt, sun_override):
    """The sun's position at the times (the ephemeris, or a fixed sun)."""
    from radscene.sun import sun_position

    if sun_override is not None:
        from types import SimpleNamespace

        ones = np.ones(times.size)
        return SimpleNamespace(zenith=sun_override[0] * ones, azimuth=sun_override[1] * ones,
                               distance=sun_override[2] * ones)
    return sun_position(_utc_index(times), lat, lon, alt)


def _shadow_history(tracer, elements, times, sun_dir, interval, progress, transmittance=None):
    """Sunlit fraction (n_times, n_elements): traced every ``interval`` s, linear between."""
    t = _seconds(times)
    if interval is None:
        traced = np.arange(times.size)
    else:
        marks = np.arange(0.0, t[-1] + interval, interval)
        traced = np.unique(np.searchsorted(t, np.minimum(marks, t[-1])))
    report = None if progress is None else (lambda done, total: progress("shadows", done, total))
    lit_at = sunlit_fraction(tracer, elements, sun_dir[traced], progress=report,
                             transmittance=transmittance)
    if traced.size == times.size:
        return lit_at
    tk = t[traced]
    hi = np.clip(np.searchsorted(tk, t, side="right"), 1, tk.size - 1)
    w = np.clip((t - tk[hi - 1]) / (tk[hi] - tk[hi - 1]), 0.0, 1.0)[:, None]
    return (1.0 - w) * lit_at[hi - 1] + w * lit_at[hi]


def solve_elements(tracer, elements, stacks, stack_index, times, location, atmosphere, weather,
                   *, absorptance=None, emissivity=None, fixed_face_exitance=None, moisture_availability=None,
                   internal_flux=0.0, air_speed=None, characteristic_length=1.0, meshes=None,
                   options=ThermalOptions(), names=None, sun_override=None, progress=None,
                   sun_transmittance=None, shadow_tracer=None, see_through=None, node_absorptance=None):
    """Surface temperatures and flux terms of every element at every time.

    Parameters
    ----------
    tracer : radscene.geometry.RayTracer
        The scene's ray engine.
    elements : SurfaceElements
    stacks : sequence of ThermalProperties
        The distinct stacks.
    stack_index : ndarray of int, (n_elements,)
        Stack of each element.
    times : ndarray of datetime64, (n_times,)
        UTC, strictly increasing.
    location : (float, float, float)
        Latitude, longitude [deg] and altitude of the ground [m].
    atmosphere : radscene.atmosphere.Atmosphere
        The scene's engine.
    weather : object with ``at(times) -> dict``
        Air temperature [K], relative humidity [-], wind speed [m s-1], cloud cover [-],
        pressure [Pa], and optionally measured ``global_shortwave`` or
        ``direct_normal_shortwave`` with ``diffuse_shortwave``, ``longwave_down`` [W m-2] (:class:`radscene.thermal.weather.WeatherSeries`).
    absorptance, emissivity : ndarray, (n_elements,), optional
        Broadband solar absorptance and long-wave emissivity [-]; default the stacks'.
    fixed_face_exitance : ndarray, (n_faces,), optional
        ε σ T⁴ of the faces that are not solved [W m-2] (their long-wave reaches the elements
        that see them, in Q_env).
    moisture_availability : ndarray, (n_elements,), optional
        β of Q_v [-]; default 0.
    internal_flux : ndarray, (n_elements,) or scalar, optional
        Q_i of internal sources [W m-2].
    air_speed : ndarray, (n_elements,) or (n_times, n_elements), optional
        Speed through the air of airborne elements [m s-1], NaN elsewhere.
    characteristic_length : ndarray or float, optional
        Length along the airflow of airborne elements [m].
    meshes : sequence of Mesh, optional
        The scene's meshes (needed with ``options.lateral``).
    options : ThermalOptions
    names : dict, optional
        ``{"material": [...], "object": [...]}``: names for the output's coordinates.
    sun_override : (float, float, float), optional
        A sun fixed at (zenith [deg], azimuth [deg], distance [AU]) instead of the ephemeris.
    progress : callable(stage, done, total), optional
    sun_transmittance : callable(points, sun), optional
        The share of the direct sun passing semi-transparent volumes on the way to points
        (:func:`radscene.thermal.exposure.sunlit_fraction`); default none in the way.
    shadow_tracer : radscene.geometry.RayTracer, optional
        The ray engine of the shadow rays, when they must not see some surfaces (the
        semi-transparent sheets, whose share ``sun_transmittance`` gives); default ``tracer``.
    see_through : callable(object, primitive, position), optional
        The share of the hemisphere a face of ``tracer`` passes (a sheet's long-wave Δτ τ;
        :func:`radscene.thermal.exposure.hemisphere_exposure`); default every face opaque.
    node_absorptance : (ndarray, ndarray), optional
        Each stack's solar absorptance of the beam and of the diffuse sky at the short-wave
        table's sun-zenith nodes, (n_nodes, n_stacks) each: interpolated to the sun of every
        step (the spectra at the ground change with the sun's height); default ``absorptance``
        at every step.

    Returns
    -------
    xarray.Dataset
        ``surface_temperature(time, element)`` [K], ``q_<term>(time, element)`` [W m-2],
        element coordinates, the sky view factor, the spin-up's figures in the attributes.
    """
    times = np.asarray(times, dtype="datetime64[ns]")
    if times.ndim != 1 or times.size < 2 or np.any(np.diff(times) <= np.timedelta64(0, "ns")):
        raise ConfigError("must be at least two strictly increasing times", key="thermal.time")
    if elements.size == 0:
        raise ConfigError("no surface to solve: every object has a fixed temperature", key="thermal")
    lat, lon, alt = location
    hemisphere = hemisphere_exposure(tracer, elements, options.hemisphere_samples, options.seed,
                                     see_through=see_through)
    if progress is not None:
        progress("hemisphere", 1, 1)
    day = int(_utc_index(times[:1])[0].day_of_year)
    sun0 = _sun(times, lat, lon, alt, sun_override)
    table = shortwave_table(atmosphere, alt, day, float(np.mean(sun0.distance)))

    def drive(at, stage):
        """The forcing at the times ``at``, and what the output keeps of it."""
        sun = _sun(at, lat, lon, alt, sun_override)
        sun_dir = sun_vectors(sun.zenith, sun.azimuth)
        w = weather.at(at)
        direct, diffuse = table.at(sun.zenith)
        cloud = np.asarray(w.get("cloud_cover", np.zeros(at.size)), float)
        direct, diffuse = _cloudy_shortwave(direct, diffuse, cloud, sun.zenith)
        if w.get("global_shortwave") is not None and w.get("diffuse_shortwave") is not None:
            mu = np.cos(np.radians(np.minimum(sun.zenith, 90.0)))
            diffuse = np.asarray(w["diffuse_shortwave"], float)
            beam = np.asarray(w["global_shortwave"], float) - diffuse
            direct = np.where(mu > 0.05, np.maximum(beam, 0.0) / np.maximum(mu, 0.05), 0.0)
        elif w.get("direct_normal_shortwave") is not None and w.get("diffuse_shortwave") is not None:
            diffuse = np.asarray(w["diffuse_shortwave"], float)
            direct = np.where(sun.zenith < 90.0, np.asarray(w["direct_normal_shortwave"], float), 0.0)
        air = np.asarray(w["air_temperature"], float)
        if w.get("longwave_down") is not None:
            longwave = np.asarray(w["longwave_down"], float)
        else:
            clear = sky_longwave_irradiance(atmosphere, alt, air)
            longwave = _cloudy_longwave(clear, air, np.asarray(w["relative_humidity"], float), cloud)
        report = None if progress is None else (lambda name, done, total: progress(stage + name, done, total))
        lit = _shadow_history(tracer if shadow_tracer is None else shadow_tracer, elements, at, sun_dir,
                              options.shadow_interval, report, sun_transmittance)
        cos_i = np.clip(sun_dir @ elements.normal.T, -1.0, 1.0)
        a_dir = a_dif = None
        if node_absorptance is not None:
            nodes = table.weights(sun.zenith)
            a_dir = (nodes @ np.asarray(node_absorptance[0], float))[:, stack_index]
            a_dif = (nodes @ np.asarray(node_absorptance[1], float))[:, stack_index]
        col = (slice(None), None)
        forcing = ThermalForcing(
            time=_seconds(at),
            direct_irradiance=direct[col],
            cos_incidence=cos_i,
            diffuse_irradiance=diffuse[col],
            sky_longwave=longwave[col],
            air_temperature=air[col],
            wind_speed=np.asarray(w["wind_speed"], float)[col],
            lit=lit,
            sky_view_fraction=hemisphere.sky_view,
            sky_view_shortwave=hemisphere.sky_view_shortwave,
            relative_humidity=np.asarray(w["relative_humidity"], float)[col],
            pressure=np.asarray(w["pressure"], float)[col],
            internal_flux=internal_flux,
            air_speed=_at_times(speed, times, at),
            environment_irradiance=environment,
            direct_absorptance=a_dir,
            diffuse_absorptance=a_dif,
        )
        return forcing, (sun, direct, diffuse, longwave, air, lit, cos_i)

    environment = 0.0
    if fixed_face_exitance is not None and hemisphere.fixed.nnz:
        environment = hemisphere.fixed @ np.asarray(fixed_face_exitance, float)
    speed = None
    if air_speed is not None and np.any(np.isfinite(air_speed)):
        speed = np.asarray(air_speed, float)
    forcing, kept = drive(times, "")
    sun, direct, diffuse, longwave, air, lit, cos_i = kept

    lateral = _lateral(elements, stacks, np.asarray(stack_index), meshes) if options.lateral else None
    balance = HeatBalance(stacks, np.asarray(stack_index), absorptance=absorptance, emissivity=emissivity,
                          n_nodes=options.nodes, convection=options.convection, cos_tilt=elements.normal[:, 2],
                          exchange=hemisphere.exchange,
                          exchange_reflections=options.exchange_reflections,
                          moisture_availability=moisture_availability, characteristic_length=characteristic_length,
                          lateral=lateral, area=elements.area if lateral is not None else None)
    spin, spin_forcing = options.spin_up, None
    seconds = _seconds(times)
    if spin and not np.any(np.isclose(seconds, DAY, rtol=0.0, atol=1e-6)):
        # no sample a day after the start (a shorter run, or a step that does not divide the
        # day): spin up on the day that begins at the start, at the nearest step that divides it
        n = max(1, int(round(DAY / options.step)))
        day_times = times[0] + (np.arange(n + 1) * (DAY / n) * 1e9).round().astype("timedelta64[ns]")
        if hasattr(weather, "covers") and not weather.covers(day_times[0], day_times[-1]):
            raise ConfigError(
                f"the spin-up repeats the day from the start, {day_times[0]}Z to {day_times[-1]}Z, which the "
                f"weather ({weather.span_text()}) does not cover; extend the weather, or set thermal.spin_up: "
                f"false (with thermal.initial_temperature)", key="thermal.spin_up")
        spin_forcing, _ = drive(day_times, "spin-up day: ")
    initial = None
    if options.initial_temperature is not None:
        initial = np.asarray(options.initial_temperature, float)
        if initial.ndim == 1:  # per stack, NaN: the first day's mean air temperature
            mean_air = float(np.mean(air[seconds <= DAY + 1e-6]))
            initial = np.where(np.isfinite(initial), initial, mean_air)[np.asarray(stack_index)]
    layer_depth, layer_name = layer_probes(stacks, np.asarray(stack_index))
    probe = layer_depth
    if options.profiles:
        probe = np.concatenate([layer_depth, balance.grid.depth], axis=1)
    result = balance.run(forcing, initial_temperature=initial, spin_up=spin, spin_up_forcing=spin_forcing,
                         spin_up_tolerance=options.spin_up_tolerance, max_spin_up_days=options.max_spin_up_days,
                         record_terms=True, progress=progress, probe_depth=probe)
    ds = _dataset(elements, hemisphere, times, result, sun, direct, diffuse, longwave, air, lit, cos_i,
                  balance, names, spin)
    n_layers = layer_depth.shape[1]
    ds["layer_temperature"] = (("time", "element", "layer"), result.probe_temperature[:, :, :n_layers], {
        "units": "K", "long_name": "temperature of each layer of the element's stack: at the middle of a layer "
        "of given thickness, one diurnal penetration depth below the top of a semi-infinite last layer "
        "(NaN: the stack has fewer layers)"})
    ds = ds.assign_coords(
        layer_depth=(("element", "layer"), layer_depth, {"units": "m", "long_name": "depth of layer_temperature"}),
        layer_name=(("element", "layer"), layer_name, {"long_name": "name of the layer"}))
    if options.profiles:
        ds["node_temperature"] = (("time", "element", "node"), result.probe_temperature[:, :, n_layers:], {
            "units": "K", "long_name": "temperature of each conduction node of the element's stack"})
        ds = ds.assign_coords(node_depth=(("element", "node"), balance.grid.depth,
                                          {"units": "m", "long_name": "depth of the conduction node"}))
    return ds


def layer_probes(stacks, stack_index, period=DAY):
    """Where each element's layer temperatures are read: the middle of every layer of given
    thickness, and one diurnal penetration depth (the e-folding depth of the daily wave) below
    the top of a semi-infinite last layer.

    Returns
    -------
    depth : ndarray, (n_elements, n_layers)
        [m], NaN beyond an element's last layer.
    name : ndarray of str, (n_elements, n_layers)
        The layers' names ("" beyond the last).
    """
    from radscene.thermal.conduction import penetration_depth

    n = max(len(st.layers) for st in stacks)
    depth, name = np.full((len(stacks), n), np.nan), np.full((len(stacks), n), "", dtype=object)
    for i, st in enumerate(stacks):
        top = 0.0
        for j, layer in enumerate(st.layers):
            last_open = j == len(st.layers) - 1 and st.bottom == "semi-infinite"
            if last_open:
                depth[i, j] = top + float(penetration_depth(layer.conductivity, layer.density,
                                                            layer.specific_heat, period))
            else:
                depth[i, j] = top + 0.5 * layer.thickness
                top += layer.thickness
            name[i, j] = layer.name
    return depth[stack_index], name[stack_index].astype(str)


def _lateral(elements, stacks, stack_index, meshes):
    """Lateral conductances between elements that share edges, from each element's stack:
    Σ k_i t_i over its layers of given thickness, each layer counted to its diurnal penetration
    depth at most (a painted sheet conducts through its paint and its metal; a thick layer
    only through what the day's wave reaches), or k d of a stack that is one semi-infinite
    layer."""
    import trimesh
    from scipy import sparse

    from radscene.thermal.conduction import penetration_depth
    from radscene.thermal.lateral import mesh_conductance

    if meshes is None:
        raise ConfigError("lateral conduction needs the scene's meshes", key="thermal.lateral")
    kt = []
    for st in stacks:
        reach = [min(layer.thickness, penetration_depth(layer.conductivity, layer.density, layer.specific_heat))
                 for layer in st.layers if layer.thickness is not None]
        if reach:
            kt.append(sum(layer.conductivity * r for layer, r in
                          zip([la for la in st.layers if la.thickness is not None], reach, strict=True)))
        else:
            top = st.layers[0]
            kt.append(top.conductivity * float(penetration_depth(top.conductivity, top.density, top.specific_heat)))
    k = np.array(kt)[stack_index]  # k t as one conductance-thickness product, t = 1 m
    t = np.ones(elements.size)
    total = sparse.csr_array((elements.size, elements.size))
    offset = 0
    for mesh in meshes:
        n = len(mesh.faces)
        fe = elements.face_element[offset:offset + n]
        offset += n
        solved = fe >= 0
        if solved.sum() < 2:
            continue
        merged = trimesh.Trimesh(mesh.vertices, mesh.faces[solved], process=False)
        merged.merge_vertices()
        total = total + mesh_conductance(merged.vertices, merged.faces, fe[solved], k, t, n_elements=elements.size)
    return total.tocsr()


def _cloudy_shortwave(direct, diffuse, cloud, zenith):
    """Direct normal and diffuse irradiance under a cloud cover N: the global irradiance times
    Kasten & Czeplak's 1 − 0.75 N^3.4, its diffuse fraction k = k_0 + (1 − k_0) N² (their
    0.3 + 0.7 N² with the clear-sky 0.3 replaced by the engine's own clear-sky k_0)."""
    from radscene.thermal.weather import cloud_shortwave_factor

    if not np.any(cloud > 0):
        return direct, diffuse
    mu = np.cos(np.radians(np.minimum(zenith, 90.0)))
    clear = direct * mu + diffuse
    k0 = np.divide(diffuse, clear, out=np.ones_like(clear), where=clear > 0)
    k = k0 + (1.0 - k0) * cloud**2
    total = clear * cloud_shortwave_factor(cloud)
    beam = (1.0 - k) * total
    return np.divide(beam, mu, out=np.zeros_like(beam), where=mu > 1e-6), k * total


def _cloudy_longwave(clear, air, humidity, cloud):
    """Sky long-wave under cloud, Crawford & Duchon (1999): ε = N + (1 − N) ε_0, i.e.
    E = (1 − N) E_0 + N σ T_a⁴ with E_0 the engine's clear sky; without the engine's sky, the
    clear-sky emissivity of Brutsaert (1975) from the weather (:mod:`radscene.thermal.weather`)."""
    from radscene.thermal.radiation import SIGMA
    from radscene.thermal.weather import sky_longwave

    if clear is None:
        return sky_longwave(air, humidity, cloud)
    return (1.0 - cloud) * clear + cloud * SIGMA * air**4


def _dataset(elements, hemisphere, times, result, sun, direct, diffuse, longwave, air, lit, cos_i, balance,
             names, spin):
    t_s = result.surface_temperature
    eps, alpha = balance.emissivity, balance.absorptance
    terms = dict(result.terms)
    el = ("element",)
    material = np.asarray(names["material"])[elements.material] if names else elements.material
    obj = np.asarray(names["object"])[elements.object] if names else elements.object
    data = {
        "surface_temperature": (("time", "element"), t_s.astype(np.float32),
                                {"units": "K", "standard_name": "surface_temperature",
                                 "long_name": "surface temperature of the element"}),
        "sky_view": (el, hemisphere.sky_view, {"units": "1", "long_name": "sky view factor"}),
        "sky_view_shortwave": (el, hemisphere.sky_view if hemisphere.sky_view_shortwave is None
                               else hemisphere.sky_view_shortwave,
                               {"units": "1", "long_name": "sky view factor of the diffuse "
                                "short-wave sky (through semi-transparent sheets)"}),
        "sunlit": (("time", "element"), lit.astype(np.float32), {"units": "1", "long_name": "sunlit fraction"}),
        "sun_zenith": (("time",), np.asarray(sun.zenith, float), {"units": "degree", "long_name": "solar zenith angle"}),
        "direct_irradiance": (("time",), direct, {"units": "W m-2", "long_name": "direct solar irradiance normal to the beam"}),
        "diffuse_irradiance": (("time",), diffuse, {"units": "W m-2", "long_name": "diffuse short-wave irradiance, horizontal"}),
        "sky_longwave": (("time",), longwave, {"units": "W m-2", "long_name": "downwelling long-wave irradiance, horizontal"}),
        "air_temperature": (("time",), air, {"units": "K", "standard_name": "air_temperature"}),
        "absorptance": (el, alpha, {"units": "1", "long_name": "broadband solar absorptance over the run's sun (the balance "
                                                     "takes the beam's and the sky's at each step from their spectra)"}),
        "emissivity": (el, eps, {"units": "1", "long_name": "broadband long-wave emissivity"}),
    }
    if result.canopy_temperature is not None:
        data["canopy_temperature"] = (("time", "element"), result.canopy_temperature.astype(np.float32), {
            "units": "K", "long_name": "temperature of the leaf layer (NaN: no leaves)"})
        data["ground_temperature"] = (("time", "element"), result.ground_temperature.astype(np.float32), {
            "units": "K", "long_name": "temperature of the soil surface under the leaves (NaN: no leaves)"})
        data["surface_temperature"][2]["long_name"] = ("surface temperature of the element (with leaves: the nadir "
                                                       "radiometric temperature of leaves and soil)")
    long_names = {"q_a": "absorbed short-wave", "q_sky": "absorbed sky long-wave", "q_env": "exchange with the scene",
                  "q_t": "emitted long-wave", "q_k": "convection", "q_v": "evaporation", "q_i": "internal sources",
                  "q_lat": "lateral conduction from the neighbours", "q_d": "conduction from the stack"}
    for name, value in terms.items():
        data[name] = (("time", "element"), np.asarray(value, np.float32),
                      {"units": "W m-2", "long_name": long_names.get(name, name) + " (into the surface positive)"})
    coords = {
        "time": times,
        "x": (el, elements.position[:, 0], {"units": "m", "long_name": "easting of the element's centroid"}),
        "y": (el, elements.position[:, 1], {"units": "m", "long_name": "northing of the element's centroid"}),
        "z": (el, elements.position[:, 2], {"units": "m", "long_name": "height of the element's centroid"}),
        "normal_x": (el, elements.normal[:, 0], {"units": "1"}),
        "normal_y": (el, elements.normal[:, 1], {"units": "1"}),
        "normal_z": (el, elements.normal[:, 2], {"units": "1"}),
        "area": (el, elements.area, {"units": "m2"}),
        "material": (el, np.asarray(material).astype(str)),
        "object": (el, np.asarray(obj).astype(str)),
    }
    data["closure"] = (("time",), np.asarray(result.closure, float), {
        "units": "1", "long_name": "energy closure of the step: |sum of terms x dt - change of heat content| "
        "/ (sum of |terms| x dt)"})
    ds = xr.Dataset(data, coords=coords)
    ds.attrs.update({
        "spin_up_days": int(result.spin_up_days),
        "spin_up_change_K": float(result.spin_up_change) if spin else float("nan"),
        "hemisphere_samples": int(hemisphere.samples),
    })
    return ds
