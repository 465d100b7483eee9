"""Objects in motion (docs/simulation.md): spline paths, attitudes along the path, tabulated
6-DOF track files, terrain following, parts that spin and ride on a parent — through
``radscene.Simulation`` and ``radscene render``, against closed forms."""

from __future__ import annotations

import numpy as np
import pytest
import yaml
from scipy.interpolate import CubicSpline
from typer.testing import CliRunner

import radscene
from radscene.cli import app
from radscene.errors import ConfigError
from radscene.geometry import rotation_matrix

#: Poses are closed-form arithmetic on float64 [m] and [deg].
EXACT = 1e-9
#: A 13-point spline around a circle of radius 50 m: its tangent against the circle's [deg].
CIRCLE_TANGENT = 0.5


def _scene(*objects, terrain=None):
    scene = {
        "name": "motion",
        "environment": {"sun": {"zenith": 30.0}, "atmosphere": {"type": "none"}},
        "materials": {"grey": {"reflectance": 0.3}, "paint": {"reflectance": 0.8}},
        "objects": list(objects) or [{"name": "ground", "shape": {"type": "plate", "width": 400, "length": 400},
                                      "material": "grey", "temperature": "290 K"}],
        "bands": [{"name": "vis", "min": 0.5, "max": 0.6}],
        "observers": [{"name": "map", "type": "orthographic", "center": [0, 0], "gsd": 1.0, "shape": [32, 32],
                       "altitude": 1000}],
        "render": {"sky_samples": 1, "shadows": False, "background_bounces": 0},
    }
    if terrain is not None:
        scene["terrain"] = terrain
    return scene


def _mover(trajectory, **extra):
    return {"name": "mover", "shape": {"type": "box", "size": [1, 2, 1]}, "material": "paint",
            "temperature": "300 K", "on_ground": False, "trajectory": trajectory, **extra}


def _poses(scene, name, times):
    """(positions, attitudes) of ``name`` at ``times`` [s], stepping a simulation."""
    sim = radscene.Simulation(scene)
    out = []
    for t in times:
        if t > sim.elapsed:
            sim.step(t - sim.elapsed)
        out.append(sim.pose(name))
    return np.array([p for p, _ in out]), np.array([a for _, a in out])


def _forward(attitudes):
    return np.array([rotation_matrix(*a)[:, 1] for a in attitudes])


def test_a_spline_through_points_of_a_cubic_is_that_cubic():
    knots = np.array([0.0, 1.0, 2.5, 4.0, 5.0])

    def cubic(t):
        return np.stack([t**3 - 2 * t, 2 * t**2 - t**3 / 5, 10 + t], axis=-1)

    waypoints = [[t, *cubic(t)] for t in knots]
    times = [0.5, 1.7, 3.2, 4.9]
    spline = _scene(_scene()["objects"][0], _mover({"waypoints": waypoints, "interpolation": "spline"}))
    got, _ = _poses(spline, "mover", times)
    np.testing.assert_allclose(got, cubic(np.array(times)), rtol=0, atol=EXACT)
    # straight lines between the same points miss it
    linear = _scene(_scene()["objects"][0], _mover({"waypoints": waypoints}))
    straight, _ = _poses(linear, "mover", [0.5])
    np.testing.assert_allclose(straight[0], (cubic(0.0) + cubic(1.0)) / 2, rtol=0, atol=EXACT)


def test_an_object_on_a_circle_spline_points_along_its_tangent_and_climbs_with_it():
    """13 points on a helix of radius 50 m climbing 1 m per 30 deg: forward is the spline's
    tangent (scipy's not-a-knot CubicSpline, independently), within 0.5 deg the circle's."""
    angle = np.radians(np.arange(0, 361, 30))
    t = np.arange(angle.size) * 10.0
    points = np.column_stack([50 * np.cos(angle), 50 * np.sin(angle), 20 + np.arange(angle.size)])
    scene = _scene(_scene()["objects"][0],
                   _mover({"waypoints": np.column_stack([t, points]).tolist(), "interpolation": "spline",
                           "attitude": "path"}))
    times = np.array([15.0, 47.0, 93.0])
    positions, attitudes = _poses(scene, "mover", times)
    velocity = CubicSpline(t, points, bc_type="not-a-knot")(times, 1)
    np.testing.assert_allclose(_forward(attitudes), velocity / np.linalg.norm(velocity, axis=1)[:, None],
                               rtol=0, atol=EXACT)
    np.testing.assert_allclose(attitudes[:, 2], 0.0, atol=EXACT)  # no bank
    phase = np.arctan2(positions[:, 1], positions[:, 0])
    circle = np.column_stack([-np.sin(phase), np.cos(phase)])  # counter-clockwise tangent
    horizontal = _forward(attitudes)[:, :2] / np.linalg.norm(_forward(attitudes)[:, :2], axis=1)[:, None]
    off = np.degrees(np.arccos(np.clip(np.sum(horizontal * circle, axis=1), -1, 1)))
    assert np.all(off < CIRCLE_TANGENT)
    # the climb: 1 m per 30 deg of a 50 m circle
    np.testing.assert_allclose(attitudes[:, 1], np.degrees(np.arctan(1 / (50 * np.radians(30)))), atol=0.05)


#: Banking: the coordinated-turn roll of a 37-point spline around a circle against the
#: circle's atan(V² / (g r)) [deg] (the spline's curvature is the circle's within 0.1 %).
BANK_TOLERANCE = 0.1


@pytest.mark.parametrize("direction", [1.0, -1.0], ids=["left-hand", "right-hand"])
def test_an_aircraft_on_a_circle_banks_into_the_turn_as_in_coordinated_flight(direction):
    """Level flight at 60 m/s round a circle of radius 400 m (counter-clockwise seen from above:
    a left-hand turn; clockwise: right-hand): roll atan(V² / (g r)) = 42.5 deg, left wing down
    in a left-hand turn, right wing down in a right-hand one; the same path with attitude
    'path' does not roll, and a straight leg does not either."""
    radius, speed = 400.0, 60.0
    angle = np.radians(np.arange(0, 361, 10)) * direction
    t = np.abs(angle) * radius / speed
    points = np.column_stack([radius * np.cos(angle), radius * np.sin(angle), np.full(angle.size, 300.0)])
    path = {"waypoints": np.column_stack([t, points]).tolist(), "interpolation": "spline"}
    times = t[[9, 18, 27]] + 1.0
    _, banked = _poses(_scene(_scene()["objects"][0], _mover({**path, "attitude": "banked"})), "mover", times)
    want = np.degrees(np.arctan(speed**2 / (9.80665 * radius)))
    np.testing.assert_allclose(banked[:, 2], -direction * want, atol=BANK_TOLERANCE)
    np.testing.assert_allclose(banked[:, 1], 0.0, atol=BANK_TOLERANCE)  # level
    _, flat = _poses(_scene(_scene()["objects"][0], _mover({**path, "attitude": "path"})), "mover", times)
    np.testing.assert_allclose(flat[:, 2], 0.0, atol=EXACT)
    np.testing.assert_allclose(banked[:, 0], flat[:, 0], atol=EXACT)  # the same heading
    straight = {"waypoints": [[0, 0, 0, 300], [10, 0, 600, 300], [20, 0, 1200, 300]],
                "interpolation": "spline", "attitude": "banked"}
    _, level = _poses(_scene(_scene()["objects"][0], _mover(straight)), "mover", [5.0])
    np.testing.assert_allclose(level[0], [0.0, 0.0, 0.0], atol=EXACT)


def test_a_banked_attitude_on_the_ground_is_refused_naming_the_key():
    vehicle = {"name": "truck", "shape": {"type": "box", "size": [2, 4, 2]}, "material": "paint",
               "temperature": "300 K", "on_ground": True,
               "trajectory": {"route": [[-50, 0], [50, 0]], "speed": "10 m/s", "attitude": "banked"}}
    with pytest.raises(ConfigError, match="airborne") as err:
        radscene.Simulation(_scene(_scene()["objects"][0], vehicle)).render()
    assert err.value.key.endswith("trajectory.attitude")


def test_a_banked_wing_tilts_in_the_image():
    """A wide flat wing (20 m span, 2 m chord) seen from straight above on a right-hand circle:
    banked, its footprint in the map (the object-id truth map) is narrowed to its span times
    cos(roll), plus its thickness times sin(roll), within two pixels."""
    radius, speed = 60.0, 30.0
    angle = -np.radians(np.arange(0, 361, 10))
    t = np.abs(angle) * radius / speed
    points = np.column_stack([radius * np.cos(angle), radius * np.sin(angle), np.full(angle.size, 100.0)])
    wing = {"name": "mover", "shape": {"type": "box", "size": [20, 2, 0.2]}, "material": "paint",
            "temperature": "300 K", "on_ground": False,
            "trajectory": {"waypoints": np.column_stack([t, points]).tolist(),
                           "interpolation": "spline", "attitude": "banked"}}
    scene = _scene(_scene()["objects"][0], wing)
    scene["observers"][0].update(shape=[200, 200], gsd=0.25)
    # at t = 0 the wing is at (60, 0) flying south (clockwise): its span lies along x
    scene["observers"][0]["center"] = [60.0, 0.0]
    sim = radscene.Simulation(scene)
    _, attitude = sim.pose("mover")
    roll = np.radians(attitude[2])
    assert np.degrees(roll) > 50.0  # atan(30² / (9.81 × 60)) = 56.8 deg
    frame = sim.render().radiance["map"]
    ids = np.asarray(frame["object_id"].values)
    wing_id = int(ids[100, 100])  # the map's centre is the wing's
    assert wing_id != int(ids[0, 0])
    covered = ids == wing_id
    rows = np.nonzero(covered.any(axis=1))[0]
    cols = np.nonzero(covered.any(axis=0))[0]
    span_px = cols.max() - cols.min() + 1
    assert abs(span_px * 0.25 - 20.0 * np.cos(roll) - 0.2 * np.sin(roll)) <= 0.5, (span_px, np.degrees(roll))
    assert rows.size >= 4


def test_waypoint_attitudes_are_slerped_and_rotation_turns_the_model_on_top():
    scene = _scene(_scene()["objects"][0],
                   _mover({"waypoints": [[0, 0, 0, 5, 0, 0, 0], [10, 10, 0, 5, 90, 0, 0]]}, rotation=[0, 0, 30]))
    _, attitudes = _poses(scene, "mover", [5.0])
    np.testing.assert_allclose(attitudes[0], [45.0, 0.0, 30.0], atol=EXACT)


@pytest.mark.parametrize("attitude_columns, row", [
    (("yaw [deg]", "pitch [deg]", "roll [deg]"), lambda yaw: [yaw, 0, 0]),
    (("qw", "qx", "qy", "qz"), lambda yaw: [np.cos(np.radians(yaw) / 2), 0, 0, -np.sin(np.radians(yaw) / 2)]),
])
def test_a_track_file_gives_interpolated_positions_and_slerped_attitudes(tmp_path, attitude_columns, row):
    """Times in ms and positions in km are converted; the quaternion of yaw ψ (clockwise from
    north, about -z) is (cos ψ/2, 0, 0, -sin ψ/2)."""
    lines = ["# a 6-DOF track", ", ".join(("time [ms]", "x [km]", "y [m]", "z [m]", *attitude_columns))]
    for t, x, yaw in ((0, 0.0, 0.0), (4000, 0.1, 60.0), (8000, 0.3, 120.0)):
        lines.append(", ".join(map(str, [t, x, 0, 7, *row(yaw)])))
    (tmp_path / "track.csv").write_text("\n".join(lines) + "\n")
    scene = _scene(_scene()["objects"][0], _mover({"file": "track.csv"}))
    path = tmp_path / "scene.yaml"
    path.write_text(yaml.safe_dump(scene))
    positions, attitudes = _poses(path, "mover", [2.0, 6.0])
    np.testing.assert_allclose(positions, [[50.0, 0, 7], [200.0, 0, 7]], atol=EXACT)
    np.testing.assert_allclose(attitudes[:, 0], [30.0, 90.0], atol=1e-6)


def test_a_netcdf_track_reads_like_a_csv(tmp_path):
    import xarray as xr

    ds = xr.Dataset({"time": ("sample", [0.0, 10.0], {"units": "s"}),
                     "x": ("sample", [0.0, 20.0], {"units": "m"}), "y": ("sample", [0.0, 0.0], {"units": "m"}),
                     "z": ("sample", [3.0, 3.0], {"units": "m"})})
    ds.to_netcdf(tmp_path / "track.nc", engine="h5netcdf")
    scene = _scene(_scene()["objects"][0], _mover({"file": str(tmp_path / "track.nc"), "attitude": "path"}))
    positions, attitudes = _poses(scene, "mover", [5.0])
    np.testing.assert_allclose(positions[0], [10.0, 0.0, 3.0], atol=EXACT)
    np.testing.assert_allclose(attitudes[0], [90.0, 0.0, 0.0], atol=EXACT)


GOOD = "time [s], x [m], y [m], z [m]\n0, 0, 0, 0\n1, 1, 0, 0\n2, 2, 0, 0\n"


@pytest.mark.parametrize("text, match", [
    ("time [s], x [m], y [m]\n0, 0, 0\n1, 1, 0\n", r"missing column 'z'"),
    (GOOD.replace("2, 2", "0.5, 2"), r"row 3 \(line 4\): time 0.5 s does not follow 1 s"),
    (GOOD.replace("2, 2", "1, 2"), r"row 3 \(line 4\): time 1 s does not follow 1 s"),
    (GOOD.replace("1, 1", "1, one"), r"row 2 \(line 3\), column 'x': not a number"),
    (GOOD.replace("y [m]", "y [s]"), r"column 'y': its unit is not one of length"),
    (GOOD.replace("x [m]", "x"), r"column 'x' has no unit; write it as 'x \[m\]'"),
    (GOOD.replace("1, 1, 0, 0", "1, 1, 0"), r"row 2 \(line 3\) has 3 values for 4 columns"),
])
def test_bad_track_files_are_one_line_naming_the_key_and_row(tmp_path, text, match):
    (tmp_path / "track.csv").write_text(text)
    scene = _scene(_scene()["objects"][0], _mover({"file": "track.csv"}))
    with pytest.raises(ConfigError, match=r"^objects\[1\]\.trajectory\.file: track\.csv: " + ".*" + match):
        radscene.load_scene(scene, base_dir=tmp_path)


def test_the_cli_refuses_a_bad_track_file_with_exit_2_and_one_line(tmp_path, one_line_refusal):
    (tmp_path / "track.csv").write_text(GOOD.replace("2, 2", "1, 2"))
    scene = _scene(_scene()["objects"][0], _mover({"file": "track.csv"}))
    path = tmp_path / "scene.yaml"
    path.write_text(yaml.safe_dump(scene))
    result = CliRunner().invoke(app, ["render", str(path), "-o", str(tmp_path / "out"), "--start",
                                      "2026-06-21T07:00:00Z", "--end", "2026-06-21T07:00:01Z", "--step", "1 s"])
    assert result.exit_code == 2
    one_line_refusal(result.output, "objects[1].trajectory.file: track.csv: row 3 (line 4)")


SLOPE = 10.0  # [deg]


def _tilted(rising="east"):
    """A plane terrain rising 10 deg towards the east (or the north), 5 m grid."""
    x = np.arange(-100.0, 100.1, 5.0)
    xx, yy = np.meshgrid(x, x[::-1])  # rows north first
    along = xx if rising == "east" else yy
    return {"type": "dem", "elevation": (np.tan(np.radians(SLOPE)) * along).tolist(), "spacing": [5, 5],
            "origin": [-100, -100], "material": "grey", "temperature": "290 K"}


@pytest.mark.parametrize("rising, pitch, roll", [("east", SLOPE, 0.0), ("north", 0.0, SLOPE)])
def test_a_vehicle_on_a_route_follows_the_slope_under_it(rising, pitch, roll):
    """Driven east at 10 m/s, 0.5 m above the plane: up the fall line of a plane rising east
    its pitch is the slope; across a plane rising north its left side is up (roll +slope:
    positive roll lowers the right side)."""
    vehicle = {"name": "truck", "shape": {"type": "box", "size": [2, 5, 2]}, "material": "paint",
               "temperature": "300 K", "trajectory": {"route": [[-50, 10, 0.5], [50, 10, 0.5]], "speed": "36 km/h",
                                                      "attitude": "path"}}
    positions, attitudes = _poses(_scene(vehicle, terrain=_tilted(rising)), "truck", [0.0, 3.0])
    height = np.tan(np.radians(SLOPE)) * (positions[:, 0] if rising == "east" else positions[:, 1])
    np.testing.assert_allclose(positions[:, 0], [-50.0, -20.0], atol=EXACT)
    np.testing.assert_allclose(positions[:, 2], height + 0.5, atol=EXACT)
    np.testing.assert_allclose(attitudes, [[90.0, pitch, roll]] * 2, atol=EXACT)


def _rotor_scene(parent_trajectory=None):
    hub = {"name": "hub", "shape": {"type": "box", "size": [2, 2, 2]}, "material": "grey", "temperature": "300 K",
           "on_ground": False, "position": [0, 0, 10]}
    if parent_trajectory is not None:
        hub["trajectory"] = parent_trajectory
    blade = {"name": "blade", "shape": {"type": "plate", "width": 2, "length": 24}, "material": "paint",
             "temperature": "300 K", "parent": "hub", "position": [0, 0, 1.5],
             "spin": {"axis": [0, 0, 1], "rate": "60 rpm"}}
    return _scene(_scene()["objects"][0], hub, blade)


def test_a_spinning_blade_is_turned_90_deg_a_quarter_turn_later_in_the_image():
    """60 rpm: T = 1 s. Seen from nadir the blade lies north-south at t = 0.5 s (half a turn),
    east-west at t + T/4: its mask is the first one turned by 90 deg."""
    sim = radscene.Simulation(_rotor_scene())
    first = sim.step(0.5).radiance["map"]
    second = sim.step(0.25).radiance["map"]
    ids = {o.name: k for k, o in enumerate(sim.scene.objects)}
    mask0 = first.object_id.values == ids["blade"]
    mask1 = second.object_id.values == ids["blade"]
    assert mask0.sum() == 2 * 24 - 4  # the hub's 2 x 2 m hides the middle of the 2 m x 24 m blade
    np.testing.assert_array_equal(np.rot90(mask0), mask1)
    _, a0 = sim.pose("blade")
    # 0.75 turn counter-clockwise seen from above: the model's north (+y) axis points east
    np.testing.assert_allclose(a0, [90.0, 0.0, 0.0], atol=EXACT)


def test_a_part_rides_on_its_moving_parent_and_only_what_moved_is_refitted():
    sim = radscene.Simulation(_rotor_scene({"waypoints": [[0, 0, 0, 10, 0, 0, 0], [4, 40, 0, 14, 90, 0, 0]]}))
    updated = []
    move = sim.tracer.move  # the simulation writes what moved with one move() a frame
    sim.tracer.move = lambda meshes: (updated.extend(meshes), move(meshes))
    sim.step(2.0)
    hub_position, hub_attitude = sim.pose("hub")
    blade_position, blade_attitude = sim.pose("blade")
    np.testing.assert_allclose(hub_position, [20.0, 0.0, 12.0], atol=EXACT)
    np.testing.assert_allclose(hub_attitude, [45.0, 0.0, 0.0], atol=EXACT)
    np.testing.assert_allclose(blade_position, hub_position + [0, 0, 1.5], atol=EXACT)
    np.testing.assert_allclose(blade_attitude, [(45.0 - 2 * 360.0) % 360.0, 0.0, 0.0], atol=1e-6)
    names = [sim.scene.objects[k].name for k in updated]
    assert sorted(names) == ["blade", "hub"]  # the ground is not touched
    # set_pose of the parent carries the part along at once
    sim.set_pose("hub", position=(0.0, 50.0, 30.0), attitude=(0.0, 0.0, 0.0))
    np.testing.assert_allclose(sim.pose("blade")[0], [0.0, 50.0, 31.5], atol=EXACT)


@pytest.mark.parametrize("change, match", [
    ({"parent": "nobody"}, r"objects\[2\]\.parent: unknown object 'nobody'"),
    ({"on_ground": True}, r"objects\[2\]\.on_ground: a part's position is in its parent's frame"),
    ({"trajectory": {"waypoints": [[0, 0, 0, 0], [1, 1, 0, 0]]}}, r"objects\[2\]\.trajectory: a part moves with"),
    ({"spin": {"axis": [0, 0, 0], "rate": "1 rpm"}}, r"objects\[2\]\.spin\.axis"),
    ({"spin": {"axis": [0, 0, 1], "rate": "1 m/s"}}, r"unknown angular_speed unit 'm/s'"),
])
def test_bad_parts_are_refused_naming_the_key(change, match):
    scene = _rotor_scene()
    scene["objects"][2].update(change)
    with pytest.raises(ConfigError, match=match):
        radscene.load_scene(scene)


def test_a_loop_of_parents_is_refused():
    scene = _rotor_scene()
    scene["objects"][1]["parent"] = "blade"
    with pytest.raises(ConfigError, match=r"objects\[\d\]\.parent: .* is a loop"):
        radscene.load_scene(scene)


def _sequence_file(tmp_path, video=None):
    scene = _rotor_scene()
    scene["environment"] = {"time": "2026-06-21T07:00:00Z", "location": {"latitude": 45.0, "longitude": 5.0},
                            "atmosphere": {"type": "none"}}
    scene["observers"][0]["shape"] = [31, 32]  # an odd height: padded for H.264
    if video is not None:
        scene["render"]["video"] = video
    path = tmp_path / "rotor.yaml"
    path.write_text(yaml.safe_dump(scene))
    return path


SPAN = ["--start", "2026-06-21T07:00:00Z", "--end", "2026-06-21T07:00:00.5Z", "--step", "250 ms"]


def test_a_sequence_writes_a_3_frame_mp4_per_band(tmp_path):
    pytest.importorskip("imageio_ffmpeg", reason="MP4 needs imageio-ffmpeg (pip install imageio imageio-ffmpeg)")
    import imageio.v3 as iio

    out = tmp_path / "out"
    result = CliRunner().invoke(app, ["render", str(_sequence_file(tmp_path, "mp4")), "-o", str(out), *SPAN])
    assert result.exit_code == 0, result.output
    frames = iio.imread(out / "map_sequence" / "vis.mp4", plugin="FFMPEG", index=None)
    assert frames.shape[:3] == (3, 32, 32)
    assert not (out / "map_sequence" / "vis.gif").exists()
    # the blade turns a quarter between frames: the frames differ
    assert np.abs(frames[1].astype(int) - frames[0].astype(int)).max() > 100


def test_a_sequence_with_video_both_writes_gif_and_mp4_and_none_writes_neither(tmp_path, one_line_refusal):
    from radscene.io.animation import mp4_available

    if not mp4_available():
        result = CliRunner().invoke(app, ["render", str(_sequence_file(tmp_path, "both")), "-o",
                                          str(tmp_path / "out"), *SPAN])
        assert result.exit_code == 2
        one_line_refusal(result.output, "render.video: both needs imageio and imageio-ffmpeg")
        pytest.skip("imageio-ffmpeg is not installed: the refusal is what can be tested")
    out = tmp_path / "out"
    assert CliRunner().invoke(app, ["render", str(_sequence_file(tmp_path, "both")), "-o", str(out), *SPAN]).exit_code == 0
    assert sorted(p.name for p in (out / "map_sequence").iterdir()) == ["vis.gif", "vis.mp4"]
    none = tmp_path / "none"
    result = CliRunner().invoke(app, ["render", str(_sequence_file(tmp_path)), "-o", str(none), "--video", "none", *SPAN])
    assert result.exit_code == 0 and not (none / "map_sequence").exists()
    bad = CliRunner().invoke(app, ["render", str(_sequence_file(tmp_path)), "-o", str(tmp_path / "bad"), "--video",
                                   "avi", *SPAN])
    assert bad.exit_code == 2
    one_line_refusal(bad.output, "--video: unknown choice 'avi'; known: auto, gif, mp4, both, none")
