"""Vegetation: PROSPECT-D leaves, 4SAIL canopies and their thermal emissivity."""

import math

import numpy as np
import pytest

from radscene.errors import ConfigError

pytest.importorskip("prosail", reason="prosail not installed: pip install prosail")

from radscene.materials import get_material  # noqa: E402
from radscene.materials.vegetation import (  # noqa: E402
    LEAF_ANGLE_DISTRIBUTIONS,
    canopy_emissivity,
    canopy_material,
    canopy_reflectance,
    leaf_material,
    leaf_optics,
)


def idx(leaf, wavelength):
    return int(np.argmin(np.abs(leaf.wavelength - wavelength)))


def test_leaf_optics_conserve_energy_and_show_pigment_and_water_features():
    leaf = leaf_optics(chlorophyll=40.0, water=0.012)
    assert leaf.wavelength[0] == pytest.approx(0.4) and leaf.wavelength[-1] == pytest.approx(2.5)
    assert np.all(leaf.reflectance >= 0) and np.all(leaf.transmittance >= 0)
    assert np.all(leaf.absorptance >= 0)
    r = leaf.reflectance
    # green peak above the red well, near-infrared plateau far above both
    assert r[idx(leaf, 0.55)] > r[idx(leaf, 0.67)]
    assert r[idx(leaf, 0.85)] > 3 * r[idx(leaf, 0.67)]
    # water bands at 1.45 and 1.94 um
    assert r[idx(leaf, 1.45)] < r[idx(leaf, 1.65)] and r[idx(leaf, 1.94)] < r[idx(leaf, 2.2)]
    # more chlorophyll absorbs more red; more water absorbs more at 1.6 um
    assert leaf_optics(chlorophyll=80.0).reflectance[idx(leaf, 0.67)] < r[idx(leaf, 0.67)]
    assert leaf_optics(water=0.03).reflectance[idx(leaf, 1.65)] < r[idx(leaf, 1.65)]
    # PROSPECT near-infrared plateau of a typical dicot: reflectance and transmittance 0.4-0.55
    assert 0.4 < r[idx(leaf, 0.85)] < 0.55 and 0.4 < leaf.transmittance[idx(leaf, 0.85)] < 0.55


def test_black_leaves_reduce_sail_to_beer_law_gap_fractions():
    """Analytic case: leaves that neither reflect nor transmit. Without a hot spot the canopy's
    bidirectional reflectance is the soil's times the gap fractions towards sun and sensor,
    r_soil exp(-LAI (k_s + k_o)): linear in the soil, log-linear in LAI; for a spherical leaf
    distribution k = G / cos(theta) with G = 1/2."""
    leaf = leaf_optics()
    zeros = np.zeros_like(leaf.reflectance)
    black = type(leaf)(leaf.wavelength, zeros, zeros, {})
    ts, tv = 30.0, 20.0

    def brf(lai, soil):
        return float(canopy_reflectance(black, lai=lai, leaf_angle="spherical", hotspot=0.0, soil=soil,
                                        sun_zenith=ts, view_zenith=tv, relative_azimuth=90.0).bidirectional[0])

    assert brf(2.0, 0.4) == pytest.approx(2.0 * brf(2.0, 0.2), rel=1e-9)  # linear in the soil
    k = [-math.log(brf(lai, 0.3) / 0.3) / lai for lai in (0.5, 1.0, 2.0, 4.0)]
    np.testing.assert_allclose(k, k[0], rtol=1e-6)  # Beer's law: one extinction for all LAI
    spherical = 0.5 / math.cos(math.radians(ts)) + 0.5 / math.cos(math.radians(tv))
    # Verhoef's "spherical" (a, b) = (-0.35, -0.15) on 18 angle classes approximates G = 1/2:
    # its extinction is within 3 % of the sphere's
    assert k[0] == pytest.approx(spherical, rel=0.03)


def test_lai_zero_is_soil_and_dense_canopy_forgets_the_soil():
    leaf = leaf_optics()
    bare = canopy_reflectance(leaf, lai=0.0, soil=0.25)
    for f in ("bidirectional", "directional_hemispherical", "hemispherical_directional", "bihemispherical"):
        np.testing.assert_allclose(getattr(bare, f), 0.25, atol=1e-6)
    dark = canopy_reflectance(leaf, lai=10.0, soil=0.05)
    bright = canopy_reflectance(leaf, lai=10.0, soil=0.5)
    np.testing.assert_allclose(dark.bihemispherical, bright.bihemispherical, atol=2e-3)


def test_hot_spot_and_leaf_angles():
    leaf = leaf_optics()
    hot = canopy_reflectance(leaf, lai=3.0, hotspot=0.1, sun_zenith=30.0, view_zenith=30.0, relative_azimuth=0.0)
    away = canopy_reflectance(leaf, lai=3.0, hotspot=0.1, sun_zenith=30.0, view_zenith=30.0, relative_azimuth=180.0)
    i = idx(leaf, 0.67)
    assert hot.bidirectional[i] > 1.3 * away.bidirectional[i]  # backscatter hot spot
    erect = canopy_reflectance(leaf, lai=3.0, leaf_angle="erectophile")
    plano = canopy_reflectance(leaf, lai=3.0, leaf_angle="planophile")
    assert plano.bidirectional[idx(leaf, 0.85)] > erect.bidirectional[idx(leaf, 0.85)]
    assert set(LEAF_ANGLE_DISTRIBUTIONS) >= {"spherical", "planophile", "erectophile"}


def test_canopy_emissivity_limits_and_cavity_effect():
    wl = np.array([8.0, 10.0, 12.0])
    bare = canopy_emissivity(wl, lai=0.0, leaf_emissivity=0.97, soil_emissivity=0.9)
    np.testing.assert_allclose(bare.hemispherical, 0.9, atol=1e-6)
    dense = canopy_emissivity(wl, lai=8.0, leaf_emissivity=0.97, soil_emissivity=0.9)
    # multiple reflection between leaves: the canopy is more emissive than a leaf, below 1
    assert np.all(dense.hemispherical > 0.97) and np.all(dense.hemispherical < 1.0)
    # emissivity grows with LAI from the soil's towards its dense-canopy value
    grow = [float(canopy_emissivity([10.0], lai=lai, soil_emissivity=0.9).hemispherical[0]) for lai in (0.5, 1, 2, 4)]
    assert np.all(np.diff(grow) > 0)
    oblique = canopy_emissivity([10.0], lai=1.0, soil_emissivity=0.9, view_zenith=60.0)
    nadir = canopy_emissivity([10.0], lai=1.0, soil_emissivity=0.9, view_zenith=0.0)
    # at 60 deg the view sees more leaves and less soil: closer to the leaf emissivity
    assert float(oblique.directional[0]) > float(nadir.directional[0])


def test_leaf_and_canopy_materials_are_kirchhoff_closed_and_stated():
    leaf = leaf_material("leaf", chlorophyll=45.0)
    assert float(leaf.transmittance(0.85)) > 0.3  # translucent in the near infrared
    assert float(leaf.transmittance(10.0)) == 0.0 and float(leaf.emissivity(10.0)) == pytest.approx(0.97)
    assert "PROSPECT-D" in leaf.source and "leaf emissivity 0.97" in leaf.source
    assert "Ribeiro da Luz & Crowley 2007" in leaf.source and "ASSUMED" not in leaf.source
    soil = get_material("bare_soil")
    canopy = canopy_material("crop", lai=3.0, soil=soil, leaf_angle="spherical")
    wl = np.linspace(0.4, 20.0, 400)
    np.testing.assert_allclose(sum(canopy.components(wl).values()), 1.0, rtol=1e-12)
    assert canopy.wavelength_range == (0.4, 20.0)
    assert float(canopy.emissivity(10.0)) > float(soil.emissivity(10.0))
    with pytest.raises(ConfigError, match="outside the tabulated range"):
        canopy.reflectance(25.0)


def test_bad_parameters_name_the_key():
    with pytest.raises(ConfigError, match=r"chlorophyll: must be in \[0, 200\]; got -5"):
        leaf_optics(chlorophyll=-5.0)
    with pytest.raises(ConfigError, match=r"lai: must be in \[0, 15\]"):
        canopy_reflectance(lai=20.0)
    with pytest.raises(ConfigError, match="unknown leaf angle distribution 'flat'; known: planophile"):
        canopy_reflectance(leaf_angle="flat")
    with pytest.raises(ConfigError, match="dry_matter"):
        leaf_optics(dry_matter=0.0)
    with pytest.raises(ConfigError, match="soil reflectance must be in"):
        canopy_reflectance(soil=1.5)


def test_library_canopies_have_the_expected_order_of_brightness():
    # LAI 5 broadleaf canopy is brighter in the near infrared than the LAI 1 sparse one is
    # relative to its red: the NDVI falls with LAI
    def ndvi(name):
        m = get_material(name)
        nir, red = float(m.reflectance(0.85)), float(m.reflectance(0.67))
        return (nir - red) / (nir + red)

    assert ndvi("deciduous_canopy") > ndvi("grass_canopy") > ndvi("sparse_canopy")
    assert ndvi("senescent_canopy") < ndvi("grass_canopy")
    assert get_material("green_leaf").transmittance(0.85) > 0.3


def test_make_material_leaf_and_canopy_types():
    from radscene.materials import make_material

    crop = make_material({"type": "canopy", "lai": 2.0, "chlorophyll": 30.0, "soil": "sand",
                          "leaf_angle": "erectophile"}, key="materials.crop")
    assert crop.name == "crop" and crop.category == "vegetation"
    assert float(crop.emissivity(10.0)) > float(get_material("sand").emissivity(10.0))
    leaf = make_material({"type": "leaf", "water": 0.02}, key="materials.leaf")
    assert float(leaf.transmittance(0.85)) > 0.3
    with pytest.raises(ConfigError, match=r"materials.l: unknown keys \['chlorophyl'\] for a leaf"):
        make_material({"type": "leaf", "chlorophyl": 3}, key="materials.l")
    with pytest.raises(ConfigError, match=r"materials.c.soil: unknown material 'mud'"):
        make_material({"type": "canopy", "soil": "mud"}, key="materials.c")
