"""A scene file's plate solved by the heat balance and rendered, against the radiative
equilibrium of an insulated plate (reference case heat_radiative_equilibrium_plate: absorbed
1000 W m-2, one emitting face, no convection, a sky at 0 K; T_a = 364.416 K for a black plate,
T_b = 329.287 K for solar absorptance 0.6 and emissivity 0.9, tolerance 0.01 K)."""

import numpy as np
import pytest

import radscene
from radscene.scene import load_scene
from radscene.sun import toa_solar_irradiance
from radscene.thermal.irradiance import SHORTWAVE

# case heat_radiative_equilibrium_plate
T_A, T_B, TOLERANCE = 364.416, 329.287, 0.01

# the heat balance integrates the sun over 0.3-4 um: a sun transmittance that makes it 1000 W m-2
_SUN = 1000.0 / np.trapezoid(toa_solar_irradiance(SHORTWAVE), SHORTWAVE)


def _scene(material, overrides):
    return {
        "name": "equilibrium",
        "environment": {"sun": {"zenith": 0.0, "azimuth": 180.0, "distance": 1.0},
                        "atmosphere": {"type": "uniform", "transmittance": 1.0, "sun_transmittance": _SUN,
                                       "sky_radiance": 0.0}},
        "materials": {"plate_material": material},
        "objects": [{"name": "plate", "shape": {"type": "plate", "width": 20, "length": 20},
                     "position": [0, 0, 0], "material": "plate_material"}],
        "bands": [{"name": "lwir", "min": "8 um", "max": "12 um"}],
        "observers": [{"name": "nadir", "type": "orthographic", "center": [0, 0], "gsd": 1.0,
                       "shape": [8, 8], "altitude": 1000}],
        "thermal": {"start": "2026-06-21T00:00:00Z", "end": "2026-06-22T00:00:00Z", "step": "10 min",
                    "convection": "none", "hemisphere_samples": 16,
                    "materials": {"plate_material": {
                        "layers": [{"thickness": 0.002, "conductivity": 50.0, "density": 7800.0,
                                    "specific_heat": 450.0}],
                        "bottom": "insulated", **overrides}}},
    }


@pytest.mark.parametrize("material, overrides, expected", [
    ({"reflectance": 0.0, "emissivity": 1.0}, {}, T_A),
    ({"reflectance": {"wavelength": [0.3, 3.0, 3.5, 100.0], "values": [0.4, 0.4, 0.1, 0.1]}},
     {"solar_absorptance": 0.6, "longwave_emissivity": 0.9}, T_B),
], ids=["black", "grey"])
def test_plate_reaches_radiative_equilibrium_and_renders_it(material, overrides, expected):
    scene = load_scene(_scene(material, overrides), base_dir=".")
    ds = radscene.solve_thermal(scene)
    final = ds.surface_temperature.isel(time=-1).values
    assert final == pytest.approx(np.full(final.shape, expected), abs=TOLERANCE)
    assert float(ds.direct_irradiance[-1]) == pytest.approx(1000.0, rel=1e-9)
    images = radscene.render(scene, "nadir")
    assert float(images.surface_temperature.mean()) == pytest.approx(expected, abs=TOLERANCE)
    if material.get("emissivity") == 1.0:
        # a black plate in vacuum under a black sky: its brightness temperature is its temperature
        bt = images.brightness_temperature.sel(band="lwir").values
        assert bt == pytest.approx(np.full(bt.shape, expected), abs=0.02)
