"""Curve projection and Hausdorff distances, smooth surfaces from meshes, support functions."""

import json

import numpy as np
import pytest

import d2vdb

from conftest import icosphere, run_cli


def segment(start, end):
    return d2vdb.Curve(np.array([start, end], float), degree=1)


def test_projection_onto_a_segment():
    line = segment((0, 0, 0), (2, 0, 0))
    result = line.project([[1.0, 1.0, 0.0], [3.0, 1.0, 0.0], [0.5, 0.0, -2.0]])
    np.testing.assert_allclose(result["parameter"], [0.5, 1.0, 0.25])
    np.testing.assert_allclose(result["point"], [[1, 0, 0], [2, 0, 0], [0.5, 0, 0]])
    np.testing.assert_allclose(result["distance"], [1.0, np.sqrt(2.0), 2.0])


def test_projection_onto_a_circle_like_curve_finds_the_global_minimum():
    angles = np.linspace(0, 2 * np.pi, 16, endpoint=False)
    curve = d2vdb.Curve(np.c_[np.cos(angles), np.sin(angles), np.zeros(16)], closed=True)
    samples = curve.evaluate(np.linspace(*curve.domain, 50001))
    probes = np.random.default_rng(3).normal(size=(40, 3))
    result = curve.project(probes)
    brute = np.min(np.linalg.norm(probes[:, None] - samples[None], axis=2), axis=1)
    assert np.all(result["distance"] <= brute + 1e-12)
    np.testing.assert_allclose(result["distance"], brute, atol=1e-6)


def test_hausdorff_of_two_segments_is_exact_and_equals_the_command(tmp_path):
    a, b = segment((0, 0, 0), (1, 0, 0)), segment((0, 1, 0), (2, 1, 0))
    result = d2vdb.hausdorff(a, b)
    assert result["a_to_b"]["distance"] == pytest.approx(1.0, abs=1e-12)
    assert result["b_to_a"]["distance"] == pytest.approx(np.sqrt(2.0), abs=1e-12)
    assert result["distance"] == result["b_to_a"]["distance"]
    assert result["lower_bound"] <= np.sqrt(2.0) <= result["upper_bound"] + 1e-15
    assert result["b_to_a"]["from_point"] == (2.0, 1.0, 0.0)
    assert result["b_to_a"]["case"] == "end points"
    a.save(tmp_path / "a.json")
    b.save(tmp_path / "b.json")
    report = json.loads(run_cli("hausdorff", tmp_path / "a.json", tmp_path / "b.json", "--json").stdout)
    assert report["distance"] == result["distance"]
    one = d2vdb.hausdorff(a, b, one_sided=True)
    assert one["distance"] == result["a_to_b"]["distance"] and "b_to_a" not in one


def test_smooth_surface_of_an_icosphere_is_nearly_a_sphere(tmp_path):
    vertices, faces = icosphere(2)
    mesh = d2vdb.Mesh(vertices, faces)
    smooth = d2vdb.SmoothSurface(mesh)
    assert smooth.face_count == len(faces)
    count = len(faces)
    result = smooth.evaluate(np.arange(count), np.full((count, 3), 1.0 / 3.0))
    radii = np.linalg.norm(result["position"], axis=1)
    # The Loop limit surface of a subdivided icosahedron lies just inside its vertices' sphere.
    assert 0.9 < radii.min() and radii.max() < 1.0
    np.testing.assert_allclose(np.sum(result["normal"] * result["position"] / radii[:, None], axis=1), 1.0, atol=2e-3)
    # Loop limit surfaces are not spheres: their curvature ripples by ~13 % around the valence-5
    # vertices of an icosphere at two subdivisions (~10 % at three), while averaging 1/r.
    np.testing.assert_allclose(result["k1"], 1.0 / radii, rtol=0.15)
    np.testing.assert_allclose(result["k2"], 1.0 / radii, rtol=0.15)
    assert np.mean(0.5 * (result["k1"] + result["k2"]) * radii) == pytest.approx(1.0, abs=0.03)
    assert np.all(result["k1"] >= result["k2"])

    tessellation = smooth.tessellate(2, curvature=True)
    assert tessellation["mesh"].face_count == 16 * count and tessellation["mesh"].validate().closed
    assert len(tessellation["k1"]) == tessellation["mesh"].vertex_count
    mesh.save(tmp_path / "sphere.obj")
    run_cli("smooth", tmp_path / "sphere.obj", tmp_path / "smooth.obj", "--lod", 2)
    theirs = d2vdb.load(tmp_path / "smooth.obj")
    assert theirs.vertices.tobytes() == smooth.tessellate(2)["mesh"].vertices.tobytes()


def test_smooth_surface_refuses_open_meshes_and_bad_face_points():
    vertices, faces = icosphere(1)
    with pytest.raises(d2vdb.InputError):
        d2vdb.SmoothSurface(d2vdb.Mesh(vertices, faces[1:]))
    smooth = d2vdb.SmoothSurface(d2vdb.Mesh(vertices, faces), source="pn")
    with pytest.raises(d2vdb.InputError, match=r"face_ids\[1\] is 80"):
        smooth.evaluate([0, 80], [[1, 0, 0], [1, 0, 0]])
    with pytest.raises(d2vdb.InputError, match=r"barycentric\[0\] must be non-negative and sum to 1"):
        smooth.evaluate([0], [[0.5, 0.6, 0]])


def test_support_function_of_a_sphere_and_its_exact_offsets():
    rng = np.random.default_rng(5)
    normals = rng.normal(size=(500, 3))
    normals /= np.linalg.norm(normals, axis=1)[:, None]
    center = np.array([1.0, -0.5, 0.25])
    support = d2vdb.SupportFunction.fit(center + 2.0 * normals, normals, degree=4)
    probes = rng.normal(size=(50, 3))
    unit = probes / np.linalg.norm(probes, axis=1)[:, None]
    np.testing.assert_allclose(support.value(probes), 2.0 + unit @ center, atol=1e-9)
    np.testing.assert_allclose(support.points(probes, 0.5), center + 2.5 * unit, atol=1e-9)
    offset = support.tessellate(-0.5, subdivisions=3)
    assert offset.vertex_count == 10 * 4**3 + 2 and offset.validate().closed
    np.testing.assert_allclose(np.linalg.norm(offset.vertices - center, axis=1), 1.5, atol=1e-6)
    with pytest.raises(d2vdb.InputError, match="normals"):
        d2vdb.SupportFunction.fit(center + 2.0 * normals)


def test_certified_hausdorff_of_meshes_brackets_a_translation_and_equals_the_command(tmp_path):
    # The unit box and its copy moved by t outward at the corner (1, 1, 1): H = |t| exactly.
    corners = np.array([[x, y, z] for z in (0, 1) for y in (0, 1) for x in (0, 1)], float)
    faces = [(0, 2, 1), (1, 2, 3), (4, 5, 6), (5, 7, 6), (0, 1, 4), (1, 5, 4), (2, 6, 3),
             (3, 6, 7), (0, 4, 2), (2, 4, 6), (1, 3, 5), (3, 7, 5)]
    shift = np.array([0.125, 0.25, 0.375])
    box, moved = d2vdb.Mesh(corners, faces), d2vdb.Mesh(corners + shift, faces)
    result = d2vdb.certified_hausdorff(box, moved, tolerance=1e-9)
    assert result["lower_bound"] <= np.linalg.norm(shift) <= result["upper_bound"]
    assert result["upper_bound"] - result["lower_bound"] <= 1e-9
    assert result["a_to_b"]["point_distances"].shape == (8,)
    # Points and one direction; the same numbers as the command.
    far = d2vdb.certified_hausdorff([[0.5, 0.5, 3.0]], box, one_sided=True, tolerance=1e-9)
    assert far["lower_bound"] == pytest.approx(2.0, abs=1e-9)
    assert "b_to_a" not in far
    box.save(tmp_path / "a.obj")
    moved.save(tmp_path / "b.obj")
    report = json.loads(run_cli("hausdorff", tmp_path / "a.obj", tmp_path / "b.obj",
                                "--tolerance", "1e-9", "--json").stdout)
    assert report["lower_bound"] == result["lower_bound"]
    assert report["upper_bound"] == result["upper_bound"]
    with pytest.raises(d2vdb.InputError):
        d2vdb.certified_hausdorff(box, np.zeros((0, 3)))
