"""Moving one mesh of a ray tracer in place (RayTracer.update) against a tracer built afresh."""

from __future__ import annotations

import numpy as np
import pytest

from radscene.errors import ConfigError
from radscene.geometry import RayTracer, box, plate


def _rays(n=4000, seed=5):
    rng = np.random.default_rng(seed)
    origins = np.column_stack([rng.uniform(-60, 60, n), rng.uniform(-60, 60, n), np.full(n, 80.0)])
    targets = np.column_stack([rng.uniform(-60, 60, n), rng.uniform(-60, 60, n), np.zeros(n)])
    return origins, targets - origins


@pytest.mark.parametrize("dynamic", [True, False])
@pytest.mark.parametrize("packets", [True, False])
def test_a_moved_mesh_is_hit_where_a_fresh_tracer_hits_it(dynamic, packets):
    ground = plate(120.0, 120.0)
    cube = box((8.0, 8.0, 8.0))
    tracer = RayTracer([ground, cube], dynamic=dynamic, packets=packets)
    origins, directions = _rays()
    before = tracer.intersect(origins, directions)
    # moved 30 m east, turned 30 deg and lifted 100 m: beyond the first clipping box
    for moved in (cube.transformed(translation=(30.0, -10.0, 0.0), rotation=(30.0, 0.0, 0.0)),
                  cube.transformed(translation=(0.0, 0.0, 100.0))):
        tracer.update(1, moved)
        fresh = RayTracer([ground, moved], packets=packets)
        got, want = tracer.intersect(origins, directions), fresh.intersect(origins, directions)
        np.testing.assert_array_equal(got.object, want.object)
        np.testing.assert_array_equal(got.primitive, want.primitive)
        np.testing.assert_allclose(got.distance[got.hit], want.distance[want.hit], rtol=0, atol=1e-3)
        np.testing.assert_array_equal(got.normal, want.normal)
        t_max = np.full(len(origins), 75.0)
        np.testing.assert_array_equal(tracer.occluded(origins, directions, t_max),
                                      fresh.occluded(origins, directions, t_max))
        assert np.any(got.object != before.object)  # the move changed what the rays hit
    np.testing.assert_array_equal(tracer.bounds[1], [60.0, 60.0, 108.0])


def test_update_refuses_another_topology_and_unknown_meshes():
    tracer = RayTracer([plate(10.0, 10.0), box((1.0, 1.0, 1.0))], dynamic=True)
    with pytest.raises(ConfigError, match="must keep its 8 vertices and 12 faces"):
        tracer.update(1, plate(1.0, 1.0))
    with pytest.raises(ConfigError, match="no mesh 2; the tracer holds 2"):
        tracer.update(2, box((1.0, 1.0, 1.0)))
