"""A scene's atmosphere chooses the solar spectrum; the renderer's sun follows it."""

from __future__ import annotations

import numpy as np
import pytest

from radscene import load_scene, render
from radscene.sun import toa_solar_irradiance

DATABASE = {"type": "database", "profile": "us_standard", "aerosol": "rural",
            "visibility": "23 km"}
BANDS = [{"name": "blue", "min": 0.44, "max": 0.46}, {"name": "swir", "min": 1.55, "max": 1.65}]


def _render(make_plate_scene, **atmosphere):
    scene = make_plate_scene({"reflectance": 0.3}, {**DATABASE, **atmosphere}, BANDS,
                             sky_samples=16, coupling=False)
    scene["objects"][0]["shape"] = {"type": "plate", "width": 2_000, "length": 2_000}
    scene["observers"][0].update(altitude=700_000.0, gsd=100.0, shape=[4, 4])
    return render(load_scene(scene))


def test_tsis1_scales_the_sun_and_the_path_by_its_band_irradiance(make_plate_scene):
    ours = _render(make_plate_scene)
    theirs = _render(make_plate_scene, solar_spectrum="tsis1")
    assert ours.attrs["solar_spectrum"] == "radscene"
    assert theirs.attrs["solar_spectrum"] == "tsis1"
    for b, band in enumerate(BANDS):
        wl = np.linspace(band["min"], band["max"], 2001)
        expected = (np.trapezoid(toa_solar_irradiance(wl, spectrum="tsis1"), wl)
                    / np.trapezoid(toa_solar_irradiance(wl), wl))
        for term in ("sun_diffuse", "path_radiance"):
            ratio = float(theirs[term].isel(band=b).mean() / ours[term].isel(band=b).mean())
            # the sun's transmittance varies across the band: the ratio of the band means
            # of the two spectra holds to a fraction of a per cent
            assert ratio == pytest.approx(expected, rel=3e-3), (band["name"], term)
        assert abs(expected - 1.0) > 0.01  # the two spectra do differ here
