"""BRDF benchmark: vectorised evaluations per second of every registered model.

For each model, ``f(wi, wo)`` is evaluated on N random direction pairs in the upper hemisphere
(local frame, constant parameters), best of a few repeats; the compiled models (RPV, Ross-Li)
are also timed on their numpy reference path, and every model through ``kernel(μ_i, μ_o,
cos g)`` (the cosines a renderer already has) and with world vectors and a normal. The first
call (compilation or loading numba's on-disk cache) is timed apart and not counted.

Targets (issue 4, on 2 cores): ≥ 10 M evaluations/s for Lambert and Phong, ≥ 1 M/s for RPV and
Ross-Li.

Run ``python benchmarks/bench_brdf.py`` (``--quick`` for a small smoke run, ``--threads`` to
set numba's thread count, default 2). Figures go to ``out/bench/bench_brdf.json`` and a
Markdown table to stdout.
"""

from __future__ import annotations

import argparse
import datetime as _dt
import json
import os
import platform
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
OUT = ROOT / "out" / "bench"

#: Representative parameters (constants) of every registered model.
MODELS = {
    "lambertian": {"reflectance": 0.3},
    "phong": {"diffuse_reflectance": 0.3, "specular_reflectance": 0.05,
              "specular_exponent": 50.0},
    "ggx": {"roughness": 0.3, "refractive_index": 1.5},
    "beckmann": {"roughness": 0.2, "refractive_index": 0.96, "extinction_coefficient": 6.69},
    "rpv": {"rho0": 0.076, "k": 0.648, "theta": -0.29},
    "rossli": {"f_iso": 0.3, "f_vol": 0.15, "f_geo": 0.03, "hotspot": True},
    "hapke": {"single_scattering_albedo": 0.6, "asymmetry": -0.2,
              "opposition_amplitude": 0.5},
    "coxmunk": {"wind_speed": 5.0, "refractive_index": 1.34},
    "lambertian_transmission": {"reflectance": 0.45, "transmittance": 0.45},
}
#: Evaluations per second required by the issue [1/s].
TARGETS = {"lambertian": 10e6, "phong": 10e6, "rpv": 1e6, "rossli": 1e6}


def _best(fn, repeat):
    times = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t0)
    return min(times)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="2^16 pairs, 2 repeats")
    parser.add_argument("--threads", type=int, default=2, help="numba threads (default 2)")
    parser.add_argument("--pairs", type=int, default=1 << 21, help="direction pairs")
    parser.add_argument("--repeat", type=int, default=5)
    args = parser.parse_args(argv)
    os.environ.setdefault("NUMBA_NUM_THREADS", str(args.threads))

    import numba
    import numpy as np

    from radscene.materials.brdf import make_brdf

    numba.set_num_threads(min(args.threads, numba.config.NUMBA_NUM_THREADS))
    n = 1 << 16 if args.quick else args.pairs
    repeat = 2 if args.quick else args.repeat
    rng = np.random.default_rng(0)

    def hemisphere(count):
        v = rng.normal(size=(count, 3))
        v /= np.linalg.norm(v, axis=1, keepdims=True)
        v[:, 2] = np.abs(v[:, 2])
        return v

    wi, wo = hemisphere(n), hemisphere(n)
    mu_i, mu_o = wi[:, 2].copy(), wo[:, 2].copy()
    cos_g = np.einsum("ij,ij->i", wi, wo)
    normal = np.array([0.0, 0.0, 1.0])
    rows = []
    for name, params in MODELS.items():
        model = make_brdf({"type": name, **params})
        t0 = time.perf_counter()
        model.f(wi[:16], wo[:16])
        first_call = time.perf_counter() - t0
        row = {
            "model": name,
            "first_call_s": first_call,
            "f_local_per_s": n / _best(lambda m=model: m.f(wi, wo), repeat),
            "kernel_per_s": n / _best(lambda m=model: m.kernel(mu_i, mu_o, cos_g), repeat),
            "f_world_per_s": n / _best(lambda m=model: m.f(wi, wo, normal=normal), repeat),
        }
        if hasattr(model, "kernel_reference"):
            row["numpy_reference_per_s"] = n / _best(
                lambda m=model: m.kernel_reference(mu_i, mu_o, cos_g), repeat)
        target = TARGETS.get(name)
        row["target_per_s"] = target
        row["pass"] = None if target is None else bool(row["f_local_per_s"] >= target)
        rows.append(row)

    print(f"BRDF evaluations, {n} pairs, numba threads {numba.get_num_threads()}, "
          f"{os.cpu_count()} CPUs visible, best of {repeat}\n")
    print("| model | f(wi, wo) [M/s] | kernel(μi, μo, cos g) [M/s] | f, world + normal [M/s] "
          "| numpy reference [M/s] | target [M/s] | |")
    print("|---|---:|---:|---:|---:|---:|---|")
    for r in rows:
        ref = r.get("numpy_reference_per_s")
        target = r["target_per_s"]
        verdict = "" if r["pass"] is None else ("pass" if r["pass"] else "**FAIL**")
        print(f"| {r['model']} | {r['f_local_per_s'] / 1e6:.1f} | {r['kernel_per_s'] / 1e6:.1f} "
              f"| {r['f_world_per_s'] / 1e6:.1f} | {'' if ref is None else f'{ref / 1e6:.1f}'} "
              f"| {'' if target is None else f'{target / 1e6:g}'} | {verdict} |")
    OUT.mkdir(parents=True, exist_ok=True)
    record = {
        "date": _dt.datetime.now(_dt.UTC).isoformat(timespec="seconds"),
        "machine": platform.platform(),
        "processor": platform.processor(),
        "cpus_visible": os.cpu_count(),
        "numba_threads": numba.get_num_threads(),
        "pairs": n,
        "repeat": repeat,
        "results": rows,
    }
    path = OUT / ("bench_brdf_quick.json" if args.quick else "bench_brdf.json")
    path.write_text(json.dumps(record, indent=2))
    print(f"\nwritten {path.relative_to(ROOT)}")
    return 0 if all(r["pass"] is not False for r in rows) else 1


if __name__ == "__main__":
    sys.exit(main())
