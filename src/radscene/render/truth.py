"""The truth maps of a render: what each pixel sees, beside its radiance.

Per-pixel means of the hits' geometry (cos θ_i, shadow, sky view, temperature, range),
weighted like the radiance; the object, material and normal of the sub-sample nearest each
pixel centre; and the geolocation of the surface seen (``docs/outputs.md``).
"""

from __future__ import annotations

import numpy as np

__all__ = ["TRUTH_SUMS", "means", "maps", "geolocation", "central_subsample",
           "central_subsamples"]

#: Per-pixel sums kept for the truth maps (the last is the weight of surface samples).
TRUTH_SUMS = ("cos_incidence", "shadow", "sky_view", "temperature", "range", "hit_weight")


def means(truth_sum, shape) -> dict:
    """The truth maps (y, x) of the weighted sums ``truth_sum`` (:data:`TRUTH_SUMS`, per
    pixel), divided in place by the weight of each pixel's surface samples; NaN where it
    has none."""
    ny, nx = shape
    hw = truth_sum["hit_weight"]
    seen = hw > 0
    # the render's sums become the maps in place (no second array of each)
    out = {}
    for k, v in truth_sum.items():
        if k != "hit_weight":
            np.divide(v, hw, out=v, where=seen)
            v[~seen] = np.nan
            out[k] = v.reshape(ny, nx)
    return out


def maps(scene, shape, object_id, material_id, normal_map, mean) -> dict:
    """The truth variables of a render's Dataset: ids, range, normal and the means of
    :func:`means`, as (dims, values, attributes)."""
    ny, nx = shape
    return {
        "object_id": (("y", "x"), object_id.reshape(ny, nx), {
            "long_name": "object index (-1: no object)",
            "flag_values": np.array([*range(len(scene.objects)), -1], dtype=np.int32),
            "flag_meanings": " ".join([*(o.name.replace(" ", "_") for o in scene.objects), "no_object"])}),
        "material_id": (("y", "x"), material_id.reshape(ny, nx), {
            "long_name": "material index (-1: no material)",
            "flag_values": np.array([*range(len(scene.materials)), -1], dtype=np.int32),
            "flag_meanings": " ".join([*(m.replace(" ", "_") for m in scene.material_names), "no_material"])}),
        "range": (("y", "x"), mean["range"], {"units": "m", "long_name": "distance from the observer to the surface"}),
        "surface_normal": (("vector", "y", "x"), normal_map.reshape(3, ny, nx), {
            "units": "1", "long_name": "unit surface normal facing the observer (east, north, up)"}),
        "cos_incidence": (("y", "x"), mean["cos_incidence"], {
            "units": "1", "long_name": "cosine of the sun's angle of incidence (negative: facing away)"}),
        "shadow_fraction": (("y", "x"), mean["shadow"], {
            "units": "1", "long_name": "fraction of the pixel not directly sunlit (cast or self shadow)"}),
        "sky_view_fraction": (("y", "x"), mean["sky_view"], {
            "units": "1", "long_name": "cosine-weighted fraction of the hemisphere that sees sky"}),
        "surface_temperature": (("y", "x"), mean["temperature"], {
            "units": "K", "standard_name": "surface_temperature", "long_name": "surface temperature"}),
    }


def geolocation(scene, hits, rays, labelled, track, kept=None) -> dict:
    """Per-pixel geodetic position and view/sun angles of the surface each pixel sees, from
    the ``labelled`` hits (one per pixel); the sun is ``track``'s at each one's time.

    ``kept``, where given, is what an observer's frame cache keeps
    (:mod:`radscene.render.frame_cache`): its ``fresh`` ray samples are those traced again by
    this frame; the geodetic position and view angles of the pixels none of whose samples
    were are the last frame's (``kept.geodetic``, written here), the same numbers.
    """
    from radscene.platform.geolocation import LocalFrame

    ny, nx = rays.shape
    loc = scene.location
    frame = LocalFrame(loc.latitude, loc.longitude, loc.altitude)
    pick = slice(None) if labelled.all() else labelled
    last = None if kept is None else getattr(kept, "geodetic", None)
    mine = True  # the samples whose pixels are worked out
    if last is not None:
        redo = np.zeros(ny * nx, dtype=bool)
        redo[rays.pixel[kept.fresh]] = True
        mine = redo[rays.pixel]
    sel = labelled if last is None else labelled & mine
    position, direction, pixel = hits.position[sel], rays.directions[sel], rays.pixel[sel]
    if int(np.max(rays.subsample)) > 0:
        # an even k×k grid has no sub-sample at the pixel's centre: the mean of the middle 2×2
        # (those that hit) is there on a plane; an odd grid's centre sample is its own mean
        middle = np.flatnonzero(central_subsamples(rays) & hits.hit & mine)
        pixel, inverse, count = np.unique(rays.pixel[middle], return_inverse=True, return_counts=True)
        inverse = inverse.ravel()
        position = np.stack([np.bincount(inverse, hits.position[middle, a], len(pixel))
                             for a in range(3)], axis=1).astype(float) / count[:, None]
        direction = np.stack([np.bincount(inverse, rays.directions[middle, a], len(pixel))
                              for a in range(3)], axis=1).astype(float)
        direction /= np.linalg.norm(direction, axis=1, keepdims=True)
    geodetic = frame.pixel_geolocation(position, direction, pixel, ny * nx)
    if last is not None:
        geodetic = np.where(redo, geodetic, last)
    if kept is not None:  # a copy: the Dataset's maps may be changed by whoever gets them
        kept.geodetic = geodetic.copy()
    lat, lon, height, vz, va = geodetic.reshape(5, ny, nx)
    hit = np.isfinite(lat)
    sun_zenith, sun_azimuth = np.full((2, ny * nx), np.nan)
    zen, azi = track.angles(rays.time[pick] if track.moving else None)
    sun_zenith[rays.pixel[pick]], sun_azimuth[rays.pixel[pick]] = zen, azi
    sun_zenith = np.where(hit, sun_zenith.reshape(ny, nx), np.nan)
    sun_azimuth = np.where(hit, sun_azimuth.reshape(ny, nx), np.nan)
    deg = {"units": "degree"}
    return {
        "latitude": (("y", "x"), lat, {"units": "degrees_north", "standard_name": "latitude",
                                        "long_name": "WGS84 latitude of the surface seen"}),
        "longitude": (("y", "x"), lon, {"units": "degrees_east", "standard_name": "longitude",
                                         "long_name": "WGS84 longitude of the surface seen"}),
        "height": (("y", "x"), height, {"units": "m", "long_name": "height above the WGS84 ellipsoid"}),
        "view_zenith": (("y", "x"), vz, {**deg, "long_name": "zenith angle of the direction from "
                                         "the surface to the sensor (scene frame)"}),
        "view_azimuth": (("y", "x"), va, {**deg, "long_name": "azimuth of that direction, "
                                          "clockwise from north (scene frame)"}),
        "sun_zenith": (("y", "x"), sun_zenith,
                       {**deg, "long_name": "solar zenith angle at the pixel's acquisition "
                        "time (scene origin; the parallax across a scene is negligible)"}),
        "sun_azimuth": (("y", "x"), sun_azimuth,
                        {**deg, "long_name": "solar azimuth, clockwise from north, at the "
                         "pixel's acquisition time"}),
    }


def central_subsamples(rays) -> np.ndarray:
    """True for the sub-samples of each pixel symmetric about its centre: the centre one of an
    odd k×k grid, the middle 2×2 of an even one (whose mean position is the centre)."""
    k2 = int(np.max(rays.subsample)) + 1
    k = int(round(np.sqrt(k2)))
    if k % 2:
        return rays.subsample == (k // 2) * k + (k // 2)
    row, col = np.divmod(rays.subsample, k)
    return (np.abs(row - (k - 1) / 2.0) < 1.0) & (np.abs(col - (k - 1) / 2.0) < 1.0)


def central_subsample(rays) -> np.ndarray:
    """True for the sub-sample of each pixel whose index is the centre of the k×k grid."""
    k2 = int(np.max(rays.subsample)) + 1
    k = int(round(np.sqrt(k2)))
    centre = (k // 2) * k + (k // 2)
    return rays.subsample == centre
