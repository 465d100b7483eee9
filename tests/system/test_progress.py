"""Progress bars of the Python API: ``radscene.render(scene, progress=True)``, the callable
``progress=`` kept, and a bar by default in Jupyter (:mod:`radscene.pipeline.progress`)."""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np
import pytest

import radscene
from radscene.pipeline import progress as progress_module
from radscene.pipeline.progress import progress_callback


def _scene():
    return {
        "name": "progress_plate",
        "environment": {"sun": {"zenith": 30.0, "azimuth": 180.0}, "atmosphere": {"type": "none"}},
        "materials": {"grey": {"reflectance": 0.3}},
        "objects": [{"name": "plate", "shape": {"type": "plate", "width": 100, "length": 100},
                     "material": "grey", "temperature": "300 K"}],
        "bands": [{"name": "red", "min": "0.6 um", "max": "0.7 um"}],
        "observers": [{"name": "map", "type": "orthographic", "center": [0, 0], "gsd": 5,
                       "shape": [4, 4], "altitude": 1000}],
    }


def test_a_callable_is_handed_on_unchanged():
    def report(done, total):
        pass

    with progress_callback(report, "render") as callback:
        assert callback is report


@pytest.mark.parametrize("progress", [False, None])
def test_no_bar_when_not_asked_outside_an_interactive_session(progress, monkeypatch, capfd):
    monkeypatch.setattr(progress_module, "interactive", lambda: False)
    with progress_callback(progress, "render") as callback:
        assert callback is None
    assert capfd.readouterr().err == ""


def test_a_bar_by_default_when_interactive(monkeypatch, capfd):
    monkeypatch.setattr(progress_module, "interactive", lambda: True)
    with progress_callback(None, "render map", backend="rich") as callback:
        callback(3, 3)
    assert "render map" in capfd.readouterr().err
    with progress_callback(None, "frame 1", when_interactive=False) as callback:
        assert callback is None


@pytest.mark.parametrize("backend", ["tqdm", "rich"])
def test_bar_counts_to_the_total(backend, capfd):
    if backend == "tqdm":
        pytest.importorskip("tqdm")
    with progress_callback(True, "render map", backend=backend) as callback:
        for done in range(1, 6):
            callback(done, 5)
    err = capfd.readouterr().err
    assert "render map" in err and "100%" in err


def test_stages_name_the_bar(capfd):
    with progress_callback(True, "heat balance", stages=True, backend="rich") as callback:
        callback("shadows", 2, 2)
    assert "heat balance: shadows" in capfd.readouterr().err


def test_a_bar_is_drawn_only_when_work_is_reported(capfd):
    with progress_callback(True, "heat balance", backend="rich"):
        pass
    assert capfd.readouterr().err == ""


def test_bad_progress_is_refused_by_type():
    with pytest.raises(TypeError, match="progress: True, False, None or a callable, not str"), \
            progress_callback("yes", "render"):
        pass


def test_render_with_a_bar_equals_render_without(capfd):
    quiet = radscene.render(_scene(), progress=False)
    assert capfd.readouterr().err == ""
    shown = radscene.render(_scene(), progress=True)
    err = capfd.readouterr().err
    assert "render map" in err and "100%" in err
    np.testing.assert_array_equal(shown["radiance"].values, quiet["radiance"].values)


def test_callable_progress_still_reports_samples():
    calls = []
    radscene.render(_scene(), progress=lambda done, total: calls.append((done, total)))
    assert calls and calls[-1][0] == calls[-1][1] > 0


def test_jupyter_shows_a_bar_by_default(tmp_path, monkeypatch):
    nbformat = pytest.importorskip("nbformat")
    nbclient = pytest.importorskip("nbclient")
    pytest.importorskip("ipykernel")
    notebook = nbformat.v4.new_notebook()
    notebook.cells = [nbformat.v4.new_code_cell(f"import radscene\nscene = {_scene()!r}\n"
                                                "images = radscene.render(scene)")]
    src = str(Path(radscene.__file__).parents[1])
    monkeypatch.setenv("PYTHONPATH", os.pathsep.join(filter(None, [src, os.environ.get("PYTHONPATH")])))
    nbclient.NotebookClient(notebook, timeout=300, kernel_name="python3",
                            resources={"metadata": {"path": str(tmp_path)}}).execute()
    outputs = notebook.cells[0].outputs
    assert not [o for o in outputs if o.output_type == "error"]
    text = "".join(o.get("text", "") for o in outputs if o.output_type == "stream" and o.name == "stderr")
    assert "render map" in text and "100%" in text
