"""What an observer's last frame traced, kept for its next frame: incremental, exact sequences.

Between two frames of a sequence the sun moves a little, the heat balance's temperatures
change and some objects move; the observer's rays are the same. A frame's terms follow the
sun and the temperatures everywhere, so every ray sample is shaded again — but most of the
rays it traced met nothing that moved, and tracing them again would give the same answers.
A :class:`FrameCache` keeps, per ray sample of one observer:

* its primary hit (the :class:`~radscene.geometry.raytracer.Hits` of the frame);
* one bit per direction of its sky fan and of its specular lobe's fan: whether the
  direction sees the sky (:mod:`radscene.render.kept_fans`);
* whether each drawn first direction of the reflected-background paths meets the scene
  (the diffuse ones beyond the sky fan, and the lobes'; :mod:`radscene.render.background_first`).
  The diffuse directions taken from the sky fan need nothing more: their ``blocked`` flags
  are the sky fan's bits, kept or traced;
* per pixel, the geodetic position and view angles of what it sees
  (:func:`radscene.render.truth.geolocation`): worked out again only for the pixels with a
  sample traced again.

The next frame traces again only the rays that pass through the bounding sphere of an
object that moved since (where it stood and where it stands): the primary rays, the fans and
the background paths' first rays through one; everything else is taken from the cache.
The sun's shadow rays, and what the background paths meet (their vertices' sun and sky), are
traced every frame: they follow the sun. The rotations of the fans and the background paths'
random numbers are drawn per ray sample (:func:`radscene.render.surface.fan_shifts`,
:func:`radscene.render.background.draws`), so a frame equals a render of the same instant
from scratch.

The cache starts afresh (a full frame) when the observer's rays change (it moved), when the
ray tracer's local frame changes (its clipping box grew), and where the render cannot keep
its rays: Embree's packets unavailable, more than :data:`~radscene.render.kept_fans.MAX_FAN`
sky or specular samples, volumes, semi-transparent sheets, scanners, motion blur.

Memory: per ray sample its ray (48 bytes: the origin and direction it compares the next
frame's with), its hit (73 bytes: distance, object, face, barycentrics, normal, position),
two uint64 of fan bits, three flags, per tile of hits their sample indices (8 bytes) and two
flags per background path (its drawn diffuse and lobe directions), and per pixel five float64
of geolocation: 167 bytes a sample measured on the demo (4 background paths a sample,
supersample 2: the geolocation 10 of them), 212 MiB for its two observers (1.33 M samples;
2026-11-26).
"""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np

from radscene.render.kept_fans import MAX_FAN, bounding_sphere, kept_fans, meets_spheres

__all__ = ["FrameCache", "moved_spheres"]

#: Added to the radius of a moved object's bounding sphere [m]: ray origins and directions
#: reach Embree in float32, about 1e-4 m off in a scene of a kilometre.
SPHERE_MARGIN = 0.05


def moved_spheres(before, after) -> list[np.ndarray]:
    """The bounding spheres of a mesh where it stood and where it stands (vertices (N, 3)
    each [m]), padded by :data:`SPHERE_MARGIN`: (4,) each, centre [m] and radius [m]."""
    out = []
    for vertices in (before, after):
        sphere = bounding_sphere(vertices)
        sphere[3] += SPHERE_MARGIN
        out.append(sphere)
    return out


class FrameCache:
    """The rays one observer's last frame traced, kept per ray sample for its next frame.

    The simulation tells it what moved (:meth:`moved`, :meth:`reset`); the render asks it
    for the primary hits (:meth:`primary`), the fans of a tile (:meth:`sky`, :meth:`lobe`)
    and the background paths' first rays (:meth:`blocked`). ``traced`` counts the rays traced
    again by the last frame, per kind.
    """

    def __init__(self, keys=None):
        self.kept = None
        self.pending = []  # the spheres of what moved since the kept frame
        self.spheres = np.zeros((0, 4))  # those the current frame traces through
        self.traced = {}
        #: the observer's key frames (:class:`radscene.render.key_frames.KeyFrames`) or None
        self.keys = keys

    def moved(self, spheres) -> None:
        """Record spheres (4,) (centre [m], radius [m]) that something moved through."""
        self.pending.extend(np.asarray(s, dtype=float) for s in spheres)

    def reset(self) -> None:
        """Keep nothing: the next frame is traced in full."""
        self.kept = None
        self.pending = []
        if self.keys is not None:
            self.keys.reset()

    @staticmethod
    def usable(scene, tables, track, rays) -> bool:
        """Whether a render of ``rays`` can keep its rays (see the module's description)."""
        settings = scene.settings
        return (tables.tracer.packets is not None and not scene.volumes
                and not tables.sheet_object.any() and not track.moving
                and settings.sky_samples <= MAX_FAN and settings.specular_samples <= MAX_FAN
                and len(rays.pixel) > 0)

    def primary(self, tracer, rays):
        """The primary hits of ``rays``: the kept ones, traced again where they pass through
        something that moved; all traced where nothing is kept."""
        from radscene.geometry.raytracer import Hits

        kept = self.kept
        n = len(rays.pixel)
        if not (kept is not None and kept.n == n and np.array_equal(kept.center, tracer.center)
                and np.array_equal(kept.half, tracer.half_size)
                and np.array_equal(kept.origins, rays.origins)
                and np.array_equal(kept.directions, rays.directions)):
            hits = tracer.intersect(rays.origins, rays.directions)
            self.kept = SimpleNamespace(
                n=n, center=tracer.center, half=tracer.half_size, origins=rays.origins.copy(),
                directions=rays.directions.copy(), hits=hits, fresh=np.ones(n, dtype=bool),
                sky=np.zeros(n, np.uint64), lobe=np.zeros(n, np.uint64),
                sky_known=np.zeros(n, dtype=bool), lobe_known=np.zeros(n, dtype=bool),
                background={})
            self.pending = []
            self.spheres = np.zeros((0, 4))
            self.traced = {"primary": n}
            if self.keys is not None:  # other rays: the key frames no longer apply
                self.keys.reset()
            return hits
        self.spheres = np.array(self.pending).reshape(-1, 4)
        self.pending = []
        redo = meets_spheres(rays.origins, rays.directions, self.spheres)
        at = np.flatnonzero(redo)
        old = kept.hits
        fields = ("distance", "object", "primitive", "u", "v", "normal", "position", "hit")
        if len(at):
            new = tracer.intersect(rays.origins[at], rays.directions[at])
            columns = {}
            for name in fields:
                column = getattr(old, name).copy()
                column[at] = getattr(new, name)
                columns[name] = column
            kept.hits = Hits(**columns)
        kept.fresh = redo
        self.traced = {"primary": len(at)}
        return kept.hits

    def _fan(self, kind, tracer, st, rows, n_samples, sky_nodes, shift, **extra):
        kept = self.kept
        bits, known = (kept.sky, kept.sky_known) if kind == "sky" else (kept.lobe, kept.lobe_known)
        samples = st.hidx[rows]
        mine = bits[samples]
        retrace = kept.fresh[samples] | ~known[samples]
        out, traced = kept_fans(tracer, st.origin[rows], st.nrm[rows], n_samples, sky_nodes,
                                shift, mine, retrace, self.spheres, **extra)
        bits[samples] = mine
        known[samples] = True
        self.traced[kind] = self.traced.get(kind, 0) + traced
        return out

    def sky(self, tracer, st, n_samples, sky_nodes, shift, sky=None, blocked=None):
        """The sky fans of a tile's hits (``st``: :func:`~radscene.render.surface.surface_state`)
        as :func:`radscene.render.illumination.sky_fractions` (``sky`` None) or
        :func:`~radscene.render.illumination.sky_sums` (``sky`` = (table, index, weight))
        return them; ``blocked`` (N, n_samples) bool, where given, gets the fans' directions
        that are not sky (kept or traced), for the reflected background's first bounce."""
        fold = None if sky is None else (st.rank, st.mat, sky[1], sky[2], sky[0])
        return self._fan("sky", tracer, st, slice(None), n_samples, sky_nodes, shift, sky=fold,
                         blocked=blocked)

    def lobe(self, tracer, st, sel, axis, exponent, n_samples, sky_nodes, shift):
        """The lobe fans of the hits ``sel`` of a tile, as
        :func:`radscene.render.illumination.lobe_sky_fractions` returns them."""
        return self._fan("lobe", tracer, st, sel, n_samples, sky_nodes, shift,
                         lobe=(axis, exponent))

    def background(self, tracer, st, sl, samples):
        """What :func:`radscene.render.background.reflected` takes as ``kept`` for the hits of
        tile ``sl`` (``samples`` paths each): the last frame's first rays where the tile's
        hits are those it had."""
        kept = self.kept
        previous = kept.background.get(sl.start)
        n = len(st.hidx)
        same = previous is not None and np.array_equal(previous[0], st.hidx)
        # per path index: the diffuse paths' drawn first rays, then the lobes'
        # (radscene.render.background_first)
        out = SimpleNamespace(blocked=np.zeros(2 * n * samples, dtype=bool),
                              filled=np.zeros(n, dtype=bool))  # the points whose paths it holds
        kept.background[sl.start] = (st.hidx.copy(), out)
        local = self.spheres.copy()
        local[:, :3] -= tracer.center
        if not same:
            return SimpleNamespace(retrace=np.ones(n, dtype=bool), known=out.blocked,
                                   spheres=local, out=out)
        return SimpleNamespace(retrace=kept.fresh[st.hidx] | ~previous[1].filled,
                               known=previous[1].blocked, spheres=local, out=out)
