"""A scene stepped through time: the step API for closed loops, and frame sequences.

:class:`Simulation` holds a loaded scene and its clock. :meth:`Simulation.step` advances the
clock, then renders every observer at the new instant — the sun from the ephemeris at that
time, the atmosphere set up for that sun, the surfaces at the heat balance's temperatures of
that instant when the heat balance runs, scanners on their trajectories from that instant — and
returns a :class:`Frame`. Between steps the caller moves objects and observers with
:meth:`Simulation.set_pose`; a tracker, a gimbal or a guidance law written by the user closes
the loop (none is part of radscene).

The ray tracer is built once, for moving geometry (``RayTracer(dynamic=True)``): moving an
object writes its new vertices into the tracer and refits that object's acceleration structure
alone (:meth:`radscene.geometry.RayTracer.update`), so a frame costs what moved, not the scene.

Frames after the first of each observer are incremental (``incremental=True``, the default):
they keep the rays of the observer's last frame that nothing moved through and trace only the
others (:mod:`radscene.render.frame_cache`): the same frames as tracing every ray. With
``render.key_frames: true`` (off by default) only key frames, ``render.key_frame_interval`` apart, shade
every ray sample; the frames between shade the pixels something moved through and extrapolate
the others in time from the last two key frames (:mod:`radscene.render.key_frames`); a
sequence, whose frame times are known (:meth:`Simulation.schedule`, :func:`render_sequence`),
renders each next key frame ahead and interpolates between the key frames behind and ahead
instead (:mod:`radscene.pipeline.look_ahead`); with ``key_frames: false`` every sample is
shaded with the frame's own sun and temperatures.

Objects move as the scene file says (:mod:`radscene.platform.motion`, built by the loader as
``scene.motions``): along ``trajectory`` waypoints, a route at a speed or a 6-DOF track file
(straight or a cubic spline; attitude fixed, along the path or the terrain's slope, or
tabulated), spinning (``spin``), or carried by a parent (``parent``); ``t`` [s] counted from
the simulation's start. The clock may not leave a trajectory's span (an error names the
object), and ``set_pose`` of a moving object holds only until the next frame; ``set_pose`` of a
parent carries its parts along at once. Each frame writes to the ray tracer only the objects
whose pose changed.

With ``render.motion_blur`` a frame is the mean of renders at sub-frame instants of its
exposure, what moves placed at each (:mod:`radscene.pipeline.motion_blur`); the sun and the
tables stay the frame's.

A scanner (pushbroom, whiskbroom) over something that moves renders its pixels in groups of
nearly one time, what moves placed at each group's time
(:mod:`radscene.pipeline.scan_motion`): a car driven during the scan comes out stretched and
sheared as in a real scanner's image.

A sea (``terrain: {type: sea}``, :mod:`radscene.geometry.sea`) moves too: at each instant
(and each sub-instant of a blurred frame) its waves are synthesised for ``t`` and written into
the tracer (:meth:`~radscene.geometry.RayTracer.update` of the sea's mesh alone).

Limits. The heat balance is solved for the objects where they stood when it was solved
(once for a span, and again when the clock runs past it): a moved object keeps the solved
temperatures of its faces, not those of where it went. Terrain does not move, except a sea's
waves.
"""

from __future__ import annotations

import datetime as _dt
from dataclasses import dataclass, field
from functools import partial
from pathlib import Path

import numpy as np
import xarray as xr

from radscene.errors import ConfigError
from radscene.geometry import Mesh
from radscene.pipeline import apply_thermal, as_scene, record_signal, solve_thermal, thermal_active
from radscene.pipeline.progress import progress_callback
from radscene.pipeline.provenance import stamp
from radscene.render.integrator import CONSTANT_ANGLES, GEOLOCATION_COORDS

__all__ = ["Frame", "FrameSequence", "Simulation", "check_sequence", "frame_times", "parse_duration",
           "render_sequence", "sequence_files"]

#: Attributes of a render that change from frame to frame: carried along ``time`` as variables
#: (``frame_<name>``) in a sequence, not as the file's attributes.
FRAME_ATTRS = ("time", "sun_zenith_deg", "sun_azimuth_deg", "earth_sun_distance_au", "render_seconds",
               "frame", "elapsed_s", "history")
#: How far past the clock the heat balance is solved when it must be (again) [s].
THERMAL_HORIZON = 3600.0


def parse_duration(value, key: str = "dt") -> float:
    """A positive duration in seconds from a number [s] or a string such as ``"40 ms"``.

    Raises
    ------
    ConfigError
        Naming ``key``: not a number or a time with a unit, not finite, or not > 0.

    Examples
    --------
    >>> parse_duration("40 ms")
    0.04
    """
    from radscene.radiometry.units import parse_quantity

    if isinstance(value, bool) or not isinstance(value, (int, float, str, np.number)):
        raise ConfigError(f"a duration is a number of seconds or a string such as '40 ms', not "
                          f"{value!r}", key=key)
    seconds = float(parse_quantity(value, "time", key=key))
    if not np.isfinite(seconds) or seconds <= 0:
        raise ConfigError(f"must be a positive finite duration, got {value!r}", key=key)
    return seconds


def _vector(value, kind: str, key: str) -> np.ndarray:
    """Three numbers in the canonical unit of ``kind`` (each a number or a string with a unit)."""
    from radscene.radiometry.units import parse_quantity

    if isinstance(value, (str, bytes)) or np.ndim(value) != 1 or len(value) != 3:
        raise ConfigError(f"three values, e.g. [x, y, z] or [yaw, pitch, roll]; got {value!r}", key=key)
    if all(isinstance(v, (int, float, np.integer, np.floating)) and not isinstance(v, bool)
           for v in value):  # plain numbers: in the canonical unit already
        out = np.array(value, float)
        if not np.isfinite(out).all():
            raise ConfigError(f"must be finite, got {value!r}", key=key)
        return out
    out = np.array([parse_quantity(v, kind, key=f"{key}[{i}]") for i, v in enumerate(value)], float)
    if not np.isfinite(out).all():
        raise ConfigError(f"must be finite, got {value!r}", key=key)
    return out


@dataclass
class Frame:
    """The images of every observer at one instant.

    Attributes
    ----------
    index : int
        The frame's number, from 1 for the first step.
    elapsed : float
        Time since the simulation's start [s].
    time : datetime or None
        The instant, timezone-aware (UTC); None for a scene with a fixed sun and no time.
    radiance : dict of str to xarray.Dataset
        Per observer the render (:func:`radscene.render`): radiance, terms and truth maps.
    signal : dict of str to xarray.Dataset
        Per observer with a sensor its output (:meth:`radscene.sensor.Sensor.apply`).
    """

    index: int
    elapsed: float
    time: _dt.datetime | None
    radiance: dict[str, xr.Dataset] = field(default_factory=dict)
    signal: dict[str, xr.Dataset] = field(default_factory=dict)


@dataclass
class FrameSequence:
    """The frames of a sequence, stacked along ``time`` per observer: in memory, or the files
    :func:`render_sequence` wrote with ``output``, opened lazily.

    Attributes
    ----------
    radiance : dict of str to xarray.Dataset
        Per observer every variable of a render (radiance, terms, truth maps) with a leading
        ``time`` dimension (UTC), ``elapsed(time)`` [s] and the frame attributes that change
        (``frame_sun_zenith_deg(time)`` ...) as variables.
    signal : dict of str to xarray.Dataset
        Per observer with a sensor its signal (``dn(time, frame, band, y, x)`` [DN] ...).
    """

    radiance: dict[str, xr.Dataset] = field(default_factory=dict)
    signal: dict[str, xr.Dataset] = field(default_factory=dict)


class Simulation:
    """A scene and its clock, stepped frame by frame.

    Parameters
    ----------
    scene : radscene.scene.Scene, dict or path
        What :func:`radscene.pipeline.as_scene` takes. A loaded Scene is changed in place (its
        time, object meshes, cameras and temperatures).
    thermal_horizon : float or str
        How far past the clock the heat balance is solved, when it runs and the clock passes
        the end of its solution [s] (or a duration string); default 1 h.
    realtime : bool
        Real-time frames (:mod:`radscene.render.realtime`): the first frame of each observer
        (and the first after it moves) keeps the band tables, the path nodes and the visible
        sky of each pixel; every later frame traces only the primary and the sun's shadow
        rays. The sun, its atmosphere and the surface temperatures stay those of the first
        frame, the reflected background that of the first frame where a pixel sees the same
        object; no coupling layers, supersampling or geolocation.
        Default False (every frame a full render). See ``docs/simulation.md``.
    incremental : bool
        Frames after the first keep the rays of the observer's last frame that nothing moved
        through (:mod:`radscene.render.frame_cache`) and trace only the others: the same
        images as full frames; with ``render.key_frames`` (the scene's, default false) the
        frames between key frames extrapolate the pixels nothing moved through
        (:mod:`radscene.render.key_frames`). Default True; False traces every ray of every
        frame.

    Examples
    --------
    >>> import radscene
    >>> sim = radscene.Simulation(radscene.example_path("demo"))          # doctest: +SKIP
    >>> sim.set_pose("vehicle", position=(10.0, 0.0, 2.0))               # doctest: +SKIP
    >>> frame = sim.step("40 ms")                                       # doctest: +SKIP
    >>> frame.radiance["map"].object_id                                  # doctest: +SKIP
    """

    def __init__(self, scene, *, thermal_horizon=THERMAL_HORIZON, realtime: bool = False,
                 incremental: bool = True):
        from radscene.geometry import RayTracer
        from radscene.render.integrator import scene_tables

        self.scene = as_scene(scene)
        self.thermal_horizon = parse_duration(thermal_horizon, key="thermal_horizon")
        self._start = self.scene.time
        if self._start is not None:
            self.scene.render_cache["motion_epoch"] = self._start  # the trajectories' t = 0
        self._elapsed = 0.0
        self._index = 0
        self._thermal = thermal_active(self.scene)
        from radscene.geometry import rotation_matrix
        from radscene.platform.motion import compose

        # every object but the terrain: its motion, its world pose and its mesh in its own frame
        self._motions = {o.name: self.scene.motions[o.name] for o in self.scene.objects
                         if not o.is_terrain and o.name in self.scene.motions}
        self._parents = {n: m.parent for n, m in self._motions.items()}
        self._children = {}  # each parent's parts
        for child, parent in self._parents.items():
            if parent is not None:
                self._children.setdefault(parent, []).append(child)
        # where the meshes stand: the scene's instant (t = 0 s) as loaded, or where a simulation
        # of the same Scene left them
        placed = dict(compose({n: m.pose(0.0) for n, m in self._motions.items()}, self._parents))
        placed.update({n: pose for n, pose in self.scene.poses.items() if n in placed})
        specs = {o.name: o for o in self.scene.spec.objects}
        # what moves by itself (a trajectory, a spin) and what a moving parent carries
        self._moving = {n for n in self._motions if self._carried(n)}
        self._poses = {}
        self._body = {}
        for k, obj in enumerate(self.scene.objects):
            if obj.name not in self._motions:
                continue
            position, rot = placed[obj.name]
            spec_rotation = np.array(specs[obj.name].rotation, float)
            if self._parents[obj.name] is None and np.array_equal(rot, rotation_matrix(*spec_rotation)):
                attitude = spec_rotation  # the scene file's (yaw, pitch, roll), exactly
            else:
                attitude = _attitude(rot)
            self._poses[obj.name] = (position, attitude, rot)
            self._body[obj.name] = (k, _to_body(obj.mesh, position, rot))
        # a sea's waves move with the clock: its mesh is rewritten at each instant
        self._sea = self.scene.sea if self.scene.sea is not None and self.scene.sea.moves else None
        self._sea_index = next((k for k, o in enumerate(self.scene.objects) if o.is_terrain), None)
        self._sea_time = 0.0
        self.tracer = RayTracer([obj.mesh for obj in self.scene.objects], dynamic=True)
        self._exposures = self._blur_exposures()
        self._follow_motions()
        tables = scene_tables(self.scene, self.tracer)
        self._realtime = None
        # per observer the rays of its last frame (none with motion blur: sub-frame renders)
        self._caches = {}
        if incremental and not realtime and self.scene.settings.motion_blur is None:
            from radscene.render.frame_cache import FrameCache
            from radscene.render.key_frames import KeyFrames

            settings = self.scene.settings
            self._caches = {setup.name: FrameCache(KeyFrames(settings.key_frame_interval)
                                                   if settings.key_frames else None)
                            for setup in self.scene.observers}
        self._thermal_solves = 0  # how many times the heat balance was solved: a key frame each
        self._ahead = None  # the frame times known in advance (schedule): key frames ahead
        if realtime:
            from radscene.render.realtime import RealtimeRenderer

            self._realtime = RealtimeRenderer(self.scene, tables)
            self._stamps = {}  # per observer: (its camera, the provenance of its key frame)

    @property
    def realtime(self) -> bool:
        """Whether frames are real-time frames (the constructor's ``realtime``)."""
        return self._realtime is not None

    # -- the clock --------------------------------------------------------------------------

    @property
    def time(self) -> _dt.datetime | None:
        """The scene's instant, timezone-aware (UTC); None for a fixed sun without a time."""
        return None if self.scene.time is None else self.scene.time.astimezone(_dt.UTC)

    @property
    def elapsed(self) -> float:
        """Time since the simulation's start [s]."""
        return self._elapsed

    def step(self, dt, *, progress=None) -> Frame:
        """Advance the clock by ``dt`` and render every observer at the new instant.

        Parameters
        ----------
        dt : float or str
            [s], > 0, or a duration string such as ``"40 ms"``.
        progress : callable(done, total) or bool, optional
            As for :func:`radscene.render`, per observer; no bar unless True (a bar per frame
            of a loop would be noise).

        Returns
        -------
        Frame
        """
        seconds = parse_duration(dt, key="dt")
        self._set_clock(self._elapsed + seconds)
        return self.render(progress=progress)

    def schedule(self, elapsed) -> None:
        """Tell the simulation the instants of the frames to come [s since its start], known
        in advance (a sequence, as :func:`render_sequence` renders it): with
        ``render.key_frames`` each key frame is followed by the render of the next one ahead,
        and the frames between interpolate between the two instead of extrapolating
        (:mod:`radscene.pipeline.look_ahead`). Frames are still made by :meth:`step` and
        :meth:`render`, at these instants. Nothing changes without key frames, or with a
        moving sea; :meth:`set_pose` of an object starts the key frames afresh."""
        from radscene.pipeline.look_ahead import LookAhead

        keyed = any(cache.keys is not None for cache in self._caches.values())
        self._ahead = LookAhead(self, elapsed) if keyed and self._sea is None else None

    def render(self, *, progress=None) -> Frame:
        """Render every observer at the clock's instant, as it is (no step); ``progress`` as for
        :meth:`step`."""
        from radscene.render import render as render_observer
        from radscene.render.hyperspectral import render_hyperspectral
        from radscene.render.integrator import scene_tables

        if self._realtime is not None:
            return self._render_realtime()
        scene = self.scene
        self._follow_motions()
        self._rebuild_scanners()
        if self._thermal:
            self._apply_thermal()
        tables = scene_tables(scene, self.tracer)  # the sun and temperatures of this instant
        self._key_instant(tables.sun)
        self._index += 1
        frame = Frame(self._index, self._elapsed, self.time)
        for setup in scene.observers:
            def one(setup=setup, tables=tables, report=None):
                if setup.spectral is not None:
                    return render_hyperspectral(scene, setup.name, progress=report)
                if self._scans_motion(setup):
                    return self._scan(setup, tables, report)
                return render_observer(scene, setup.name, progress=report, tables=tables,
                                       cache=self._caches.get(setup.name))
            images = None if self._ahead is None else self._ahead.take(setup.name, self._elapsed)
            if images is None:
                with progress_callback(progress, f"frame {self._index} {setup.name}",
                                       when_interactive=False) as report:
                    images = self._expose(setup, partial(one, report=report), tables)
            images.attrs.update({"frame": self._index, "elapsed_s": self._elapsed})
            stamp(images, scene, setup.name)
            frame.radiance[setup.name] = images
            if setup.sensor is not None and setup.spectral is None:
                seed = int(np.random.SeedSequence([scene.settings.seed, self._index]).generate_state(1)[0])
                frame.signal[setup.name] = record_signal(scene, setup, images, seed=seed)
        if self._ahead is not None:  # the next key frames, rendered ahead
            self._ahead.render_ahead(lambda name, tables: render_observer(
                scene, name, tables=tables, cache=self._caches[name]))
        return frame

    def _render_realtime(self) -> Frame:
        """A frame of real-time frames (:mod:`radscene.render.realtime`)."""
        from radscene.pipeline.provenance import provenance
        from radscene.render.integrator import scene_tables

        scene = self.scene
        self._follow_motions()
        if self._thermal and self._index == 0:  # the temperatures of the first frame, kept
            self._apply_thermal()
            self._realtime.tables = scene_tables(scene, self.tracer)
        self._index += 1
        frame = Frame(self._index, self._elapsed, self.time)
        for setup in scene.observers:
            images = self._realtime.render(setup)
            camera, stamp_attrs = self._stamps.get(setup.name, (None, None))
            if camera is not setup.camera:  # the provenance changes with the observer only
                stamp_attrs = provenance(scene, setup.name)
                self._stamps[setup.name] = (setup.camera, stamp_attrs)
            images.attrs.update(stamp_attrs)
            images.attrs.update({"frame": self._index, "elapsed_s": self._elapsed,
                                 "time": "" if self.time is None else self.time.isoformat()})
            frame.radiance[setup.name] = images
            if setup.sensor is not None:
                seed = int(np.random.SeedSequence([scene.settings.seed, self._index]).generate_state(1)[0])
                frame.signal[setup.name] = record_signal(scene, setup, images, seed=seed)
        return frame

    def _key_instant(self, sun, names=None) -> None:
        """Tell the observers' key frames (:mod:`radscene.render.key_frames`; those of
        ``names`` only, where given) this frame's instant, its sun [deg] and the heat
        balance's time step it lies in."""
        segment = self._thermal_segment(self._elapsed)
        for name, cache in self._caches.items():
            if cache.keys is not None and (names is None or name in names):
                cache.keys.at(self._elapsed, sun.zenith, sun.azimuth, segment)

    def _thermal_segment(self, elapsed: float):
        """What tells apart the heat balance's time steps at ``elapsed`` [s]: (its solutions so
        far, the index of its step), "outside" past its solution; None without one."""
        solution = self.scene.render_cache.get("thermal") if self._thermal else None
        if solution is None or self._start is None:
            return None
        when = np.datetime64(self._instant(elapsed).astimezone(_dt.UTC).replace(tzinfo=None), "ns")
        if when > solution.time.values[-1]:
            return "outside"
        return (self._thermal_solves, int(np.searchsorted(solution.time.values, when, side="right")))

    def _instant(self, elapsed: float) -> _dt.datetime | None:
        """The scene's instant ``elapsed`` [s] after the start (None without a time)."""
        return None if self._start is None else self._start + _dt.timedelta(seconds=elapsed)

    def _set_clock(self, elapsed: float) -> None:
        """Put the clock at ``elapsed`` [s] since the start (nothing moved or rendered)."""
        self._elapsed = elapsed
        if self._start is not None:
            self.scene.time = self._instant(elapsed)

    def _carried(self, name) -> bool:
        """Whether an object moves with time: by its own motion or a moving ancestor's."""
        while name is not None:
            if self._motions[name].moves:
                return True
            name = self._parents[name]
        return False

    def _blur_exposures(self) -> dict[str, float]:
        """Per observer its exposure [s] when motion blur is on (``render.motion_blur``)."""
        from radscene.pipeline.motion_blur import observer_exposure

        blur = self.scene.settings.motion_blur
        if blur is None:
            return {}
        return {setup.name: observer_exposure(setup, blur.exposure) for setup in self.scene.observers}

    def _expose(self, setup, render_once, tables):
        """The image of an observer over its exposure: ``render_once()`` at each sub-frame
        instant (what moves placed there, the sun and the tables of the frame's instant kept),
        averaged (:mod:`radscene.pipeline.motion_blur`); one render when nothing moves."""
        from radscene.pipeline.motion_blur import exposure_offsets, mean_frame

        scanners = self.scene.time is not None and any(
            o.kind in ("pushbroom", "whiskbroom") for o in self.scene.observers)
        if setup.name not in self._exposures or not (self._moving or scanners or self._sea):
            return render_once()
        offsets = exposure_offsets(self.scene.settings.motion_blur.samples, self._exposures[setup.name])
        if len(offsets) == 1:
            return render_once()
        sheets = [self._body[n][0] for n in self._moving
                  if getattr(self.scene.objects[self._body[n][0]], "transmissive", False)]
        layers = []
        try:
            for offset in offsets:
                self._follow_motions(self._elapsed + offset)
                self._rebuild_scanners(offset)
                if sheets:  # the sheets' own tracers follow them (the sun stays the frame's)
                    from radscene.render.integrator import scene_tables

                    tables = scene_tables(self.scene, self.tracer)
                layers.append(render_once(tables=tables))
        finally:  # back at the frame's instant
            self._follow_motions()
            self._rebuild_scanners()
            if sheets:
                from radscene.render.integrator import scene_tables

                scene_tables(self.scene, self.tracer)
        bands = None if setup.spectral is not None else [self.scene.band(b) for b in setup.bands]
        return mean_frame(layers, bands)

    def _scans_motion(self, setup) -> bool:
        """Whether a band observer is a scanner over something that moves (objects, waves)."""
        return setup.kind in ("pushbroom", "whiskbroom") and setup.spectral is None and bool(
            self._moving or self._sea)

    def _scan(self, setup, tables, progress=None):
        """A scanner's image, each group of its pixels rendered with what moves placed at the
        group's time (:mod:`radscene.pipeline.scan_motion`); what moves is put back where it
        was."""
        from radscene.pipeline.scan_motion import compose, motion_groups, pixel_times
        from radscene.platform.cameras import RayBundle
        from radscene.render.integrator import render as render_observer
        from radscene.render.integrator import scene_tables

        camera = setup.camera
        rays = camera.rays(supersample=setup.supersample)
        # the scanner's clock against the simulation's: its t = 0 is its epoch
        epoch = getattr(camera, "epoch", None)
        shift = 0.0 if epoch is None or self._start is None else (epoch - self._start).total_seconds()
        moving = [self._body[n][0] for n in sorted(self._moving)]
        if self._sea is not None:
            moving.append(self._sea_index)
        sheets = any(getattr(self.scene.objects[k], "transmissive", False) for k in moving)
        here = self._placed_at

        def vertices(t):
            self._follow_motions(shift + t)
            return np.concatenate([self.scene.objects[k].mesh.vertices for k in moving])

        parts, masks, done = [], [], 0
        try:
            group, times = motion_groups(pixel_times(rays), vertices, lambda t: camera.sensor_axes(t)[0],
                                         camera.ifov)
            for g, t in enumerate(times):
                mask = group == g
                keep = mask[rays.pixel]
                bundle = RayBundle(rays.origins[keep], rays.directions[keep], rays.pixel[keep],
                                   rays.weight[keep], rays.shape, rays.subsample[keep], time=rays.time[keep])
                self._follow_motions(shift + t)
                if sheets:  # the sheets' own tracers follow them
                    tables = scene_tables(self.scene, self.tracer)
                report = None if progress is None else (
                    lambda n, total, done=done: progress(done + n, len(rays)))
                parts.append(render_observer(self.scene, setup.name, progress=report, tables=tables,
                                             rays=bundle))
                masks.append(mask.reshape(rays.shape))
                done += len(bundle)
        finally:  # back where they were
            self._follow_motions(here)
            if sheets:
                scene_tables(self.scene, self.tracer)
        return compose(parts, masks)

    def _follow_motions(self, t=None):
        """Objects that move (trajectories, spins, parts of moving parents) where they are at
        ``t`` [s] since the start (default the clock's time); only those whose pose changed
        are written to the ray tracer."""
        from radscene.platform.motion import compose

        t = self._elapsed if t is None else t
        self._placed_at = t
        self._advance_sea(t)
        if not self._moving:
            return
        local = {n: self._motions[n].pose(t) for n in self._moving}
        # what does not move stands where it is (set_pose included), a root of the family
        local.update({n: self._poses[n][::2] for n in self._motions if n not in self._moving})
        parents = {n: self._parents[n] if n in self._moving else None for n in local}
        world = compose(local, parents)
        self._place([(name, *world[name]) for name in self._moving])

    def _advance_sea(self, t):
        """The sea's waves at ``t`` [s] since the start, written into its mesh and the ray
        tracer (the sea's BVH refitted alone); nothing when they are already there."""
        if self._sea is None or t == self._sea_time:
            return
        k = self._sea_index
        mesh = self._sea.mesh(t, name=self.scene.objects[k].mesh.name)
        for cache in self._caches.values():  # the terrain moved: every ray may change
            cache.reset()
        self.tracer.update(k, mesh)
        self.scene.objects[k].mesh = mesh
        self._sea_time = t

    def _place(self, placements):
        """Write objects' world poses into their meshes and the ray tracer, those that changed
        (one :meth:`RayTracer.move <radscene.geometry.RayTracer.move>` for all).

        ``placements``: ``(name, position (3,), rotation (3, 3))`` or with the attitude
        ``(yaw, pitch, roll)`` [deg] as a fourth item (then written even when unchanged);
        without it the attitude is worked out from the rotation when asked for (:meth:`pose`).
        """
        moved = {}
        for name, position, rotation, *attitude in placements:
            old_position, _, old_rotation = self._poses[name]
            if not attitude and np.array_equal(position, old_position) and np.array_equal(
                    rotation, old_rotation):
                continue
            k, body = self._body[name]
            moved[k] = body.with_vertices(body.vertices @ rotation.T + position)
            self._poses[name] = (np.asarray(position, float),
                                 np.asarray(attitude[0], float) if attitude else None, rotation)
            self.scene.poses[name] = (self._poses[name][0], rotation)
        if moved:
            if self._caches:  # where each stood and stands: the rays to trace again
                from radscene.render.frame_cache import moved_spheres

                spheres = [s for k, mesh in moved.items()
                           for s in moved_spheres(self.scene.objects[k].mesh.vertices, mesh.vertices)]
                for cache in self._caches.values():
                    cache.moved(spheres)
            self.tracer.move(moved)
            for k, mesh in moved.items():
                self.scene.objects[k].mesh = mesh

    def _apply_thermal(self):
        scene = self.scene
        solution = scene.render_cache.get("thermal")
        now = np.datetime64(scene.time.astimezone(_dt.UTC).replace(tzinfo=None), "ns")
        if solution is None or now > solution.time.values[-1]:
            spec = scene.spec.thermal
            start = spec.start or (self._start - _dt.timedelta(days=1))
            end = scene.time + _dt.timedelta(seconds=self.thermal_horizon)
            if spec.end is not None and spec.end > end:
                end = spec.end
            solution = solve_thermal(scene, start=start, end=end)
            self._thermal_solves += 1
        apply_thermal(scene, solution, scene.time)

    def _rebuild_scanners(self, offset=0.0):
        """Scanners fly their trajectories from the clock's instant (plus ``offset`` [s])."""
        if self.scene.time is None:
            return
        from radscene.platform.config import build_observer
        from radscene.platform.geolocation import LocalFrame

        loc = self.scene.location
        for i, (setup, spec) in enumerate(zip(self.scene.observers, self.scene.spec.observers, strict=True)):
            if setup.kind in ("pushbroom", "whiskbroom"):
                instant = self.scene.time + _dt.timedelta(seconds=float(offset))
                setup.camera = build_observer(spec, LocalFrame(loc.latitude, loc.longitude, loc.altitude),
                                              instant, key=f"observers[{i}]")

    # -- poses ------------------------------------------------------------------------------

    def pose(self, name: str) -> tuple[np.ndarray, np.ndarray]:
        """``(position (3,) [m], attitude (yaw, pitch, roll) [deg])`` of an object or a
        perspective observer (an orthographic one: its centre and altitude, and zenith,
        azimuth, 0)."""
        kind, target = self._find(name)
        if kind == "object":
            position, attitude, rotation = self._poses[name]
            return position.copy(), _attitude(rotation) if attitude is None else attitude.copy()
        cam = target.camera
        if target.kind == "perspective":
            return np.array(cam.position, float), np.array(cam.attitude, float)
        if target.kind == "orthographic":
            return np.array([*cam.center, cam.altitude]), np.array([cam.azimuth, cam.zenith, 0.0])
        raise ConfigError(f"observer {name!r} is a {target.kind} scanner: it flies its trajectory",
                          key="name")

    def set_pose(self, name: str, position=None, attitude=None) -> None:
        """Move an object or an observer; what is left out stays as it is.

        Parameters
        ----------
        name : str
            An object (not the terrain) or an observer of the scene.
        position : array_like, optional
            ``(x, y, z)`` in the scene frame (east, north, up) [m] — z an altitude, not a height
            above the terrain; for an orthographic observer ``(centre x, centre y, altitude)``.
        attitude : array_like, optional
            ``(yaw, pitch, roll)`` [deg] as ``rotation`` of an object and ``attitude`` of a
            perspective observer in the scene file (:func:`radscene.geometry.rotation_matrix`):
            yaw the heading of the body's +y axis clockwise from north. An orthographic observer
            takes none.

        Raises
        ------
        ConfigError
            An unknown name (the message lists the known ones), the terrain, a scanner, or a
            position or attitude that is not three finite values.
        """
        kind, target = self._find(name)
        if position is not None:
            position = _vector(position, "length", "set_pose.position")
        if attitude is not None:
            attitude = _vector(attitude, "angle", "set_pose.attitude")
        if kind == "object":
            if self._ahead is not None:  # the key frames rendered ahead did not see it
                self._ahead.drop()
            self._move_object(name, position, attitude)
        else:
            self._move_observer(target, position, attitude)

    def set_poses(self, poses: dict) -> None:
        """Move several objects and observers at once, as :meth:`set_pose` each.

        The objects' meshes go to the ray tracer in one :meth:`RayTracer.move
        <radscene.geometry.RayTracer.move>` (one rebuild of Embree's top level), and their
        rotations are made in one call: the way to move many objects every frame.

        Parameters
        ----------
        poses : dict of str to (position, attitude)
            Per name what :meth:`set_pose` takes; either may be None (left as it is).

        Raises
        ------
        ConfigError
            As :meth:`set_pose`, naming the first bad entry; nothing is moved then.
        """
        from radscene.geometry import rotation_matrix

        objects, observers = [], []
        for name, pose in poses.items():
            if isinstance(pose, (str, bytes)) or len(pose) != 2:
                raise ConfigError(f"{name!r}: a pair (position, attitude), either None; got "
                                  f"{pose!r}", key="set_poses")
            kind, target = self._find(name)
            position, attitude = (None if v is None else _vector(v, unit, f"set_poses[{name}].{key}")
                                  for v, unit, key in ((pose[0], "length", "position"),
                                                       (pose[1], "angle", "attitude")))
            (objects if kind == "object" else observers).append((name, target, position, attitude))
        placements = []
        if objects and self._ahead is not None:  # the key frames rendered ahead did not see them
            self._ahead.drop()
        for name, _, position, attitude in objects:
            old_position, old_attitude, old_rotation = self._poses[name]
            if attitude is None:
                attitude = _attitude(old_rotation) if old_attitude is None else old_attitude
            placements.append((name, old_position if position is None else position, attitude))
        if placements:
            attitudes = np.array([a for _, _, a in placements]).reshape(-1, 3)
            rotations = rotation_matrix(attitudes[:, 0], attitudes[:, 1], attitudes[:, 2])
            self._place([(name, position, rotation, attitude) for (name, position, attitude), rotation
                         in zip(placements, rotations, strict=True)])
            for name, *_ in placements:
                self._place_parts(name)
        for _, setup, position, attitude in observers:
            self._move_observer(setup, position, attitude)

    def _find(self, name):
        if getattr(self, "_by_name", None) is None:  # the scene's objects and observers stay
            self._by_name = ({o.name: o for o in self.scene.objects},
                             {o.name: o for o in self.scene.observers})
        objects, observers = self._by_name
        if name in objects and name in observers:
            raise ConfigError(f"{name!r} names both an object and an observer", key="set_pose.name")
        if name in observers:
            return "observer", observers[name]
        if name in objects and objects[name].is_terrain:
            raise ConfigError(f"{name!r} is the terrain, which does not move", key="set_pose.name")
        if name in self._body:
            return "object", objects[name]
        movable = [n for n in objects if n in self._body]
        raise ConfigError(f"unknown name {name!r}; objects: {', '.join(movable) or 'none'}; "
                          f"observers: {', '.join(observers)}", key="set_pose.name")

    def _move_object(self, name, position, attitude):
        """set_pose of an object: it, and the parts it carries, move now."""
        from radscene.geometry import rotation_matrix

        old_position, old_attitude, old_rotation = self._poses[name]
        position = old_position if position is None else position
        if attitude is None:
            attitude = _attitude(old_rotation) if old_attitude is None else old_attitude
        self._place([(name, position, rotation_matrix(*attitude), attitude)])
        self._place_parts(name)

    def _place_parts(self, name):
        """The parts carried by ``name`` where its pose and theirs at the clock's time put them."""
        parent_position, _, parent_rotation = self._poses[name]
        for child in self._children.get(name, ()):
            p, rot = self._motions[child].pose(self._elapsed)
            self._place([(child, parent_position + parent_rotation @ p, parent_rotation @ rot)])
            self._place_parts(child)

    def _move_observer(self, setup, position, attitude):
        from radscene.platform import OrthographicCamera, PerspectiveCamera

        cam = setup.camera
        if setup.name in self._caches:  # its rays change
            self._caches[setup.name].reset()
        if setup.kind == "perspective":
            setup.camera = PerspectiveCamera(cam.position if position is None else position, cam.shape,
                                             fov=cam.fov, attitude=cam.attitude if attitude is None else attitude)
        elif setup.kind == "orthographic":
            if attitude is not None:
                raise ConfigError(f"observer {setup.name!r} is orthographic: it takes a position "
                                  "(centre x, centre y, altitude) and no attitude", key="set_pose.attitude")
            if position is not None:
                setup.camera = OrthographicCamera(center=position[:2], shape=cam.shape, gsd=cam.gsd,
                                                  altitude=position[2], zenith=cam.zenith, azimuth=cam.azimuth)
        else:
            raise ConfigError(f"observer {setup.name!r} is a {setup.kind} scanner: it flies its "
                              "trajectory and takes no pose", key="set_pose.name")


def _to_body(mesh, position, rotation):
    """The mesh in its own frame: the inverse of placing it at ``position`` turned by
    ``rotation`` (3, 3)."""
    # world = R body + t  ->  body = R^T (world - t), row-wise (world - t) R
    return Mesh((mesh.vertices - position) @ rotation, mesh.faces, name=mesh.name)


def _attitude(rotation) -> np.ndarray:
    """(yaw, pitch, roll) [deg] of a rotation matrix."""
    from radscene.platform.trajectory import attitude_from_matrix

    return np.array([float(a) for a in attitude_from_matrix(rotation)])


# -- sequences ------------------------------------------------------------------------------


def frame_times(start: _dt.datetime, end: _dt.datetime, step) -> list[_dt.datetime]:
    """The instants of a sequence: ``start + k step`` up to ``end`` inclusive.

    Parameters
    ----------
    start, end : datetime
        Timezone-aware; ``end`` not before ``start``.
    step : float or str
        [s] > 0, or a duration string.

    Raises
    ------
    ConfigError
        Naming ``time.start``, ``time.end`` or ``time.step``.
    """
    seconds, count = _frame_count(start, end, step)
    return [start + _dt.timedelta(seconds=k * seconds) for k in range(count)]


def _frame_count(start, end, step) -> tuple[float, int]:
    """The step [s] and the number of frames of a span, checked (see :func:`frame_times`)."""
    seconds = parse_duration(step, key="time.step")
    for value, key in ((start, "time.start"), (end, "time.end")):
        if not isinstance(value, _dt.datetime) or value.tzinfo is None:
            raise ConfigError(f"a timezone-aware time, e.g. '2026-06-21T10:30:00Z', not {value!r}", key=key)
    if end < start:
        raise ConfigError(f"{end.isoformat()} lies before the start {start.isoformat()}", key="time.end")
    # whole steps that fit, with a microsecond's grace for steps such as 1/3 s
    return seconds, int(np.floor((end - start).total_seconds() / seconds + 1e-6 / seconds)) + 1


def check_sequence(scene, *, start=None, end=None, step=None, observers=None, output=None,
                   incremental: bool = True) -> int:
    """Check a sequence before its first frame: its span, its observers and the memory its
    frames need (:func:`radscene.scene.memory.check_sequence_memory`, against the scene's
    limit): all of them held until the last, or, with ``output``, a frame at a time written to
    disk, and then the disk space the frames take in ``output``
    (:func:`radscene.scene.memory.check_sequence_disk`); returns the number of frames.

    Parameters and defaults as for :func:`render_sequence`.

    Raises
    ------
    ConfigError
        No sequence given, a bad span, an unknown observer, or too many frames for the memory
        or, with ``output``, for the free disk space there (naming ``time.step``, with the
        figures).
    """
    from radscene.scene.memory import (
        check_sequence_disk,
        check_sequence_memory,
        estimate,
        memory_limit,
    )

    scene = as_scene(scene)
    span = scene.spec.time
    start = start or (span.start if span else None)
    end = end or (span.end if span else None)
    step = step if step is not None else (span.step if span else None)
    if start is None or end is None or step is None:
        raise ConfigError("a sequence needs time.start, time.end and time.step (or --start, --end "
                          "and --step)", key="time")
    _, count = _frame_count(start, end, step)
    names = [o.name for o in scene.observers] if observers is None else list(observers)
    sizes = []
    cached = incremental and scene.settings.motion_blur is None
    for name in names:
        setup = scene.observer(name)
        bands = len(setup.spectral) if setup.spectral is not None else len(setup.bands)
        rows, columns = setup.camera.shape
        samples = float(rows) * float(columns) * setup.supersample ** 2 if cached else 0.0
        sizes.append((setup.camera.shape, max(1, bands), samples))
    render = 0.0
    if output is not None:  # the largest render, beside the frames written
        renders = estimate(scene.spec, scene.base_dir)["observers"]
        chosen = {f"observers[{i}]" for i, o in enumerate(scene.spec.observers) if o.name in names}
        render = max((need for need, key, _ in renders if key.split(".")[0] in chosen), default=0.0)
    # key frames rendered ahead (pipeline.look_ahead): one frame more held
    ahead = cached and scene.settings.key_frames and not (scene.sea is not None and scene.sea.moves)
    check_sequence_memory(count, sizes, scene.memory_limit or memory_limit(scene.spec),
                          streamed=output is not None, render=render, ahead=bool(ahead))
    if output is not None:
        check_sequence_disk(count, sizes, output)
    return count


def render_sequence(scene, *, start=None, end=None, step=None, observers=None,
                    progress=None, incremental: bool = True, output=None,
                    overwrite: bool = False) -> FrameSequence:
    """Render a sequence of frames: every observer at every instant, stacked along ``time``.

    By default every frame is held in memory until the last and the Datasets returned hold
    them all (refused up front when they would not fit, :func:`check_sequence`). With
    ``output`` each frame is written to disk as soon as it is rendered, so that the memory
    needed does not grow with the number of frames (one frame of every observer and the frame
    cache): per observer ``output/NAME_sequence.nc`` (``NAME_signal_sequence.nc`` with a
    sensor), or Zarr stores ``NAME_sequence.zarr`` when ``output`` is named ``*.zarr`` — the
    files ``radscene render`` writes, equal to the in-memory Datasets written with
    :func:`radscene.io.write_netcdf` (:func:`radscene.io.write_zarr`). Each file grows under a
    temporary name (:mod:`radscene.io.sequence_file`) and takes its place when the last frame
    is written; a sequence that fails or is stopped leaves none.

    Parameters
    ----------
    scene : radscene.scene.Scene, dict or path
        As for :class:`Simulation`.
    start, end : datetime, optional
        Timezone-aware; default the scene file's ``time.start`` and ``time.end``.
    step : float or str, optional
        [s] or a duration string; default ``time.step``.
    observers : list of str, optional
        Only these (all by default).
    progress : callable(done, total) or bool, optional
        A callable is called after each frame; True shows a bar of the frames, False none;
        by default a bar when Python runs interactively (:mod:`radscene.pipeline.progress`).
    incremental : bool
        As for :class:`Simulation`: frames after the first trace only the rays that something
        moved through (the same frames); False: every frame traced in full.
    output : str or path-like, optional
        A folder (created when missing): stream the frames to files there instead of holding
        them. Its free disk space is checked before the first frame
        (:func:`radscene.scene.memory.check_sequence_disk`).
    overwrite : bool
        With ``output``: replace sequence files of an earlier run there (refused otherwise).

    Returns
    -------
    FrameSequence
        Per observer the renders and, with a sensor, the signals, along ``time``: in memory,
        or with ``output`` the written files opened lazily (values read when used; close
        them when done).

    Raises
    ------
    ConfigError
        No sequence given (neither arguments nor ``time`` in the scene file), a bad span, frames
        that would not fit in memory or, with ``output``, on disk (:func:`check_sequence`), or
        an ``output`` that cannot be written or holds earlier results (naming ``output``).

    Examples
    --------
    >>> seq = render_sequence("scene.yaml", output="out")                  # doctest: +SKIP
    >>> seq.radiance["map"].radiance.isel(time=-1).values                  # doctest: +SKIP
    """
    scene = as_scene(scene)
    check_sequence(scene, start=start, end=end, step=step, observers=observers, output=output,
                   incremental=incremental)
    span = scene.spec.time
    start = start or (span.start if span else None)
    end = end or (span.end if span else None)
    step = step if step is not None else (span.step if span else None)
    times = frame_times(start, end, step)
    names = [o.name for o in scene.observers] if observers is None else list(observers)
    for name in names:
        scene.observer(name)
    if output is not None:
        from radscene.io.files import check_output_folder

        folder = Path(output)
        check_output_folder(folder, sequence_files(scene, names, folder), overwrite, key="output")
    scene.time = times[0]
    if scene.document is not None:  # the provenance records the span rendered
        scene.document = {**scene.document, "time": {
            "start": start.isoformat(), "end": end.isoformat(),
            "step": parse_duration(step, key="time.step")}}
    sim = Simulation(scene, incremental=incremental)
    sim.schedule([(t - times[0]).total_seconds() for t in times])
    if output is not None:
        return _stream(sim, times, names, Path(output), progress)
    frames = {name: [] for name in names}
    signals = {name: [] for name in names}
    with progress_callback(progress, "frames") as report:
        for k, instant in enumerate(times):
            frame = sim.render() if k == 0 else sim.step((instant - sim.time).total_seconds())
            for name in names:
                frames[name].append(_frame_layer(frame.radiance[name], frame))
                if name in frame.signal:
                    signals[name].append(_frame_layer(frame.signal[name], frame))
            if report is not None:
                report(k + 1, len(times))
    return FrameSequence({name: _stack(layers) for name, layers in frames.items()},
                         {name: _stack(layers) for name, layers in signals.items() if layers})


def sequence_files(scene, names, folder) -> list[str]:
    """The names of the data files a sequence of these observers writes into ``folder``
    (``NAME_sequence`` and, with a sensor, ``NAME_signal_sequence``; ``.zarr`` stores when the
    folder is named ``*.zarr``, else ``.nc``)."""
    ext = ".zarr" if Path(folder).suffix.lower() == ".zarr" else ".nc"
    files = []
    for name in names:
        setup = as_scene(scene).observer(name)
        files.append(f"{name}_sequence{ext}")
        if setup.sensor is not None and setup.spectral is None:
            files.append(f"{name}_signal_sequence{ext}")
    return files


def _stream(sim, times, names, folder, progress) -> FrameSequence:
    """The frames of ``times`` written to ``folder`` as they are rendered (render_sequence with
    ``output``); the files opened lazily."""
    import contextlib

    from radscene.io.sequence_file import SequenceWriter, open_sequence

    ext = ".zarr" if folder.suffix.lower() == ".zarr" else ".nc"
    stamps = np.array([np.datetime64(t.astimezone(_dt.UTC).replace(tzinfo=None), "ns") for t in times])
    paths = {}
    with contextlib.ExitStack() as stack:
        writers = {}

        def append(key, stem, ds, frame, first):
            if key not in writers:
                paths[key] = folder / f"{stem}{ext}"
                writers[key] = stack.enter_context(SequenceWriter(paths[key], stamps))
            writers[key].append(_stream_layer(ds, frame, first))

        first = None
        with progress_callback(progress, "frames") as report:
            for k, instant in enumerate(times):
                frame = sim.render() if k == 0 else sim.step((instant - sim.time).total_seconds())
                first = frame.elapsed if first is None else first
                for name in names:
                    append((name, "radiance"), f"{name}_sequence", frame.radiance[name], frame, first)
                    if name in frame.signal:
                        append((name, "signal"), f"{name}_signal_sequence", frame.signal[name],
                               frame, first)
                del frame  # let go before the next is rendered
                if report is not None:
                    report(k + 1, len(times))
    return FrameSequence({name: open_sequence(paths[(name, "radiance")]) for name in names},
                         {name: open_sequence(paths[(name, "signal")]) for name in names
                          if (name, "signal") in paths})


def _stream_layer(ds: xr.Dataset, frame: Frame, first: float) -> xr.Dataset:
    """One frame of a streamed sequence as :func:`_stack` leaves it in the stack: elapsed
    from the first frame, the attributes of ``time``, ``elapsed`` and ``frame_*``, the
    geolocation as coordinates."""
    layer = _frame_layer(ds, frame)
    layer["elapsed"] = layer["elapsed"] - first
    _sequence_attrs(layer)
    return layer.set_coords([n for n in GEOLOCATION_COORDS if n in layer.data_vars])


def _sequence_attrs(ds: xr.Dataset) -> None:
    """The attributes a sequence gives ``elapsed``, ``time`` and the ``frame_*`` variables."""
    ds["elapsed"].attrs.update({"units": "s", "long_name": "time since the first frame"})
    ds["time"].attrs.update({"long_name": "frame time (UTC)", "standard_name": "time"})
    for name in ds.data_vars:
        if name.startswith("frame_"):
            ds[name].attrs["long_name"] = f"{name.removeprefix('frame_')} of each frame"


def _frame_layer(ds: xr.Dataset, frame: Frame) -> xr.Dataset:
    """One frame of a sequence: the frame's attributes that change as variables, a time."""
    ds = ds.copy()
    # per frame: the geolocation of a moving observer changes (coordinates would not take the
    # time axis)
    ds = ds.reset_coords([n for n in GEOLOCATION_COORDS if n in ds.coords])
    for key in FRAME_ATTRS:
        value = ds.attrs.pop(key, None)
        if key in ("time", "history", "frame", "elapsed_s") or value is None:
            continue
        ds[f"frame_{key}"] = ((), value)
    ds["elapsed"] = ((), frame.elapsed, {"units": "s", "long_name": "time since the first frame"})
    when = frame.time.astimezone(_dt.UTC).replace(tzinfo=None) if frame.time is not None else None
    return ds.expand_dims(time=[np.datetime64(when, "ns")] if when else [frame.elapsed])


def _stack(layers: list[xr.Dataset]) -> xr.Dataset:
    for name in CONSTANT_ANGLES:  # one value in some frames, a map in others: maps in all
        shaped = [ds[name] for ds in layers if name in ds and ds[name].ndim > 1]
        if shaped and len(shaped) < sum(name in ds for ds in layers):
            # the value over the map, at the frame's own time (not aligned away to NaN)
            layers = [ds.assign({name: xr.full_like(shaped[0], float(ds[name].values.ravel()[0]))
                                 .assign_coords(time=ds["time"].values)})
                      if name in ds and ds[name].ndim == 1 else ds for ds in layers]
    out = xr.concat(layers, dim="time", data_vars="minimal", coords="minimal", compat="override",
                    combine_attrs="override")
    out["elapsed"] = out["elapsed"] - float(out["elapsed"].values[0])
    _sequence_attrs(out)
    out.attrs["frames"] = len(layers)
    return out.set_coords([n for n in GEOLOCATION_COORDS if n in out.data_vars])
