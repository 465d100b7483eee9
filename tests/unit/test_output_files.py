"""Output files: whole or absent, readable like any new file, unique temporaries."""

import os
import stat
from pathlib import Path

import numpy as np
import pytest
import xarray as xr

from radscene.io import write_netcdf
from radscene.io.files import atomic_output
from radscene.io.quicklook import _save, subplots


def _mode(path):
    return stat.S_IMODE(os.stat(path).st_mode)


@pytest.fixture()
def umask_022():
    old = os.umask(0o022)
    yield
    os.umask(old)


def test_netcdf_and_png_get_the_permissions_of_a_new_file(tmp_path, umask_022):
    nc = write_netcdf(xr.Dataset({"a": (("y", "x"), np.zeros((2, 2)))}), tmp_path / "a.nc")
    assert _mode(nc) == 0o644  # not mkstemp's 0600
    fig, _ = subplots()
    png = _save(fig, tmp_path / "a.png")
    assert _mode(png) == 0o644


def test_a_failed_write_leaves_nothing(tmp_path):
    with pytest.raises(RuntimeError), atomic_output(tmp_path / "b.nc") as tmp:
        open(tmp, "w").write("half")
        raise RuntimeError("stopped")
    assert list(tmp_path.iterdir()) == []


def test_temporaries_are_unique(tmp_path):
    with atomic_output(tmp_path / "c.png") as one, atomic_output(tmp_path / "c.png") as two:
        assert one != two


def test_a_folder_output_is_whole_or_absent(tmp_path, umask_022):
    from radscene.io.files import atomic_output_dir

    store = tmp_path / "a.zarr"
    with atomic_output_dir(store) as tmp:
        (Path(tmp) / "part").write_text("one")
    assert (store / "part").read_text() == "one"
    assert _mode(store) == 0o755 and _mode(store / "part") == 0o644
    # a failed rewrite leaves the earlier folder as it was and no temporary
    with pytest.raises(RuntimeError), atomic_output_dir(store) as tmp:
        (Path(tmp) / "part").write_text("half")
        raise RuntimeError("stopped")
    assert (store / "part").read_text() == "one"
    assert [p.name for p in tmp_path.iterdir()] == ["a.zarr"]
    # a finished rewrite replaces it whole
    with atomic_output_dir(store) as tmp:
        (Path(tmp) / "other").write_text("two")
    assert sorted(p.name for p in store.iterdir()) == ["other"]
    assert [p.name for p in tmp_path.iterdir()] == ["a.zarr"]


def test_the_manifest_lists_each_file_of_a_store(tmp_path):
    import json

    from radscene.io.run_record import MANIFEST, RunRecord

    scene = tmp_path / "s.yaml"
    scene.write_text("name: s\n")
    out = tmp_path / "out.zarr"
    with RunRecord(out, scene, ["a"]) as record:
        (out / "a.zarr" / "v").mkdir(parents=True)
        (out / "a.zarr" / ".zattrs").write_text("{}")
        (out / "a.zarr" / "v" / "0.0").write_bytes(b"12345")
        record.finish("a", [out / "a.zarr"])
    files = json.loads((out / MANIFEST).read_text())["files"]
    assert [(f["file"], f["bytes"]) for f in files] == [("a.zarr/.zattrs", 2),
                                                        ("a.zarr/v/0.0", 5)]
