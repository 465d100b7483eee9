"""Sweeps on dask (radscene.distributed, ``radscene sweep``): every variant rendered, each equal
to a render of the same scene with the same settings, bad settings refused before any render."""

from __future__ import annotations

import json

import numpy as np
import pytest
import xarray as xr
import yaml
from typer.testing import CliRunner

pytest.importorskip("distributed", reason="the dask extra is not installed (pip install '.[dask]')")

import radscene  # noqa: E402
from radscene.cli import app  # noqa: E402
from radscene.distributed import apply_setting, render_sweep, variants  # noqa: E402
from radscene.errors import ConfigError  # noqa: E402


def _scene():
    return {
        "name": "sweep",
        "environment": {"sun": {"zenith": 30.0}, "atmosphere": {"type": "none"}},
        "materials": {"grey": {"reflectance": 0.3}, "paint": {"reflectance": 0.8}},
        "objects": [{"name": "ground", "shape": {"type": "plate", "width": 100, "length": 100},
                     "material": "grey", "temperature": "290 K"},
                    {"name": "box", "shape": {"type": "box", "size": [10, 10, 5]},
                     "material": "paint", "temperature": "300 K"}],
        "bands": [{"name": "vis", "min": 0.5, "max": 0.6}],
        "observers": [{"name": "map", "type": "orthographic", "center": [0, 0], "gsd": 2.0,
                       "shape": [16, 16], "altitude": 1000}],
        "render": {"sky_samples": 1, "background_bounces": 0},
    }


def test_settings_expand_to_every_combination_and_set_nested_keys():
    assert variants({"a": [1, 2], "b": [3]}) == [{"a": 1, "b": 3}, {"a": 2, "b": 3}]
    doc = apply_setting(_scene(), "observers[map].gsd", 4.0)
    assert doc["observers"][0]["gsd"] == 4.0 and _scene()["observers"][0]["gsd"] == 2.0
    assert apply_setting(_scene(), "observers[0].altitude", 500)["observers"][0]["altitude"] == 500
    with pytest.raises(ConfigError, match="no item named 'mapp'; named: map"):
        apply_setting(_scene(), "observers[mapp].gsd", 1.0)
    with pytest.raises(ConfigError, match="out of range"):
        apply_setting(_scene(), "observers[3].gsd", 1.0)


def test_each_variant_equals_a_render_of_that_variant(tmp_path):
    from distributed import Client

    suns = [20.0, 60.0]
    with Client(processes=False, n_workers=1, threads_per_worker=1, dashboard_address=None) as client:
        files = render_sweep(_scene(), {"environment.sun.zenith": suns}, tmp_path / "out",
                             client=client)
    assert list(files) == ["variant_000", "variant_001"]
    index = json.loads((tmp_path / "out" / "sweep.json").read_text())
    assert [v["settings"] for v in index["variants"]] == [{"environment.sun.zenith": s} for s in suns]
    means = []
    for paths, sun in zip(files.values(), suns, strict=True):
        with xr.open_dataset(paths[0]) as got:
            want = radscene.render(apply_setting(_scene(), "environment.sun.zenith", sun))
            np.testing.assert_allclose(got["radiance"].values, want["radiance"].values,
                                       rtol=1e-6)  # stored as float32
            assert json.loads(got.attrs["sweep_settings"]) == {"environment.sun.zenith": sun}
            means.append(float(got["radiance"].mean()))
    assert means[0] > 1.5 * means[1]  # the higher sun is brighter: the variants differ


def test_a_bad_variant_is_refused_before_any_render(tmp_path):
    with pytest.raises(ConfigError, match=r"variant_001 \(environment.sun.zenith=abc\)") as err:
        render_sweep(_scene(), {"environment.sun.zenith": [20.0, "abc"]}, tmp_path / "out")
    assert "environment.sun.zenith" in err.value.key
    assert not (tmp_path / "out").exists()


def test_the_cli_sweeps_on_a_local_cluster_and_refuses_bad_settings(tmp_path):
    scene_file = tmp_path / "scene.yaml"
    scene_file.write_text(yaml.safe_dump(_scene()))
    out = tmp_path / "out"
    result = CliRunner().invoke(app, ["sweep", str(scene_file), "-o", str(out), "--set",
                                      "observers[map].gsd=1,2", "--workers", "1"])
    assert result.exit_code == 0, result.output
    with xr.open_dataset(out / "variant_000" / "map.nc") as a, \
            xr.open_dataset(out / "variant_001" / "map.nc") as b:
        assert json.loads(a.attrs["sweep_settings"]) == {"observers[map].gsd": 1}
        spacing = [float(np.abs(np.diff(ds["x"].values)).mean()) for ds in (a, b)]
        assert spacing == pytest.approx([1.0, 2.0])  # each variant's own ground sampling
    bad = CliRunner().invoke(app, ["sweep", str(scene_file), "-o", str(tmp_path / "bad"),
                                   "--set", "environment.sun.zenit=20"])
    assert bad.exit_code == 2
    assert len(bad.output.strip().splitlines()) == 1 and "zenit" in bad.output
    assert not (tmp_path / "bad").exists()


def test_the_cli_sweep_quiet_and_verbose(tmp_path, monkeypatch, one_line_refusal):
    """--quiet prints nothing; --verbose adds the variants, the cluster and each variant
    finished with its time; both together are refused before any render. The printing alone
    is checked here: the renders are the test above's."""
    import radscene.distributed as distributed

    calls = []

    def fake_sweep(scene, settings, output, *, client=None, workers=None, overwrite=False,
                   progress=None):
        calls.append(settings)
        files = {f"variant_{i:03d}": [output / f"variant_{i:03d}" / "map.nc"] for i in range(2)}
        for done in (1, 2):
            progress(done, 2)
        return files

    monkeypatch.setattr(distributed, "render_sweep", fake_sweep)
    scene_file = tmp_path / "scene.yaml"
    scene_file.write_text(yaml.safe_dump(_scene()))
    args = ["sweep", str(scene_file), "-o", str(tmp_path / "out"), "--set",
            "environment.sun.zenith=20,40", "--set", "observers[map].gsd=2"]
    runner = CliRunner()
    normal = runner.invoke(app, args)
    assert normal.exit_code == 0 and "variant 2/2" in normal.output
    assert "sweep.json" in normal.output.replace("\n", "")  # a long path wraps
    quiet = runner.invoke(app, [*args, "--quiet"])
    assert quiet.exit_code == 0 and quiet.output == "", quiet.output
    loud = runner.invoke(app, [*args, "-v"])
    assert loud.exit_code == 0, loud.output
    for words in ("2 variant(s) of 2 setting(s): environment.sun.zenith=20,40; "
                  "observers[map].gsd=2",
                  "local dask cluster of 1 process(es)", "variant 2/2 finished (",
                  "2 variant(s) rendered and written"):
        assert words in loud.output, words
    assert len(calls) == 3
    both = runner.invoke(app, [*args, "-q", "-v"])
    assert both.exit_code == 2 and one_line_refusal(both.output, "--quiet")
    assert len(calls) == 3
