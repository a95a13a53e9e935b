# Type stub of the d2vdb module, for editors and type checkers. Units: world units for lengths,
# 1/world units for curvatures, voxels for half-widths. Long calls take threads (0: all cores;
# results never depend on it) and progress (None or callable(stage, fraction)).
from os import PathLike
from typing import Any, Callable, Dict, List, Optional, Sequence, Tuple, Union

import numpy as np
import numpy.typing as npt

__version__: str

ArrayLike = npt.ArrayLike
Path = Union[str, PathLike]
Progress = Optional[Callable[[str, float], Any]]
Box = Tuple[Tuple[float, float, float], Tuple[float, float, float]]

class InputError(ValueError): ...
class RuntimeFailure(RuntimeError): ...

class MeshReport:
    vertex_count: int
    triangle_count: int
    edge_count: int
    boundary_edge_count: int
    non_manifold_edge_count: int
    non_manifold_vertex_count: int
    boundary_loop_count: int
    degenerate_triangle_count: int
    inconsistently_oriented_edge_count: int
    unreferenced_vertex_count: int
    connected_component_count: int
    closed: bool
    manifold: bool
    oriented: bool
    euler_characteristic: int
    problems: str

class Mesh:
    def __init__(self, vertices: ArrayLike, faces: ArrayLike, normals: Optional[ArrayLike] = ...) -> None: ...
    vertices: npt.NDArray[np.float32]  # (N, 3), read-only view
    faces: npt.NDArray[np.uint32]  # (M, 3), read-only view
    normals: Optional[npt.NDArray[np.float32]]
    vertex_count: int
    face_count: int
    bounding_box: Box
    def validate(self) -> MeshReport: ...
    def save(self, path: Path, binary: bool = ...) -> None: ...

class LevelSet:
    @staticmethod
    def from_mesh(mesh: Mesh, *, voxel_size: float = ..., resolution: int = ..., half_width: float = ...,
                  signed: bool = ..., exact_signs: bool = ..., max_voxels: int = ..., threads: int = ...,
                  progress: Progress = ...) -> "LevelSet": ...
    @staticmethod
    def sphere(center: ArrayLike, radius: float, *, voxel_size: float = ..., resolution: int = ...,
               half_width: float = ..., max_voxels: int = ..., threads: int = ...) -> "LevelSet": ...
    @staticmethod
    def box(min: ArrayLike, max: ArrayLike, *, voxel_size: float = ..., resolution: int = ...,
            half_width: float = ..., max_voxels: int = ..., threads: int = ...) -> "LevelSet": ...
    @staticmethod
    def torus(center: ArrayLike, major_radius: float, minor_radius: float, *, voxel_size: float = ...,
              resolution: int = ..., half_width: float = ..., max_voxels: int = ...,
              threads: int = ...) -> "LevelSet": ...
    @staticmethod
    def cylinder(center: ArrayLike, radius: float, height: float, *, voxel_size: float = ...,
                 resolution: int = ..., half_width: float = ..., max_voxels: int = ...,
                 threads: int = ...) -> "LevelSet": ...
    @staticmethod
    def from_openvdb(grid: Any) -> "LevelSet": ...
    def to_openvdb(self) -> Any: ...
    def to_mesh(self, isovalue: float = ..., *, normals: bool = ..., threads: int = ...,
                progress: Progress = ...) -> Mesh: ...
    def values(self, points: ArrayLike, *, threads: int = ...) -> npt.NDArray[np.float64]: ...
    def save(self, path: Path, *, compression: bool = ..., half_float: bool = ..., source: str = ...) -> None: ...
    voxel_size: float
    half_width: float
    active_voxel_count: int
    signed: bool
    name: str
    bounding_box: Optional[Box]
    mesh_report: Optional[MeshReport]
    signs: Optional[Dict[str, Any]]
    warnings: List[str]

class PointSet:
    def __init__(self, points: ArrayLike) -> None: ...
    points: npt.NDArray[np.float64]
    def __len__(self) -> int: ...
    def save(self, path: Path) -> None: ...

class Curve:
    def __init__(self, control_points: ArrayLike, *, degree: int = ..., closed: bool = ...,
                 knots: Optional[ArrayLike] = ..., dimension: int = ...) -> None: ...
    degree: int
    closed: bool
    dimension: int
    knots: npt.NDArray[np.float64]
    domain: Tuple[float, float]
    control_points: npt.NDArray[np.float64]
    def evaluate(self, t: ArrayLike) -> npt.NDArray[np.float64]: ...
    def project(self, points: ArrayLike, *, threads: int = ...) -> Dict[str, npt.NDArray[np.float64]]: ...
    def save(self, path: Path) -> None: ...

class Surface:
    def __init__(self, control_points: ArrayLike, *, degree_u: int = ..., degree_v: int = ...,
                 knots_u: Optional[ArrayLike] = ..., knots_v: Optional[ArrayLike] = ...) -> None: ...
    degree_u: int
    degree_v: int
    closed_u: bool
    closed_v: bool
    knots_u: npt.NDArray[np.float64]
    knots_v: npt.NDArray[np.float64]
    control_points: npt.NDArray[np.float64]  # (count_u, count_v, 3)
    def evaluate(self, u: ArrayLike, v: ArrayLike) -> npt.NDArray[np.float64]: ...
    def save(self, path: Path) -> None: ...

class SupportFunction:
    @staticmethod
    def fit(points: Union["Field", ArrayLike], normals: Optional[ArrayLike] = ..., *, degree: int = ...,
            regularization: Optional[float] = ..., allow_singular: bool = ...,
            threads: int = ...) -> "SupportFunction": ...
    degree: int
    def value(self, normals: ArrayLike) -> npt.NDArray[np.float64]: ...
    def points(self, normals: ArrayLike, offset: float = ...) -> npt.NDArray[np.float64]: ...
    def tessellate(self, offset: float = ..., *, subdivisions: int = ...) -> Mesh: ...
    def save(self, path: Path) -> None: ...
    def to_json(self) -> str: ...

class SmoothSurface:
    def __init__(self, mesh: Mesh, *, source: str = ..., max_bidegree: int = ..., threads: int = ...,
                 progress: Progress = ...) -> None: ...
    face_count: int
    def evaluate(self, face_ids: ArrayLike, barycentric: ArrayLike, *,
                 threads: int = ...) -> Dict[str, npt.NDArray[np.float64]]: ...
    def tessellate(self, lod: int = ..., *, curvature: bool = ..., threads: int = ...) -> Dict[str, Any]: ...

Target = Union[Mesh, LevelSet, PointSet, Curve, ArrayLike]

class Field:
    def __init__(self, target: Target, *, voxel_size: float = ..., resolution: int = ...,
                 half_width: float = ..., padding: float = ..., smooth: Optional[str] = ...,
                 max_voxels: int = ..., threads: int = ..., progress: Progress = ...) -> None: ...
    def query(self, points: ArrayLike, *, threads: int = ...) -> Dict[str, npt.NDArray[Any]]: ...
    def sdm_form(self, points: ArrayLike, *, threads: int = ...) -> Tuple[
        npt.NDArray[np.float64], npt.NDArray[np.float64], npt.NDArray[np.float64]]: ...
    def save(self, path: Path, *, compression: bool = ..., half_float: bool = ..., source: str = ...) -> None: ...
    def grids(self) -> Dict[str, Any]: ...
    distance_grid: LevelSet
    voxel_size: float
    half_width: float
    kind: str
    of: str
    domain: Box
    active_voxel_count: int
    warnings: List[str]

def load(path: Path, *, grid: str = ..., threads: int = ..., progress: Progress = ...) -> Union[
    Mesh, PointSet, LevelSet, Field, Curve, Surface, SupportFunction, List[npt.NDArray[np.float64]]]: ...

class FitResult:
    spline: Union[Curve, Surface]
    status: str  # 'converged', 'stalled' or 'iteration cap'
    reason: str
    history: Dict[str, npt.NDArray[Any]]  # row 0: the initial spline

# Further keywords of both fits: method ('pdm', 'tdm', 'sdm', 'tdm+pdm'), iterations,
# smoothness (None: automatic), smoothing_bias, step_smoothness, stretch, pdm_weight, tolerance,
# step_tolerance, move_tolerance, exact_second_order.
def fit_curve(target: Union[Field, Curve, PointSet, ArrayLike], initial: Union[str, Curve] = ..., *,
              control_points: int = ..., degree: int = ..., closed: bool = ..., offset: float = ...,
              sensors: int = ..., footpoint_correction: bool = ..., threads: int = ...,
              progress: Progress = ..., **options: Any) -> FitResult: ...
def fit_surface(target: Union[Field, Surface, PointSet, ArrayLike], initial: Union[str, Surface] = ..., *,
                control_points: Tuple[int, int] = ..., degree: Tuple[int, int] = ..., closed_u: bool = ...,
                closed_v: bool = ..., ruled: bool = ..., offset: float = ..., sensors: int = ...,
                reparametrize: bool = ..., threads: int = ..., progress: Progress = ...,
                **options: Any) -> FitResult: ...

def certified_hausdorff(a: Union[Mesh, LevelSet, Curve, Surface, PointSet, ArrayLike],
                        b: Union[Mesh, LevelSet, Curve, Surface, PointSet, ArrayLike], *,
                        tolerance: float = ..., relative: bool = ..., one_sided: bool = ...,
                        max_depth: int = ..., threads: int = ...,
                        progress: Progress = ...) -> Dict[str, Any]: ...
def hausdorff(a: Curve, b: Curve, *, tolerance: float = ..., max_depth: int = ..., one_sided: bool = ...,
              threads: int = ..., progress: Progress = ...) -> Dict[str, Any]: ...
