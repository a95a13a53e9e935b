"""Brings a d2vdb mesh and level set into Blender as objects.

  PYTHONPATH=build/python blender --background --python examples/python/blender_import.py

Debian 12's blender runs /usr/bin/python3's python3.11, so the module built for it imports.
Makes the mesh of a torus level set (d2vdb's marching cubes, with normals) and the level set
itself as a volume object (a .vdb file Blender reads), then saves /tmp/d2vdb-scene.blend.
Not run by CI (Blender is not a dependency).
"""

import bpy

import d2vdb

level_set = d2vdb.LevelSet.torus((0, 0, 0), 1.0, 0.3, voxel_size=0.02)
mesh = level_set.to_mesh()

data = bpy.data.meshes.new("d2vdb_torus")
data.from_pydata(mesh.vertices.tolist(), [], mesh.faces.tolist())
data.update()
bpy.context.collection.objects.link(bpy.data.objects.new("d2vdb_torus", data))

level_set.save("/tmp/d2vdb-torus.vdb")
volume = bpy.data.volumes.new("d2vdb_torus_level_set")
volume.filepath = "/tmp/d2vdb-torus.vdb"
bpy.context.collection.objects.link(bpy.data.objects.new("d2vdb_torus_level_set", volume))

bpy.ops.wm.save_as_mainfile(filepath="/tmp/d2vdb-scene.blend")
print("d2vdb", d2vdb.__version__, ": mesh", mesh, "and level set", level_set, "-> /tmp/d2vdb-scene.blend")
