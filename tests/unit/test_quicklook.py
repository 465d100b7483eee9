"""Quicklooks drawn for a report: named categories in the truth figure, colour bars that show
clipping, units in print form, angle axes on perspective views, no empty panels."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
import xarray as xr

from radscene.io.quicklook import (
    band_plot,
    band_quicklooks,
    categories,
    colorbar_extend,
    observer_fov,
    terms_plot,
    truth_plot,
    unit_text,
)
from radscene.render import TERMS

NY, NX = 6, 8
FOV = 40.0  # [deg]


def _dataset(empty_band=False, perspective=True):
    rng = np.random.default_rng(3)
    bands = ["red", "lwir"]
    radiance = rng.uniform(1.0, 2.0, (2, NY, NX))
    radiance[0, 0, 0] = 50.0  # a hot pixel above the 99 % stretch
    if empty_band:
        radiance[1] = np.nan
    objects = np.full((NY, NX), -1)
    objects[1:3, 1:3], objects[4, 5:7] = 0, 2
    data = {
        "radiance": (("band", "y", "x"), radiance, {"units": "W m-2 sr-1"}),
        "brightness_temperature": (("band", "y", "x"), np.full((2, NY, NX), np.nan), {"units": "K"}),
        "object_id": (("y", "x"), objects, {"flag_values": np.arange(3, dtype=np.int32),
                                            "flag_meanings": "farmhouse barn truck"}),
        "material_id": (("y", "x"), np.where(objects < 0, 0, 1),
                        {"flag_values": np.arange(2, dtype=np.int32),
                         "flag_meanings": "dry_grass roof_tile"}),
        "range": (("y", "x"), rng.uniform(100, 200, (NY, NX)), {"units": "m"}),
        "cos_incidence": (("y", "x"), rng.uniform(0, 1, (NY, NX)), {"units": "1"}),
        "shadow_fraction": (("y", "x"), rng.uniform(0, 1, (NY, NX)), {"units": "1"}),
        "sky_view_fraction": (("y", "x"), rng.uniform(0, 1, (NY, NX)), {"units": "1"}),
        "surface_temperature": (("y", "x"), np.full((NY, NX), np.nan), {"units": "K"}),
        "surface_normal": (("vector", "y", "x"), np.ones((3, NY, NX)), {"units": "1"}),
    }
    for term in TERMS:
        data[term] = (("band", "y", "x"), radiance / len(TERMS), {"units": "W m-2 sr-1"})
    geometry = {"settings": {"type": "perspective" if perspective else "orthographic"},
                "fov_deg": FOV, "shape": [NY, NX]}
    return xr.Dataset(
        data, coords={"band": bands, "vector": ["east", "north", "up"],
                      "wavelength_center": ("band", [0.66, 10.0]),
                      "x": ("x", np.arange(NX), {"long_name": "pixel column"}),
                      "y": ("y", np.arange(NY), {"long_name": "pixel row"})},
        attrs={"observer": "oblique", "observer_geometry": json.dumps(geometry),
               **({"observer_type": "perspective"} if perspective else {})})


def test_truth_figure_names_the_objects_and_materials_in_legends():
    fig = truth_plot(_dataset())
    legends = {ax.get_title(): [t.get_text() for t in ax.get_legend().get_texts()]
               for ax in fig.axes if ax.get_legend() is not None}
    # object 1 (barn) is not in the picture; pixels of -1 are "(none)"
    assert legends["object id"] == ["farmhouse", "truck", "(none)"]
    assert legends["material id"] == ["dry_grass", "roof_tile"]


def test_categorical_maps_use_a_discrete_colour_map():
    fig = truth_plot(_dataset())
    ax = next(a for a in fig.axes if a.get_title() == "object id")
    image = ax.get_images()[0]
    assert image.cmap.N == 2 and image.norm.boundaries.tolist() == [-0.5, 0.5, 1.5]


def test_a_scene_without_objects_draws_an_object_map_of_none():
    """A scene of terrain alone: every pixel's object is -1 (no category)."""
    ds = _dataset()
    ds["object_id"] = ds["object_id"].copy(data=np.full((NY, NX), -1))
    fig = truth_plot(ds)
    ax = next(a for a in fig.axes if a.get_title() == "object id")
    assert [t.get_text() for t in ax.get_legend().get_texts()] == ["(none)"]


def test_truth_colour_bars_sit_beside_their_own_maps():
    """Each map's colour bar right of it, closer to it than to the next panel, also in a row
    below the categorical maps, whose legends widen their columns."""
    fig = truth_plot(_dataset())
    fig.draw_without_rendering()
    axes = [*fig.axes, *(child for ax in fig.axes for child in ax.child_axes)]
    bars = [ax.get_window_extent() for ax in axes if ax.get_label() == "<colorbar>"]
    maps = [ax for ax in fig.axes if ax.get_label() != "<colorbar>" and ax.get_legend() is None]
    assert len(maps) == 5 and len(bars) == 5
    for ax in maps:
        box = ax.get_window_extent()
        right = [b.x0 - box.x1 for b in bars if b.x0 >= box.x1 - 1 and b.y0 < box.y1
                 and b.y1 > box.y0]
        assert right and 0 <= min(right) < 0.1 * box.width, (ax.get_title(), right)


def test_categories_fall_back_to_numbers_when_the_names_do_not_split():
    variable = xr.DataArray([0, 1], attrs={"flag_values": [0, 1],
                                           "flag_meanings": "0.6 grass + 0.4 soil"})
    assert categories(variable) == {0: "0", 1: "1"}


def test_truth_figure_leaves_out_maps_without_data_and_says_so():
    fig = truth_plot(_dataset())
    titles = [ax.get_title() for ax in fig.axes]
    assert not any("surface temperature" in t for t in titles)
    assert "surface_temperature" in fig.get_suptitle()
    assert all(ax.get_images() for ax in fig.axes if ax.get_label() != "<colorbar>")


@pytest.mark.parametrize("values, expected", [
    ([0.0, 1.0, 2.0], "neither"), ([-1.0, 1.0], "min"), ([1.0, 3.0], "max"),
    ([-1.0, 3.0, np.nan], "both"),
])
def test_colorbar_extend(values, expected):
    assert colorbar_extend(np.array(values), 0.0, 2.0) == expected


def test_band_colour_bar_shows_the_clipped_hot_pixel():
    fig = band_plot(_dataset(), "red")
    (bar,) = [ax for ax in fig.axes if ax.get_label() == "<colorbar>"]
    assert bar._colorbar.extend in ("max", "both")
    assert bar.get_ylabel() == "radiance [W m⁻² sr⁻¹]"


def test_band_title_writes_micrometres():
    title = band_plot(_dataset(), "red").axes[0].get_title()
    assert "µm" in title and "um" not in title


@pytest.mark.parametrize("units, text", [
    ("W m-2 sr-1", "W m⁻² sr⁻¹"), ("W m-2 sr-1 um-1", "W m⁻² sr⁻¹ µm⁻¹"), ("um", "µm"),
    ("m-1", "m⁻¹"), ("K", "K"), ("1", ""), ("m2", "m²"),
])
def test_unit_text(units, text):
    assert unit_text(units) == text


def test_perspective_views_have_angle_axes():
    ds = _dataset()
    assert observer_fov(ds) == pytest.approx(FOV, rel=1e-12)
    ax = band_plot(ds, "red").axes[0]
    labels = [t.get_text() for t in ax.get_xticklabels()]
    assert "0°" in labels and "boresight" in ax.get_xlabel()
    # the 0° tick sits on the image centre, the field's edges at ±fov/2 on the image edges
    ticks = dict(zip(labels, ax.get_xticks(), strict=True))
    assert ticks["0°"] == pytest.approx(NX / 2 - 0.5, abs=1e-9)
    assert ticks["20°"] == pytest.approx(NX - 0.5, abs=1e-9)
    assert ticks["\N{MINUS SIGN}20°"] == pytest.approx(-0.5, abs=1e-9)
    half = math.tan(math.radians(FOV / 2))
    rows = [t.get_text() for t in ax.get_yticklabels()]
    top = math.degrees(math.atan(half * NY / NX))
    assert all(abs(float(r.rstrip("°").replace("\N{MINUS SIGN}", "-"))) <= top for r in rows)


def test_other_views_keep_pixel_axes():
    ds = _dataset(perspective=False)
    assert observer_fov(ds) is None
    ax = band_plot(ds, "red").axes[0]
    assert "pixel" in ax.get_xlabel()


def test_bands_without_data_are_left_out_with_a_note(tmp_path):
    ds = _dataset(empty_band=True)
    with pytest.warns(UserWarning, match="lwir"):
        written = band_quicklooks(ds, tmp_path)
    assert [p.name for p in written] == ["red.png"]
    fig = terms_plot(ds)
    assert "lwir" in fig.get_suptitle()
    assert all(ax.get_images() for ax in fig.axes if ax.get_label() != "<colorbar>")


def _tick_labels(ax):
    return ([t.get_text() for t in ax.get_xticklabels()],
            [t.get_text() for t in ax.get_yticklabels()])


def test_truth_panels_of_a_perspective_view_have_the_band_pictures_angle_axes():
    ds = _dataset()
    band_ax = band_plot(ds, "red").axes[0]
    expected = _tick_labels(band_ax)
    assert all(label.endswith("°") for label in expected[0] + expected[1])
    fig = truth_plot(ds)
    panels = [ax for ax in fig.axes if ax.get_label() != "<colorbar>"]
    assert len(panels) == 7  # the maps with data, the surface temperature left out
    for ax in panels:
        assert _tick_labels(ax) == expected, ax.get_title()
    # the axis labels once per row and column of panels
    assert {ax.get_xlabel() for ax in panels} == {band_ax.get_xlabel(), ""}
    assert {ax.get_ylabel() for ax in panels} == {band_ax.get_ylabel(), ""}
    bottom = [ax for ax in panels if ax.get_xlabel()]
    assert len(bottom) == 4


def test_truth_panels_of_a_pixel_view_stay_without_ticks():
    fig = truth_plot(_dataset(perspective=False))
    panels = [ax for ax in fig.axes if ax.get_label() != "<colorbar>"]
    assert all(not ax.get_xticks().size and not ax.get_yticks().size for ax in panels)
