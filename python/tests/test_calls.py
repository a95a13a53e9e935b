"""What a Python user expects of every long call: progress, Ctrl-C, threads, errors; and load()."""

import os
import signal
import threading
import time

import numpy as np
import pytest

import d2vdb

from conftest import SOURCE_DIR, icosphere


def big_mesh_level_set(**options):
    vertices, faces = icosphere(5)
    return d2vdb.LevelSet.from_mesh(d2vdb.Mesh(vertices, faces), **options)


def test_progress_reports_stages_and_fractions():
    reports = []
    big_mesh_level_set(resolution=96, progress=lambda stage, fraction: reports.append((stage, fraction)))
    stages = [stage for stage, _ in reports]
    assert "mesh to level set" in stages and any(s.startswith("exact signs") for s in stages)
    assert all(isinstance(s, str) and 0.0 <= f <= 1.0 for s, f in reports)


def test_an_exception_in_the_progress_callable_stops_the_call():
    calls = []

    def stop(stage, fraction):
        calls.append(stage)
        raise ZeroDivisionError("stop here")

    with pytest.raises(ZeroDivisionError, match="stop here"):
        big_mesh_level_set(resolution=96, progress=stop)
    assert len(calls) == 1


def test_ctrl_c_stops_a_long_call_within_a_second(tmp_path):
    # A level set at resolution 1024 of a sphere takes many seconds; SIGINT arrives after 0.5 s.
    sent = []

    def interrupt():
        time.sleep(0.5)
        sent.append(time.monotonic())
        os.kill(os.getpid(), signal.SIGINT)

    threading.Thread(target=interrupt).start()
    start = time.monotonic()
    with pytest.raises(KeyboardInterrupt):
        big_mesh_level_set(resolution=1024)
    stopped = time.monotonic()
    assert sent, "the call ended before the interrupt was sent"
    assert stopped - sent[0] < 1.0, f"stopped {stopped - sent[0]:.2f} s after Ctrl-C"
    assert stopped - start < 5.0


def test_calls_run_without_the_gil():
    # Another Python thread keeps running while the engine works.
    ticks = []
    done = threading.Event()

    def tick():
        while not done.is_set():
            ticks.append(1)
            time.sleep(0.005)

    thread = threading.Thread(target=tick)
    thread.start()
    start_ticks = len(ticks)
    big_mesh_level_set(resolution=256)
    done.set()
    thread.join()
    assert len(ticks) - start_ticks > 5


def test_bad_call_options():
    with pytest.raises(d2vdb.InputError, match="threads must be"):
        big_mesh_level_set(resolution=32, threads=-1)
    with pytest.raises(d2vdb.InputError, match="progress must be None or a callable"):
        big_mesh_level_set(resolution=32, progress=3)


def test_load_recognises_every_kind(tmp_path):
    assert isinstance(d2vdb.load(SOURCE_DIR / "volumes" / "bunny.vdb"), d2vdb.LevelSet)
    vertices, faces = icosphere(1)
    d2vdb.Mesh(vertices, faces).save(tmp_path / "a.ply")
    assert isinstance(d2vdb.load(tmp_path / "a.ply"), d2vdb.Mesh)
    d2vdb.PointSet(vertices).save(tmp_path / "p.xyz")
    points = d2vdb.load(tmp_path / "p.xyz")
    assert isinstance(points, d2vdb.PointSet) and points.points.tobytes() == vertices.tobytes()
    curve = d2vdb.Curve(vertices[:6], degree=3)
    curve.save(tmp_path / "c.json")
    loaded = d2vdb.load(tmp_path / "c.json")
    assert isinstance(loaded, d2vdb.Curve)
    assert loaded.control_points.tobytes() == curve.control_points.tobytes()
    assert loaded.knots.tobytes() == curve.knots.tobytes()
    grid = np.stack(np.meshgrid(np.linspace(0, 1, 5), np.linspace(0, 2, 4), indexing="ij"), -1)
    control = np.concatenate([grid, np.sin(grid[..., :1])], axis=-1)
    surface = d2vdb.Surface(control, degree_u=3, degree_v=2)
    surface.save(tmp_path / "s.json")
    loaded = d2vdb.load(tmp_path / "s.json")
    assert isinstance(loaded, d2vdb.Surface)
    np.testing.assert_array_equal(loaded.control_points, control)
    # Clamped surfaces interpolate their corners.
    np.testing.assert_allclose(surface.evaluate([0, 1], [0, 1]), [control[0, 0], control[-1, -1]], atol=1e-15)


def test_load_errors(tmp_path):
    with pytest.raises(FileNotFoundError):
        d2vdb.load(tmp_path / "missing.obj")
    (tmp_path / "bad.obj").write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 7\n")
    with pytest.raises(d2vdb.InputError, match="bad.obj"):
        d2vdb.load(tmp_path / "bad.obj")
    truncated = (SOURCE_DIR / "volumes" / "bunny.vdb").read_bytes()
    (tmp_path / "cut.vdb").write_bytes(truncated[: len(truncated) // 2])
    with pytest.raises(d2vdb.InputError, match="cut.vdb"):
        d2vdb.load(tmp_path / "cut.vdb")
    (tmp_path / "what.txt").write_text("hello\n")
    with pytest.raises(d2vdb.InputError, match="what.txt"):
        d2vdb.load(tmp_path / "what.txt")
