"""Shared fixtures of the d2vdb Python tests: the d2vdb command, the source tree, test shapes."""

import os
import pathlib
import subprocess

import numpy as np
import pytest

SOURCE_DIR = pathlib.Path(os.environ.get("D2VDB_SOURCE_DIR", pathlib.Path(__file__).parents[2]))


def cli_path():
    path = os.environ.get("D2VDB_CLI")
    if not path:
        pytest.skip("D2VDB_CLI is not set (ctest sets it to the built d2vdb command)")
    return path


def run_cli(*arguments):
    """Runs the d2vdb command; fails the test with its stderr when it does not exit 0."""
    result = subprocess.run([cli_path(), *map(str, arguments)], capture_output=True, text=True)
    assert result.returncode == 0, result.stderr
    return result


def icosphere(subdivisions=3, radius=1.0):
    """A closed, consistently oriented triangulated sphere (vertices on the sphere)."""
    t = (1.0 + 5.0**0.5) / 2.0
    vertices = [(-1, t, 0), (1, t, 0), (-1, -t, 0), (1, -t, 0), (0, -1, t), (0, 1, t),
                (0, -1, -t), (0, 1, -t), (t, 0, -1), (t, 0, 1), (-t, 0, -1), (-t, 0, 1)]
    faces = [(0, 11, 5), (0, 5, 1), (0, 1, 7), (0, 7, 10), (0, 10, 11), (1, 5, 9), (5, 11, 4),
             (11, 10, 2), (10, 7, 6), (7, 1, 8), (3, 9, 4), (3, 4, 2), (3, 2, 6), (3, 6, 8),
             (3, 8, 9), (4, 9, 5), (2, 4, 11), (6, 2, 10), (8, 6, 7), (9, 8, 1)]
    vertices = [np.array(v, float) / np.linalg.norm(v) for v in vertices]
    for _ in range(subdivisions):
        midpoint_of = {}

        def midpoint(a, b):
            key = (min(a, b), max(a, b))
            if key not in midpoint_of:
                m = vertices[a] + vertices[b]
                vertices.append(m / np.linalg.norm(m))
                midpoint_of[key] = len(vertices) - 1
            return midpoint_of[key]

        refined = []
        for a, b, c in faces:
            ab, bc, ca = midpoint(a, b), midpoint(b, c), midpoint(c, a)
            refined += [(a, ab, ca), (b, bc, ab), (c, ca, bc), (ab, bc, ca)]
        faces = refined
    return radius * np.array(vertices), np.array(faces, dtype=np.int64)


@pytest.fixture
def sphere_arrays():
    return icosphere()
