#!/usr/bin/python3
"""Mesh -> level set -> approximant field -> surface fit -> mesh, with a convergence plot.

  PYTHONPATH=build/python /usr/bin/python3 examples/python/walkthrough.py [OUT_DIR]

Builds a torus mesh from numpy arrays, makes its level set with exact signs, the field of the
level set, fits a bicubic B-spline torus to it (SDM, then PDM for comparison), meshes an offset of
the level set, and plots the RMS distance per iteration of both fits (matplotlib, Debian's
python3-matplotlib). Everything lands in OUT_DIR (default: out/python).
"""

import pathlib
import sys

import numpy as np

import d2vdb


def torus_mesh(major=1.0, minor=0.35, segments=96, rings=48):
    """A closed, outward-oriented triangulated torus about the z axis."""
    u, v = np.meshgrid(np.linspace(0, 2 * np.pi, segments, endpoint=False),
                       np.linspace(0, 2 * np.pi, rings, endpoint=False), indexing="ij")
    radius = major + minor * np.cos(v)
    vertices = np.stack([radius * np.cos(u), radius * np.sin(u), minor * np.sin(v)], -1).reshape(-1, 3)
    index = np.arange(segments * rings).reshape(segments, rings)
    a, b = index, np.roll(index, -1, axis=0)
    c, d = np.roll(b, -1, axis=1), np.roll(a, -1, axis=1)
    faces = np.concatenate([np.stack([a, b, c], -1).reshape(-1, 3), np.stack([a, c, d], -1).reshape(-1, 3)])
    return d2vdb.Mesh(vertices, faces)


def main():
    out = pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else "out/python")
    out.mkdir(parents=True, exist_ok=True)
    mesh = torus_mesh()
    print(mesh, mesh.validate())

    def progress(stage, fraction):
        print(f"\r  {stage}: {100 * fraction:5.1f} %", end="", flush=True)

    level_set = d2vdb.LevelSet.from_mesh(mesh, resolution=192, progress=progress)
    print(f"\n{level_set}, signs by {level_set.signs['method']}")
    level_set.save(out / "torus.vdb")

    field = d2vdb.Field(level_set)
    answers = field.query([[1.0, 0.0, 0.5], [1.35, 0.0, 0.0]])
    print("distances", answers["distance"], "curvatures k1", answers["k1"], "k2", answers["k2"])

    fits = {method: d2vdb.fit_surface(field, "torus", control_points=(12, 8), method=method)
            for method in ("sdm", "pdm")}
    for method, fit in fits.items():
        print(f"{method}: {fit.status} after {fit.history['iteration'][-1]} iterations, "
              f"RMS distance {fit.history['rms_distance'][-1]:.3g}")
    fits["sdm"].spline.save(out / "torus-fit.json")
    level_set.to_mesh(0.05).save(out / "torus-offset.obj")

    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print("matplotlib is not installed (Debian: python3-matplotlib): no plot")
        return
    figure, axes = plt.subplots(figsize=(6, 4))
    for method, fit in fits.items():
        axes.semilogy(fit.history["iteration"], fit.history["rms_distance"], marker="o", label=method.upper())
    axes.set_xlabel("iteration")
    axes.set_ylabel("RMS distance (world units)")
    axes.set_title("Bicubic torus fitted to a torus level set")
    axes.legend()
    figure.tight_layout()
    figure.savefig(out / "convergence.png", dpi=120)
    print(f"wrote {out}/torus.vdb, torus-fit.json, torus-offset.obj, convergence.png")


if __name__ == "__main__":
    main()
