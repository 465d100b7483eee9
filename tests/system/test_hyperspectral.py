"""Hyperspectral mode against band mode: the cube integrated with a band's response equals that
band rendered in band mode.

The statement (radscene.radiometry.channels): for a response S linear between the grid's
centres and zero outside the grid, Σ_c S(λ_c) fwhm_c L_c = ∫ S L dλ exactly, because every
signature term is linear in the response. The scene has what makes per-pixel values differ —
two materials (one specular), a box that casts a shadow and hides part of the sky, two
temperatures, tabulated spectra with kinks between the grid's centres, a specular reflectance
that is zero in part of a grid — and the cube is rendered in several passes, so the passes
must share rays and random numbers.
"""

from __future__ import annotations

import numpy as np
import pytest

import radscene
from radscene.render.hyperspectral import band_radiance

#: Float32 storage of the cube (seven significant digits) and the quadratures' rounding.
REL = 1e-6

ATMOSPHERE = {
    "type": "uniform",
    "transmittance": {"wavelength": [0.4, 0.553, 0.61, 0.9, 3.0, 8.0, 9.63, 10.0, 13.0],
                      "values": [0.70, 0.80, 0.74, 0.90, 0.75, 0.80, 0.55, 0.88, 0.70]},
    "sun_transmittance": {"wavelength": [0.4, 0.58, 2.0, 14.0], "values": [0.8, 0.9, 0.92, 0.9]},
    "path_radiance": {"wavelength": [0.4, 0.637, 1.0, 5.0, 9.1, 14.0],
                      "values": [30.0, 18.0, 5.0, 0.5, 1.3, 2.0]},
    "sky_radiance": {"wavelength": [0.4, 0.6, 1.0, 8.0, 14.0], "values": [40, 25, 8, 3, 4]},
    "sky_zenith": [0, 60, 85], "sky_profile": [1.0, 1.3, 2.0],
}
#: Band responses with knots on the grids (0.50-0.70 um every 10 nm, 8-12 um every 0.25 um),
#: zero beyond the grids; each is nonzero at one end of its grid (a half-width end channel).
VIS = ([0.50, 0.53, 0.56, 0.60, 0.61, 0.66], [0.4, 0.3, 1.0, 0.8, 0.9, 0.0])
LWIR = ([8.25, 8.5, 9.5, 10.75, 11.5, 12.0], [0.0, 0.6, 1.0, 0.7, 0.4, 0.5])


#: The shipped database, without the surface–atmosphere coupling (whose layers combine band
#: means non-linearly; docs/hyperspectral.md).
DATABASE = {"type": "database", "profile": "midlatitude_summer", "aerosol": "rural",
            "visibility": "23 km"}


def _scene(tmp_path, supersample, atmosphere=None, background=0):
    for name, (wl, s) in (("vis", VIS), ("lwir", LWIR)):
        np.savetxt(tmp_path / f"{name}.csv", np.c_[wl, s], delimiter=",")
    camera = {"type": "orthographic", "center": [0, 0], "gsd": 2.0, "shape": [20, 20],
              "altitude": 1000, "supersample": supersample}
    spec = {
        "name": "hyperspectral_vs_bands",
        "environment": {"sun": {"zenith": 50, "azimuth": 120},
                        "atmosphere": atmosphere or ATMOSPHERE},
        "materials": {
            "soil": {"reflectance": {"wavelength": [0.4, 0.515, 0.58, 0.655, 1.0, 8.7, 10.2, 14],
                                     "values": [0.05, 0.09, 0.20, 0.26, 0.35, 0.10, 0.03, 0.05]},
                     # specular only beyond 0.6 um: some passes hold no specular channel
                     "specular_reflectance": {"wavelength": [0.4, 0.6, 0.62, 14.0],
                                              "values": [0.0, 0.0, 0.03, 0.03]},
                     "specular_exponent": 10},
            "paint": {"reflectance": 0.25, "specular_reflectance": 0.05, "specular_exponent": 30},
        },
        "objects": [
            {"name": "ground", "shape": {"type": "plate", "width": 120, "length": 120},
             "position": [0, 0, 0], "material": "soil", "temperature": "300 K"},
            {"name": "box", "shape": {"type": "box", "size": [12, 12, 10]},
             "position": [4, -4, 0], "material": "paint", "temperature": "325 K"},
        ],
        "bands": [{"name": "vis", "file": "vis.csv"}, {"name": "lwir", "file": "lwir.csv"}],
        "observers": [
            {"name": "bands", **camera},
            {"name": "vnir", **camera, "spectral": {"min": "500 nm", "max": "700 nm",
                                                    "step": "10 nm"}},
            {"name": "tir", **camera, "spectral": {"min": 8.0, "max": 12.0, "step": 0.25}},
        ],
        # the reflected background off by default here: band mode reflects the neighbours'
        # radiance with band-mean reflectances, so it equals the integrated cube only where
        # the materials are grey within the band (test_background_..._within_its_approximation)
        "render": {"sky_samples": 9, "specular_samples": 9, "seed": 4,
                   "coupling": atmosphere is None, "background_bounces": background},
    }
    return radscene.load_scene(spec, base_dir=tmp_path)


@pytest.mark.parametrize("supersample, atmosphere", [
    (1, None), (2, None), pytest.param(1, DATABASE, marks=pytest.mark.slow)])
def test_cube_integrated_with_a_response_equals_band_mode(tmp_path, supersample, atmosphere):
    scene = _scene(tmp_path, supersample, atmosphere)
    bands = radscene.render(scene, "bands")
    # the scene is not trivial: a shadow, the box, partial sky view
    assert float(bands["shadow_fraction"].max()) > 0.5
    assert {0, 1} <= set(np.unique(bands["object_id"].values))
    assert float(bands["sky_view_fraction"].min()) < 0.9
    for observer, band, per_pass in (("vnir", "vis", 4), ("tir", "lwir", 5)):
        cube = radscene.render_hyperspectral(scene, observer, channels_per_pass=per_pass)
        assert cube["radiance"].attrs["units"] == "W m-2 sr-1 um-1"
        got = band_radiance(cube, scene.band(band).response).values
        want = bands["radiance"].sel(band=band).values
        np.testing.assert_allclose(got, want, rtol=REL, atol=0)
        # the per-pixel maps are the band render's
        np.testing.assert_array_equal(cube["object_id"].values, bands["object_id"].values)
        np.testing.assert_array_equal(cube["shadow_fraction"].values,
                                      bands["shadow_fraction"].values)


def test_with_the_reflected_background_band_mode_agrees_within_its_approximation(tmp_path):
    """With one bounce of reflected background (band mode: band-mean reflectances at the
    neighbours), the integrated cube and band mode agree within 0.1 %; measured 5.4e-4."""
    scene = _scene(tmp_path, 1, background=1)
    bands = radscene.render(scene, "bands")
    assert float(np.abs(bands["background_reflected"]).max()) > 0.0
    cube = radscene.render_hyperspectral(scene, "vnir", channels_per_pass=4)
    got = band_radiance(cube, scene.band("vis").response).values
    np.testing.assert_allclose(got, bands["radiance"].sel(band="vis").values, rtol=1e-3, atol=0)


@pytest.mark.parametrize("supersample", [1, 2])
def test_with_a_grey_volume_the_integrated_cube_equals_band_mode(tmp_path, supersample):
    """A volume grey in both bands: its transmittance is the same in every channel, its
    emission is integrated spectrally, so the cube integrates to band mode — but for the
    volume's own radiance reflected by the surfaces under it (along their sky rays), which
    band mode reflects with band-mean reflectances and τ_a, as the reflected background does:
    within 0.1 % in the LWIR, where it is not zero (measured 3.0e-4 with this non-grey soil and
    atmosphere)."""
    spec = _scene(tmp_path, supersample).spec.model_dump(mode="json")
    spec["volumes"] = [{"name": "smoke", "shape": {"type": "ellipsoid", "radii": [15, 10, 6]},
                        "position": [-5, 5, 12], "optical_depth": 0.8, "temperature": 330.0,
                        "profile": {"type": "gaussian", "sigma": 6.0}}]
    scene = radscene.load_scene(spec, base_dir=tmp_path)
    bands = radscene.render(scene, "bands")
    assert float(bands["volume_transmittance"].min()) < 0.6
    for observer, band, per_pass, rel in (("vnir", "vis", 4, REL), ("tir", "lwir", 5, 1e-3)):
        cube = radscene.render_hyperspectral(scene, observer, channels_per_pass=per_pass)
        got = band_radiance(cube, scene.band(band).response).values
        np.testing.assert_allclose(got, bands["radiance"].sel(band=band).values, rtol=rel,
                                   atol=0)


def test_passes_do_not_change_the_cube(tmp_path):
    """Also with the reflected background on: every pass draws the same directions."""
    scene = _scene(tmp_path, 1, background=1)
    one = radscene.render_hyperspectral(scene, "vnir", channels_per_pass=1)
    all_ = radscene.render_hyperspectral(scene, "vnir", channels_per_pass=len(
        scene.observer("vnir").spectral))
    np.testing.assert_array_equal(one["radiance"].values, all_["radiance"].values)


def test_channel_value_is_spectral_radiance(tmp_path):
    """A channel's value is the band radiance of its triangular response divided by its
    equivalent width (the step; half of it at the grid's ends)."""
    from radscene.radiometry import TabulatedResponse
    from radscene.render.hyperspectral import Channel

    scene = _scene(tmp_path, 1)
    cube = radscene.render_hyperspectral(scene, "vnir")
    wl = cube["wavelength"].values
    c = 15  # 0.65 um: both materials specular, as in every pass of the cube
    hat = TabulatedResponse(wl[c - 1:c + 2], [0.0, 1.0, 0.0], name="hat")
    band = radscene.render(scene, "vnir", bands=[Channel("hat", hat)])
    np.testing.assert_allclose(cube["radiance"].values[c],
                               band["radiance"].values[0] / 0.01, rtol=REL)
    assert float(cube["fwhm"][c]) == pytest.approx(0.01, rel=1e-12)
    assert float(cube["fwhm"][0]) == pytest.approx(0.005, rel=1e-12)


def test_render_of_a_spectral_observer_is_its_cube(tmp_path):
    from radscene.errors import ConfigError
    from radscene.render import render as band_render

    scene = _scene(tmp_path, 1)
    cube = radscene.render(scene, "tir")
    assert cube["radiance"].dims == ("wavelength", "y", "x")
    np.testing.assert_array_equal(
        cube["radiance"].values, radscene.render_hyperspectral(scene, "tir")["radiance"].values)
    assert set(radscene.render_all(scene)) == {"bands", "vnir", "tir"}
    with pytest.raises(ConfigError, match="'tir' records a spectral grid"):
        band_render(scene, "tir")


@pytest.mark.parametrize("bad", [0, -2, 1.5, True])
def test_channels_per_pass_must_be_a_positive_whole_number(tmp_path, bad):
    from radscene.errors import ConfigError

    scene = _scene(tmp_path, 1)
    with pytest.raises(ConfigError, match="channels_per_pass: must be a whole number >= 1"):
        radscene.render_hyperspectral(scene, "vnir", channels_per_pass=bad)


#: Layers that band mode integrates exactly as the cube does (docs/hyperspectral.md, "What
#: equals what"): to float32 storage of the cube.
EXACT_TERMS = ("sun_diffuse", "sun_specular", "thermal_emission", "sky_reflected",
               "path_radiance")
#: Layers band mode makes with band means instead (docs/hyperspectral.md): their difference
#: from the integrated cube, as a fraction of the pixel's radiance.
APPROXIMATE_TERMS = {"background_reflected": 2e-3, "multiple_reflection": 2e-3,
                     "diffuse_transmitted": 2e-3, "adjacency": 2e-3, "transmitted": 1e-3,
                     "volume_emission": 1e-3, "volume_scattered": 1e-3,
                     # under a volume: its own radiance along the surfaces' sky rays
                     "sky_reflected": 1e-3}
#: float32 machine epsilon: each stored term and the stored radiance are within half of it.
EPS32 = float(np.finfo(np.float32).eps)


def _check_terms(scene, bands, observer, band, per_pass, approximate=()):
    """The cube's terms sum to its radiance to float32 rounding, and each integrated with the
    band's response is band mode's layer of the same name (exactly but for the layers
    ``approximate`` and those band mode makes with band means)."""
    from radscene.render.hyperspectral import TERM_LAYERS
    from radscene.render.outputs import PART_LAYERS

    cube = radscene.render_hyperspectral(scene, observer, channels_per_pass=per_pass,
                                         terms=True)
    names = [n for n in TERM_LAYERS if n in cube.data_vars]
    assert names == [n for n in TERM_LAYERS if n in bands.data_vars]
    for name in names:
        assert cube[name].dims == ("wavelength", "y", "x") and cube[name].dtype == np.float32
        assert cube[name].attrs["units"] == "W m-2 sr-1 um-1"
    # Σ terms − radiance: each float32 value within eps/2 of its float64 value
    total = sum(cube[n].values.astype(float) for n in names)
    size = sum(np.abs(cube[n].values.astype(float)) for n in names)
    np.testing.assert_array_less(np.abs(total - cube["radiance"].values),
                                 EPS32 * size + 1e-30)
    for layer, parts in PART_LAYERS.items():  # the parts by origin, beside their layer
        assert all(p in cube.data_vars for p in parts)
        pair = sum(cube[p].values.astype(float) for p in parts)
        np.testing.assert_array_less(np.abs(pair - cube[layer].values),
                                     EPS32 * (np.abs(pair) + np.abs(cube[layer].values)) + 1e-30)
    response = scene.band(band).response
    radiance = bands["radiance"].sel(band=band).values
    for name in names:
        got = band_radiance(cube, response, name).values
        want = bands[name].sel(band=band).values
        if name in EXACT_TERMS and name not in approximate:
            np.testing.assert_allclose(got, want, rtol=REL, atol=0, err_msg=name)
        else:
            np.testing.assert_array_less(np.abs(got - want),
                                         APPROXIMATE_TERMS[name] * radiance + 1e-30,
                                         err_msg=name)
    return cube


def test_each_term_is_a_spectral_layer_and_the_layers_sum_to_the_radiance(tmp_path):
    """Visible and thermal grids, several passes, with the reflected background: the terms sum
    to the radiance (measured 0.84 eps32 of Σ|term|); the five signature terms integrate to
    band mode's within 2.4e-8, the reflected background within 5.4e-4 (visible) and 1.2e-3
    (LWIR) of the radiance."""
    scene = _scene(tmp_path, 1, background=1)
    bands = radscene.render(scene, "bands")
    for observer, band, per_pass in (("vnir", "vis", 4), ("tir", "lwir", 5)):
        cube = _check_terms(scene, bands, observer, band, per_pass)
        assert float(np.abs(cube["background_reflected"]).max()) > 0.0
        assert float(np.abs(cube["sun_diffuse" if band == "vis" else "thermal_emission"]
                            ).max()) > 0.0
    # the default keeps the radiance alone, the same radiance
    plain = radscene.render_hyperspectral(scene, "vnir", channels_per_pass=4)
    assert "sun_diffuse" not in plain.data_vars
    with_terms = radscene.render_hyperspectral(scene, "vnir", channels_per_pass=7, terms=True)
    np.testing.assert_array_equal(plain["radiance"].values, with_terms["radiance"].values)


def test_volume_terms_are_spectral_layers_too(tmp_path):
    """A grey volume adds transmitted, volume_emission and volume_scattered; in the LWIR the
    transmitted layer and the sky reflected under the volume integrate to band mode's within
    1e-3 of the radiance (measured 2.9e-4 and 3.0e-4), the volume's emission within 3e-8."""
    spec = _scene(tmp_path, 1).spec.model_dump(mode="json")
    spec["volumes"] = [{"name": "smoke", "shape": {"type": "ellipsoid", "radii": [15, 10, 6]},
                        "position": [-5, 5, 12], "optical_depth": 0.8, "temperature": 330.0,
                        "profile": {"type": "gaussian", "sigma": 6.0}}]
    scene = radscene.load_scene(spec, base_dir=tmp_path)
    bands = radscene.render(scene, "bands")
    cube = _check_terms(scene, bands, "tir", "lwir", 5, approximate=("sky_reflected",))
    assert float(cube["volume_emission"].max()) > 0.0
    assert float(cube["transmitted"].max()) > 0.0


@pytest.mark.slow
def test_coupling_terms_are_spectral_layers_within_their_approximation(tmp_path):
    """The shipped database with the surface–atmosphere coupling: its three layers integrate
    to band mode's within 2e-3 of the radiance (measured: multiple_reflection 7.1e-4,
    diffuse_transmitted 1.4e-3; the signature terms still within 3.6e-8)."""
    spec = _scene(tmp_path, 1, DATABASE).spec.model_dump(mode="json")
    spec["render"]["coupling"] = True
    scene = radscene.load_scene(spec, base_dir=tmp_path)
    bands = radscene.render(scene, "bands")
    cube = _check_terms(scene, bands, "vnir", "vis", 4)
    assert float(np.abs(cube["multiple_reflection"]).max()) > 0.0


def test_terms_shrink_the_pass(tmp_path):
    from radscene.render.hyperspectral import (
        LAYERS_PER_CHANNEL,
        PASS_MEMORY,
        SPECTRAL_TERMS,
        pass_size,
        render_passes,
    )

    scene = _scene(tmp_path, 1)
    grid = scene.observer("vnir").spectral
    pixels = 1024 * 1024
    assert pass_size(grid, pixels) == int(PASS_MEMORY // (LAYERS_PER_CHANNEL * 8 * pixels)) == 11
    assert pass_size(grid, pixels, terms=True) == int(
        PASS_MEMORY // ((LAYERS_PER_CHANNEL + len(SPECTRAL_TERMS)) * 8 * pixels)) == 5
    # the render's passes: 400 samples, a memory of 5 channels without terms
    memory = 5 * LAYERS_PER_CHANNEL * 8 * 400
    plain = [p.sizes["wavelength"] for p in render_passes(scene, "vnir", memory=memory)]
    terms = [p.sizes["wavelength"] for p in render_passes(scene, "vnir", memory=memory,
                                                            terms=True)]
    assert plain[0] == 5 and terms[0] == 2
    assert sum(plain) == sum(terms) == len(grid)


@pytest.mark.parametrize("name", ["cube.nc", "cube.zarr"])
def test_a_file_written_in_passes_is_the_file_written_at_once(tmp_path, name):
    from radscene.io import read_netcdf, read_zarr, write_spectral
    from radscene.render.hyperspectral import render_passes

    if name.endswith(".zarr"):
        pytest.importorskip("zarr")
    read = read_zarr if name.endswith(".zarr") else read_netcdf
    scene = _scene(tmp_path, 1)
    grid = scene.observer("tir").spectral
    files = {}
    for per_pass in (3, len(grid)):
        out = tmp_path / str(per_pass)
        out.mkdir()
        write_spectral(render_passes(scene, "tir", channels_per_pass=per_pass, terms=True),
                       out / name, grid, envi=out / "cube.img")
        files[per_pass] = read(out / name)
    several, one = files[3], files[len(grid)]
    assert set(several.data_vars) == set(one.data_vars)
    assert {"radiance", "sun_diffuse", "thermal_emission", "path_radiance",
            "background_reflected"} <= set(one.data_vars)
    for var in several.data_vars:
        np.testing.assert_array_equal(several[var].values, one[var].values, err_msg=var)
        if "wavelength" in one[var].dims:
            assert one[var].dtype == np.float32 and one[var].dims == ("wavelength", "y", "x")
    # the ENVI image is the radiance alone
    image = np.fromfile(tmp_path / "3" / "cube.img", dtype="<f4")
    np.testing.assert_array_equal(image.reshape(one["radiance"].shape), one["radiance"].values)
    # and terms=False leaves them out of the file
    write_spectral(render_passes(scene, "tir", terms=True), tmp_path / f"plain_{name}", grid,
                   terms=False)
    assert "thermal_emission" not in read(tmp_path / f"plain_{name}").data_vars


def test_asking_for_terms_the_passes_lack_is_refused(tmp_path):
    from radscene.errors import ConfigError
    from radscene.io import write_spectral
    from radscene.render.hyperspectral import render_passes

    scene = _scene(tmp_path, 1)
    grid = scene.observer("tir").spectral
    with pytest.raises(ConfigError, match="terms: the passes carry no term layers"):
        write_spectral(render_passes(scene, "tir"), tmp_path / "c.nc", grid, terms=True)
    assert not (tmp_path / "c.nc").exists()
    cube = radscene.render_hyperspectral(scene, "tir")
    with pytest.raises(ConfigError, match="variable: the cube has no spectral variable "
                                          "'sun_diffuse'; it has radiance"):
        band_radiance(cube, scene.band("lwir").response, "sun_diffuse")


def _resolved(tmp_path, band, grid, background=1, volume=False, atmosphere=None):
    """The test scene with ``render.spectral_grid`` = the ``grid`` observer's, its band observer
    rendering ``band`` alone: (scene resolved, scene with band means)."""
    spec = _scene(tmp_path, 1, atmosphere, background=background).spec.model_dump(mode="json")
    spec["observers"][0]["bands"] = [band]
    if volume:
        spec["volumes"] = [{"name": "smoke", "shape": {"type": "ellipsoid", "radii": [15, 10, 6]},
                            "position": [-5, 5, 12], "optical_depth": 0.8, "temperature": 330.0,
                            "profile": {"type": "gaussian", "sigma": 6.0}}]
    if atmosphere is not None:
        spec["render"]["coupling"] = True
    plain = radscene.load_scene(spec, base_dir=tmp_path)
    observer = next(o for o in spec["observers"] if o["name"] == grid)
    spec["render"]["spectral_grid"] = {k: observer["spectral"][k] for k in ("min", "max", "step")}
    return radscene.load_scene(spec, base_dir=tmp_path), plain


def _check_resolved(scene, plain, band, grid, per_pass, layers):
    """The resolved band render equals the cube integrated with the band's response, layer by
    layer, within REL (the cube in float64); the band-mean render does not, in ``layers``."""
    resolved = radscene.render(scene, "bands")
    means = radscene.render(plain, "bands")
    cube = radscene.render_hyperspectral(scene, grid, channels_per_pass=per_pass, terms=True,
                                         dtype=np.float64)
    response = scene.band(band).response
    radiance = resolved["radiance"].sel(band=band).values
    for name in ["radiance"] + [n for n in cube.data_vars if n in resolved.data_vars
                                and "wavelength" in cube[n].dims]:
        got = band_radiance(cube, response, name).values
        np.testing.assert_allclose(resolved[name].sel(band=band).values, got, rtol=REL,
                                   atol=1e-12 * float(np.abs(radiance).max()), err_msg=name)
    for name in layers:  # where the band means differed
        off = np.abs(means[name].sel(band=band).values - resolved[name].sel(band=band).values)
        assert float((off / radiance).max()) > 1e-5, name
    assert "resolved on channels" in resolved.attrs["spectral_grid"]
    if band == "lwir":  # the brightness temperature follows the resolved radiance
        from radscene.radiometry import band_brightness_temperature

        np.testing.assert_allclose(resolved["brightness_temperature"].sel(band=band).values,
                                   band_brightness_temperature(radiance, response), rtol=1e-12)
    return resolved


def test_a_resolved_band_render_equals_the_integrated_cube_with_the_background(tmp_path):
    """render.spectral_grid: the reflected background (non-linear in the response) resolved on
    the grid, so the band render equals the integrated cube in every layer within 1e-6 (the
    band means were up to 5.4e-4 apart)."""
    scene, plain = _resolved(tmp_path, "vis", "vnir")
    out = _check_resolved(scene, plain, "vis", "vnir", 7, ["background_reflected"])
    assert float(np.abs(out["background_reflected"]).max()) > 0.0


def test_a_resolved_band_render_equals_the_integrated_cube_under_a_volume(tmp_path):
    """With a volume every layer is resolved (its band-mean transmittance dims them all): the
    LWIR band render equals the integrated cube within 1e-6, background and volume included."""
    scene, plain = _resolved(tmp_path, "lwir", "tir", volume=True)
    _check_resolved(scene, plain, "lwir", "tir", 6, ["sky_reflected", "transmitted"])


@pytest.mark.slow
def test_a_resolved_band_render_equals_the_integrated_cube_with_the_coupling(tmp_path):
    """The shipped database with the surface-atmosphere coupling, resolved on the grid: equal
    within 1e-6 (band means: multiple_reflection 7.1e-4 and diffuse_transmitted 1.4e-3 of the
    radiance apart)."""
    scene, plain = _resolved(tmp_path, "vis", "vnir", background=0, atmosphere=DATABASE)
    _check_resolved(scene, plain, "vis", "vnir", 7, ["multiple_reflection",
                                                     "diffuse_transmitted"])


def test_resolved_bands_of_any_response_in_any_number_of_passes(tmp_path, monkeypatch):
    """Two bands on one grid — the tabulated one and a rectangle (not linear between the
    centres: its weights follow its interpolant, scaled to its own integral) — rendered with
    one channel per pass and with all at once: the same layers; the tabulated band equals its
    integrated cube; the rectangle's resolved background stays within 2 % of its band-mean one
    (its interpolant alone would put it 25 % off)."""
    import radscene.render.hyperspectral as hs

    scene, plain = _resolved(tmp_path, "vis", "vnir")
    spec = scene.spec.model_dump(mode="json")
    spec["bands"].append({"name": "green", "min": 0.52, "max": 0.58})
    spec["observers"][0]["bands"] = ["vis", "green"]
    scene = radscene.load_scene(spec, base_dir=tmp_path)
    spec["render"]["spectral_grid"] = None
    means = radscene.render(radscene.load_scene(spec, base_dir=tmp_path), "bands")
    once = radscene.render(scene, "bands")
    monkeypatch.setattr(hs, "PASS_MEMORY", 1.0)  # one channel a pass
    passes = radscene.render(scene, "bands")
    for name in ("radiance", "background_reflected"):
        np.testing.assert_allclose(passes[name].values, once[name].values, rtol=1e-12, err_msg=name)
    cube = radscene.render_hyperspectral(scene, "vnir", terms=True, dtype=np.float64)
    np.testing.assert_allclose(once["radiance"].sel(band="vis").values,
                               band_radiance(cube, scene.band("vis").response).values, rtol=REL)
    green = once["background_reflected"].sel(band="green").values
    mean = means["background_reflected"].sel(band="green").values
    seen = mean > 1e-3 * float(mean.max())
    assert float(np.abs(green[seen] / mean[seen] - 1.0).max()) < 0.02


def test_a_resolving_grid_must_hold_every_band(tmp_path):
    spec = _scene(tmp_path, 1).spec.model_dump(mode="json")
    spec["render"]["spectral_grid"] = {"min": "500 nm", "max": "700 nm", "step": "10 nm"}
    from radscene.errors import ConfigError

    with pytest.raises(ConfigError, match=r"render.spectral_grid: band 'lwir' .* reaches beyond"):
        radscene.load_scene(spec, base_dir=tmp_path)
    spec["render"]["spectral_grid"] = {"min": "500 nm", "max": "700 nm", "step": "0 nm"}
    with pytest.raises(ConfigError, match=r"render.spectral_grid.step"):
        radscene.load_scene(spec, base_dir=tmp_path)
    # a band narrower than a step: zero at every centre
    spec["bands"] = [{"name": "thin", "min": 0.5025, "max": 0.5075}]
    spec["observers"] = [spec["observers"][0] | {"bands": ["thin"]}]
    spec["render"]["spectral_grid"] = {"min": "500 nm", "max": "700 nm", "step": "10 nm"}
    with pytest.raises(ConfigError, match=r"render.spectral_grid: band 'thin' .* zero at every "):
        radscene.load_scene(spec, base_dir=tmp_path)
    # beyond the atmosphere's wavelengths (and the soil's table, from 0.4 um)
    spec["bands"] = [{"name": "blue", "min": 0.45, "max": 0.5}]
    spec["observers"] = [spec["observers"][0] | {"bands": ["blue"]}]
    spec["render"]["spectral_grid"] = {"min": "390 nm", "max": "600 nm", "step": "10 nm"}
    with pytest.raises(ConfigError, match=r"render.spectral_grid: .* asked for 0.39"):
        radscene.load_scene(spec, base_dir=tmp_path)
    # a spectral observer rendered as bands is still refused, with its own message
    spec = _scene(tmp_path, 1).spec.model_dump(mode="json")
    spec["observers"][0]["bands"] = ["vis"]
    spec["render"]["spectral_grid"] = {"min": "500 nm", "max": "700 nm", "step": "10 nm"}
    from radscene.render.integrator import render as render_bands

    with pytest.raises(ConfigError, match="render it with radscene.render_hyperspectral"):
        render_bands(radscene.load_scene(spec, base_dir=tmp_path), "vnir")


def test_a_resolved_scene_file_through_the_command_line(tmp_path):
    """`radscene render` of a scene file with render.spectral_grid: the written render carries
    the resolved layers, equal to the API's, and names them in its `spectral_grid` attribute."""
    import glob

    import xarray as xr
    import yaml
    from typer.testing import CliRunner

    from radscene.cli import app

    scene, _ = _resolved(tmp_path, "vis", "vnir")
    spec = scene.spec.model_dump(mode="json", exclude_none=True)
    spec["observers"] = [spec["observers"][0]]
    (tmp_path / "scene.yaml").write_text(yaml.safe_dump(spec), encoding="utf-8")
    run = CliRunner().invoke(app, ["render", str(tmp_path / "scene.yaml"), "-o",
                                   str(tmp_path / "out")])
    assert run.exit_code == 0, run.output
    with xr.open_dataset(glob.glob(str(tmp_path / "out" / "bands*.nc"))[0],
                         engine="h5netcdf") as ds:
        assert "background_reflected" in ds.attrs["spectral_grid"]
        api = radscene.render(radscene.load_scene(spec, base_dir=tmp_path), "bands")
        np.testing.assert_allclose(ds["background_reflected"].values,
                                   api["background_reflected"].values, rtol=1e-6)
