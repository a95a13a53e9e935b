#!/usr/bin/python3
"""The Python module's overhead against the C++ calls it wraps, measured in the same run.

  PYTHONPATH=build/python /usr/bin/python3 tools/bench/bench_python.py [--repeat 11]

1. 1,000,000 random queries of the bunny's field from numpy (Field.query) against the engine's
   batch query answerAll() on the same points (timed inside the extension): ratio of rates.
2. Handing a level set of about 10 M active voxels to pyopenvdb and back (to_openvdb() and
   LevelSet.from_openvdb()): milliseconds, no copy.
3. fit_surface() of a 12 x 8 bicubic torus to the bundled torus field against the same C++ fit
   (fitTargetFromField() + fitSurface(), timed inside the extension): ratio of times.
Medians of --repeat runs each; the machine's thread count is used throughout.
"""

import argparse
import pathlib
import statistics
import time

import numpy as np

import d2vdb
from d2vdb import _d2vdb

ROOT = pathlib.Path(__file__).resolve().parents[2]


def median_seconds(call, repeat):
    times = []
    for _ in range(repeat):
        start = time.perf_counter()
        call()
        times.append(time.perf_counter() - start)
    return statistics.median(times)


def interleaved(python_call, engine_seconds, repeat):
    """Medians of the Python call's wall time and the engine's own timing, run alternately so that
    both see the same machine state."""
    python, engine = [], []
    for _ in range(repeat):
        start = time.perf_counter()
        python_call()
        python.append(time.perf_counter() - start)
        engine.append(engine_seconds())
    return statistics.median(python), statistics.median(engine)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=11)
    repeat = parser.parse_args().repeat

    field = d2vdb.Field(d2vdb.load(ROOT / "volumes" / "bunny.vdb"))
    low, high = (np.array(corner) for corner in field.domain)
    points = np.random.default_rng(1).uniform(low, high, size=(1_000_000, 3))
    field.query(points[:1000])  # builds the coarse levels once, outside the timing
    python, engine = interleaved(lambda: field.query(points),
                                 lambda: _d2vdb._answer_all_seconds(field, points), repeat)
    print(f"queries: 1e6 points, Field.query {python * 1e3:.1f} ms, answerAll {engine * 1e3:.1f} ms,"
          f" rate ratio {engine / python:.3f} (goal >= 0.9)")

    sphere = d2vdb.LevelSet.sphere((0, 0, 0), 1.0, voxel_size=1.0 / 364)
    handoff = median_seconds(lambda: d2vdb.LevelSet.from_openvdb(sphere.to_openvdb()), repeat)
    print(f"pyopenvdb hand-off: {sphere.active_voxel_count / 1e6:.2f} M voxels, to_openvdb + "
          f"from_openvdb {handoff * 1e3:.3f} ms (goal <= 1 ms)")

    torus = d2vdb.Field(d2vdb.load(ROOT / "volumes" / "torus.vdb"))
    initial = d2vdb.fit_surface(torus, "torus", control_points=(12, 8), iterations=0).spline
    python, engine = interleaved(lambda: d2vdb.fit_surface(torus, initial),
                                 lambda: _d2vdb._fit_surface_seconds(torus, initial), repeat)
    print(f"fit_surface: torus 12 x 8, Python {python * 1e3:.1f} ms, C++ {engine * 1e3:.1f} ms, "
          f"ratio {python / engine:.3f} (goal <= 1.05)")


if __name__ == "__main__":
    main()
