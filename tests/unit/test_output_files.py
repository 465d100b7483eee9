"""Output files: whole or absent, readable like any new file, unique temporaries."""

import os
import stat

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
