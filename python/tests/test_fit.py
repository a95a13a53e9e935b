"""fit_curve and fit_surface: analytic targets, the command's own fits bit for bit, threads."""

import json

import numpy as np
import pytest

import d2vdb

from conftest import SOURCE_DIR, run_cli


def circle_points(count=400, radius=2.0):
    angles = np.linspace(0.0, 2.0 * np.pi, count, endpoint=False)
    return np.c_[radius * np.cos(angles), radius * np.sin(angles), np.zeros(count)]


def test_curve_fit_to_points_of_a_circle_reaches_the_cubic_floor():
    result = d2vdb.fit_curve(circle_points(), "circle", control_points=12)
    assert result.status == "converged", result.reason
    curve = result.spline
    assert isinstance(curve, d2vdb.Curve) and curve.closed and curve.degree == 3
    # A uniform periodic cubic with 12 control points approximates a circle of radius 1 to
    # 1.05e-4 (the fitting floor, engine/README.md); radius 2 doubles it.
    samples = curve.evaluate(np.linspace(*curve.domain, 2000))
    radial = np.abs(np.linalg.norm(samples[:, :2], axis=1) - 2.0)
    assert np.max(radial) < 2 * 1.05e-4 * 1.5
    history = result.history
    assert len(history["rms_distance"]) == history["iteration"][-1] + 1
    assert history["rms_distance"][-1] < 0.1 * history["rms_distance"][0]


def test_curve_fit_equals_the_command_bit_for_bit(tmp_path):
    cloud = SOURCE_DIR / "volumes" / "cloud.xyz"
    out = tmp_path / "fit.json"
    run_cli("fit-curve", "--target", cloud, "--init", "ellipse", "--ctrl", 16, "--out", out)
    theirs = d2vdb.load(out)
    ours = d2vdb.fit_curve(d2vdb.load(cloud), "ellipse", control_points=16).spline
    assert ours.control_points.tobytes() == theirs.control_points.tobytes()
    assert ours.knots.tobytes() == theirs.knots.tobytes()


def test_surface_fit_to_the_torus_equals_the_command_and_any_thread_count(tmp_path):
    torus = SOURCE_DIR / "volumes" / "torus.vdb"
    out = tmp_path / "torus.json"
    run_cli("fit-surface", "--target", torus, "--init", "torus", "--ctrl", "12,8", "--out", out,
            "--json")
    theirs = d2vdb.load(out)
    field = d2vdb.Field(d2vdb.load(torus))
    one = d2vdb.fit_surface(field, "torus", control_points=(12, 8), threads=1)
    two = d2vdb.fit_surface(field, "torus", control_points=(12, 8), threads=2)
    assert one.spline.closed_u and one.spline.closed_v
    assert one.spline.control_points.tobytes() == theirs.control_points.tobytes()
    assert two.spline.control_points.tobytes() == one.spline.control_points.tobytes()
    assert one.status == "converged", one.reason
    # The fitted surface lies on the torus level set to a fraction of a voxel.
    grid = np.stack(np.meshgrid(np.linspace(0, 1, 40, endpoint=False),
                                np.linspace(0, 1, 40, endpoint=False), indexing="ij"), -1)
    surface = one.spline
    u0, u1 = surface.knots_u[surface.degree_u], surface.knots_u[-surface.degree_u - 1]
    v0, v1 = surface.knots_v[surface.degree_v], surface.knots_v[-surface.degree_v - 1]
    points = surface.evaluate(u0 + (u1 - u0) * grid[..., 0].ravel(), v0 + (v1 - v0) * grid[..., 1].ravel())
    distances = field.query(points)["distance"]
    assert np.max(np.abs(distances)) < 0.5 * field.voxel_size


def test_surface_fit_to_points_of_a_sheet():
    u, v = np.meshgrid(np.linspace(-1, 1, 30), np.linspace(-1, 1, 30))
    sheet = np.c_[u.ravel(), v.ravel(), 0.1 * np.sin(2 * u.ravel()) * np.cos(v.ravel())]
    # Without smoothing a bicubic 8 x 8 net follows the sheet to ~1e-6; the automatic smoothing
    # trades some of that for smoothness, staying well within the sheet's amplitude 0.1.
    exact = d2vdb.fit_surface(sheet, "plane", control_points=(8, 8), smoothness=0, iterations=30)
    assert isinstance(exact.spline, d2vdb.Surface)
    assert exact.history["rms_distance"][-1] < 1e-5
    smooth = d2vdb.fit_surface(sheet, "plane", control_points=(8, 8))
    assert smooth.status == "converged"
    assert 1e-5 < smooth.history["rms_distance"][-1] < 0.03


def test_fit_options_are_checked():
    with pytest.raises(d2vdb.InputError, match="unknown fit option 'iteration'"):
        d2vdb.fit_curve(circle_points(), iteration=3)
    with pytest.raises(d2vdb.InputError, match="xyz"):
        d2vdb.fit_curve(circle_points(), method="xyz")
    with pytest.raises(d2vdb.InputError, match="circle, ellipse or polyline"):
        d2vdb.fit_curve(circle_points(), "square")
    mesh = d2vdb.Mesh(np.eye(3), np.array([[0, 1, 2]]))
    with pytest.raises(d2vdb.InputError, match="d2vdb.Field"):
        d2vdb.fit_surface(mesh)
    with pytest.raises(d2vdb.InputError, match="plane, cylinder or torus"):
        d2vdb.fit_surface(circle_points() + [0, 0, 0.1], "cone")
