"""The quicklook figures of real renders: the terms figure shows every layer that sums to the
radiance, the truth figure of a perspective view has the same angle axes as its band PNGs."""

from __future__ import annotations

import numpy as np
import pytest

from radscene import render
from radscene.io.quicklook import term_layers, terms_plot
from radscene.render.outputs import PART_LAYERS, TERM_LAYERS, finest_layers


def _slab_scene():
    """A scattering, emitting box volume over a grey plate in the sun, seen from above."""
    return {
        "name": "slab",
        "environment": {"sun": {"zenith": 30.0, "azimuth": 180.0},
                        "atmosphere": {"type": "none"}},
        "materials": {"plate": {"reflectance": 0.3}},
        "objects": [{"name": "plate", "shape": {"type": "plate", "width": 400, "length": 400},
                     "material": "plate", "temperature": 300.0}],
        "volumes": [{"name": "smoke", "shape": {"type": "box", "size": [6.0, 6.0, 2.0]},
                     "position": [0, 0, 20], "temperature": 350.0,
                     "single_scattering_albedo": 0.5, "optical_depth": 0.7}],
        "bands": [{"name": "vis", "min": 0.5, "max": 0.6},
                  {"name": "lwir", "min": 8.0, "max": 12.0}],
        "observers": [{"name": "cam", "type": "orthographic", "center": [0, 0], "gsd": 1.0,
                       "shape": [12, 12], "altitude": 1000}],
        "render": {"background_bounces": 0},
    }


@pytest.fixture(scope="module")
def slab():
    return render(_slab_scene())


def _panel_titles(fig):
    return [ax.get_title() for ax in fig.axes if ax.get_images()]


def test_terms_figure_shows_the_volume_layers(slab):
    fig = terms_plot(slab)
    titles = _panel_titles(fig)
    for layer in ("transmitted", "volume emission", "volume scattered", "sun diffuse",
                  "thermal emission"):
        assert any(t.endswith(f": {layer}") for t in titles), (layer, titles)
    # the layers left out are named in the figure: the coupling layers of a scene without
    # coupling are zero everywhere
    for layer in ("multiple reflection", "diffuse transmitted", "adjacency"):
        assert not any(layer in t for t in titles)
        assert layer in fig.get_suptitle()
    # two bands, each its layers and the radiance in rows of five: no empty panel
    shown, _ = term_layers(slab)
    assert len(titles) == 2 * (len(shown) + 1)


def test_terms_figure_layers_sum_to_the_radiance(slab):
    shown, left_out = term_layers(slab)
    assert set(shown) | set(left_out["all zero"]) | set(left_out["no finite value"]) == set(
        finest_layers(slab.data_vars))
    # the reflected sky and background as their parts: seed 001 eq. 1's B, E, G, H apart
    for layer, parts in PART_LAYERS.items():
        assert layer in TERM_LAYERS and layer not in finest_layers(slab.data_vars)
        assert set(parts) <= set(finest_layers(slab.data_vars))
    total = sum(slab[name].values for name in shown)
    assert np.allclose(total, slab["radiance"].values, rtol=1e-12, atol=0.0)


def test_truth_panels_of_a_map_product_have_its_map_axes(slab):
    from radscene.io.quicklook import band_plot, truth_plot

    band_ax = band_plot(slab, "vis").axes[0]
    expected = [t.get_text() for t in band_ax.get_xticklabels()]
    assert band_ax.get_xlabel() == "easting [m]" and expected
    panels = [ax for ax in truth_plot(slab).axes if ax.get_label() != "<colorbar>"]
    assert panels
    for ax in panels:
        assert [t.get_text() for t in ax.get_xticklabels()] == expected, ax.get_title()
