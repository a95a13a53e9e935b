"""d2vdb: sparse-grid implicit modelling from Python.

Narrow-band distance fields (OpenVDB grids) whose voxels carry local quadratic approximants of
the squared distance, built from meshes, level sets, point sets and B-spline curves; queries,
meshing and files, all on numpy arrays. World units throughout; signed distances are negative
inside a closed surface. The extension module _d2vdb holds the bindings; this package re-exports
them. Long calls release the GIL, take ``threads=`` (0: all cores; results never depend on it)
and ``progress=callable(stage, fraction)``, and stop on Ctrl-C.

    import d2vdb
    sphere = d2vdb.LevelSet.sphere((0, 0, 0), 1.0, voxel_size=0.05)
    field = d2vdb.Field(sphere)
    answers = field.query([[0.0, 0.0, 2.0]])
    answers["distance"], answers["footpoint"], answers["k1"]
"""

from ._d2vdb import (  # noqa: F401  (the public API)
    Curve,
    Field,
    FitResult,
    InputError,
    LevelSet,
    Mesh,
    MeshReport,
    PointSet,
    RuntimeFailure,
    SmoothSurface,
    Surface,
    SupportFunction,
    __version__,
    certified_hausdorff,
    fit_curve,
    fit_surface,
    hausdorff,
    load,
)

__all__ = [
    "Curve",
    "Field",
    "FitResult",
    "InputError",
    "LevelSet",
    "Mesh",
    "MeshReport",
    "PointSet",
    "RuntimeFailure",
    "SmoothSurface",
    "Surface",
    "SupportFunction",
    "certified_hausdorff",
    "fit_curve",
    "fit_surface",
    "hausdorff",
    "load",
]
