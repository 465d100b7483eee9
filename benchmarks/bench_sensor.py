"""Sensor benchmark: the full chain on a 4096 x 4096 oversampled radiance frame in 8 bands.

The chain: polychromatic OTF (diffraction × wavefront error × jitter × smear × footprint)
applied in the Fourier domain and sampled to a 1024 x 1024 detector grid (oversample 4), eq. 7
flux with the self-emission terms, eq. 6 current with PRNU and DSNU, Poisson shot noise, read
and 1/f noise, ADC, then DCS, two-point NUC and AGC, with every truth layer carried along.

Target (the issue): <= 5 s on 2 cores. Figures: wall time of ``Sensor.apply`` (best of
``--repeat``) and its CPU time (all threads), the load average of the machine while it ran
(other work on a shared machine slows the wall time), the time per stage from a cProfile run,
megasamples per second, peak resident memory.

Run ``python benchmarks/bench_sensor.py`` (``--quick`` for a 1024 x 1024 smoke run). Figures go
to ``out/bench/bench_sensor.json``. Threads: numpy / scipy FFTs use ``--threads`` workers (2 by
default); set ``OMP_NUM_THREADS`` etc. to the same value to pin the rest.
"""

from __future__ import annotations

import argparse
import cProfile
import io
import json
import os
import platform
import pstats
import resource
import time
from pathlib import Path

import numpy as np
import xarray as xr

ROOT = Path(__file__).resolve().parents[1]
OUT = ROOT / "out" / "bench"

#: Eight bands from blue to LWIR [um] (those of the render benchmark).
BANDS = {"blue": (0.45, 0.52), "green": (0.52, 0.60), "red": (0.63, 0.69), "nir": (0.76, 0.90),
         "swir1": (1.55, 1.75), "swir2": (2.08, 2.35), "mwir": (3.0, 5.0), "lwir": (8.0, 12.0)}


def sensor_config(oversample: int) -> dict:
    return {
        "name": "bench", "oversample": oversample,
        "optics": {"focal_length": "200 mm", "f_number": 2.0, "obscuration": 0.25,
                   "transmittance": 0.85, "temperature": "293 K", "wavefront_error": "0.05 um",
                   "relative_illumination": "cos4",
                   "dome": {"transmittance": 0.95, "temperature": "300 K"}},
        "detector": {"type": "photon", "pitch": "15 um", "fill_factor": 0.9,
                     "quantum_efficiency": 0.7, "integration_time": "1 ms", "temperature": "80 K",
                     "dark_current": "10 fA", "full_well": 1e7, "read_noise": 300,
                     "flicker_corner": "10 kHz", "prnu": 0.01, "dsnu": 0.1,
                     "cold_shield_f_number": 2.0},
        "electronics": {"gain": 700, "offset": 500, "bits": 14, "frame_rate": "100 Hz"},
        "motion": {"jitter": "5 urad", "smear": [0.3, 0.0]},  # along-track smear
        "processing": {"dcs": {"shutter_temperature": "293 K"},
                       "nuc": {"low": "290 K", "high": "320 K"}, "agc": {"bits": 8}},
        "bands": {name: {"response": {"type": "rectangular", "wavelength_min": lo,
                                      "wavelength_max": hi}} for name, (lo, hi) in BANDS.items()},
    }


def radiance(n: int, seed: int = 0) -> xr.Dataset:
    """A textured radiance cube (band, y, x) [W m-2 sr-1] with a few object-like squares."""
    rng = np.random.default_rng(seed)
    from radscene.radiometry import band_radiance

    base = np.array([band_radiance(lo, hi, 300.0) if lo > 2.5 else 30.0 * (hi - lo) / 0.1
                     for lo, hi in BANDS.values()])
    texture = np.fft.irfft2(np.fft.rfft2(rng.standard_normal((n, n)))
                            / (1.0 + np.hypot(*np.meshgrid(np.fft.rfftfreq(n) * n,
                                                           np.fft.fftfreq(n) * n))), s=(n, n))
    texture = 1.0 + 0.2 * texture / texture.std()
    cube = (base[:, None, None] * texture[None]).astype(np.float32)
    labels = np.zeros((n, n), dtype=np.int32)
    for i in range(8):
        y, x = rng.integers(0, n - n // 16, 2)
        cube[:, y : y + n // 16, x : x + n // 16] *= 1.3
        labels[y : y + n // 16, x : x + n // 16] = i + 1
    return xr.Dataset(
        {"radiance": (("band", "y", "x"), cube, {"units": "W m-2 sr-1"}),
         "object_id": (("y", "x"), labels),
         "range": (("y", "x"), np.full((n, n), 5000.0, dtype=np.float32), {"units": "m"})},
        coords={"band": list(BANDS)})


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="1024 x 1024 smoke run")
    parser.add_argument("--threads", type=int, default=2, help="FFT workers")
    parser.add_argument("--repeat", type=int, default=3)
    args = parser.parse_args(argv)

    from radscene.sensor import make_sensor

    n = 1024 if args.quick else 4096
    k = 4
    ds = radiance(n)
    sensor = make_sensor(sensor_config(k))
    sensor.apply(ds.isel(y=slice(0, 64), x=slice(0, 64)), workers=args.threads)  # warm-up
    times, cpu = [], []
    for r in range(args.repeat):
        t0, c0 = time.perf_counter(), time.process_time()
        signal = sensor.apply(ds, seed=r, workers=args.threads)
        times.append(time.perf_counter() - t0)
        cpu.append(time.process_time() - c0)
    profile = cProfile.Profile()
    profile.enable()
    sensor.apply(ds, seed=99, workers=args.threads)
    profile.disable()
    stream = io.StringIO()
    pstats.Stats(profile, stream=stream).sort_stats("cumulative").print_stats(25)
    best = min(times)
    samples = ds["radiance"].size
    figures = {
        "machine": platform.processor() or platform.machine(),
        "cpu_count": os.cpu_count(),
        "threads": args.threads,
        "fine_shape": [len(BANDS), n, n],
        "detector_shape": list(signal["dn"].shape),
        "oversample": k,
        "processing": "dcs nuc agc",
        "apply_seconds": [round(t, 3) for t in times],
        "best_seconds": round(best, 3),
        "cpu_seconds": [round(t, 3) for t in cpu],
        "load_average": [round(x, 2) for x in os.getloadavg()],
        "megasamples_per_second": round(samples / best / 1e6, 1),
        "peak_rss_mib": round(resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024, 1),
        "target_seconds": 5.0,
        "meets_target": bool(best <= 5.0) if not args.quick else None,
    }
    OUT.mkdir(parents=True, exist_ok=True)
    (OUT / "bench_sensor.json").write_text(json.dumps(figures, indent=2))
    (OUT / "bench_sensor_profile.txt").write_text(stream.getvalue())
    print(json.dumps(figures, indent=2))


if __name__ == "__main__":
    main()
