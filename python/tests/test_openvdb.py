"""Grids handed to and from Debian's pyopenvdb in memory: the same grid, not a copy."""

import numpy as np
import pytest

import d2vdb

pyopenvdb = pytest.importorskip("pyopenvdb")


def test_to_openvdb_shares_the_grid():
    sphere = d2vdb.LevelSet.sphere((0, 0, 0), 1.0, voxel_size=0.1)
    grid = sphere.to_openvdb()
    assert isinstance(grid, pyopenvdb.FloatGrid)
    assert grid.activeVoxelCount() == sphere.active_voxel_count
    assert grid.sharesWith(sphere.to_openvdb())
    # A change through pyopenvdb is seen by d2vdb: the tree is the same.
    grid.getAccessor().setValueOn((10, 0, 0), 0.25)
    assert sphere.values([[1.0, 0.0, 0.0]])[0] == pytest.approx(0.25)


def test_from_openvdb_shares_the_grid():
    grid = pyopenvdb.createLevelSetSphere(radius=1.0, center=(0, 0, 0), voxelSize=0.05,
                                          halfWidth=3.0)
    level_set = d2vdb.LevelSet.from_openvdb(grid)
    assert level_set.to_openvdb().sharesWith(grid)
    assert level_set.signed and level_set.voxel_size == pytest.approx(0.05)
    mesh = level_set.to_mesh()
    assert mesh.validate().closed
    assert np.max(np.abs(np.linalg.norm(mesh.vertices, axis=1) - 1.0)) < 0.01
    # A d2vdb field of pyopenvdb's level set answers like the analytic sphere.
    answers = d2vdb.Field(level_set).query([[0.0, 0.0, 1.07]])
    assert answers["distance"][0] == pytest.approx(0.07, abs=0.003)
    grid.getAccessor().setValueOn((0, 0, 20), -0.01)
    assert level_set.values([[0.0, 0.0, 1.0]])[0] == pytest.approx(-0.01, abs=1e-6)


def test_field_grids_open_in_pyopenvdb():
    field = d2vdb.Field(d2vdb.LevelSet.sphere((0, 0, 0), 1.0, voxel_size=0.1))
    grids = field.grids()
    assert field.distance_grid.to_openvdb().sharesWith(grids[field.distance_grid.name])
    for name, grid in grids.items():
        assert grid.activeVoxelCount() == field.active_voxel_count, name


def test_other_objects_are_refused():
    with pytest.raises(d2vdb.InputError, match="takes a pyopenvdb.FloatGrid; got a Vec3SGrid"):
        d2vdb.LevelSet.from_openvdb(pyopenvdb.Vec3SGrid())
    with pytest.raises(d2vdb.InputError, match="got a list"):
        d2vdb.LevelSet.from_openvdb([1, 2, 3])


def test_files_written_by_d2vdb_open_in_pyopenvdb(tmp_path):
    field = d2vdb.Field(d2vdb.LevelSet.sphere((0, 0, 0), 1.0, voxel_size=0.1))
    field.save(tmp_path / "field.vdb")
    grids, metadata = pyopenvdb.readAll(str(tmp_path / "field.vdb"))
    assert {grid.name for grid in grids} == set(field.grids())
