"""Key frames rendered ahead: a sequence whose frame instants are known interpolates in time.

With ``render.key_frames`` a :class:`~radscene.pipeline.simulation.Simulation` stepped live
cannot see its next key frame, so the frames between key frames extrapolate from the last two
(:mod:`radscene.render.key_frames`). A sequence (:func:`radscene.render_sequence`,
``radscene render`` of a ``time`` span) knows its frame times: told them
(:meth:`Simulation.schedule <radscene.pipeline.simulation.Simulation.schedule>`), each key
frame is followed at once by the render of the next key frame *ahead* — the scene placed at
that frame's instant (what moves, the sun, the heat balance's temperatures), then put back —,
and the frames between take every pixel that nothing moved through interpolated between the
key frame behind and the one ahead:

.. math::
    L(t) = L(t_a) + \\frac{t - t_a}{t_b - t_a}\\,\\bigl(L(t_b) - L(t_a)\\bigr),
    \\quad t_a < t < t_b.

The pixels something moved through since the key frame behind — at its instant, at the
frame's or at the one ahead's, whose render marks them — are shaded at the frame's instant as
with extrapolation. When the sequence reaches the key frame ahead, its render is the frame (it
is not rendered twice) and the next one ahead is rendered.

The key frame ahead lies at the first frame time ``render.key_frame_interval`` after the one
behind (the last frame where none is that far), brought nearer where the frames up to it
cannot be interpolated: the latest frame within the heat balance's time step of the one
behind and inside its solution (it is not solved ahead), to which the sun turns at most
:data:`~radscene.render.key_frames.MAX_SUN_STEP`. Where no later frame qualifies (the next
frame crosses a time step of the heat balance, or the sun turns farther in one frame), no key
frame is rendered ahead: the next frame is shaded in full and is the next key frame behind.
Where the two key frames' path nodes differ the frames between are shaded in full (and the
one ahead is still the frame at its instant). A reset of an observer's frame cache (it moved,
a grown clipping box) lets its key frames go, the one ahead with them; moving an object with
:meth:`~radscene.pipeline.simulation.Simulation.set_pose` lets every observer's go. A moving
sea, whose waves reset the frame caches every frame, takes no look-ahead.

Memory: per observer one frame more (the render ahead, held until its instant) beside the two
key frames' sums.
"""

from __future__ import annotations

import numpy as np

from radscene.render.key_frames import INSTANT_TOLERANCE, MAX_SUN_STEP, sun_vector

__all__ = ["LookAhead"]


class LookAhead:
    """The frame instants of a sequence and the key frames rendered ahead of them.

    Parameters
    ----------
    sim : radscene.pipeline.simulation.Simulation
    elapsed : sequence of float
        The instants of the sequence's frames [s since the simulation's start].
    """

    def __init__(self, sim, elapsed):
        self.sim = sim
        self.times = np.unique(np.asarray(elapsed, dtype=float))
        self.stored = {}  # per observer: (instant [s], its render there)
        for cache in sim._caches.values():
            if cache.keys is not None:
                cache.keys.look_ahead = True
                cache.keys.reset()

    def drop(self) -> None:
        """Let every key frame go (something was moved by hand): the next frame starts
        them afresh."""
        self.stored = {}
        for cache in self.sim._caches.values():
            if cache.keys is not None:
                cache.keys.reset()

    def take(self, name: str, now: float):
        """The render of observer ``name`` at ``now`` [s] made ahead, or None; once taken its
        key frame is the one behind."""
        stored = self.stored.get(name)
        keys = self.sim._caches[name].keys if name in self.sim._caches else None
        if stored is None or keys is None or abs(stored[0] - now) > INSTANT_TOLERANCE:
            return None
        del self.stored[name]
        if not keys.keys or abs(keys.keys[-1].elapsed - stored[0]) > INSTANT_TOLERANCE:
            return None  # its key frame let go since (a reset)
        keys.advance()
        return stored[1]

    def render_ahead(self, render_one) -> None:
        """After a frame: the next key frame of every observer whose key frame behind is this
        frame's, rendered by ``render_one(name, tables)`` at its instant, the scene put back."""
        now = self.sim.elapsed
        wanted = {}
        for name, cache in self.sim._caches.items():
            keys = cache.keys
            if keys is None or not keys.look_ahead:
                continue
            if name in self.stored and not keys.holds(self.stored[name][0]):
                del self.stored[name]  # its key frames let go (a reset)
            if (name in self.stored or len(keys.keys) != 1
                    or abs(keys.keys[0].elapsed - now) > INSTANT_TOLERANCE):
                continue
            ahead = self._next_key(now, keys.keys[0], keys.interval)
            if ahead is not None:
                wanted.setdefault(ahead, []).append(name)
        for ahead, names in sorted(wanted.items()):
            self._render_at(ahead, names, render_one)

    def _next_key(self, now: float, key, interval: float):
        """The instant of the key frame ahead of ``key`` (at ``now``), or None (see the
        module's description)."""
        later = self.times[self.times > now + INSTANT_TOLERANCE]
        if not len(later):
            return None
        far = np.flatnonzero(later >= now + interval * (1 - 1e-9))
        last = int(far[0]) if len(far) else len(later) - 1
        for t in later[last::-1]:
            if self._fits(key, float(t)):
                return float(t)
        return None

    def _fits(self, key, t: float) -> bool:
        """Whether a key frame at ``t`` can be interpolated to from ``key``: the same time step
        of the heat balance (inside its solution) and the sun turned at most MAX_SUN_STEP."""
        sim = self.sim
        if key.segment is not None and sim._thermal_segment(t) != key.segment:
            return False
        when = sim._instant(t)
        if when is None or sim.scene.sun is not None:
            return True
        from radscene.sun import sun_position

        loc = sim.scene.location
        pos = sun_position(when, loc.latitude, loc.longitude, loc.altitude)
        other = sun_vector(float(pos.zenith), float(pos.azimuth))
        turned = np.degrees(np.arccos(np.clip(key.sun @ other, -1.0, 1.0)))
        return bool(turned <= MAX_SUN_STEP)

    def _render_at(self, t: float, names, render_one) -> None:
        """Render observers ``names`` at ``t`` [s] as key frames ahead; the scene's clock, poses,
        temperatures and tables put back as they were."""
        from radscene.render.integrator import scene_tables

        sim, scene = self.sim, self.sim.scene
        here, tables_here = sim._elapsed, scene.render_cache.get("tables")
        temperatures = [(o.face_temperature, o.face_corner_temperature) for o in scene.objects]
        try:
            sim._set_clock(t)
            sim._follow_motions()
            if sim._thermal:
                sim._apply_thermal()
            tables = scene_tables(scene, sim.tracer)
            sim._key_instant(tables.sun, names)
            for name in names:
                keys = sim._caches[name].keys
                keys.rendering_ahead = True
                try:
                    images = render_one(name, tables)
                finally:
                    keys.rendering_ahead = False
                if keys.holds(t):
                    self.stored[name] = (t, images)
        finally:
            sim._set_clock(here)
            sim._follow_motions()
            for obj, (faces, corners) in zip(scene.objects, temperatures, strict=True):
                obj.face_temperature, obj.face_corner_temperature = faces, corners
            if tables_here is None:
                scene.render_cache.pop("tables", None)
            else:
                scene.render_cache["tables"] = tables_here

