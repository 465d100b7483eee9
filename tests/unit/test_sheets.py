"""Semi-transparent sheets: band transmittances, the layers' sum with sheets and volumes
together, and bad input."""

from __future__ import annotations

import numpy as np
import pytest

from radscene import load_scene, render
from radscene.errors import ConfigError
from radscene.materials import Material
from radscene.radiometry import RectangularResponse
from radscene.render import sheets


class _Band:
    def __init__(self, lo, hi):
        self.response = RectangularResponse(lo, hi)


def test_band_transmittance_is_the_response_weighted_mean():
    net = Material.create("net", reflectance=0.1,
                          transmittance={"wavelength": [0.4, 1.0, 14.0],
                                         "values": [0.2, 0.8, 0.8]})
    t = sheets.band_transmittance([net], [_Band(0.5, 0.7), _Band(8.0, 12.0)])
    # the mean of a line over [0.5, 0.7]: its value at 0.6 um
    assert t[0] == pytest.approx([0.2 + 0.6 * (0.6 - 0.4) / 0.6, 0.8], rel=1e-12)


def test_band_transmittance_beyond_the_table_raises_unless_held():
    """The heat balance weights a sheet's τ by a 300 K blackbody over 4-50 um, past the
    library's 20 um: there (``hold``) the table's end value is kept; a band does not."""
    net = Material.create("net", reflectance=0.1,
                          transmittance={"wavelength": [0.4, 3.0, 20.0],
                                         "values": [0.8, 0.3, 0.3]})
    with pytest.raises(ConfigError, match="outside the tabulated range"):
        sheets.band_transmittance([net], [_Band(8.0, 30.0)])
    held = sheets.band_transmittance([net], [_Band(8.0, 30.0), _Band(0.2, 0.4)], hold=True)
    assert held[0] == pytest.approx([0.3, 0.8], rel=1e-12)
    assert net.transmittance.extend == "error"  # the material itself is left as it was


def _scene(supersample):
    return {
        "name": "net and smoke",
        "environment": {"sun": {"zenith": 35.0, "azimuth": 160.0},
                        "atmosphere": {"type": "uniform", "sky_radiance": 3.0,
                                       "transmittance": 0.9, "path_radiance": 1.0}},
        "materials": {"grey": {"reflectance": 0.4},
                      "net": {"reflectance": 0.2, "transmittance": {
                          "wavelength": [0.4, 0.7, 14.0], "values": [0.3, 0.5, 0.5]}}},
        "objects": [{"name": "plate", "shape": {"type": "plate", "width": 100, "length": 100},
                     "material": "grey", "temperature": "300 K"},
                    {"name": "block", "shape": {"type": "box", "size": [4, 4, 6]},
                     "position": [0, 6, 0], "material": "grey", "temperature": "330 K"},
                    {"name": "net", "shape": {"type": "plate", "width": 12, "length": 12},
                     "position": [2, 0, 8], "rotation": [0, 20, 0], "material": "net",
                     "temperature": "310 K", "transmissive": True}],
        "volumes": [{"name": "cloud", "shape": {"type": "ellipsoid", "radii": [5, 4, 3]},
                     "position": [-6, 0, 12], "optical_depth": 0.9, "temperature": "320 K"}],
        "bands": [{"name": "vis", "min": 0.5, "max": 0.6}, {"name": "lwir", "min": 8, "max": 12}],
        "observers": [{"name": "cam", "type": "perspective", "position": [30, -30, 25],
                       "look_at": [0, 0, 3], "fov": 50, "shape": [24, 24],
                       "supersample": supersample}],
        "render": {"background_samples": 4},
    }


LAYERS = ("sun_diffuse", "sun_specular", "thermal_emission", "sky_reflected", "path_radiance",
          "background_reflected", "multiple_reflection", "diffuse_transmitted", "adjacency",
          "transmitted", "volume_emission", "volume_scattered")


@pytest.mark.parametrize("supersample", [1, 2])
def test_radiance_is_the_sum_of_the_layers_with_sheets_and_volumes(supersample):
    ds = render(load_scene(_scene(supersample)))
    total = sum(ds[name] for name in LAYERS)
    assert ds["radiance"].values == pytest.approx(total.values, rel=1e-12)
    net = ds["object_id"].values == 2
    assert np.count_nonzero(net) > 20
    assert np.all(ds["transmitted"].values[:, net] > 0.0)
    assert float(ds["volume_emission"].max()) > 0.0


def test_transmissive_object_needs_a_material_with_transmittance():
    scene = _scene(1)
    scene["objects"][1]["transmissive"] = True
    with pytest.raises(ConfigError, match=r"objects\[1\]\.transmissive"):
        load_scene(scene)
