"""d2vdb.LevelSet: primitives and meshes against analytic distances, the command's own files bit
for bit, marching cubes, files and determinism."""

import numpy as np
import pytest

import d2vdb

from conftest import icosphere, run_cli


def dense_values(level_set):
    """The grid's values over its active bounding box, through pyopenvdb (an independent reader)."""
    grid = level_set.to_openvdb()
    low, high = grid.evalActiveVoxelBoundingBox()
    values = np.zeros(tuple(h - l + 1 for l, h in zip(low, high)), np.float32)
    grid.copyToArray(values, ijk=low)
    return low, values


def band_points(level_set):
    """World centres of the active voxels (pyopenvdb's iterator) and their values."""
    grid = level_set.to_openvdb()
    voxel = level_set.voxel_size
    points, values = [], []
    for item in grid.citerOnValues():
        if item["count"] == 1:
            points.append(np.array(item["min"], float) * voxel)
            values.append(item["value"])
    return np.array(points), np.array(values)


def test_sphere_band_holds_exact_distances():
    sphere = d2vdb.LevelSet.sphere((0.1, -0.2, 0.3), 1.0, voxel_size=0.05)
    assert sphere.signed and sphere.voxel_size == 0.05 and sphere.half_width == 3.0
    points, values = band_points(sphere)
    assert len(points) == sphere.active_voxel_count > 0
    exact = np.linalg.norm(points - (0.1, -0.2, 0.3), axis=1) - 1.0
    np.testing.assert_allclose(values, exact, atol=1e-6)
    assert np.all(np.abs(exact) < 3 * 0.05 + 1e-9)


def test_values_interpolate_the_grid():
    box = d2vdb.LevelSet.box((-1, -1, -1), (1, 1, 1), voxel_size=0.1)
    points = np.array([[0.0, 0.0, 1.0], [0.0, 0.0, 1.05], [0.0, 0.0, 0.93], [0.5, 0.2, -1.02]])
    np.testing.assert_allclose(box.values(points), [0.0, 0.05, -0.07, 0.02], atol=1e-6)
    assert box.values(np.array([[0.0, 0.0, 0.0]]))[0] == pytest.approx(-0.3)  # inside: -background


def test_primitives_equal_the_commands_bit_for_bit(tmp_path):
    out = tmp_path / "torus.vdb"
    run_cli("primitive", "torus", out, "--major", 1.0, "--minor", 0.3, "--voxel-size", 0.04)
    ours = d2vdb.LevelSet.torus((0, 0, 0), 1.0, 0.3, voxel_size=0.04)
    theirs = d2vdb.load(out)
    assert isinstance(theirs, d2vdb.LevelSet)
    assert theirs.active_voxel_count == ours.active_voxel_count
    low_ours, ours_values = dense_values(ours)
    low_theirs, theirs_values = dense_values(theirs)
    assert low_ours == low_theirs
    assert ours_values.tobytes() == theirs_values.tobytes()


def test_mesh_level_set_matches_the_analytic_sphere_and_the_command(tmp_path):
    vertices, faces = icosphere(4)
    mesh = d2vdb.Mesh(vertices, faces)
    level_set = d2vdb.LevelSet.from_mesh(mesh, voxel_size=0.04)
    assert level_set.signs["method"] == "closest feature"
    assert level_set.mesh_report.closed and level_set.warnings == []
    points, values = band_points(level_set)
    # The mesh lies inside the sphere by at most its chord sagitta (~1.2e-3 at 4 subdivisions).
    exact = np.linalg.norm(points, axis=1) - 1.0
    near = np.abs(values) < 0.04
    np.testing.assert_allclose(values[near], exact[near], atol=0.004)
    assert np.all(np.sign(values[np.abs(exact) > 0.01]) == np.sign(exact[np.abs(exact) > 0.01]))

    mesh_file = tmp_path / "sphere.obj"
    mesh.save(mesh_file)
    out = tmp_path / "sphere.vdb"
    run_cli("mesh2sdf", mesh_file, out, "--voxel-size", 0.04)
    theirs = d2vdb.load(out)
    assert dense_values(theirs)[1].tobytes() == dense_values(level_set)[1].tobytes()


def test_unsigned_distance_of_an_open_sheet():
    vertices = np.array([[-1, -1, 0], [1, -1, 0], [1, 1, 0], [-1, 1, 0]], float)
    sheet = d2vdb.Mesh(vertices, np.array([[0, 1, 2], [0, 2, 3]]))
    level_set = d2vdb.LevelSet.from_mesh(sheet, voxel_size=0.1, signed=False)
    assert not level_set.signed and level_set.signs is None
    probe = np.array([[0.2, 0.3, 0.15], [0.0, 0.0, -0.2], [0.5, -0.4, 0.0]])
    np.testing.assert_allclose(level_set.values(probe), [0.15, 0.2, 0.0], atol=0.02)


def test_to_mesh_gives_a_closed_sphere_and_equals_the_command(tmp_path):
    sphere = d2vdb.LevelSet.sphere((0, 0, 0), 1.0, voxel_size=0.05)
    mesh = sphere.to_mesh()
    report = mesh.validate()
    assert report.closed and report.oriented and report.euler_characteristic == 2
    radii = np.linalg.norm(mesh.vertices.astype(float), axis=1)
    assert np.max(np.abs(radii - 1.0)) < 0.05 * 0.05  # linear interpolation error, << a voxel
    normals = mesh.normals.astype(float)
    assert np.min(np.sum(normals * mesh.vertices / radii[:, None], axis=1)) > 0.999
    offset = sphere.to_mesh(0.1, normals=False)
    assert offset.normals is None
    assert np.max(np.abs(np.linalg.norm(offset.vertices, axis=1) - 1.1)) < 0.003

    grid_file, mesh_file = tmp_path / "sphere.vdb", tmp_path / "sphere.obj"
    sphere.save(grid_file)
    run_cli("mesh", grid_file, mesh_file)
    theirs = d2vdb.load(mesh_file)
    np.testing.assert_array_equal(theirs.vertices, mesh.vertices)
    np.testing.assert_array_equal(theirs.faces, mesh.faces)


def test_iso_value_beyond_the_band_is_refused():
    sphere = d2vdb.LevelSet.sphere((0, 0, 0), 1.0, voxel_size=0.05)
    with pytest.raises(d2vdb.InputError, match="band"):
        sphere.to_mesh(0.5)


def test_results_do_not_depend_on_the_thread_count():
    vertices, faces = icosphere(3)
    mesh = d2vdb.Mesh(vertices, faces[2:])  # open: its hole is closed virtually
    one = d2vdb.LevelSet.from_mesh(mesh, voxel_size=0.05, threads=1)
    two = d2vdb.LevelSet.from_mesh(mesh, voxel_size=0.05, threads=2)
    assert dense_values(one)[1].tobytes() == dense_values(two)[1].tobytes()
    assert one.signs["holes_closed"] >= 1 and one.warnings  # the hole was capped
    m1, m2 = one.to_mesh(threads=1), two.to_mesh(threads=2)
    assert m1.vertices.tobytes() == m2.vertices.tobytes() and m1.faces.tobytes() == m2.faces.tobytes()


def test_save_round_trip_and_half_floats(tmp_path):
    sphere = d2vdb.LevelSet.sphere((0, 0, 0), 1.0, voxel_size=0.1)
    sphere.save(tmp_path / "full.vdb")
    sphere.save(tmp_path / "half.vdb", half_float=True)
    full, half = d2vdb.load(tmp_path / "full.vdb"), d2vdb.load(tmp_path / "half.vdb")
    assert dense_values(full)[1].tobytes() == dense_values(sphere)[1].tobytes()
    np.testing.assert_allclose(dense_values(half)[1], dense_values(sphere)[1], rtol=2**-11, atol=1e-7)


def test_degenerate_and_absurd_requests_are_refused_before_allocating():
    with pytest.raises(d2vdb.InputError, match="radius"):
        d2vdb.LevelSet.sphere((0, 0, 0), -1.0, voxel_size=0.1)
    with pytest.raises(d2vdb.InputError):
        d2vdb.LevelSet.sphere((0, 0, 0), 1.0, voxel_size=1e-5)
    with pytest.raises(d2vdb.InputError, match="center must be finite"):
        d2vdb.LevelSet.sphere((0, np.nan, 0), 1.0, voxel_size=0.1)
    flat = d2vdb.Mesh(np.zeros((3, 3)), np.array([[0, 1, 2]]))
    with pytest.raises(d2vdb.InputError):
        d2vdb.LevelSet.from_mesh(flat)
