"""Shared by the validation tests: a scene rendered through the ``radscene render`` command."""

from __future__ import annotations

import subprocess
import sys

import pytest
import xarray as xr
import yaml


def _render_scene(folder, scene, observer="cam") -> xr.Dataset:
    """Write ``scene`` (a dict) as YAML into ``folder``, run ``radscene render`` on it in a
    subprocess and return the observer's Dataset, loaded."""
    folder.mkdir(parents=True, exist_ok=True)
    path = folder / "scene.yaml"
    path.write_text(yaml.safe_dump(scene))
    out = folder / "out"
    run = subprocess.run([sys.executable, "-m", "radscene", "render", str(path), "-o", str(out),
                          "--no-quicklooks"], capture_output=True, text=True)
    assert run.returncode == 0, run.stderr
    with xr.open_dataset(out / f"{observer}.nc", engine="h5netcdf") as ds:
        return ds.load()


@pytest.fixture(scope="session")
def render_scene():
    """:func:`_render_scene`: ``render_scene(folder, scene_dict) -> Dataset``."""
    return _render_scene


def _database_and_lowtran(profile, aerosol, aot550, sun_zenith=40.0):
    """The database at one of its AOT550 nodes (``aerosol`` ``none``: aerosol-free) and the
    ``lowtran`` engine at the visibility the database records for that node: LOWTRAN7 itself
    at the database's condition, the pair the line-of-sight validations compare."""
    from radscene.atmosphere.database import DatabaseAtmosphere
    from radscene.atmosphere.lowtran import LowtranAtmosphere

    db = DatabaseAtmosphere(profile=profile, aerosol=aerosol, sun_zenith=sun_zenith,
                            **({"aot550": aot550} if aerosol != "none" else {}))
    vis = (float(db.source["visibility"].values[db._nodes[-1][0]]) / 1000.0
           if aerosol != "none" else None)
    return db, LowtranAtmosphere(model=profile, aerosol=aerosol, visibility=vis, workers=2)


@pytest.fixture(scope="session")
def database_and_lowtran():
    """:func:`_database_and_lowtran`: ``database_and_lowtran(profile, aerosol, aot550)``."""
    return _database_and_lowtran


def _night_over_black_ground(name, atmosphere, bands, temperature, size, spacing, camera):
    """A scene at night (the sun 120 deg from the zenith) over flat ground of reflectance 0
    at ``temperature`` [K]: what an observer sees is the ground's emission and the air's.
    ``bands``: {name: (min, max) [um]}; ``size`` [m] (x, y); ``camera``: the perspective
    observer's position, look_at, fov and shape (its name is ``cam``)."""
    return {
        "name": name,
        "environment": {
            "location": {"latitude": 40.0, "longitude": -105.0, "altitude": "0 m"},
            "sun": {"zenith": 120.0, "azimuth": 180.0, "distance": 1.0},
            "atmosphere": atmosphere,
        },
        "materials": {"black": {"reflectance": 0.0}},
        "terrain": {"type": "flat", "size": [f"{size[0]} m", f"{size[1]} m"],
                    "spacing": f"{spacing} m", "material": "black",
                    "temperature": f"{temperature} K"},
        "bands": [{"name": band, "min": f"{lo} um", "max": f"{hi} um"}
                  for band, (lo, hi) in bands.items()],
        "observers": [{"name": "cam", "type": "perspective", **camera}],
    }


@pytest.fixture(scope="session")
def night_over_black_ground():
    """:func:`_night_over_black_ground`."""
    return _night_over_black_ground
