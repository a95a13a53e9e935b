#!/usr/bin/python3
"""Grids to and from pyopenvdb (Debian's python3-openvdb) in memory, without a copy or a file.

  PYTHONPATH=build/python /usr/bin/python3 examples/python/pyopenvdb_handoff.py
"""

import pyopenvdb

import d2vdb

# pyopenvdb -> d2vdb: OpenVDB's own sphere, meshed and measured by d2vdb.
grid = pyopenvdb.createLevelSetSphere(radius=1.0, voxelSize=0.02, halfWidth=3.0)
level_set = d2vdb.LevelSet.from_openvdb(grid)
print("shared:", level_set.to_openvdb().sharesWith(grid))
answers = d2vdb.Field(level_set).query([[0.0, 0.0, 1.05]])
print("distance at (0, 0, 1.05):", answers["distance"][0], "curvature:", answers["k1"][0])
print("mesh:", level_set.to_mesh().validate())

# d2vdb -> pyopenvdb: a level set with exact signs, edited with pyopenvdb's accessor.
torus = d2vdb.LevelSet.torus((0, 0, 0), 1.0, 0.3, voxel_size=0.02)
handle = torus.to_openvdb()
handle.getAccessor().setValueOn((50, 0, 0), 0.0)
print("value seen by d2vdb:", torus.values([[1.0, 0.0, 0.0]])[0])
pyopenvdb.write("/tmp/torus-from-d2vdb.vdb", grids=[handle])
print("pyopenvdb wrote /tmp/torus-from-d2vdb.vdb")
