"""Key frames: a sequence's unchanged pixels extrapolated in time between fully shaded frames.

Between two frames of a sequence the sun moves a little (the demo's 1.7e-4° in 40 ms) and the
heat balance's temperatures, linear in time between its steps, change a little; where nothing
that moved touched a pixel's rays its radiance is a smooth function of time. An incremental
frame (:mod:`radscene.render.frame_cache`) still shades every ray sample again; with key
frames only some frames do — the *key frames* — and the frames between them shade only the
pixels that something moved through since the older of the last two key frames, and take
every other pixel's sums (the signature terms, the transmittance and the truth sums)
extrapolated linearly in time from the last two key frames:

.. math::
    L(t) = L(t_a) + \\frac{t - t_a}{t_b - t_a}\\,\\bigl(L(t_b) - L(t_a)\\bigr).

The shaded pixels of a frame between take the band tables (sun, sky, path radiance and
transmittance at the atmosphere's path nodes) extrapolated the same way from those of the
key frames; their geometry, shadows, fans, temperatures and emission are the frame's own.
The reflected background is every pixel's own in every frame (its paths' vertices may see
what moved anywhere: the pass follows them all, as an incremental frame does), with the band
tables of the newer key frame's sun — except with look-ahead (below) where the pass has one
bounce and no volumes or sheets: then the key frames record their paths
(:mod:`radscene.render.background_record`), a pixel whose recorded rays something moved
through or whose vertices the sun lit otherwise at the two key frames is shaded, and every
other pixel's background is interpolated with its other sums. The surface–atmosphere coupling layers are formed every
frame from the image so made. Truth maps of labels and positions (object and material ids,
normals, geolocation, range) are the frame's own, exactly: an unchanged pixel sees what it
saw; the truth sums (cos θ_i, shadow, sky view, surface temperature) are extrapolated as the
radiance is.

What makes a pixel *shaded* in a frame between (any of its ray samples):

* its primary ray was traced again (it passes through the bounding sphere of an object moved
  since the last frame: :meth:`~radscene.render.frame_cache.FrameCache.primary`);
* a direction of its sky fan or specular lobe fan passes through such a sphere
  (:func:`~radscene.render.kept_fans.fans_meet_spheres`);
* its sun shadow ray (traced every frame) answers otherwise than in either key frame — a
  moved object's shadow, or a shadow edge that the sun moved across the sample;

once shaded, a pixel is shaded until the next key frame but one (its key-frame values hold
what moved). Key frames lie ``render.key_frame_interval`` apart (the first frame, then the
first frame at least that long after the newer key frame), so that a frame is extrapolated
from a baseline of that interval, at most as far again: an extrapolation from two frames
40 ms apart would carry every small step of a frame's numbers (the emission's 1 mK
temperature step, :data:`~radscene.render.band_setup.EMISSION_TEMPERATURE_STEP`) 25 times
over a second. Until a second key frame is kept, and wherever a frame cannot be
extrapolated, every pixel is shaded (an incremental frame). A frame cannot be extrapolated
where the sun has turned by more than :data:`MAX_SUN_STEP` since the older key frame, where
the heat balance has passed one of its time steps (or was solved again) since then — such a
frame starts the key frames afresh —, where the atmosphere's path nodes differ from the key
frames', and wherever the frame cache cannot keep the rays (a full frame).

With look-ahead (``look_ahead``, set by :mod:`radscene.pipeline.look_ahead` for a sequence
whose frame times are known) the second key frame lies ahead of the frames between: it is
rendered (``rendering_ahead``) right after the key frame behind, and a frame between, at
``t_a < t < t_b``, takes the same line between the two, interpolated (weight in (0, 1)); the
pixels it shades are those something moved through since the key frame behind, which the
render ahead marks for the moved objects' places at ``t_b``. Reaching the key frame ahead
(:meth:`KeyFrames.advance`) makes it the one behind. A frame shaded in full between two key
frames that cannot be interpolated is not kept; any other frame shaded in full starts the key
frames afresh.

Memory: per observer two key frames of per-pixel sums (the five terms and the transmittance
per band, six truth sums, the labels) and one sun flag per ray sample (float64), and their
band tables: for the demo's two observers at supersample 2 and eight bands about 0.14 GB.
"""

from __future__ import annotations

import copy
from dataclasses import fields, replace
from types import SimpleNamespace

import numba
import numpy as np

from radscene.render.background_record import PathRecord, meeting_samples
from radscene.render.kept_fans import fans_meet_spheres

__all__ = ["KeyFrames", "MAX_SUN_STEP", "sun_vector"]

#: The most the sun may turn between the older key frame and a frame extrapolated from it
#: [deg]: 12 s of the sun's motion. Extrapolating a sun term over an angle θ is off by
#: about θ² (radians) relative: 8e-7 at this step.
MAX_SUN_STEP = 0.05

#: How far two frames' path nodes may lie apart and count as the same: observer and target
#: altitude [m], view zenith and relative azimuth [deg]. Engines whose path does not depend
#: on the geometry put one node at the hits' mean geometry, which a moving object shifts a
#: little every frame (the demo's truck: its mean target altitude by about 1e-4 m); an
#: engine's spectra change over 0.01 m of altitude by about 1e-6 relative (scale heights of
#: kilometres). A relative azimuth node that the pixels share follows the sun's azimuth,
#: smoothly: it may move as far as the sun may turn.
NODE_TOLERANCE = (0.01, 0.01, 1e-4, MAX_SUN_STEP)
#: Two instants closer than this are the same frame's [s] (frame times summed step by step).
INSTANT_TOLERANCE = 1e-6


def sun_vector(zenith, azimuth) -> np.ndarray:
    """The unit vector towards the sun (east, north, up) at ``zenith``, ``azimuth`` [deg]."""
    z, a = np.radians(zenith), np.radians(azimuth)
    return np.array([np.sin(z) * np.sin(a), np.sin(z) * np.cos(a), np.cos(z)])


class KeyFrames:
    """The last two key frames of one observer, and the pixels changed since each.

    Parameters
    ----------
    interval : float
        The time between key frames [s] (``render.key_frame_interval``): frames are
        extrapolated from the last two over less than that past the newer.

    The simulation tells it each frame's instant (:meth:`at`); the render asks it whether the
    frame is a key frame (:meth:`plan`), which samples to shade (:meth:`tile`), and keeps or
    fills the sums (:meth:`finish`). ``between`` counts the frames made between key frames
    (``between_background`` those whose reflected background was interpolated too),
    ``shaded`` the pixels the last frame shaded.
    """

    def __init__(self, interval: float):
        self.interval = float(interval)
        self.keys = []  # oldest first, at most two
        self.instant = None
        self.between = 0
        self.shaded = 0
        #: frames between key frames whose reflected background was interpolated too
        self.between_background = 0
        #: frames interpolated between the key frame behind and one rendered ahead
        #: (:mod:`radscene.pipeline.look_ahead`), not extrapolated
        self.look_ahead = False
        #: True while the key frame ahead is rendered
        self.rendering_ahead = False

    def reset(self) -> None:
        """Keep no key frame: the next frame is one."""
        self.keys = []

    def at(self, elapsed: float, sun_zenith: float, sun_azimuth: float, segment=None) -> None:
        """The instant of the next frame: ``elapsed`` [s] since the start, the sun [deg], and
        ``segment`` — anything equal for two instants between the same time steps of the
        heat balance's solution (None without one)."""
        self.instant = SimpleNamespace(elapsed=float(elapsed), sun=sun_vector(sun_zenith, sun_azimuth),
                                       segment=segment)

    def _weight(self):
        """The extrapolation weight (t - t_a) / (t_b - t_a) of the next frame, or None where it
        cannot be extrapolated by time, sun or heat balance."""
        now = self.instant
        if now is None or len(self.keys) < 2:
            return None
        if self.look_ahead:
            return interpolation_weight(self.keys, now, self.rendering_ahead)
        a, b = self.keys
        if not (b.elapsed < now.elapsed < b.elapsed + self.interval * (1 - 1e-9)):
            return None  # at an interval from the newer key frame: the next one
        if self._turned(a, now) > MAX_SUN_STEP or not (a.segment == b.segment == now.segment):
            return None
        return (now.elapsed - a.elapsed) / (b.elapsed - a.elapsed)

    @staticmethod
    def _turned(key, now) -> float:
        """The angle the sun turned from a key frame to ``now`` [deg]."""
        return float(np.degrees(np.arccos(np.clip(key.sun @ now.sun, -1.0, 1.0))))

    def _due(self, nodes) -> bool:
        """Whether a frame shaded in full is kept as a key frame: the first; one across a jump
        of the sun, the heat balance or the path nodes (the key frames start afresh); one an
        interval after the newer key frame."""
        now = self.instant
        if self.keys:
            newest = self.keys[-1]
            if (self._turned(newest, now) > MAX_SUN_STEP or newest.segment != now.segment
                    or not _same(newest.nodes, nodes)):
                self.keys = []
        return not self.keys or now.elapsed >= self.keys[-1].elapsed + self.interval * (1 - 1e-9)

    def plan(self, cache, rays, hits, shadow_pass, path_nodes, build_tables,
             background=False):
        """What this frame is: a namespace with ``bset`` (the band tables: built by
        ``build_tables()`` for a key frame, extrapolated for a frame between), ``between``
        (bool), ``background`` (bool: the reflected background of the pixels not shaded is
        interpolated too), ``record`` (the key frame's :class:`~radscene.render.
        background_record.PathRecord`, or None) and what :meth:`launch` and :meth:`finish`
        need. ``shadow_pass`` is the future of every hit's sun flag, ``path_nodes`` the
        atmosphere's nodes of the frame's hits; ``background`` tells whether the render's
        reflected background can be interpolated (one bounce, no volumes or sheets): with
        look-ahead its key frames record their paths (:mod:`radscene.render.
        background_record`)."""
        n = len(rays.pixel)
        nodes = _fingerprint(path_nodes)
        w = self._weight()
        if w is not None and not (self.keys[0].n == n and _same(self.keys[0].nodes, nodes)
                                  and _same(self.keys[1].nodes, nodes)
                                  and self.keys[1].bset.brdf is None):
            w = None
        between = w is not None
        if between:
            a, b = self.keys
            bset = copy.copy(b.bset)
            bset.coefficients = replace(b.bset.coefficients, **{
                f.name: _extrapolate(getattr(a.bset.coefficients, f.name),
                                     getattr(b.bset.coefficients, f.name), w)
                for f in fields(b.bset.coefficients)})
            # the sun at the reflected background's vertices (radscene.render.background)
            bset.sun_spectra = [_extrapolate(x, y, w) for x, y in
                                zip(a.bset.sun_spectra, b.bset.sun_spectra, strict=True)]
        else:
            bset = build_tables()
        paths = bool(background) and self.look_ahead
        plan = SimpleNamespace(
            between=between, weight=w, bset=bset, nodes=nodes, cache=cache, rays=rays,
            hits=hits, shadow_pass=shadow_pass, lit=None,
            active=np.zeros(n, bool) if between else None,
            n_pix=rays.shape[0] * rays.shape[1],
            background=between and paths and all(k.paths is not None for k in self.keys),
            record=PathRecord(n) if paths and not between else None)
        turn = self._turn()
        for key in self.keys:  # what moved through the kept key frames' background paths
            self._touch(plan, meeting_samples(key.paths, cache.spheres, turn))
        return plan

    def _turn(self) -> float:
        """The largest angle between the suns of the kept key frames and this frame [rad]:
        how far a vertex's shadow ray may turn from the one its key frame recorded."""
        suns = [key.sun for key in self.keys]
        if self.instant is not None:
            suns.append(self.instant.sun)
        return max((float(np.arccos(np.clip(a @ b, -1.0, 1.0))) for i, a in enumerate(suns)
                    for b in suns[i + 1:]), default=0.0)

    def _touch(self, plan, samples) -> None:
        """Mark the pixels of ray ``samples`` changed in every kept key frame's record."""
        if len(samples):
            changed = plan.rays.pixel[samples]
            for key in self.keys:
                key.touched[changed] = True

    @staticmethod
    def _lit(plan) -> np.ndarray:
        """Each ray sample's sun flag (NaN: no hit), from the frame's shadow rays."""
        if plan.lit is None:
            plan.lit = np.full(len(plan.rays.pixel), np.nan)
            plan.lit[plan.hits.hit] = plan.shadow_pass.result()
        return plan.lit

    def launch(self, plan, sl, st, shifts, settings, exponent):
        """Mark the pixels of tile ``sl`` that something moved through (see the module's
        description) in every kept key frame's record; return the tile's hits to shade and
        their fans' rotations: ``st`` (:func:`~radscene.render.surface.surface_state`, None
        where the tile has no hit) and ``shifts`` (:func:`~radscene.render.surface.fan_shifts`)
        as they are in a key frame, else only those of the pixels changed since the older key
        frame (None where there are none), with ``full`` = (the tile's hits, the rows kept,
        the rotations of every hit's sky fan). ``exponent`` is every material's lobe
        exponent."""
        if self.keys:
            self._mark(plan, sl, st, shifts, settings, exponent)
        if not plan.between:
            return st, shifts
        active = self.keys[0].touched[plan.rays.pixel[sl]]
        plan.active[sl] = active
        if st is None:
            return None, None
        rows = np.flatnonzero(active[st.hidx - sl.start])
        n = len(st.hidx)
        sub = SimpleNamespace(**{k: v[rows] if isinstance(v, np.ndarray) and len(v) == n
                                 and not (k == "sun" and len(v) == 1) else v
                                 for k, v in vars(st).items()})
        sub.full = (st, rows, shifts[0])
        lobe = None
        if shifts[1] is not None:
            chosen = np.zeros(n, dtype=bool)
            chosen[rows] = True
            lobe = shifts[1][chosen[st.specular]]
            lobe = lobe if len(lobe) else None
        return sub, (shifts[0][rows], lobe)

    def _mark(self, plan, sl, st, shifts, settings, exponent):
        cache = plan.cache
        dirty = cache.kept.fresh[sl].copy()  # primary rays traced again
        if st is not None:
            spheres = cache.spheres
            moved = fans_meet_spheres(st.origin, st.nrm, settings.sky_samples, shifts[0],
                                      spheres)
            if shifts[1] is not None and len(spheres):
                sel = st.specular
                axis = 2.0 * st.cos_v[sel, None] * st.nrm[sel] - st.wo[sel]
                moved[sel] |= fans_meet_spheres(st.origin[sel], st.nrm[sel],
                                                settings.specular_samples, shifts[1], spheres,
                                                lobe=(axis, exponent[st.mat[sel]]))
            lit = self._lit(plan)[st.hidx]
            for key in self.keys:
                moved |= lit != key.lit[st.hidx]
            dirty[st.hidx - sl.start] |= moved
        changed = plan.rays.pixel[sl][dirty]
        for key in self.keys:
            key.touched[changed] = True

    def finish(self, plan, image) -> None:
        """After the tiles: in a frame between, the pixels not shaded take the key frames'
        sums extrapolated (and the totals are formed again); in a key frame its sums are kept
        and the older key frame let go where two are kept."""
        if plan.between:
            a, b = self.keys
            clean = ~a.touched
            if image.sky_thermal is None and "sky_thermal" in b.sums:  # no split band shaded
                image.sky_thermal = np.zeros_like(b.sums["sky_thermal"])
            for name, target in _layers(image, plan.background):
                if name not in a.sums or name not in b.sums:
                    continue
                _line_where(a.sums[name], b.sums[name], plan.weight, clean, target)
            for name, target in _labels(image):
                np.copyto(target, b.sums[name], where=np.broadcast_to(clean, target.shape))
            if image.radiance is not None:  # formed per tile: again for every pixel
                image.totals(np.arange(plan.n_pix))
            self.between += 1
            self.between_background += bool(plan.background)
            self.shaded = int(np.count_nonzero(~clean))
            return
        self.shaded = plan.n_pix
        now = self.instant
        if now is None:  # no instant known: nothing to extrapolate over
            self.keys = []
            return
        if self.look_ahead:
            if not self._kept_ahead():
                return
        elif not self._due(plan.nodes):
            return
        paths = None if plan.record is None else plan.record.finish()
        sums = {name: target.copy() for name, target in
                (*_layers(image, paths is not None), *_labels(image))}
        self.keys.append(SimpleNamespace(
            n=len(plan.rays.pixel), elapsed=now.elapsed, sun=now.sun, segment=now.segment,
            sums=sums, lit=self._lit(plan), nodes=plan.nodes, bset=plan.bset,
            touched=np.zeros(plan.n_pix, dtype=bool), paths=paths))
        self.keys = self.keys[-2:]
        if self.rendering_ahead and len(self.keys) == 2 and paths is not None:
            # the paths of the key frame ahead through what moved to it, and the samples
            # whose vertices the sun lit otherwise at the two key frames
            self._touch(plan, meeting_samples(paths, plan.cache.spheres, self._turn()))
            behind = self.keys[0].paths
            if behind is not None:
                self._touch(plan, np.flatnonzero(behind.checksum != paths.checksum))

    def _kept_ahead(self) -> bool:
        """With look-ahead: whether a frame shaded in full is kept — the key frame ahead
        beside the one behind; a frame at its instant where no key frame lies ahead (the
        key frames start afresh: any kept one let go). A frame shaded in full between two key
        frames that cannot be interpolated (their sun, heat balance or path nodes differ)
        is not kept."""
        if self.rendering_ahead:
            self.keys = self.keys[:1]
            return True
        now = self.instant.elapsed
        if len(self.keys) == 2 and self.keys[0].elapsed < now < self.keys[1].elapsed:
            return False
        self.keys = []
        return True

    def holds(self, elapsed: float) -> bool:
        """Whether a key frame at ``elapsed`` [s] is kept."""
        return any(abs(key.elapsed - elapsed) <= INSTANT_TOLERANCE for key in self.keys)

    def advance(self) -> None:
        """The key frame ahead, reached: it becomes the one behind (the older let go), and
        the pixels something moves through are counted from it afresh."""
        self.keys = self.keys[-1:]
        self.keys[0].touched[:] = False
        self.shaded = 0


def interpolation_weight(keys, now, ahead: bool):
    """With look-ahead: the weight (t - t_a) / (t_b - t_a) of the frame at ``now`` between
    the key frame behind (``keys[0]``) and the one ahead, or None where it is not between
    them (or is the one ahead, ``ahead``) or they cannot be interpolated: the sun turned
    more than :data:`MAX_SUN_STEP` between them, or the heat balance's time step differs."""
    a, b = keys
    if ahead or not a.elapsed < now.elapsed < b.elapsed:
        return None
    if KeyFrames._turned(a, b) > MAX_SUN_STEP or not (a.segment == b.segment == now.segment):
        return None
    return (now.elapsed - a.elapsed) / (b.elapsed - a.elapsed)


def whole_fan(cache, st, shaded_only=False) -> None:
    """Give the tile's hits ``st.full`` (:meth:`KeyFrames.launch`) their sky fans (the first
    directions of the reflected background's paths): the shaded hits' as this frame traced
    them (``st.fan``), the others' from the frame cache's bits, as a kept fan gives them —
    or, with ``shaded_only`` (only the shaded hits' paths are followed), as blocking
    nothing."""
    from radscene.render.background import Fan

    whole, rows, shift = st.full
    fan = getattr(st, "fan", None)
    if fan is None:
        whole.fan = None
        return
    if shaded_only:
        blocked = np.zeros((len(whole.hidx), fan.samples), dtype=bool)
    else:
        bits = cache.kept.sky[whole.hidx]
        blocked = ((bits[:, None] >> np.arange(fan.samples, dtype=np.uint64))
                   & np.uint64(1)) == 0
    blocked[rows] = fan.blocked
    whole.fan = Fan(shift, fan.samples, blocked)


def _extrapolate(a, b, w):
    return a + w * (b - a)


def _line_where(a, b, w, clean, target) -> None:
    """``target = a + w (b - a)`` at the pixels ``clean`` (the last axis), in place."""
    shape = target.shape
    flat = [np.ascontiguousarray(x).reshape(-1, shape[-1]) for x in (a, b)]
    out = target.reshape(-1, shape[-1])
    if not np.shares_memory(out, target):  # not a view: the slow way
        np.copyto(target, _extrapolate(a, b, w), where=np.broadcast_to(clean, shape))
        return
    _line_kernel(flat[0], flat[1], float(w), np.flatnonzero(clean), out)


@numba.njit(parallel=True, cache=True)
def _line_kernel(a, b, w, pixels, out):
    for r in numba.prange(out.shape[0]):
        for k in range(pixels.shape[0]):
            p = pixels[k]
            out[r, p] = a[r, p] + w * (b[r, p] - a[r, p])


def _layers(image, background=False):
    """The per-pixel sums of a :class:`~radscene.render.tiles.TileSums` extrapolated in
    time: (name, array) with the pixel as the last axis. The reflected background only with
    ``background`` (:mod:`radscene.render.background_record`); otherwise every pixel's is the
    frame's own."""
    out = [("acc", image.acc), ("transmittance", image.transmittance)]
    if background and image.background is not None and image.background_thermal is not None:
        out += [("background", image.background),
                ("background_thermal", image.background_thermal)]
    out += [(f"truth_{k}", v) for k, v in image.truth.items()]
    # the sky's emission in the bands whose sky also holds sunlight (its part layer), and the
    # volumes' own radiance along the sky rays and the sky view through them, where present
    out += [(name, v) for name in ("sky_thermal", "media_light", "media_heat", "sky_open")
            if (v := getattr(image, name)) is not None]
    return out


def _labels(image):
    """The labels of the pixels (object, material, normal): those of the newer key frame."""
    return [("object_id", image.object_id), ("material_id", image.material_id),
            ("normal_map", image.normal_map)]


def _fingerprint(path_nodes) -> list:
    """The arrays that define the atmosphere's path nodes (not the hits' mixing of them), to
    compare two frames' nodes."""
    return [np.asarray(getattr(path_nodes, name), dtype=float) for name in
            ("observer_altitude", "target_altitude", "view_zenith", "relative_azimuth")
            if getattr(path_nodes, name) is not None]


def _same(a, b) -> bool:
    """Whether two frames' path nodes (:func:`_fingerprint`) are the same, to
    :data:`NODE_TOLERANCE` each."""
    return len(a) == len(b) and all(
        x.shape == y.shape and np.allclose(x, y, rtol=0.0, atol=tol)
        for x, y, tol in zip(a, b, NODE_TOLERANCE, strict=False))
