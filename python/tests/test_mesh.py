"""d2vdb.Mesh: arrays in and out, the validation report, files, and bad input."""

import numpy as np
import pytest

import d2vdb

from conftest import icosphere


def test_mesh_from_arrays_keeps_vertices_and_faces(sphere_arrays):
    vertices, faces = sphere_arrays
    mesh = d2vdb.Mesh(vertices, faces)
    assert mesh.vertex_count == len(vertices) and mesh.face_count == len(faces)
    np.testing.assert_array_equal(mesh.vertices, vertices.astype(np.float32))
    np.testing.assert_array_equal(mesh.faces, faces)
    assert mesh.vertices.dtype == np.float32 and mesh.faces.dtype == np.uint32
    assert not mesh.vertices.flags.writeable
    assert mesh.normals is None


def test_icosphere_report_is_closed_genus_zero(sphere_arrays):
    report = d2vdb.Mesh(*sphere_arrays).validate()
    # 10 * 4^3 + 2 vertices, 20 * 4^3 faces, 30 * 4^3 edges: Euler characteristic 2.
    assert (report.vertex_count, report.triangle_count, report.edge_count) == (642, 1280, 1920)
    assert report.closed and report.manifold and report.oriented
    assert report.euler_characteristic == 2 and report.connected_component_count == 1
    assert report.boundary_edge_count == 0 and report.problems == ""


def test_open_mesh_report_counts_the_hole(sphere_arrays):
    vertices, faces = sphere_arrays
    report = d2vdb.Mesh(vertices, faces[1:]).validate()
    assert not report.closed
    assert report.boundary_edge_count == 3 and report.boundary_loop_count == 1
    assert "boundary" in report.problems


def test_any_array_like_is_accepted(sphere_arrays):
    vertices, faces = sphere_arrays
    reference = d2vdb.Mesh(vertices, faces)
    fortran = np.asfortranarray(vertices.astype(np.float32))
    strided = np.repeat(vertices, 2, axis=0)[::2]
    for variant in (fortran, strided, vertices.tolist()):
        mesh = d2vdb.Mesh(variant, faces.astype(np.int32))
        np.testing.assert_array_equal(mesh.vertices, reference.vertices)
    mesh = d2vdb.Mesh(vertices, np.asfortranarray(faces.astype(np.uint16)))
    np.testing.assert_array_equal(mesh.faces, reference.faces)


@pytest.mark.parametrize(
    "change, message",
    [
        (lambda v, f: (np.where(np.arange(v.size).reshape(v.shape) == 31, np.nan, v), f),
         r"vertices\[10, 1\] is nan"),
        (lambda v, f: (np.where(np.arange(v.size).reshape(v.shape) == 5, np.inf, v), f),
         r"vertices\[1, 2\] is inf"),
        (lambda v, f: (v, np.where(np.arange(f.size).reshape(f.shape) == 7, -1, f)),
         r"faces\[2, 1\] is -1"),
        (lambda v, f: (v, np.where(np.arange(f.size).reshape(f.shape) == 3, len(v), f)),
         r"faces\[1, 0\] is 642; vertex indices must lie in \[0, 642\)"),
        (lambda v, f: (v[:, :2], f), r"vertices must have shape \(N, 3\); it has shape \(642, 2\)"),
        (lambda v, f: (v, f.reshape(-1)), r"faces must have shape \(M, 3\)"),
        (lambda v, f: (v, f.astype(float)), r"faces must hold integer vertex indices"),
    ],
)
def test_bad_arrays_are_refused_naming_the_first_bad_element(sphere_arrays, change, message):
    vertices, faces = change(*sphere_arrays)
    with pytest.raises(d2vdb.InputError, match=message):
        d2vdb.Mesh(vertices, faces)


def test_input_error_is_a_value_error():
    assert issubclass(d2vdb.InputError, ValueError)
    assert issubclass(d2vdb.RuntimeFailure, RuntimeError)


@pytest.mark.parametrize("extension", ["obj", "ply", "stl"])
def test_save_and_load_read_back_bit_for_bit(tmp_path, sphere_arrays, extension):
    mesh = d2vdb.Mesh(*sphere_arrays)
    path = tmp_path / f"sphere.{extension}"
    mesh.save(path)
    loaded = d2vdb.load(path)
    assert isinstance(loaded, d2vdb.Mesh)
    if extension == "stl":  # STL stores triangle corners: same triangles, vertices merged
        corners = loaded.vertices[loaded.faces.reshape(-1)]
        np.testing.assert_array_equal(corners, mesh.vertices[mesh.faces.reshape(-1)])
    else:
        np.testing.assert_array_equal(loaded.vertices, mesh.vertices)
        np.testing.assert_array_equal(loaded.faces, mesh.faces)


def test_failed_save_keeps_the_existing_file(tmp_path, sphere_arrays):
    path = tmp_path / "keep.obj"
    path.write_text("v 0 0 0\n")
    with pytest.raises(d2vdb.InputError):
        d2vdb.Mesh(np.zeros((0, 3)), np.zeros((0, 3), np.int64)).save(path)
    assert path.read_text() == "v 0 0 0\n"


def test_bounding_box(sphere_arrays):
    (low, high) = d2vdb.Mesh(*icosphere(1, radius=2.0)).bounding_box
    np.testing.assert_allclose(low, (-2, -2, -2), atol=1e-6)
    np.testing.assert_allclose(high, (2, 2, 2), atol=1e-6)
