"""The render's rays traced straight through embreex: the floor the render is held to."""

from __future__ import annotations

import os
import time
from concurrent.futures import ThreadPoolExecutor

import numpy as np

#: Embree work unit, the same as radscene's RayTracer default [rays].
CHUNK = 65536


def _cosine_directions(normals, n_samples, rng):
    """``n_samples`` cosine-distributed unit directions about each normal: (N, n_samples, 3)."""
    n = len(normals)
    side = int(round(np.sqrt(n_samples)))
    if side * side == n_samples:  # stratified, as radscene does, rotated per point
        i, j = np.divmod(np.arange(n_samples), side)
        b1, b2 = (i + 0.5) / side, (j + 0.5) / side
    else:
        k = np.arange(n_samples)
        b1, b2 = (k + 0.5) / n_samples, (k * 0.6180339887498949) % 1.0
    shift = rng.random((n, 2))
    u1 = (b1[None, :] + shift[:, :1]) % 1.0
    u2 = (b2[None, :] + shift[:, 1:]) % 1.0
    r, phi = np.sqrt(u1), 2.0 * np.pi * u2
    local = np.stack([r * np.cos(phi), r * np.sin(phi), np.sqrt(np.maximum(0.0, 1.0 - u1))], -1)
    # orthonormal frame about each normal (Duff et al. 2017, doi:10.1145/3095054)
    nz = normals
    sign = np.where(nz[:, 2] >= 0.0, 1.0, -1.0)
    a = -1.0 / (sign + nz[:, 2])
    b = nz[:, 0] * nz[:, 1] * a
    t = np.stack([1.0 + sign * nz[:, 0] ** 2 * a, sign * b, -sign * nz[:, 0]], -1)
    s = np.stack([b, sign + nz[:, 1] ** 2 * a, -nz[:, 1]], -1)
    return (local[..., :1] * t[:, None, :] + local[..., 1:2] * s[:, None, :]
            + local[..., 2:] * nz[:, None, :])


def _pool_map(threads, function, items):
    if threads == 1:
        return [function(x) for x in items]
    with ThreadPoolExecutor(max_workers=threads) as pool:
        return list(pool.map(function, items))


class BareTrace:
    """The render's rays, traced straight through embreex: the floor the render is held to.

    Primary rays start just above the terrain (radscene's tracer clips them to the scene box)
    and go straight down through the pixel centres; shadow rays leave each hit, offset along
    the normal, towards the sun where the sun is above the face; ``sky_samples``
    cosine-distributed rays per hit, those above the horizon, test for sky. Everything —
    Embree scene, BVH, all rays as float32 — is prepared once; :meth:`run` times only the
    Embree calls, on ``threads`` threads over chunks of :data:`CHUNK` rays.
    """

    def __init__(self, mesh, image_size, sun_direction, sky_samples, robust=True,
                 threads=None, seed=0):
        from embreex import mesh_construction, rtcore_scene

        self.threads = threads or os.cpu_count() or 1
        self.robust = robust
        lo, hi = mesh.bounds
        center = 0.5 * (lo + hi)
        t0 = time.perf_counter()
        self.scene = rtcore_scene.EmbreeScene(robust=robust)
        mesh_construction.TriangleMesh(self.scene, (mesh.vertices - center).astype(np.float32),
                                       mesh.faces.astype(np.int32))
        self.scene.run(np.zeros((1, 3), np.float32), np.array([[0, 0, 1]], np.float32))
        self.build_s = time.perf_counter() - t0
        epsilon = 1e-4 + 2e-6 * float(np.linalg.norm(hi - lo))

        # primary: pixel centres over the terrain extent, straight down
        g = (np.arange(image_size) + 0.5) / image_size
        xx, yy = np.meshgrid(lo[0] + g * (hi[0] - lo[0]), hi[1] - g * (hi[1] - lo[1]))
        n = xx.size
        origins = np.column_stack([xx.ravel(), yy.ravel(), np.full(n, hi[2] + 1.0)]) - center
        down = np.broadcast_to(np.array([0.0, 0.0, -1.0]), (n, 3))
        self.primary = self._chunked(origins.astype(np.float32), down.astype(np.float32))
        results = [self.scene.run(o, d, output=1) for o, d in self.primary]
        prim = np.concatenate([r["primID"] for r in results])
        tfar = np.concatenate([r["tfar"] for r in results]).astype(np.float64)
        hit = prim >= 0
        nrm = mesh.face_normals[prim[hit]]
        start = origins[hit] + tfar[hit, None] * down[hit] + epsilon * nrm

        # shadow rays towards the sun, where it is above the face
        sun = np.asarray(sun_direction, dtype=float)
        so = start[nrm @ sun > 0.0]
        self.shadow = self._chunked(so.astype(np.float32),
                                    np.broadcast_to(sun, so.shape).astype(np.float32))
        # sky rays, per block of hits
        rng = np.random.default_rng(seed)
        self.sky = []
        per_block = max(1, CHUNK // sky_samples)
        for s in range(0, len(start), per_block):
            dirs = _cosine_directions(nrm[s:s + per_block], sky_samples, rng)
            up = dirs[..., 2] > 0.0
            o = np.repeat(start[s:s + per_block, None, :], sky_samples, axis=1)[up]
            self.sky.append((o.astype(np.float32), dirs[up].astype(np.float32)))
        self.rays = {"primary": n, "shadow": len(so), "sky": sum(len(b[0]) for b in self.sky)}
        # the same occlusion rays as Embree packets of eight, where radscene uses them
        from radscene.geometry import embree

        self.packets = None
        if embree.packets_available():
            self.packets = embree.PacketScene([(mesh.vertices - center).astype(np.float32)],
                                              [mesh.faces], robust)
            self.packet_rays = {
                "shadow": tuple(np.concatenate(x) for x in zip(*self.shadow, strict=True)),
                "sky": tuple(np.concatenate(x) for x in zip(*self.sky, strict=True))}
            self.packets.occluded(self.packet_rays["sky"][0][:64], self.packet_rays["sky"][1][:64])

    @staticmethod
    def _chunked(o, d):
        return [(o[s:s + CHUNK], np.ascontiguousarray(d[s:s + CHUNK]))
                for s in range(0, len(o), CHUNK)]

    def run(self) -> dict:
        """Trace all rays once; returns the timings [s] and counts."""
        scene = self.scene
        work = {"primary": (self.primary, lambda c: scene.run(c[0], c[1], output=1)),
                "shadow": (self.shadow, lambda c: scene.run(c[0], c[1], query="OCCLUDED")),
                "sky": (self.sky, lambda c: scene.run(c[0], c[1], query="OCCLUDED"))}
        timing = {}
        for kind, (chunks, call) in work.items():
            t0 = time.perf_counter()
            _pool_map(self.threads, call, chunks)
            timing[kind] = time.perf_counter() - t0
        total_s = sum(timing.values())
        total_rays = sum(self.rays.values())
        out = {"rays": dict(self.rays), "time_s": timing, "total_rays": total_rays,
               "total_s": total_s, "rays_per_s": total_rays / total_s, "threads": self.threads,
               "robust": self.robust, "bvh_build_s": self.build_s}
        if self.packets is not None:  # primary rays as above; occlusion as packets
            packet = {"primary": timing["primary"]}
            for kind, (o, d) in self.packet_rays.items():
                t0 = time.perf_counter()
                self.packets.occluded(o, d)
                packet[kind] = time.perf_counter() - t0
            out["packets_time_s"] = packet
            out["packets_total_s"] = sum(packet.values())
        return out
