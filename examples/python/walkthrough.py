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


def torus_mesh(major=1.0, minor=0.35, segments=256, rings=128):
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
        print(f"\r  {stage}: {100 * fraction:5.1f} %   ", end="", flush=True)

    # A band of 6 voxels each side holds the offset meshed at the end (0.05, ~3.6 voxels).
    level_set = d2vdb.LevelSet.from_mesh(mesh, resolution=192, half_width=6, progress=progress)
    print()
    print(f"{level_set}, signs by {level_set.signs['method']}")
    level_set.save(out / "torus.vdb")

    field = d2vdb.Field(level_set)
    # Above the tube (footpoint on its top circle) and on the outer equator, where the analytic
    # torus has k1 = 1/0.35 = 2.857 at both, k2 = 0 and 1/1.35 = 0.741. The level set of a mesh
    # has the curvatures of its facets and creases at the scale of a voxel (facets here are about
    # two voxels wide); the field of the mesh's smooth (Loop limit) surface has the surface's own.
    probes = [[1.0, 0.0, 0.5], [1.35, 0.0, 0.0]]
    print("analytic:     distance [0.15 0]  k1 [2.857 2.857]  k2 [0 0.741]")
    for name, of in (("level set:", field), ("smooth mesh:", d2vdb.Field(mesh, resolution=192, smooth="loop"))):
        answers = of.query(probes)
        print(f"{name:13} distance {np.round(answers['distance'], 4)}  k1 {np.round(answers['k1'], 3)}"
              f"  k2 {np.round(answers['k2'], 3)}")

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
