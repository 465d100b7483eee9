"""The machine and the commit measured, and the figures as a two-column table."""

from __future__ import annotations

import os
import platform

from render_bench import ROOT


def source_version() -> dict:
    """The radscene commit measured, and whether its sources differ from it."""
    import subprocess

    def git(*cmd):
        try:
            return subprocess.run(["git", *cmd], cwd=ROOT, capture_output=True, text=True,
                                  timeout=30).stdout.strip()
        except (OSError, subprocess.SubprocessError):
            return ""

    return {"commit": git("rev-parse", "--short", "HEAD"),
            "src_modified": bool(git("status", "--porcelain", "--", "src"))}


def machine() -> dict:
    cpu = platform.processor() or ""
    try:
        with open("/proc/cpuinfo") as f:
            for line in f:
                if line.startswith("model name"):
                    cpu = line.split(":", 1)[1].strip()
                    break
    except OSError:
        pass
    try:
        mem = os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES") / 2**30
    except (ValueError, OSError):
        mem = float("nan")
    import embreex
    import numpy

    return {"cpus": os.cpu_count(), "cpu_model": cpu, "ram_gib": round(mem, 1),
            "python": platform.python_version(), "numpy": numpy.__version__,
            "embreex": getattr(embreex, "__version__", "?"), "platform": platform.platform()}


def _verdict(targets, key):
    if not targets["apply"]:
        return "n/a (the targets are for 1024 x 1024, 16 sky rays, ~1 M triangles)"
    return "met" if targets[key] else "NOT met"


def print_table(r: dict) -> None:
    """The figures as a two-column table on stdout."""
    ren, bare = r["render"], r["bare"]
    walls = ", ".join(f"{w:.2f}" for w in ren["walls_s"])
    rows = [
        ("triangles", f"{r['triangles']:,}"),
        ("image", f"{r['settings']['size']} x {r['settings']['size']} x "
                  f"{r['settings']['bands']} bands, {r['settings']['sky_samples']} sky rays/px"),
        ("scene load", f"{r['load_s']:.2f} s"),
        ("scene", f"{100 * (ren['mean_shadow_fraction'] or 0):.1f} % of pixels in shadow, mean "
                  f"sky view {ren['mean_sky_view'] or float('nan'):.3f}"),
        ("render wall (median)", f"{ren['wall_s']:.2f} s  (runs: {walls})"),
        ("pixel·bands/s", f"{ren['pixel_bands_per_s'] / 1e6:.2f} M"),
        ("rays (render)", "  ".join(f"{k} {v / 1e6:.2f} M" for k, v in ren["rays"].items())),
        ("rays total / rays/s", f"{ren['total_rays'] / 1e6:.2f} M / "
                                f"{ren['rays_per_s'] / 1e6:.2f} M/s"),
        ("time in ray engine", f"{ren['engine_total_s']:.2f} s ("
         + "  ".join(f"{k} {v:.2f}" for k, v in ren["engine_s"].items()) + ")"),
        ("time in queries", "  ".join(f"{k} {v:.2f} s" for k, v in ren["query_s"].items())),
        ("render CPU / wall", f"{ren['cpu_s'] / ren['wall_s']:.2f} cores busy on average"),
        ("peak RSS (render)", f"{ren['peak_rss_mib']:.0f} MiB, "
                              f"{ren['peak_rss_mib'] - ren['rss_at_start_mib']:.0f} MiB above the "
                              f"{ren['rss_at_start_mib']:.0f} MiB held before it"),
        ("bare embreex (median)", f"{bare['total_s']:.2f} s for {bare['total_rays'] / 1e6:.2f} M "
                                  f"rays = {bare['rays_per_s'] / 1e6:.2f} M/s on "
                                  f"{bare['threads']} threads"),
        ("bare by kind", "  ".join(f"{k} {bare['time_s'][k]:.2f} s/{bare['rays'][k] / 1e6:.2f} M"
                                   for k in bare["rays"])),
        ("render / bare (median)", f"{r['render_over_bare']:.2f}  (rounds: "
         + ", ".join(f"{x:.2f}" for x in r["render_over_bare_each"]) + ")"),
        ("bare BVH build", f"{bare['bvh_build_s']:.2f} s (not in the bare time)"),
    ]
    if "packets_total_s" in bare:
        rows += [
            ("bare, Embree packets", f"{bare['packets_total_s']:.2f} s ("
             + "  ".join(f"{k} {v:.2f}" for k, v in bare["packets_time_s"].items())
             + " s; shadow and sky rays as packets of eight, as radscene traces them)"),
            ("render / bare packets", f"{r['render_over_bare_packets']:.2f}  (rounds: "
             + ", ".join(f"{x:.2f}" for x in r["render_over_bare_packets_each"]) + ")"),
        ]
    rows += [
        ("target wall <= 2 s", _verdict(r["targets"], "wall_met")),
        ("target ratio <= 1.5", _verdict(r["targets"], "ratio_met")),
    ]
    atm = r.get("atmosphere")
    if atm:
        sec = atm["seconds"]
        rows.append(("atmosphere look-ups", f"{atm['engine']}: {atm['lookup_s']:.2f} s of a "
                     f"{atm['wall_s']:.2f} s render = {100 * atm['lookup_fraction']:.1f} % "
                     f"(queries {sec['queries']:.2f} s, path-node mixing {sec['mixing']:.2f} s "
                     f"of {sec['mixing'] + sec.get('terms', 0.0):.2f} s in mix_terms, "
                     f"sky-table sums in the sky fold {sec.get('sky_fold', 0.0):.2f} s; "
                     f"band tables {sec['band_tables']:.2f} s incl. their queries); target "
                     "<= 15 %: " + (("met" if atm["lookup_met"] else "NOT met")
                                    if r["targets"]["apply"] else _verdict(r["targets"], ""))))
    brk = r.get("breakdown")
    if brk:
        top = sorted(brk["seconds"].items(), key=lambda kv: -kv[1])[:8]
        rows.append(("breakdown (1 render)", f"{brk['wall_s']:.2f} s wall; inclusive: "
                     + ", ".join(f"{k} {v:.2f}" for k, v in top)))
    mit = r.get("mitsuba")
    if mit and "skipped" in mit:
        rows.append(("mitsuba", f"skipped: {mit['skipped']}"))
    elif mit:
        rows.append(("mitsuba", f"{mit['version']} {mit['variant']}, {mit['passes']} passes, "
                                f"{mit['noise']['spp']} spp for equal noise (needed "
                                f"{mit['noise']['equal_noise_spp']:.1f})"))
        rows.append(("mitsuba render", f"{mit['wall_s']:.2f} s without JIT compilation ("
                                       f"with: sun {mit['render_s']['sun']:.2f}, "
                                       f"sky {mit['render_s']['sky']:.2f}); scene build "
                                       f"{mit['scene_build_s']:.2f} s, JIT warm-up "
                                       f"{mit['jit_warmup_s']:.2f} s; in the timed renders "
                                       f"JIT compile {mit['jit_compile_s']:.2f} s, kernels "
                                       f"{mit['kernel_execution_s']:.2f} s"))
        rows.append(("radscene / mitsuba", f"{mit['radscene_over_mitsuba']:.2f}"))
        for b in mit["bands"]:
            rows.append((f"  {b['band']}", f"mean {b['radscene_mean']:.4g} vs "
                         f"{b['mitsuba_mean']:.4g} W m-2 sr-1 "
                         f"({100 * b['mean_rel_diff']:+.3f} %), rms "
                         f"{100 * b['rms_rel_diff']:.2f} %; sun+emission "
                         f"{100 * b['sun_emission_mean_rel_diff']:+.3f} % "
                         f"({100 * b['sun_emission_pixels_off_1pct']:.2f} % px off >1 %); sky "
                         f"{100 * b['sky_mean_rel_diff']:+.2f} %, rms/noise "
                         f"{b['sky_rms_diff_over_noise']:.2f}"))
    width = max(len(k) for k, _ in rows)
    for k, v in rows:
        print(f"{k:<{width}}  {v}")
