"""The benchmark scene: procedural terrain, land cover, eight bands, a fixed sun, one nadir
map camera, and its atmospheres."""

from __future__ import annotations

#: Terrain extent [m] and sample spacing [m] of the full benchmark: 708 x 708 samples,
#: 2 x 707 x 707 = 999 698 triangles.
TERRAIN_SIZE = 3535.0
TERRAIN_SPACING = 5.0

#: Eight bands from blue to LWIR (the demo scene's).
BANDS = [
    {"name": "blue", "min": 0.45, "max": 0.52},
    {"name": "green", "min": 0.52, "max": 0.60},
    {"name": "red", "min": 0.63, "max": 0.69},
    {"name": "nir", "min": 0.76, "max": 0.90},
    {"name": "swir1", "min": 1.55, "max": 1.75},
    {"name": "swir2", "min": 2.08, "max": 2.35},
    {"name": "mwir", "min": 3.0, "max": 5.0},
    {"name": "lwir", "min": 8.0, "max": 12.0},
]
#: Land cover (built-in, diffuse) and surface temperature of each [K].
COVER = {"green_vegetation": 297.0, "dry_grass": 303.0, "bare_soil": 306.0, "sand": 309.0}
#: Sun placed by hand: zenith, azimuth [deg] (a morning sun: hills cast shadows).
SUN = (60.0, 135.0)
#: Peak-to-trough relief of the hills as a fraction of the terrain side (354 m on 3.5 km:
#: about 4 % of the image in shadow, mean sky view 0.94).
RELIEF = 0.1
#: Uniform atmosphere (the demo scene's illustrative clear-sky spectra).
_WL = [0.4, 0.5, 0.6, 0.7, 0.9, 1.6, 2.2, 3.0, 4.0, 4.5, 5.0, 8.0, 10.0, 12.0, 20.0]
ATMOSPHERE = {
    "type": "uniform",
    "transmittance": {"wavelength": _WL, "values": [0.70, 0.78, 0.83, 0.87, 0.90, 0.94, 0.95,
                                                    0.70, 0.85, 0.55, 0.75, 0.80, 0.85, 0.75,
                                                    0.30]},
    "path_radiance": {"wavelength": _WL, "values": [40.0, 30.0, 20.0, 13.0, 7.0, 1.5, 0.5, 0.2,
                                                    0.1, 0.4, 0.3, 1.5, 1.2, 2.0, 4.0]},
    "sky_radiance": {"wavelength": _WL, "values": [60.0, 45.0, 30.0, 20.0, 10.0, 2.0, 0.8, 0.5,
                                                   0.3, 0.8, 0.6, 3.0, 2.0, 3.5, 5.0]},
    "sky_zenith": [0, 60, 85],
    "sky_profile": [1.0, 1.3, 2.0],
}
#: The shipped atmospheric database under the demo scene's conditions (``--atmosphere database``).
DATABASE_ATMOSPHERE = {"type": "database", "profile": "midlatitude_summer", "aerosol": "rural",
                       "visibility": "23 km"}
ATMOSPHERES = {"uniform": ATMOSPHERE, "database": DATABASE_ATMOSPHERE}


def scene_dict(size: int, sky_samples: int, terrain_size: float, lake: bool = False,
               seed: int = 1, atmosphere: str = "uniform", background_samples: int = 0) -> dict:
    """The benchmark scene: procedural terrain, 8 bands, a fixed sun, one nadir map camera.

    The camera's ``size`` x ``size`` pixels tile the terrain exactly (every primary ray hits).
    ``background_samples`` > 0 turns on one bounce of the reflected background at that many
    paths per pixel (0: off, the five-term render the figures since the start measure).
    """
    terrain = {
        "type": "procedural",
        "size": [terrain_size, terrain_size],
        "spacing": TERRAIN_SPACING,
        "relief": RELIEF * terrain_size,
        "seed": 7,
        "material_map": {"type": "noise", "materials": list(COVER), "scale": 150.0, "seed": 3},
        "temperature": 300.0,
        "temperatures": dict(COVER),
    }
    if lake:  # a flat specular water surface: adds specular-lobe rays
        terrain["lakes"] = [{"x": 0.3 * terrain_size, "y": 0.6 * terrain_size,
                             "radius": 0.08 * terrain_size, "depth": 3.0}]
        terrain["water_material"] = "water"
        terrain["temperatures"]["water"] = 295.0
    extent = round(terrain_size / TERRAIN_SPACING) * TERRAIN_SPACING
    return {
        "name": "bench_render",
        "environment": {
            "location": {"latitude": -25.75, "longitude": 27.86, "altitude": 1200.0},
            "sun": {"zenith": SUN[0], "azimuth": SUN[1]},
            "atmosphere": ATMOSPHERES[atmosphere],
        },
        "terrain": terrain,
        "bands": BANDS,
        "observers": [{
            "name": "nadir", "type": "orthographic", "center": [extent / 2, extent / 2],
            "gsd": extent / size, "shape": [size, size], "altitude": 8000.0, "supersample": 1,
        }],
        "render": {"sky_samples": sky_samples, "specular_samples": 16, "shadows": True,
                   "seed": seed, "background_bounces": 1 if background_samples else 0,
                   "background_samples": max(background_samples, 1)},
    }
