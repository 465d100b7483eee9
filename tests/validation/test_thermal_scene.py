"""The heat balance of whole scenes, through the public API: a building's shadow on asphalt
leaves a cool patch that trails the moving shadow, in the solved temperatures and in the
rendered thermal image."""

import numpy as np
import pytest

import radscene
from radscene.scene import load_scene

_SCENE = {
    "name": "shadow_trail",
    "environment": {
        "location": {"latitude": 35.0, "longitude": 0.0, "altitude": 0.0},
        "time": "2026-06-21T15:00:00Z",
        "atmosphere": {"type": "database", "profile": "midlatitude_summer", "aerosol": "rural",
                       "visibility": "23 km"},
    },
    "terrain": {"type": "dem", "elevation": np.zeros((61, 61)).tolist(), "spacing": [1.0, 1.0],
                "origin": [-30.0, -30.0], "material": "asphalt"},
    "objects": [{"name": "block", "shape": {"type": "box", "size": [6.0, 6.0, 12.0]},
                 "position": [0.0, 0.0, 0.0], "material": "concrete", "temperature": "300 K"}],
    "bands": [{"name": "lwir", "min": "8 um", "max": "12 um"}],
    "observers": [{"name": "map", "type": "orthographic", "center": [0.0, 0.0], "altitude": 500.0,
                   "gsd": 1.0, "shape": [56, 56]}],
    "thermal": {"step": "10 min", "weather": {"t_min": "18 degC", "t_max": "30 degC",
                                              "relative_humidity": 0.4, "wind_speed": 1.5}},
    "render": {"sky_samples": 4, "specular_samples": 1},
}


@pytest.fixture(scope="module")
def solved():
    scene = load_scene(_SCENE, base_dir=".")
    ds = radscene.solve_thermal(scene)
    return scene, ds


def test_cool_patch_trails_the_shadow(solved):
    scene, ds = solved
    cells = ds.where(ds.object == "terrain", drop=True)
    lit_now = cells.sunlit.isel(time=-1).values
    lit_before = cells.sunlit.isel(time=-7).values  # an hour earlier
    temp = cells.surface_temperature.isel(time=-1).values
    shade = lit_now < 0.01
    emerged = (lit_now > 0.99) & (lit_before < 0.01)  # in the sun again for less than an hour
    sunny = (lit_now > 0.99) & (cells.sunlit.isel(time=slice(-25, None)).min("time").values > 0.99)
    assert shade.sum() > 10 and emerged.sum() > 3 and sunny.sum() > 100
    t_shade, t_emerged, t_sunny = temp[shade].mean(), temp[emerged].mean(), temp[sunny].mean()
    # the patch that left the shadow is warming but still well below the cells lit all along
    assert t_shade + 1.0 < t_emerged < t_sunny - 2.0
    assert ds.attrs["spin_up_days"] >= 2
    # every term of the balance is there, and the energy closes at every step
    assert {"q_a", "q_sky", "q_env", "q_t", "q_k", "q_v", "q_i", "q_d"} <= set(ds.data_vars)
    assert float(ds.closure[1:].max()) <= 1e-6
    # the ground under the block sees only the block (300 K): Q_env keeps it near that
    under = (np.abs(cells.x) < 2.5) & (np.abs(cells.y) < 2.5)
    assert np.all(np.abs(cells.surface_temperature.isel(time=-1).values[under] - 300.0) < 5.0)


def test_rendered_thermal_image_shows_the_trailing_patch(solved):
    scene, ds = solved
    images = radscene.render(scene, "map")
    bt = images.brightness_temperature.sel(band="lwir")
    truth = images.surface_temperature
    # the map's truth is the solution at the scene's time, face by face
    cells = ds.where(ds.object == "terrain", drop=True)
    assert float(truth.max()) == pytest.approx(float(cells.surface_temperature.isel(time=-1).max()), abs=0.5)
    # brightness temperature follows the surface temperature: coolest in the shade, warmest in
    # the open (asphalt's emissivity ~0.93-0.95 keeps it a few K below the surface)
    seen = np.isfinite(truth.values) & np.isfinite(bt.values)
    t, b = truth.values[seen], bt.values[seen]
    hot, cold = t >= np.percentile(t, 80), t <= np.percentile(t, 5)
    assert b[hot].mean() - b[cold].mean() > 0.7 * (t[hot].mean() - t[cold].mean())


@pytest.mark.slow  # about 60 s: the coupled surface solve of lateral conduction at every step
def test_lateral_conduction_softens_the_shadow_edge():
    """With lateral conduction (thermal.lateral) heat flows from the sunlit asphalt into the
    shaded cells beside it: the shade's edge warms, the sun's edge cools, the far field stays."""
    scene = load_scene({**_SCENE, "thermal": {**_SCENE["thermal"], "lateral": True}}, base_dir=".")
    with_lateral = radscene.solve_thermal(scene)
    without = radscene.solve_thermal(load_scene(_SCENE, base_dir="."))
    assert "q_lat" in with_lateral.data_vars and float(with_lateral.closure[1:].max()) <= 1e-6
    a = with_lateral.where(with_lateral.object == "terrain", drop=True).isel(time=-1)
    b = without.where(without.object == "terrain", drop=True).isel(time=-1)
    diff = a.surface_temperature.values - b.surface_temperature.values
    shade = b.sunlit.values < 0.01
    far = np.hypot(b.x.values, b.y.values) > 25.0
    assert diff[shade & ~far].max() > 0.05  # some shaded cell next to the sun gains
    assert np.abs(diff[far & ~shade]).max() < 0.05


#: A block on 40 m × 40 m of asphalt for two hours of an afternoon at 10 min steps, no spin-up
#: (its own day would trace shadows too), few hemisphere rays: a solve takes 1-2 s.
_INTERVAL_SCENE = {
    "name": "shadow_interval",
    "environment": {"location": {"latitude": 35.0, "longitude": 0.0, "altitude": 0.0},
                    "time": "2026-06-21T16:00:00Z", "atmosphere": {"type": "none"}},
    "terrain": {"type": "dem", "elevation": np.zeros((41, 41)).tolist(), "spacing": [1.0, 1.0],
                "origin": [-20.0, -20.0], "material": "asphalt"},
    "objects": [{"name": "block", "shape": {"type": "box", "size": [6.0, 6.0, 12.0]},
                 "position": [0.0, 0.0, 0.0], "material": "concrete", "temperature": "300 K"}],
    "bands": [{"name": "lwir", "min": "8 um", "max": "12 um"}],
    "observers": [{"name": "map", "type": "orthographic", "center": [0.0, 0.0], "gsd": 1.0,
                   "shape": [8, 8]}],
    "thermal": {"start": "2026-06-21T14:00:00Z", "step": "10 min", "hemisphere_samples": 8, "spin_up": False,
                "weather": {"t_min": "18 degC", "t_max": "30 degC", "relative_humidity": 0.4,
                            "wind_speed": 1.5}},
}


def _solve_with_shadow_interval(interval):
    """The solution and the number of sun positions traced for the shadows."""
    traced = []

    def progress(stage, done, total):
        if stage == "shadows":
            traced.append(total)

    spec = {**_INTERVAL_SCENE, "thermal": {**_INTERVAL_SCENE["thermal"], "shadow_interval": interval}}
    ds = radscene.solve_thermal(load_scene(spec, base_dir="."), progress=progress)
    return ds, set(traced)


def test_shadow_interval_traces_less_often_and_interpolates_between():
    """thermal.shadow_interval of 1 h on 10 min steps traces the shadows at 14:00, 15:00 and
    16:00 only; at the steps between, the sunlit fraction is the linear interpolation in time
    of those traces, which differs from tracing every step where the shadow's edge moved."""
    every_step, traced_every = _solve_with_shadow_interval(None)
    hourly, traced_hourly = _solve_with_shadow_interval("1 h")
    assert every_step.sizes["time"] == 13
    assert traced_every == {13} and traced_hourly == {3}
    exact, lit = every_step.sunlit.values, hourly.sunlit.values
    tol = 1e-6  # the sunlit fraction is stored as float32
    hours = [0, 6, 12]
    np.testing.assert_allclose(lit[hours], exact[hours], rtol=0, atol=tol)
    for k in range(13):
        before, w = 6 * (k // 6), (k % 6) / 6.0
        after = min(before + 6, 12)
        expected = (1.0 - w) * exact[before] + w * exact[after]
        np.testing.assert_allclose(lit[k], expected, rtol=0, atol=tol, err_msg=f"step {k}")
    # half-way between traces (14:30) cells that the moving shadow entered or left are half lit,
    # where the trace of that step has them in the sun or in the shade
    assert np.sum(np.abs(lit[3] - exact[3]) > 0.25) > 10
    # and the heat balance uses the interpolated fraction
    change = np.abs(hourly.surface_temperature.values[-1] - every_step.surface_temperature.values[-1])
    assert change.max() > 0.5
