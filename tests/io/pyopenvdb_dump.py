#!/usr/bin/python3
"""Reads a .vdb file with Debian's pyopenvdb (python3-openvdb) and prints what it read, for
tests/io/PyOpenVdbReadTest.cc: readAllGridMetadata() must succeed, then readAll() gives, per grid,
a line "grid NAME VALUE_TYPE ACTIVE_VOXELS" followed by one line "i j k value..." per active voxel
(exact: Python's repr of a float32 value widened to double round-trips). Exit 1 with the error on
stderr when pyopenvdb cannot read the file."""
import sys

import pyopenvdb


def main(path):
    try:
        pyopenvdb.readAllGridMetadata(path)
        grids, _ = pyopenvdb.readAll(path)
    except Exception as error:  # pyopenvdb raises TypeError, IOError, ...: report any
        print("pyopenvdb cannot read %s: %s" % (path, error), file=sys.stderr)
        return 1
    out = sys.stdout
    for grid in grids:
        out.write("grid %s %s %d\n" % (grid.name, grid.valueTypeName, grid.activeVoxelCount()))
        for item in grid.iterOnValues():
            value = item.value
            values = value if isinstance(value, tuple) else (value,)
            text = " ".join(repr(float(v)) for v in values)
            (i0, j0, k0), (i1, j1, k1) = item.min, item.max
            for i in range(i0, i1 + 1):
                for j in range(j0, j1 + 1):
                    for k in range(k0, k1 + 1):
                        out.write("%d %d %d %s\n" % (i, j, k, text))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1]))
