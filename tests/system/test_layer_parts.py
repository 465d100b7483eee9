"""The reflected sky and background split by the light's origin (seed 001 eq. 1, B, E, G, H).

Rendered through the public API: ``sky_reflected_solar`` + ``sky_reflected_thermal`` is
``sky_reflected`` and ``background_reflected_solar`` + ``background_reflected_thermal`` is
``background_reflected``; the layers of TERM_LAYERS still sum to the radiance (the parts are
not in it); each part is what a render whose engine holds only that part of the sky gives; a
flat Lambertian plate's parts equal their closed forms; and a sun below the horizon leaves no
sunlight in the background.
"""

from __future__ import annotations

import numpy as np
import pytest

from radscene import load_scene, render, render_hyperspectral
from radscene.render.outputs import PART_LAYERS, PART_NAMES, TERM_LAYERS

#: Parts against their layer: the solar part is the layer less the thermal one.
SUM = 1e-6
#: A closed form against the renderer's band quadrature of spectrally flat factors.
CLOSED = 1e-9

VIS = {"name": "vis", "min": 0.5, "max": 0.6}
MWIR = {"name": "mwir", "min": 3.5, "max": 4.1}
LWIR = {"name": "lwir", "min": 8.0, "max": 12.0}
SKY_SOLAR = {"wavelength": [0.3, 2.0, 5.0, 14.0], "values": [40.0, 3.0, 0.05, 0.002]}
SKY_THERMAL = {"wavelength": [0.3, 2.0, 3.0, 5.0, 14.0], "values": [0.0, 0.0, 0.02, 0.6, 9.0]}


def _with_box(scene, temperature="330 K"):
    """A warm 10 m box beside the plate's seen part, whose radiance the plate reflects."""
    scene["objects"].append({"name": "box", "shape": {"type": "box", "size": [10, 10, 20]},
                             "position": [10, 0, 0], "material": "plate_material",
                             "temperature": temperature})
    return scene


def _uniform(**sky):
    return {"type": "uniform", "transmittance": 0.8, "path_radiance": 0.5, **sky}


def _check_sums(ds):
    """Each pair of parts sums to its layer; the layers of TERM_LAYERS to the radiance."""
    for layer, (solar, thermal) in PART_LAYERS.items():
        whole = ds[layer].values
        assert ds[solar].attrs["units"] == "W m-2 sr-1"
        assert layer in ds[solar].attrs["comment"] and layer in ds[thermal].attrs["comment"]
        np.testing.assert_allclose(ds[solar].values + ds[thermal].values, whole, rtol=SUM,
                                   atol=1e-12 * float(np.abs(whole).max()), err_msg=layer)
    total = sum(ds[name].values for name in TERM_LAYERS if name in ds)
    np.testing.assert_allclose(total, ds["radiance"].values, rtol=1e-12, atol=0.0)
    assert not set(PART_NAMES) & set(TERM_LAYERS)


def test_database_mwir_parts_sum_and_both_are_nonzero(make_plate_scene):
    """The database's sky holds scattered sunlight and emission at 3.5-4.1 µm: both parts
    are there, in one and in two bounces of the background."""
    for bounces in (1, 2):
        scene = _with_box(make_plate_scene(
            {"reflectance": 0.3}, {"type": "database", "profile": "midlatitude_summer",
                                   "aerosol": "rural", "visibility": "23 km"},
            [VIS, MWIR], sun_zenith=40.0, background_bounces=bounces, background_samples=8))
        ds = render(load_scene(scene))
        _check_sums(ds)
        mwir, vis = ds.sel(band="mwir"), ds.sel(band="vis")
        for name in PART_NAMES:
            assert float(mwir[name].mean()) > 0.0, name
        # the visible sky holds no emission: its thermal part is exactly zero
        assert np.all(vis["sky_reflected_thermal"].values == 0.0)
        assert np.array_equal(vis["sky_reflected_solar"].values, vis["sky_reflected"].values)


@pytest.mark.parametrize("material", [
    {"reflectance": 0.3},
    {"reflectance": 0.25, "specular_reflectance": 0.05, "specular_exponent": 30},
    {"reflectance": 0.3, "brdf": {"type": "lambertian", "reflectance": 0.3}},
], ids=["lambertian", "phong", "brdf-model"])
def test_each_part_is_the_render_of_its_sky_alone(make_plate_scene, material):
    """Rendered with the sky's two parts, each part layer equals the ``sky_reflected`` of a
    render whose engine's sky holds only that part (the solar-only and thermal-only engines),
    in every band — the fused sky sums, the specular lobe's and a BRDF model's."""
    bands = [VIS, MWIR, LWIR]

    def sky_of(**sky):
        scene = make_plate_scene(material, _uniform(**sky), bands, sun_zenith=30.0,
                                 background_bounces=0)
        return render(load_scene(scene))

    both = sky_of(sky_solar_radiance=SKY_SOLAR, sky_thermal_radiance=SKY_THERMAL)
    solar = sky_of(sky_solar_radiance=SKY_SOLAR)
    thermal = sky_of(sky_thermal_radiance=SKY_THERMAL)
    _check_sums(both)
    np.testing.assert_allclose(both["sky_reflected_solar"].values, solar["sky_reflected"].values,
                               rtol=SUM, atol=0.0)
    np.testing.assert_allclose(both["sky_reflected_thermal"].values,
                               thermal["sky_reflected"].values, rtol=SUM, atol=0.0)
    assert np.all(both["sky_reflected_thermal"].sel(band="vis").values == 0.0)
    assert float(both["sky_reflected_thermal"].sel(band="mwir").mean()) > 0.0
    assert float(both["sky_reflected_solar"].sel(band="lwir").mean()) > 0.0  # small, kept


def test_lambertian_plate_parts_equal_their_closed_forms(make_plate_scene):
    """A flat Lambertian plate under an open sky of flat solar and thermal radiances:
    sky_reflected_solar = ρ_d L_sky,solar τ ∫S dλ and the thermal part likewise."""
    rho, tau, solar, thermal = 0.3, 0.8, 0.5, 2.0
    scene = make_plate_scene({"reflectance": rho},
                             {"type": "uniform", "transmittance": tau,
                              "sky_solar_radiance": solar, "sky_thermal_radiance": thermal},
                             [MWIR, LWIR], sun_zenith=30.0, background_bounces=0)
    ds = render(load_scene(scene))
    for band in (MWIR, LWIR):
        width = band["max"] - band["min"]
        sel = ds.sel(band=band["name"])
        assert sel["sky_reflected_solar"].values == pytest.approx(
            np.full((8, 8), rho * solar * tau * width), rel=CLOSED)
        assert sel["sky_reflected_thermal"].values == pytest.approx(
            np.full((8, 8), rho * thermal * tau * width), rel=CLOSED)
        assert np.all(sel["background_reflected_solar"].values == 0.0)


def test_a_sun_below_the_horizon_leaves_no_sunlight_in_the_background(make_plate_scene):
    scene = _with_box(make_plate_scene(
        {"reflectance": 0.3}, _uniform(sky_thermal_radiance=SKY_THERMAL), [MWIR, LWIR],
        sun_zenith=100.0, background_bounces=2, background_samples=8))
    ds = render(load_scene(scene))
    _check_sums(ds)
    assert np.all(ds["background_reflected_solar"].values == 0.0)
    assert np.all(ds["sky_reflected_solar"].values == 0.0)
    assert np.array_equal(ds["background_reflected_thermal"].values,
                          ds["background_reflected"].values)
    assert float(ds["background_reflected_thermal"].sel(band="lwir").mean()) > 0.0


def test_the_background_parts_follow_their_sources(make_plate_scene):
    """A sunlit 330 K box: in the visible, where the box's sunlit side is seen, the
    background is all sunlight (its emission, 1.5e-26 W m-2 sr-1, in the thermal part); in
    the LWIR mostly its emission, with some sunlight."""
    scene = _with_box(make_plate_scene(
        {"reflectance": 0.3}, _uniform(sky_solar_radiance=SKY_SOLAR,
                                       sky_thermal_radiance=SKY_THERMAL), [VIS, MWIR, LWIR],
        sun_zenith=40.0, background_bounces=1, background_samples=8))
    ds = render(load_scene(scene))
    _check_sums(ds)
    vis, lwir = ds.sel(band="vis"), ds.sel(band="lwir")
    seen = vis["background_reflected"].values > 1e-6  # the box's sunlit side (not its shade)
    assert seen.any()
    assert np.all(vis["background_reflected_thermal"].values[seen]
                  < 1e-12 * vis["background_reflected"].values[seen])
    assert float(lwir["background_reflected_thermal"].sum()) > 10 * float(
        lwir["background_reflected_solar"].sum()) > 0.0


def test_hyperspectral_terms_carry_the_parts(make_plate_scene):
    """An observer's spectral grid with ``terms: true`` across 3.6-4.4 µm: each channel's
    parts are in the cube and sum to their layer."""
    scene = make_plate_scene({"reflectance": 0.3},
                             _uniform(sky_solar_radiance=SKY_SOLAR,
                                      sky_thermal_radiance=SKY_THERMAL),
                             [MWIR], sun_zenith=30.0, background_bounces=0)
    scene["observers"][0]["spectral"] = {"min": "3.6 um", "max": "4.4 um", "step": "0.2 um",
                                         "terms": True}
    cube = render_hyperspectral(load_scene(scene))
    for layer, parts in PART_LAYERS.items():
        pair = sum(cube[p].values.astype(float) for p in parts)
        np.testing.assert_allclose(pair, cube[layer].values.astype(float), rtol=1e-6,
                                   atol=1e-30, err_msg=layer)
    assert float(cube["sky_reflected_thermal"].min()) > 0.0
    assert float(cube["sky_reflected_solar"].min()) > 0.0


def test_parts_under_a_volume_stay_their_layers_share(make_plate_scene):
    """A smoke box above part of the plate: the volume pass moves the share of each layer
    behind it into ``transmitted``, and each part with its layer, so they still sum to it."""
    scene = make_plate_scene({"reflectance": 0.3},
                             _uniform(sky_solar_radiance=SKY_SOLAR,
                                      sky_thermal_radiance=SKY_THERMAL),
                             [MWIR, LWIR], sun_zenith=30.0, background_bounces=1,
                             background_samples=4)
    scene["volumes"] = [{"name": "smoke", "shape": {"type": "box", "size": [4.0, 4.0, 2.0]},
                         "position": [-2, -2, 20], "temperature": 350.0,
                         "single_scattering_albedo": 0.5, "optical_depth": 0.7}]
    ds = render(load_scene(scene))
    assert "transmitted" in ds and float(ds["transmitted"].max()) > 0.0
    _check_sums(ds)
    assert float(ds["sky_reflected_thermal"].sel(band="mwir").mean()) > 0.0


@pytest.mark.parametrize("material", [
    {"reflectance": 0.3},
    {"reflectance": 0.3, "specular_reflectance": 0.2, "specular_exponent": 10},
], ids=["lambertian", "phong"])
def test_a_volume_dims_each_part_of_the_sky_as_its_own(make_plate_scene, material):
    """A cold (50 K: its own radiance ~1e-9), absorbing smoke box above
    the plate hides part of each hit's sky: each part of the reflected sky is what a render
    with that part of the sky alone gives (the volume's change of the sky split as the sky
    is, sky_change_thermal; of a Phong lobe's, lobe_change_thermal), and none is negative."""
    def sky_of(**sky):
        scene = make_plate_scene(material, _uniform(**sky), [VIS, MWIR, LWIR],
                                 sun_zenith=30.0, background_bounces=0)
        scene["volumes"] = [{"name": "smoke", "shape": {"type": "box", "size": [6.0, 6.0, 2.0]},
                             "position": [3, 0, 4], "temperature": 50.0,
                             "single_scattering_albedo": 0.0, "optical_depth": 2.0}]
        return render(load_scene(scene))

    both = sky_of(sky_solar_radiance=SKY_SOLAR, sky_thermal_radiance=SKY_THERMAL)
    solar = sky_of(sky_solar_radiance=SKY_SOLAR)
    thermal = sky_of(sky_thermal_radiance=SKY_THERMAL)
    _check_sums(both)
    dimmed = both["sky_view_transmitted"].sel(band="mwir").values < 0.99
    assert dimmed.any()
    for part, alone in (("sky_reflected_solar", solar), ("sky_reflected_thermal", thermal)):
        np.testing.assert_allclose(both[part].values, alone["sky_reflected"].values, rtol=SUM,
                                   atol=1e-9, err_msg=part)
        assert float(both[part].min()) >= 0.0


def test_a_warm_volume_splits_its_light_by_origin(make_plate_scene):
    """A warm (350 K), scattering smoke box above the plate, a wall beside it: the volume's
    own radiance reflected along the sky rays and met on the background's paths goes into each
    part by its origin — its emission into the thermal parts, the sun it scatters into the
    solar ones. So the thermal parts equal the render of a night (sun below the horizon, the
    thermal sky alone), and the solar parts those of the solar sky alone under the same
    volume at 1 K (whose emission is nil; the wall's is still the background's thermal
    part)."""
    def render_with(sun_zenith, temperature, **sky):
        scene = _with_box(make_plate_scene(
            {"reflectance": 0.3, "specular_reflectance": 0.1, "specular_exponent": 10},
            _uniform(**sky), [MWIR, LWIR], sun_zenith=sun_zenith, background_bounces=1,
            background_samples=8))
        scene["volumes"] = [{"name": "smoke", "shape": {"type": "box", "size": [12.0, 12.0, 4.0]},
                             "position": [4, 0, 6], "temperature": temperature,
                             "single_scattering_albedo": 0.5, "optical_depth": 1.5}]
        return render(load_scene(scene))

    both = render_with(30.0, 350.0, sky_solar_radiance=SKY_SOLAR,
                       sky_thermal_radiance=SKY_THERMAL)
    night = render_with(120.0, 350.0, sky_thermal_radiance=SKY_THERMAL)
    cold = render_with(30.0, 1.0, sky_solar_radiance=SKY_SOLAR)
    _check_sums(both)
    for part, alone, layer in (("sky_reflected_thermal", night, "sky_reflected"),
                               ("sky_reflected_solar", cold, "sky_reflected"),
                               ("background_reflected_thermal", night, "background_reflected"),
                               ("background_reflected_solar", cold, "background_reflected_solar")):
        np.testing.assert_allclose(both[part].values, alone[layer].values, rtol=SUM, atol=1e-9,
                                   err_msg=part)
    # the volume's emission is a good share of the night's reflected sky under it
    assert float(night["sky_reflected"].sel(band="mwir").max()) > 2.0 * float(
        night["sky_reflected"].sel(band="mwir").min())


def test_a_material_tabulated_over_the_visible_alone_renders_with_the_background(
        make_plate_scene):
    """The background pass's direction sampler weighs each material's lobes by its mean over a
    fixed grid of wavelengths; a material tabulated over 0.4-0.7 um only is averaged where it is
    defined, not refused at 0.70 um."""
    scene = _with_box(make_plate_scene(
        {"reflectance": {"wavelength": [0.4, 0.55, 0.7], "values": [0.1, 0.3, 0.2]}},
        _uniform(sky_solar_radiance=SKY_SOLAR), [VIS], background_bounces=1,
        background_samples=4))
    ds = render(load_scene(scene))
    assert np.all(np.isfinite(ds["background_reflected"].values))
    assert float(ds["background_reflected"].max()) > 0.0
