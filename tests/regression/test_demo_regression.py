"""Regression: summary statistics of the demo scene's renders against stored values.

The demo is rendered at a quarter of its resolution with 4 sky samples, so the test stays fast;
the statistics (per observer and band: mean, standard deviation, minimum, maximum of the total
radiance and of each term's mean) are compared with ``demo_stats.json`` at a stated tolerance.
Regenerate after an intended change with ``RADSCENE_REGEN=1 make test`` and review the diff.
"""

from __future__ import annotations

import json
import os
from pathlib import Path

import numpy as np
import pytest
import yaml

import radscene
from radscene.render import BACKGROUND_TERM, COUPLING_TERMS, TERMS
from radscene.render.outputs import PART_LAYERS, PART_NAMES

STATS = Path(__file__).with_name("demo_stats.json")
#: Relative tolerance: renders are seeded and deterministic; this allows for floating-point
#: differences between machines and library versions.
REL = 1e-4


def _reduced_demo() -> dict:
    data = yaml.safe_load(radscene.example_path("demo").read_text())
    for obs in data["observers"]:
        ny, nx = obs["shape"]
        obs["shape"] = [ny // 4, nx // 4]
        obs["supersample"] = 1
        if obs["type"] == "orthographic":
            obs["gsd"] = "12 m"
    data["render"]["sky_samples"] = 4
    data["render"]["specular_samples"] = 4
    return data


def _statistics() -> dict:
    scene = radscene.load_scene(_reduced_demo())
    stats = {}
    for name, ds in radscene.render_all(scene).items():
        for band in ds["band"].values:
            sel = ds.sel(band=band)
            rad = sel["radiance"].values
            entry = {"mean": float(rad.mean()), "std": float(rad.std()),
                     "min": float(rad.min()), "max": float(rad.max())}
            entry.update({f"{t}_mean": float(sel[t].values.mean())
                          for t in TERMS + (BACKGROUND_TERM,) + COUPLING_TERMS + PART_NAMES})
            stats[f"{name}/{band}"] = entry
        stats[f"{name}/truth"] = {
            "shadow_fraction_mean": float(ds["shadow_fraction"].mean()),
            "sky_view_fraction_mean": float(ds["sky_view_fraction"].mean()),
            "surface_temperature_mean": float(ds["surface_temperature"].mean()),
            "object_pixels": int((ds["object_id"].values > 0).sum()),
        }
    return stats


@pytest.fixture(scope="module")
def stats():
    return _statistics()


def test_demo_statistics_match_stored_values(stats):
    if os.environ.get("RADSCENE_REGEN"):
        STATS.write_text(json.dumps(stats, indent=1, sort_keys=True) + "\n")
    stored = json.loads(STATS.read_text())
    assert sorted(stored) == sorted(stats)
    for key, entry in stored.items():
        for name, value in entry.items():
            assert stats[key][name] == pytest.approx(value, rel=REL, abs=1e-12), f"{key} {name}"


def test_demo_statistics_are_physical(stats):
    for key, entry in stats.items():
        if key.endswith("/truth"):
            assert 0.0 <= entry["shadow_fraction_mean"] <= 1.0
            assert 0.5 < entry["sky_view_fraction_mean"] <= 1.0
            assert 280.0 < entry["surface_temperature_mean"] < 330.0
            assert entry["object_pixels"] > 0
        else:
            assert entry["min"] >= 0.0
            assert np.isclose(sum(entry[f"{t}_mean"]
                                  for t in TERMS + (BACKGROUND_TERM,) + COUPLING_TERMS),
                              entry["mean"], rtol=1e-9)
            for layer, parts in PART_LAYERS.items():  # the parts by origin sum to their layer
                assert np.isclose(sum(entry[f"{p}_mean"] for p in parts), entry[f"{layer}_mean"],
                                  rtol=1e-9, atol=1e-15)
