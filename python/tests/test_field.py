"""d2vdb.Field: queries against analytic spheres, curves and points, SDM forms, the command's
query answers bit for bit, files and determinism."""

import json

import numpy as np
import pytest

import d2vdb

from conftest import icosphere, run_cli

RNG = np.random.default_rng(7)


def shell_points(count, radius_low, radius_high, center=(0, 0, 0)):
    directions = RNG.normal(size=(count, 3))
    directions /= np.linalg.norm(directions, axis=1)[:, None]
    radii = RNG.uniform(radius_low, radius_high, size=count)
    return np.asarray(center) + directions * radii[:, None]


@pytest.fixture(scope="module")
def sphere_field():
    return d2vdb.Field(d2vdb.LevelSet.sphere((0, 0, 0), 1.0, voxel_size=0.02))


def test_band_queries_match_the_analytic_sphere(sphere_field):
    points = shell_points(2000, 0.97, 1.03)
    answers = sphere_field.query(points)
    radii = np.linalg.norm(points, axis=1)
    unit = points / radii[:, None]
    assert np.all(answers["status"] == 0) and np.all(answers["level"] == 0)
    np.testing.assert_allclose(answers["distance"], radii - 1.0, atol=0.05 * 0.02)
    np.testing.assert_allclose(answers["footpoint"], unit, atol=0.05 * 0.02)
    np.testing.assert_allclose(answers["normal"], unit, atol=2e-3)
    np.testing.assert_allclose(answers["k1"], 1.0, rtol=0.02)
    np.testing.assert_allclose(answers["k2"], 1.0, rtol=0.02)
    assert np.all(np.abs(np.sum(answers["e1"] * answers["normal"], axis=1)) < 1e-6)
    assert answers["distance"].dtype == np.float64 and answers["level"].dtype == np.int32


def test_coarse_levels_answer_beyond_the_band_within_their_bound(sphere_field):
    points = shell_points(500, 1.2, 1.9)
    answers = sphere_field.query(points)
    assert np.all(answers["level"] > 0)
    radii = np.linalg.norm(points, axis=1)
    np.testing.assert_allclose(answers["distance"], radii - 1.0, rtol=0.02, atol=0.01)


def test_outside_the_domain_has_status_1_and_nan(sphere_field):
    answers = sphere_field.query([[10.0, 0, 0], [0, 0, 1.0]])
    assert list(answers["status"]) == [1, 0] and list(answers["level"])[0] == -1
    assert np.isnan(answers["distance"][0]) and np.all(np.isnan(answers["footpoint"][0]))
    with pytest.raises(d2vdb.InputError, match=r"points\[0\]: the point \(10, 0, 0\) lies"):
        sphere_field.sdm_form([[10.0, 0, 0]])


def test_sdm_form_gives_the_squared_distance_at_its_point(sphere_field):
    points = shell_points(300, 0.95, 1.05)
    A, b, c = sphere_field.sdm_form(points)
    assert A.shape == (300, 3, 3) and b.shape == (300, 3) and c.shape == (300,)
    np.testing.assert_allclose(A, np.transpose(A, (0, 2, 1)), atol=1e-12)
    assert np.all(np.linalg.eigvalsh(A) > -1e-12)
    # Q(x) = x.A x - 2 b.x + c is d(x)^2 at the point the form was taken at.
    q = np.einsum("ni,nij,nj->n", points, A, points) - 2 * np.sum(b * points, axis=1) + c
    distance = sphere_field.query(points)["distance"]
    np.testing.assert_allclose(q, distance**2, rtol=1e-4, atol=1e-12)
    np.testing.assert_allclose(np.sqrt(q), np.abs(np.linalg.norm(points, axis=1) - 1.0), atol=1e-3)


def test_point_set_field_finds_the_nearest_point():
    cloud = RNG.uniform(-1, 1, size=(400, 3))
    field = d2vdb.Field(d2vdb.PointSet(cloud), voxel_size=0.05)
    assert field.kind == "points" and field.of == "points"
    probes = cloud[:50] + RNG.normal(scale=0.01, size=(50, 3))
    answers = field.query(probes)
    # Each answer is a point of the cloud (footpoints stored at float precision) and its
    # distance; the point is the nearest to the query's voxel centre, so it is never nearer than
    # the nearest point and at most a voxel diagonal (2 x half of it) farther.
    gap = np.min(np.linalg.norm(answers["footpoint"][:, None] - cloud[None], axis=2), axis=1)
    assert np.max(gap) < 1e-5
    np.testing.assert_allclose(answers["distance"], np.linalg.norm(probes - answers["footpoint"], axis=1), atol=1e-5)
    brute = np.min(np.linalg.norm(probes[:, None] - cloud[None], axis=2), axis=1)
    assert np.all(answers["distance"] >= brute - 1e-5)
    assert np.all(answers["distance"] <= brute + np.sqrt(3) * 0.05)
    assert np.mean(np.abs(answers["distance"] - brute) < 1e-5) > 0.9
    # A bare (N, 3) array is a point set too.
    again = d2vdb.Field(cloud, voxel_size=0.05).query(probes)
    assert again["distance"].tobytes() == answers["distance"].tobytes()


def test_curve_field_of_a_circle():
    # A closed quadratic B-spline is not a circle; compare against the curve's own samples.
    angles = np.linspace(0, 2 * np.pi, 12, endpoint=False)
    control = np.c_[np.cos(angles), np.sin(angles), np.zeros(12)]
    curve = d2vdb.Curve(control, degree=3, closed=True)
    field = d2vdb.Field(curve, voxel_size=0.02)
    assert field.kind == "curve"
    samples = curve.evaluate(np.linspace(*curve.domain, 20000))
    probes = samples[::997] + np.array([0.0, 0.0, 0.03])
    answers = field.query(probes)
    brute = np.min(np.linalg.norm(probes[:, None] - samples[None], axis=2), axis=1)
    np.testing.assert_allclose(answers["distance"], brute, atol=1e-4)


def test_queries_equal_the_commands_batch_answers_bit_for_bit(tmp_path):
    vertices, faces = icosphere(3)
    mesh = d2vdb.Mesh(vertices, faces)
    mesh_file, field_file = tmp_path / "sphere.obj", tmp_path / "field.vdb"
    mesh.save(mesh_file)
    run_cli("field", mesh_file, field_file, "--resolution", 64)
    points = shell_points(64, 0.8, 1.4)
    np.savetxt(tmp_path / "points.xyz", points, fmt="%.17g")
    run_cli("query", field_file, "--points", tmp_path / "points.xyz", "--out", tmp_path / "answers.json")
    records = json.loads((tmp_path / "answers.json").read_text())["points"]
    assert all(record["status"] == "ok" for record in records)
    theirs_distance = np.array([record["distance"] for record in records])

    ours = d2vdb.Field(mesh, resolution=64)
    loaded = d2vdb.load(field_file)
    assert isinstance(loaded, d2vdb.Field) and loaded.of == "field"
    for field in (ours, loaded):
        answers = field.query(points)
        assert answers["distance"].tobytes() == theirs_distance.tobytes()
    A, b, c = ours.sdm_form(points)
    theirs_c = np.array([record["forms"]["sdm"]["c"] for record in records])
    theirs_A = np.array([record["forms"]["sdm"]["A"] for record in records])
    assert A.tobytes() == theirs_A.tobytes()
    assert c.tobytes() == theirs_c.tobytes()


def test_field_file_round_trip(tmp_path, sphere_field):
    sphere_field.save(tmp_path / "field.vdb")
    loaded = d2vdb.load(tmp_path / "field.vdb")
    points = shell_points(500, 0.97, 1.03)
    a, b = sphere_field.query(points), loaded.query(points)
    for key in ("distance", "footpoint", "normal", "k1", "k2", "e1", "flags", "level"):
        assert a[key].tobytes() == b[key].tobytes(), key


def test_field_queries_do_not_depend_on_the_thread_count(sphere_field):
    points = shell_points(5000, 0.5, 1.8)
    one, two = sphere_field.query(points, threads=1), sphere_field.query(points, threads=2)
    for key in one:
        assert one[key].tobytes() == two[key].tobytes(), key
    vertices, faces = icosphere(2)
    f1 = d2vdb.Field(d2vdb.Mesh(vertices, faces), resolution=48, threads=1)
    f2 = d2vdb.Field(d2vdb.Mesh(vertices, faces), resolution=48, threads=2)
    assert f1.query(points)["distance"].tobytes() == f2.query(points)["distance"].tobytes()


def test_bad_targets_and_points():
    with pytest.raises(d2vdb.InputError, match="pass d2vdb.load"):
        d2vdb.Field("sphere.obj")
    with pytest.raises(d2vdb.InputError, match=r"target points must have shape \(N, 3\)"):
        d2vdb.Field(np.zeros((4, 2)))
    field = d2vdb.Field(d2vdb.LevelSet.sphere((0, 0, 0), 1.0, voxel_size=0.1))
    with pytest.raises(d2vdb.InputError, match=r"points\[1, 0\] is nan"):
        field.query([[0, 0, 0], [np.nan, 0, 0]])
    with pytest.raises(d2vdb.InputError, match="smooth must be"):
        d2vdb.Field(d2vdb.Mesh(*icosphere(1)), smooth="catmull")
