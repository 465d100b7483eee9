"""The layers of a render and the Dataset that holds them.

Each signature term is an output layer of its own (``docs/outputs.md``); their sum is the
``radiance``. :func:`dataset` packs the render's per-pixel sums into the CF Dataset, with the
brightness temperature of the thermal bands, the path transmittance and the truth maps
(:mod:`radscene.render.truth`); :func:`cf_conventions` gives it its CF form.
"""

from __future__ import annotations

import datetime as _dt

import numpy as np
import xarray as xr

from radscene.render import truth
from radscene.render.sky_split import PART_COMMENTS, PART_LAYERS, PART_NAMES
from radscene.render.spectral import solar_spectrum
from radscene.render.volumes import VOLUME_TERMS

__all__ = ["TERMS", "TERM_LONG_NAMES", "BACKGROUND_TERM", "BACKGROUND_LONG_NAME",
           "COUPLING_TERMS", "COUPLING_LONG_NAMES", "TERM_LAYERS", "PART_LAYERS", "PART_NAMES",
           "PART_LONG_NAMES", "finest_layers", "THERMAL_BAND_START", "GEOLOCATION_COORDS",
           "CONSTANT_ANGLES", "dataset", "cf_conventions", "grid_mapping_attrs", "pixel_coordinates",
           "sky_view_transmitted"]

#: Output layer names of the signature terms, in the order they are summed.
TERMS = ("sun_diffuse", "sun_specular", "thermal_emission", "sky_reflected", "path_radiance")
TERM_LONG_NAMES = {
    "sun_diffuse": "directly reflected sunlight, diffuse",
    "sun_specular": "directly reflected sunlight, specular",
    "thermal_emission": "self-emitted thermal radiance",
    "sky_reflected": "reflected sky radiance",
    "path_radiance": "atmospheric path radiance (sky radiance where a ray leaves the scene)",
}
#: Output layer of the reflected background (:mod:`radscene.render.background`), summed into
#: the radiance after the terms.
BACKGROUND_TERM = "background_reflected"
BACKGROUND_LONG_NAME = "reflected background: the radiance of the scene's other surfaces " \
    "reflected by the surface seen"
#: Output layers of the surface–atmosphere coupling (:mod:`radscene.render.coupling`),
#: summed into the radiance after the terms.
COUPLING_TERMS = ("multiple_reflection", "diffuse_transmitted", "adjacency")
COUPLING_LONG_NAMES = {
    "multiple_reflection": "surface radiance from light reflected between the ground and "
                           "the atmosphere",
    "diffuse_transmitted": "the surface's own radiance scattered on its way to the sensor "
                           "(diffuse upward transmittance, uniform surroundings)",
    "adjacency": "adjacency effect: the surroundings' radiance through the atmospheric "
                 "point-spread function, minus the uniform-surroundings part",
}
#: Every layer of a band render that sums to its ``radiance``, in the order they are summed:
#: the signature terms, the reflected background, the coupling layers and the layers of
#: semi-transparent sheets and volumes (:data:`radscene.render.volumes.VOLUME_TERMS`). A render
#: lacks those its scene does not make (no ``transmitted`` without a sheet or volume); the
#: hyperspectral term cubes, the ``all`` GeoTIFF level and the terms quicklook take their
#: layers from here.
TERM_LAYERS = TERMS + (BACKGROUND_TERM,) + COUPLING_TERMS + VOLUME_TERMS
#: The parts of ``sky_reflected`` and ``background_reflected`` by the light's origin
#: (:data:`PART_LAYERS`, :mod:`radscene.render.sky_split`): each pair sums to its layer. Not in
#: :data:`TERM_LAYERS`, which would count them twice; a band render writes them beside it.
PART_LONG_NAMES = {
    "sky_reflected_solar": "reflected sky radiance: the sky's scattered sunlight",
    "sky_reflected_thermal": "reflected sky radiance: the sky's own emission",
    "background_reflected_solar": "reflected background: the other surfaces' sunlight",
    "background_reflected_thermal": "reflected background: the other surfaces' self-emitted "
                                    "radiance",
}
#: Bands whose response centre is at or beyond this wavelength get a brightness temperature [um].
THERMAL_BAND_START = 2.5
#: Per-pixel geolocation stored as CF auxiliary coordinates of the image.
GEOLOCATION_COORDS = ("latitude", "longitude", "height")
#: Angle maps stored as scalars when they are one value over the image [deg].
CONSTANT_ANGLES = ("sun_zenith", "sun_azimuth", "view_zenith", "view_azimuth")


def dataset(scene, setup, bands, shape, sums, transmittance, truth_sum, object_id, material_id,
            normal_map, sun, elapsed, pool=None, brightness=None,
            pixel_coords=None, radiance=None) -> xr.Dataset:
    """The render's Dataset; ``pool``, an executor, may take the brightness temperatures.

    ``sums`` holds each layer (band, pixel) [W m-2 sr-1] by name, ``transmittance`` (band,
    pixel) and ``truth_sum`` (:data:`~radscene.render.truth.TRUTH_SUMS`) the weighted sums
    of the path transmittance and the truth, divided in place by the surface samples' weight;
    ``elapsed`` [s] the render's time. ``brightness`` (band, pixel), when given, holds the
    brightness temperatures [K] already for the thermal bands; ``pixel_coords`` the
    observer's pixel coordinates (:func:`pixel_coordinates`); ``radiance`` (band, pixel) the
    terms' sum, when the render made it.
    """
    from radscene.radiometry import band_brightness_temperature

    ny, nx = shape
    n_b = len(bands)
    cube = {name: s.reshape(n_b, ny, nx) for name, s in sums.items()}
    if radiance is not None:
        total = radiance.reshape(n_b, ny, nx)
    else:
        total = cube[TERMS[0]].copy()  # the terms summed in TERMS order, in place
        for name in TERMS[1:] + (BACKGROUND_TERM,) + COUPLING_TERMS:
            total += cube[name]
    thermal = [b for b, band in enumerate(bands) if band.response.center >= THERMAL_BAND_START]
    if brightness is not None:
        thermal = []  # done during the render
    if pool is not None:  # while the rest is assembled here
        bt_jobs = {b: pool.submit(band_brightness_temperature, total[b], bands[b].response)
                   for b in thermal}
    mean = truth.means(truth_sum, shape)
    hw = truth_sum["hit_weight"]
    tau_map = transmittance.reshape(n_b, ny, nx)
    seen = (hw > 0).reshape(ny, nx)
    np.divide(tau_map, hw.reshape(ny, nx), out=tau_map, where=seen)
    tau_map[:, ~seen] = np.nan
    data = _radiance_layers(total, cube)
    bt = np.full((n_b, ny, nx), np.nan) if brightness is None else brightness.reshape(n_b, ny, nx)
    for b in thermal:
        bt[b] = (bt_jobs[b].result() if pool is not None
                 else band_brightness_temperature(total[b], bands[b].response))
    data["brightness_temperature"] = (("band", "y", "x"), bt, {
        "units": "K", "long_name": "band brightness temperature of the total radiance",
        "comment": f"computed for bands centred at or beyond {THERMAL_BAND_START} um; NaN elsewhere"})
    data["path_transmittance"] = (("band", "y", "x"), tau_map, {
        "units": "1", "long_name": "response-weighted target-to-sensor transmittance"})
    data.update(truth.maps(scene, shape, object_id, material_id, normal_map, mean))
    coords = _band_coordinates(bands)
    coords.update(pixel_coordinates(setup, shape) if pixel_coords is None else pixel_coords)
    ds = xr.Dataset(data, coords=coords)
    ds.attrs = _attributes(scene, setup, sun, elapsed)
    return ds


def _radiance_layers(total, cube) -> dict:
    """The radiance and each layer of it, (band, y, x), as Dataset variables."""
    radiance_attrs = {"units": "W m-2 sr-1"}
    data = {
        "radiance": (("band", "y", "x"), total, {
            **radiance_attrs, "long_name": "at-aperture band radiance, sum of the signature terms",
        }),
    }
    for name in TERMS:
        data[name] = (("band", "y", "x"), cube[name],
                      {**radiance_attrs, "long_name": TERM_LONG_NAMES[name]})
    data[BACKGROUND_TERM] = (("band", "y", "x"), cube[BACKGROUND_TERM],
                             {**radiance_attrs, "long_name": BACKGROUND_LONG_NAME})
    for name in COUPLING_TERMS:
        data[name] = (("band", "y", "x"), cube[name],
                      {**radiance_attrs, "long_name": COUPLING_LONG_NAMES[name]})
    for name in (n for n in PART_NAMES if n in cube):
        data[name] = (("band", "y", "x"), cube[name], {
            **radiance_attrs, "long_name": PART_LONG_NAMES[name],
            "comment": PART_COMMENTS[name]})
    return data


def finest_layers(names) -> list[str]:
    """The layers of :data:`TERM_LAYERS` among ``names`` (in that order), each with parts
    (:data:`PART_LAYERS`) replaced by them where ``names`` holds them all: a set of layers
    that still sums to the radiance, each term of seed 001 eq. 1 apart."""
    names = set(names)
    out = []
    for name in (n for n in TERM_LAYERS if n in names):
        parts = PART_LAYERS.get(name, ())
        out.extend(parts if parts and names.issuperset(parts) else (name,))
    return out


def _band_coordinates(bands) -> dict:
    """The band axis's coordinates: names, response centres and limits [um], and the
    surface-normal vector axis."""
    return {
        "band": ("band", [b.name for b in bands]),
        "wavelength_center": ("band", [float(b.response.center) for b in bands],
                              {"units": "um", "long_name": "response centre wavelength"}),
        "wavelength_min": ("band", [float(b.response.support[0]) for b in bands], {"units": "um"}),
        "wavelength_max": ("band", [float(b.response.support[1]) for b in bands], {"units": "um"}),
        "equivalent_width": ("band", [float(b.response.equivalent_width()) for b in bands],
                             {"units": "um", "long_name": "integral of the response"}),
        "vector": ("vector", ["east", "north", "up"]),
    }


def _attributes(scene, setup, sun, elapsed) -> dict:
    """The render Dataset's global attributes (CF, provenance, sun and settings)."""
    from radscene import __version__

    return {
        "Conventions": "CF-1.10",
        "title": f"radscene render of {scene.name!r}, observer {setup.name!r}",
        "source": f"radscene {__version__}",
        "history": f"{_dt.datetime.now(_dt.UTC).isoformat(timespec='seconds')} rendered by radscene {__version__}",
        "scene": scene.name,
        "observer": setup.name,
        "observer_type": setup.kind,
        "time": scene.time.astimezone(_dt.UTC).isoformat() if scene.time else "",
        "sun_zenith_deg": sun.zenith,
        "sun_azimuth_deg": sun.azimuth,
        "earth_sun_distance_au": sun.distance,
        "solar_spectrum": solar_spectrum(scene.atmosphere),
        "atmosphere": scene.atmosphere.name,
        "latitude_deg": scene.location.latitude,
        "longitude_deg": scene.location.longitude,
        "supersample": setup.supersample,
        "sky_samples": scene.settings.sky_samples,
        "background_bounces": scene.settings.background_bounces,
        "background_samples": scene.settings.background_samples,
        "render_seconds": round(elapsed, 3),
        "band_radiance_definition": "integral of S(lambda) L(lambda) d lambda with the band "
                                    "response S (peak 1 for rectangular and Gaussian bands)",
    }


def sky_view_transmitted(sky_open, hit_weight, shape):
    """The ``sky_view_transmitted`` variable (band, y, x) of a render whose sky rays cross
    volumes or sheets: ``sky_open``, the weighted per-pixel sums (band, pixel), divided in
    place by the weight of each pixel's surface samples ``hit_weight``; NaN where it has
    none."""
    ny, nx = shape
    seen = hit_weight > 0.0
    sky_open[:, seen] /= hit_weight[seen]
    sky_open[:, ~seen] = np.nan
    return (("band", "y", "x"), sky_open.reshape(len(sky_open), ny, nx), {
        "units": "1", "long_name": "cosine-weighted fraction of the hemisphere that sees "
        "sky, each direction weighted by the band transmittance of the volumes and sheets "
        "along it"})


def cf_conventions(ds: xr.Dataset, scene) -> xr.Dataset:
    """A render's Dataset in CF form: latitude, longitude and height as auxiliary coordinates
    (each image variable's ``coordinates`` on writing); an angle map that holds one value
    (within 1e-9 deg) where the image sees the scene as a scalar; a map product (``x``/``y``
    in metres of the scene frame) with the ``crs`` grid-mapping variable of the frame's
    projection (rioxarray: ``ds.rio.crs``)."""
    ds = ds.set_coords([n for n in GEOLOCATION_COORDS if n in ds.data_vars])
    for name in CONSTANT_ANGLES:
        if name not in ds.data_vars or ds[name].ndim == 0:
            continue
        values = ds[name].values
        seen = values[np.isfinite(values)]
        if seen.size and float(seen.max() - seen.min()) <= 1e-9:
            ds[name] = ((), float(seen[0]), {**ds[name].attrs, "comment": "one value over the image"})
    if "x" in ds.coords and ds["x"].attrs.get("units") == "m":
        from radscene.platform.geolocation import LocalFrame

        loc = scene.location
        crs = LocalFrame(loc.latitude, loc.longitude, loc.altitude).crs()
        ds = ds.assign_coords(crs=((), 0, grid_mapping_attrs(crs, ds["x"].values,
                                                             ds["y"].values)))
        for var in ds.data_vars.values():
            if "x" in var.dims and "y" in var.dims:
                var.encoding["grid_mapping"] = "crs"
    return ds


def grid_mapping_attrs(crs, x, y) -> dict:
    """The attributes of a map product's grid-mapping variable, as rioxarray writes them: the
    CF grid mapping of ``crs``, its WKT (``crs_wkt``, ``spatial_ref``) and the GDAL
    ``GeoTransform`` of the pixel centres ``x``, ``y`` [m] (regular, as a map's are).

    Made on a scalar stand-in rather than through the render's own ``.rio`` accessor, whose
    ``write_crs`` deep-copies every layer and whose cached accessor keeps each render alive
    until a garbage collection (the render benchmark took 4.0 s instead of 1.8 s)."""
    import rioxarray  # noqa: F401  (the .rio accessor)
    from affine import Affine

    dx = float(x[1] - x[0]) if len(x) > 1 else 1.0
    dy = float(y[1] - y[0]) if len(y) > 1 else -1.0
    transform = Affine(dx, 0.0, float(x[0]) - dx / 2, 0.0, dy, float(y[0]) - dy / 2)
    stand_in = xr.DataArray(0).rio.write_crs(crs).rio.write_transform(transform)
    return dict(stand_in["spatial_ref"].attrs)


def pixel_coordinates(setup, shape) -> dict:
    """The image's ``x`` and ``y`` coordinates: eastings and northings [m] in the scene frame
    for a nadir orthographic map, else pixel columns and rows."""
    ny, nx = shape
    if setup.kind == "orthographic" and getattr(setup.camera, "zenith", 0.0) == 0.0:
        xs, ys = setup.camera.map_axes()
        return {"x": ("x", xs, {"units": "m", "long_name": "easting in the scene frame"}),
                "y": ("y", ys, {"units": "m", "long_name": "northing in the scene frame"})}
    return {"x": ("x", np.arange(nx), {"long_name": "pixel column"}),
            "y": ("y", np.arange(ny), {"long_name": "pixel row"})}
